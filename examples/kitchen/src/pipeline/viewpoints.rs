//! Mapping viewpoints computed from the static base map: free base poses from which the head
//! camera's handle detector sees every face of the map's shapes that looks into the room,
//! chosen greedily (set cover) and visited in a nearest-neighbour tour from the start.
//!
//! The robot knows only the base map before mapping (the parts and their handles are what the
//! mapping looks for), so the faces to cover are the edges of the map's navigation grid: an
//! occupied cell with a free 4-neighbour is a piece of a wall, counter or cabinet front, its
//! outward normal the sum of the directions to its free neighbours. When the map has a floor
//! (shapes that reach below the grid's height band), only the faces over the floor count, and
//! only poses over it are candidates: the outside of the room's walls is not the room.

use std::collections::BinaryHeap;
use std::f64::consts::{PI, SQRT_2};

use kinscene::scene::nav::{GridBounds, NavGrid, NavGridSettings};
use kinscene::scene::{BaseMap, SceneModelBuilder};
use nalgebra::{Point2, Vector2};

use super::PipelineError;

/// How the viewpoints are chosen: a model of the head camera's handle detector (its range,
/// field of view and the angles it sees a handle at) and the search's resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewpointSettings {
    /// Clearance (m) kept between the robot's footprint disc and the base map's shapes: the
    /// closed fronts and handles of the unknown parts stand a few centimetres proud of them.
    pub clearance: f64,
    /// Smallest horizontal distance (m) from the camera to a face it covers.
    pub min_distance: f64,
    /// Largest horizontal distance (m) from the camera to a face it covers: the detector's
    /// 3 m range from the 1.3 m mast to a handle 0.3 m high leaves 2.83 m horizontally; 2.5 m
    /// keeps a margin for the detector's confidence, which falls with distance.
    pub max_distance: f64,
    /// Half the horizontal field of view (rad) a covered face lies in: the detector's 43.5°
    /// less the margin of a handle 0.3 m to the side of the covered cell at 2.5 m.
    pub half_fov: f64,
    /// Largest angle (rad) between a face's outward normal and the direction to the camera:
    /// handles seen edge-on are hidden by their neighbours' fronts and bars.
    pub max_obliquity: f64,
    /// Spacing (m) of the candidate positions.
    pub stride: f64,
    /// Candidate headings per position (evenly spaced).
    pub headings: usize,
    /// Largest number of viewpoints.
    pub max_views: usize,
    /// A viewpoint must cover at least this much (m) of faces not yet covered enough.
    pub min_gain: f64,
    /// Views each face should be in: the detector misses a visible handle now and then (10 %
    /// of the time in the simulator), and a handle in two views is missed by both 1 % of the
    /// time.
    pub views_per_face: usize,
}

impl Default for ViewpointSettings {
    /// 0.15 m clearance, faces 0.5–2.5 m away within ±35° of the heading and 70° of their
    /// normal, candidates every 0.2 m with 16 headings, at most 12 viewpoints each covering
    /// 0.25 m of faces seen fewer than twice.
    fn default() -> Self {
        ViewpointSettings {
            clearance: 0.15,
            min_distance: 0.5,
            max_distance: 2.5,
            half_fov: 35f64.to_radians(),
            max_obliquity: 70f64.to_radians(),
            stride: 0.2,
            headings: 16,
            max_views: 12,
            min_gain: 0.25,
            views_per_face: 2,
        }
    }
}

/// A face cell of the base map: where it is and which way it looks.
#[derive(Debug, Clone, Copy)]
struct Face {
    /// A point just in front of the face (the centre of the free side of the cell's edge).
    point: Point2<f64>,
    /// Unit outward normal.
    normal: Vector2<f64>,
}

/// The mapping viewpoints for a robot whose footprint disc has radius `robot_radius` (m),
/// starting at `start` (x, y in m, yaw in rad): base poses x (m), y (m), yaw (rad) in the
/// order to visit them. The start pose is not among them unless it is chosen.
///
/// Steps: the base map's grid and its floor ([`grids`]); the faces to cover ([`faces`]); the
/// free candidate positions the robot reaches from the start ([`candidates`]); what each
/// candidate pose sees ([`visible_faces`]); the greedy cover ([`greedy`]); the tour
/// ([`nearest_neighbour_tour`]).
///
/// # Errors
/// [`PipelineError::Scene`] if the base map's grid cannot be built;
/// [`PipelineError::Config`] for settings out of range or a start off the map.
pub fn viewpoints(
    base: &BaseMap,
    robot_radius: f64,
    start: [f64; 3],
    settings: &ViewpointSettings,
) -> Result<Vec<[f64; 3]>, PipelineError> {
    check(settings, robot_radius)?;
    let (grid, floor) = grids(base)?;
    let free = grid.inflate(robot_radius + settings.clearance)?;
    let reachable = reachable_from(&free, Point2::new(start[0], start[1]))?;
    let faces = faces(&grid, floor.as_ref());
    let positions = candidates(&grid, &reachable, floor.as_ref(), settings.stride);
    let seen: Vec<Vec<(usize, f64)>> = positions
        .iter()
        .map(|p| visible_faces(&grid, &faces, p, settings))
        .collect();
    let chosen = greedy(&positions, &seen, &faces, grid.resolution(), settings);
    Ok(nearest_neighbour_tour(&free, &reachable, start, chosen))
}

fn check(s: &ViewpointSettings, robot_radius: f64) -> Result<(), PipelineError> {
    let ok = robot_radius.is_finite()
        && robot_radius > 0.0
        && s.clearance.is_finite()
        && s.clearance >= 0.0
        && s.min_distance.is_finite()
        && s.min_distance >= 0.0
        && s.max_distance.is_finite()
        && s.max_distance > s.min_distance
        && s.half_fov > 0.0
        && s.half_fov <= PI
        && s.max_obliquity > 0.0
        && s.max_obliquity <= PI / 2.0
        && s.stride.is_finite()
        && s.stride > 0.0
        && s.headings > 0
        && s.views_per_face > 0
        && s.min_gain.is_finite()
        && s.min_gain >= 0.0;
    if ok {
        Ok(())
    } else {
        Err(PipelineError::Config(format!(
            "viewpoint settings {s:?} with robot radius {robot_radius} m are out of range"
        )))
    }
}

/// The base map's navigation grid, and its floor: the cells under shapes that reach below the
/// grid's height band (a floor slab, and whatever stands on the floor), on the same cells;
/// `None` when no shape does (a map without a floor).
fn grids(base: &BaseMap) -> Result<(NavGrid, Option<Vec<bool>>), PipelineError> {
    let map = SceneModelBuilder {
        base: base.clone(),
        parts: Vec::new(),
    }
    .build()?;
    let grid = map.base_grid().clone();
    let res = grid.resolution();
    let origin = grid.origin();
    let bounds = GridBounds {
        min: origin,
        max: origin + Vector2::new(grid.width() as f64, grid.height() as f64) * res,
    };
    let low = BaseMap {
        name: base.name.clone(),
        shapes: base.shapes.clone(),
        nav: NavGridSettings {
            min_height: base.nav.min_height - 1.0,
            max_height: base.nav.min_height,
            bounds: Some(bounds),
            ..base.nav
        },
    };
    let floor_map = SceneModelBuilder {
        base: low,
        parts: Vec::new(),
    }
    .build()?;
    let f = floor_map.base_grid();
    let same = f.width() == grid.width()
        && f.height() == grid.height()
        && (f.origin() - origin).norm() < 1e-9;
    let floor = (same && f.occupied_count() > 0).then(|| f.cells().to_vec());
    Ok((grid, floor))
}

/// The four neighbours' offsets.
const FOUR: [(isize, isize); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];

fn neighbour(g: &NavGrid, i: usize, j: usize, (di, dj): (isize, isize)) -> Option<(usize, usize)> {
    let (ni, nj) = (i as isize + di, j as isize + dj);
    ((0..g.width() as isize).contains(&ni) && (0..g.height() as isize).contains(&nj))
        .then_some((ni as usize, nj as usize))
}

/// The faces: occupied cells with a free 4-neighbour (over the floor, when there is one),
/// in cell order.
fn faces(grid: &NavGrid, floor: Option<&Vec<bool>>) -> Vec<Face> {
    let w = grid.width();
    let half = 0.5 * grid.resolution();
    let mut out = Vec::new();
    for (i, j) in grid.occupied_cells() {
        let mut normal = Vector2::zeros();
        for d in FOUR {
            let Some((ni, nj)) = neighbour(grid, i, j, d) else {
                continue;
            };
            let on_floor = floor.is_none_or(|f| f[nj * w + ni]);
            if !grid.is_occupied(ni, nj) && on_floor {
                normal += Vector2::new(d.0 as f64, d.1 as f64);
            }
        }
        if let Some(n) = normal.try_normalize(1e-9) {
            out.push(Face {
                point: grid.cell_center(i, j) + n * half,
                normal: n,
            });
        }
    }
    out
}

/// The cells of `free` connected (4-neighbours) to the cell of `from`; when that cell is not
/// free, to the free cells within 0.5 m of it (a start parked close to a counter).
fn reachable_from(free: &NavGrid, from: Point2<f64>) -> Result<Vec<bool>, PipelineError> {
    let (w, h) = (free.width(), free.height());
    let (si, sj) = free.cell_of(from).ok_or_else(|| {
        PipelineError::Config(format!("the start {from:?} is off the base map's grid"))
    })?;
    let reach = (0.5 / free.resolution()).ceil() as isize;
    let mut seen = vec![false; w * h];
    let mut stack = Vec::new();
    for dj in -reach..=reach {
        for di in -reach..=reach {
            let Some((i, j)) = neighbour(free, si, sj, (di, dj)) else {
                continue;
            };
            let near = (di * di + dj * dj) as f64 <= (reach * reach) as f64;
            let seed = (di, dj) == (0, 0) || (near && free.is_occupied(si, sj));
            if seed && !free.is_occupied(i, j) && !seen[j * w + i] {
                seen[j * w + i] = true;
                stack.push((i, j));
            }
        }
    }
    while let Some((i, j)) = stack.pop() {
        for d in FOUR {
            if let Some((ni, nj)) = neighbour(free, i, j, d)
                && !free.is_occupied(ni, nj)
                && !seen[nj * w + ni]
            {
                seen[nj * w + ni] = true;
                stack.push((ni, nj));
            }
        }
    }
    Ok(seen)
}

/// Candidate positions: reachable cells (over the floor, when there is one) every `stride`.
fn candidates(
    grid: &NavGrid,
    reachable: &[bool],
    floor: Option<&Vec<bool>>,
    stride: f64,
) -> Vec<Point2<f64>> {
    let w = grid.width();
    let step = ((stride / grid.resolution()).round() as usize).max(1);
    let mut out = Vec::new();
    for j in (0..grid.height()).step_by(step) {
        for i in (0..w).step_by(step) {
            let k = j * w + i;
            if reachable[k] && floor.is_none_or(|f| f[k]) {
                out.push(grid.cell_center(i, j));
            }
        }
    }
    out
}

/// Whether the segment from `a` to `b` crosses only free cells of `grid` (sampled every
/// quarter cell; the cell of `b` itself is not tested).
fn line_of_sight(grid: &NavGrid, a: &Point2<f64>, b: &Point2<f64>) -> bool {
    let d = b - a;
    let n = (d.norm() / (0.25 * grid.resolution())).ceil() as usize;
    let end = grid.cell_of(*b);
    (0..n).all(|k| {
        let p = a + d * (k as f64 / n as f64);
        match grid.cell_of(p) {
            Some(c) if Some(c) == end => true,
            Some((i, j)) => !grid.is_occupied(i, j),
            None => false,
        }
    })
}

/// The faces the camera at `p` could see with some heading: in distance, facing it within
/// the obliquity limit, in line of sight; each with its bearing (rad) from `p`.
fn visible_faces(
    grid: &NavGrid,
    faces: &[Face],
    p: &Point2<f64>,
    s: &ViewpointSettings,
) -> Vec<(usize, f64)> {
    let cos_max = s.max_obliquity.cos();
    faces
        .iter()
        .enumerate()
        .filter_map(|(k, f)| {
            let to_camera = p - f.point;
            let d = to_camera.norm();
            let in_range = (s.min_distance..=s.max_distance).contains(&d);
            (in_range
                && f.normal.dot(&to_camera) >= cos_max * d
                && line_of_sight(grid, p, &f.point))
            .then(|| (k, (-to_camera.y).atan2(-to_camera.x)))
        })
        .collect()
}

/// `a - b` wrapped into (-π, π].
fn wrap(a: f64) -> f64 {
    let d = a.rem_euclid(2.0 * PI);
    if d > PI { d - 2.0 * PI } else { d }
}

/// Greedy set multicover: repeatedly the candidate pose (position, heading) that sees the
/// most faces seen fewer than `views_per_face` times so far, each pose at most once, until
/// none gains `min_gain` of faces or `max_views` are chosen. Ties go to the lower candidate
/// index, then the lower heading.
fn greedy(
    positions: &[Point2<f64>],
    seen: &[Vec<(usize, f64)>],
    faces: &[Face],
    resolution: f64,
    s: &ViewpointSettings,
) -> Vec<[f64; 3]> {
    let mut views = vec![0usize; faces.len()];
    let mut chosen = Vec::new();
    let mut taken = Vec::new();
    let min_cells = (s.min_gain / resolution).ceil().max(1.0) as usize;
    let yaw = |h: usize| wrap(2.0 * PI * h as f64 / s.headings as f64);
    while chosen.len() < s.max_views {
        let mut best: Option<(usize, usize, usize)> = None;
        for (c, list) in seen.iter().enumerate() {
            for h in 0..s.headings {
                if taken.contains(&(c, h)) {
                    continue;
                }
                let y = yaw(h);
                let gain = list
                    .iter()
                    .filter(|(k, b)| {
                        views[*k] < s.views_per_face && wrap(b - y).abs() <= s.half_fov
                    })
                    .count();
                if best.is_none_or(|(g, _, _)| gain > g) {
                    best = Some((gain, c, h));
                }
            }
        }
        let Some((gain, c, h)) = best else {
            break;
        };
        if gain < min_cells {
            break;
        }
        let y = yaw(h);
        for (k, b) in &seen[c] {
            if wrap(b - y).abs() <= s.half_fov {
                views[*k] += 1;
            }
        }
        taken.push((c, h));
        chosen.push([positions[c].x, positions[c].y, y]);
    }
    chosen
}

/// Path lengths (m) from `from` over the cells of `reachable` (8-neighbours, no corner
/// cutting), `INFINITY` where there is no path.
fn distances(free: &NavGrid, reachable: &[bool], from: Point2<f64>) -> Vec<f64> {
    let (w, h) = (free.width(), free.height());
    let mut dist = vec![f64::INFINITY; w * h];
    let Some((si, sj)) = free.cell_of(from) else {
        return dist;
    };
    #[derive(PartialEq)]
    struct Entry(f64, usize);
    impl Eq for Entry {}
    impl PartialOrd for Entry {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Entry {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
        }
    }
    let res = free.resolution();
    let open = |k: usize| reachable[k];
    dist[sj * w + si] = 0.0;
    let mut heap = BinaryHeap::from([Entry(0.0, sj * w + si)]);
    while let Some(Entry(d, k)) = heap.pop() {
        if d > dist[k] {
            continue;
        }
        let (i, j) = ((k % w) as isize, (k / w) as isize);
        for dj in -1..=1isize {
            for di in -1..=1isize {
                let (ni, nj) = (i + di, j + dj);
                if (di, dj) == (0, 0) || !(0..w as isize).contains(&ni) {
                    continue;
                }
                if !(0..h as isize).contains(&nj) {
                    continue;
                }
                let nk = nj as usize * w + ni as usize;
                let diagonal = di != 0 && dj != 0;
                let corner_free = !diagonal
                    || (open(j as usize * w + ni as usize) && open(nj as usize * w + i as usize));
                if !open(nk) || !corner_free {
                    continue;
                }
                let nd = d + res * if diagonal { SQRT_2 } else { 1.0 };
                if nd < dist[nk] {
                    dist[nk] = nd;
                    heap.push(Entry(nd, nk));
                }
            }
        }
    }
    dist
}

/// `chosen` in nearest-neighbour order from `start` by path length on the free cells (ties:
/// the earlier chosen).
fn nearest_neighbour_tour(
    free: &NavGrid,
    reachable: &[bool],
    start: [f64; 3],
    mut chosen: Vec<[f64; 3]>,
) -> Vec<[f64; 3]> {
    let mut at = Point2::new(start[0], start[1]);
    let mut tour = Vec::with_capacity(chosen.len());
    while !chosen.is_empty() {
        let dist = distances(free, reachable, at);
        let length = |v: &[f64; 3]| {
            free.cell_of(Point2::new(v[0], v[1]))
                .map_or(f64::INFINITY, |(i, j)| dist[j * free.width() + i])
        };
        let next = (0..chosen.len())
            .min_by(|&a, &b| {
                length(&chosen[a])
                    .total_cmp(&length(&chosen[b]))
                    .then(a.cmp(&b))
            })
            .unwrap_or(0);
        let v = chosen.remove(next);
        at = Point2::new(v[0], v[1]);
        tour.push(v);
    }
    tour
}
