//! Time shortcuts of a free arm path: OMPL's simplifier shortens the path in its Euclidean
//! metric, but the arm's time on a segment is set by its slowest joint (the largest
//! `|Δq_j| / v_j`). A path that is shortest in length can still make one joint travel far:
//! a detour through a folded arm, a wrist turned one way and back.
//!
//! **Which path is quicker.** A shortcut is proposed by the slowest joint's cruise time (the
//! cheap filter), but taken only when the path with it is quicker as the planner times it
//! ([`Timer`]: blended corners under the joints' speed and acceleration limits): a shortcut
//! that saves cruise time but adds corners can be slower to execute.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::motion::paths::first_invalid;
use crate::motion::timing::{BlendSettings, time_optimal, time_parameterise};

/// How the planner times an arm path: the joints' speed and acceleration limits, and the
/// corner blending (`None`: a stop at every corner).
pub(super) struct Timer<'a> {
    pub vmax: &'a [f64],
    pub amax: &'a [f64],
    pub blend: Option<&'a BlendSettings>,
}

impl Timer<'_> {
    /// The path's duration (s) as the planner times it ([`time_optimal`] or
    /// [`time_parameterise`]), before any blend is re-checked; `+∞` when it cannot be timed.
    fn duration(&self, path: &[Vec<f64>]) -> f64 {
        let timed = match self.blend {
            Some(blend) => time_optimal(path, self.vmax, self.amax, None, blend),
            None => time_parameterise(path, self.vmax, self.amax, None),
        };
        timed.map_or(f64::INFINITY, |t| t.duration)
    }

    /// Whether the speed limits are usable (finite and positive): otherwise no shortcut.
    fn usable(&self) -> bool {
        self.vmax.len() == self.amax.len()
            && self
                .vmax
                .iter()
                .chain(self.amax)
                .all(|v| v.is_finite() && *v > 0.0)
    }
}

/// Relative improvement below which a shortcut is not taken (avoids trading corners for
/// rounding).
const MIN_GAIN: f64 = 1e-6;

/// The time (s) of the straight motion `a → b` at the joints' speed limits `vmax`: the slowest
/// joint's.
fn leg_time(a: &[f64], b: &[f64], vmax: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .zip(vmax)
        .map(|((x, y), v)| (y - x).abs() / v)
        .fold(0.0, f64::max)
}

/// `path` with shortcuts that lower its velocity-limited time `Σ leg_time`: each segment is
/// divided into `subdivisions` equal parts, and from each point in turn the path goes
/// straight to the farthest later point whose straight motion is free (`valid` at every
/// `resolution` of the largest joint change, the dense re-check's own rule) and quicker than
/// the path between them. Deterministic; the first and last configurations are kept; with
/// `subdivisions == 0`, or when no shortcut helps, the path is returned unchanged. Points
/// that end up on a straight line between their neighbours are dropped. The result is kept
/// only when `timer` times it quicker than `path` (else `path` is returned).
pub(super) fn time_shortcuts(
    path: Vec<Vec<f64>>,
    timer: &Timer<'_>,
    subdivisions: usize,
    resolution: f64,
    valid: &dyn Fn(&[f64]) -> bool,
) -> Vec<Vec<f64>> {
    if subdivisions == 0 || path.len() < 2 || !timer.usable() {
        return path;
    }
    let vmax = timer.vmax;
    // The points: the waypoints and `subdivisions - 1` points inside each segment.
    let mut points = vec![path[0].clone()];
    for w in path.windows(2) {
        for k in 1..=subdivisions {
            let f = k as f64 / subdivisions as f64;
            points.push(
                w[0].iter()
                    .zip(&w[1])
                    .map(|(a, b)| a + f * (b - a))
                    .collect(),
            );
        }
    }
    // Time along the path up to each point.
    let mut along = vec![0.0];
    for w in points.windows(2) {
        along.push(along[along.len() - 1] + leg_time(&w[0], &w[1], vmax));
    }
    let last = points.len() - 1;
    let mut kept = vec![0];
    let mut i = 0;
    while i < last {
        let mut next = i + 1;
        for j in (i + 2..=last).rev() {
            let direct = leg_time(&points[i], &points[j], vmax);
            let current = along[j] - along[i];
            if direct < current * (1.0 - MIN_GAIN)
                && first_invalid(
                    &[points[i].clone(), points[j].clone()],
                    resolution,
                    false,
                    valid,
                )
                .is_none()
            {
                next = j;
                break;
            }
        }
        kept.push(next);
        i = next;
    }
    let out: Vec<Vec<f64>> = kept.iter().map(|&k| points[k].clone()).collect();
    if out.len() == points.len() {
        // No shortcut: the original waypoints.
        return path;
    }
    let out = drop_collinear(out);
    if timer.duration(&out) < timer.duration(&path) * (1.0 - MIN_GAIN) {
        out
    } else {
        path
    }
}

/// Whether the straight motion `a → b` is valid at the states [`first_invalid`] checks on it
/// (every `resolution` of the Euclidean joint distance, `a` and `b` included), visited coarse
/// to fine so that a blocked motion fails after a few checks.
fn straight_free(a: &[f64], b: &[f64], resolution: f64, valid: &dyn Fn(&[f64]) -> bool) -> bool {
    let length = a
        .iter()
        .zip(b)
        .map(|(x, y)| (y - x) * (y - x))
        .sum::<f64>()
        .sqrt();
    let steps = ((length / resolution).ceil() as usize).max(1);
    if !(valid(a) && valid(b)) {
        return false;
    }
    let at = |j: usize| -> Vec<f64> {
        let t = j as f64 / steps as f64;
        a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect()
    };
    // Odd multiples of each stride, the largest stride first: every `1..steps` once.
    let mut stride = steps.next_power_of_two();
    while stride >= 1 {
        let mut j = stride;
        while j < steps {
            if !valid(&at(j)) {
                return false;
            }
            j += 2 * stride;
        }
        stride /= 2;
    }
    true
}

/// The point at time `t` along `path` (legs timed by [`leg_time`], `along[k]` the time at
/// vertex `k`): the leg it lies on and the point.
fn point_at(path: &[Vec<f64>], along: &[f64], t: f64) -> (usize, Vec<f64>) {
    let k = along.partition_point(|&s| s <= t).clamp(1, path.len() - 1) - 1;
    let span = along[k + 1] - along[k];
    let f = if span > 0.0 {
        ((t - along[k]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = path[k]
        .iter()
        .zip(&path[k + 1])
        .map(|(a, b)| a + f * (b - a))
        .collect();
    (k, q)
}

/// Random time shortcuts (Hauser and Ng-Thow-Hing's shortcutting): `attempts` times, two
/// times along the path are drawn (seeded, reproducible; the path's times by the slowest
/// joint), and the path between the two points at those times is replaced by the straight
/// motion when that is quicker by the slowest joint, the whole path is then quicker as
/// `timer` times it (corners included), and the motion is free (every `resolution`, the
/// dense re-check's rule). Where the greedy [`time_shortcuts`] only jump between points it
/// divided the path into, these also cut a corner at any depth, so the path converges
/// towards the quickest one around the same obstacles. The result passes [`first_invalid`]
/// at `resolution` whenever `path` does (else `path` is returned unchanged); the ends are
/// kept.
pub(super) fn random_time_shortcuts(
    path: Vec<Vec<f64>>,
    timer: &Timer<'_>,
    attempts: usize,
    seed: u64,
    resolution: f64,
    valid: &dyn Fn(&[f64]) -> bool,
) -> Vec<Vec<f64>> {
    if attempts == 0 || path.len() < 3 || !timer.usable() {
        return path;
    }
    let vmax = timer.vmax;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = path.clone();
    let mut current = timer.duration(&out);
    for _ in 0..attempts {
        if out.len() < 3 {
            break;
        }
        let mut along = vec![0.0];
        for w in out.windows(2) {
            along.push(along[along.len() - 1] + leg_time(&w[0], &w[1], vmax));
        }
        let total = along[along.len() - 1];
        let (u, v): (f64, f64) = (rng.random(), rng.random());
        let (t0, t1) = (total * u.min(v), total * u.max(v));
        let ((k0, a), (k1, b)) = (point_at(&out, &along, t0), point_at(&out, &along, t1));
        if k0 == k1 {
            // On one leg: already straight.
            continue;
        }
        if leg_time(&a, &b, vmax) >= (t1 - t0) * (1.0 - MIN_GAIN) {
            continue;
        }
        let mut next = out[..=k0].to_vec();
        next.push(a.clone());
        next.push(b.clone());
        next.extend_from_slice(&out[k1 + 1..]);
        let next = drop_collinear(dedup(next));
        let time = timer.duration(&next);
        if time >= current * (1.0 - MIN_GAIN) || !straight_free(&a, &b, resolution, valid) {
            continue;
        }
        out = next;
        current = time;
    }
    let out = drop_collinear(dedup(out));
    if out.len() == path.len() && out == path {
        return path;
    }
    if first_invalid(&out, resolution, false, valid).is_some() {
        return path;
    }
    out
}

/// `path` without consecutive repeated points.
fn dedup(mut path: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    path.dedup_by(|b, a| a.iter().zip(b.iter()).all(|(x, y)| (x - y).abs() <= 1e-12));
    path
}

/// `path` without the points that lie on the straight line between their neighbours (within
/// 1e-9 in every coordinate).
fn drop_collinear(path: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::with_capacity(path.len());
    for (k, q) in path.iter().enumerate() {
        if k == 0 || k + 1 == path.len() {
            out.push(q.clone());
            continue;
        }
        let (a, b) = (&out[out.len() - 1], &path[k + 1]);
        // The fraction of `q` between `a` and `b`, from the largest coordinate change.
        let (mut f, mut big) = (0.0, 0.0);
        for ((x, y), z) in a.iter().zip(b).zip(q) {
            if (y - x).abs() > big {
                big = (y - x).abs();
                f = (z - x) / (y - x);
            }
        }
        let on_line = big > 0.0
            && (0.0..=1.0).contains(&f)
            && a.iter()
                .zip(b)
                .zip(q)
                .all(|((x, y), z)| (x + f * (y - x) - z).abs() <= 1e-9);
        if !on_line {
            out.push(q.clone());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A timer whose time is the slowest joint's cruise time up to a hair: accelerations so
    /// high that stopping at the corners costs nothing measurable (the tests written for
    /// the cruise metric).
    fn cruise(vmax: &[f64]) -> Timer<'_> {
        Timer {
            vmax,
            amax: &[1e9; 2],
            blend: None,
        }
    }

    /// A 2-joint path around a square obstacle: the shortcut may not cross it, and takes the
    /// diagonal where it is free. Expected values by hand: the obstacle is the open square
    /// (0.2, 0.8)² in joint space.
    #[test]
    fn shortcuts_go_straight_where_free_and_not_through_the_obstacle() {
        let blocked = |q: &[f64]| q[0] > 0.2 && q[0] < 0.8 && q[1] > 0.2 && q[1] < 0.8;
        let valid = |q: &[f64]| !blocked(q);
        let vmax = [1.0, 1.0];
        // Around the obstacle: (0,0) → (1,0) → (1,1): time 2. The diagonal is blocked.
        let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
        let out = time_shortcuts(path.clone(), &cruise(&vmax), 4, 0.01, &valid);
        let time = |p: &[Vec<f64>]| {
            p.windows(2)
                .map(|w| leg_time(&w[0], &w[1], &vmax))
                .sum::<f64>()
        };
        assert!(time(&out) < time(&path), "{out:?}");
        // Every leg is free (dense check) and the ends are kept.
        assert_eq!(out.first(), path.first());
        assert_eq!(out.last(), path.last());
        assert!(
            first_invalid(&out, 0.001, false, &valid).is_none(),
            "{out:?}"
        );
        // From (0,0) the farthest quicker free point is (1, 0.25) (time 1 against 1.25); from
        // there straight to (1,1) is the path itself: 1.75 in all.
        assert!((time(&out) - 1.75).abs() < 1e-9, "{out:?}");

        // Without the obstacle the whole path becomes the diagonal: time 1.
        let out = time_shortcuts(path.clone(), &cruise(&vmax), 4, 0.01, &|_: &[f64]| true);
        assert_eq!(out, vec![vec![0.0, 0.0], vec![1.0, 1.0]]);
        // Off: unchanged.
        assert_eq!(
            time_shortcuts(path.clone(), &cruise(&vmax), 0, 0.01, &valid),
            path
        );
    }

    /// The speed limits decide: a detour on a slow joint is cut even where the Euclidean
    /// length barely changes.
    #[test]
    fn the_slow_joint_sets_the_time() {
        let vmax = [10.0, 0.1];
        // Joint 1 goes out 0.5 and back: 10 s at 0.1 rad/s; straight, 0.1 s.
        let path = vec![vec![0.0, 0.0], vec![0.5, 0.5], vec![1.0, 0.0]];
        let out = time_shortcuts(path, &cruise(&vmax), 2, 0.01, &|_: &[f64]| true);
        assert_eq!(out, vec![vec![0.0, 0.0], vec![1.0, 0.0]]);
    }

    /// Random shortcuts cut a corner the greedy pass cannot reach between its points: around
    /// the same square obstacle as above, from a path with a long detour, the result is
    /// quicker, free at the check's spacing, keeps its ends, and is the same for the same
    /// seed. By hand: the detour takes 1.5 + 1.5 + 0.5 = 3.5 (slowest joint, 1/s), and no
    /// path from (0,0) to (1,1) takes less than 1 (each joint travels 1).
    #[test]
    fn random_shortcuts_cut_corners_and_are_reproducible() {
        let blocked = |q: &[f64]| q[0] > 0.2 && q[0] < 0.8 && q[1] > 0.2 && q[1] < 0.8;
        let valid = |q: &[f64]| !blocked(q);
        let vmax = [1.0, 1.0];
        let detour = vec![
            vec![0.0, 0.0],
            vec![1.5, -0.5],
            vec![1.5, 1.0],
            vec![1.0, 1.0],
        ];
        let time = |p: &[Vec<f64>]| {
            p.windows(2)
                .map(|w| leg_time(&w[0], &w[1], &vmax))
                .sum::<f64>()
        };
        let out = random_time_shortcuts(detour.clone(), &cruise(&vmax), 200, 7, 0.01, &valid);
        assert!(time(&out) < time(&detour) - 0.5, "{} {out:?}", time(&out));
        assert!(time(&out) >= 1.0 - 1e-9);
        assert_eq!(out.first(), detour.first());
        assert_eq!(out.last(), detour.last());
        // Free at the check's spacing (what the function promises: a discrete check can clip
        // a corner thinner than its spacing, as every discrete check can).
        assert!(
            first_invalid(&out, 0.01, false, &valid).is_none(),
            "{out:?}"
        );
        assert_eq!(
            out,
            random_time_shortcuts(detour.clone(), &cruise(&vmax), 200, 7, 0.01, &valid)
        );
        // Off, or nothing to cut: unchanged.
        assert_eq!(
            random_time_shortcuts(detour.clone(), &cruise(&vmax), 0, 7, 0.01, &valid),
            detour
        );
        let straight = vec![vec![0.0, 0.0], vec![1.0, 0.0]];
        assert_eq!(
            random_time_shortcuts(straight.clone(), &cruise(&vmax), 50, 7, 0.01, &valid),
            straight
        );
    }

    /// A cut that saves cruise time but adds corners is not taken when the corners cost
    /// more. An L through a corridor 0.1 wide, `(0,0) → (1,0) → (1,1)`, at 1 rad/s and
    /// 1 rad/s², stopping at every corner: by hand each leg takes `2·√L` (a triangular
    /// profile), 4 s in all. A free cut from `(x, 0)` to `(1, y)` (both within 0.1 of the
    /// corner) makes three legs of `2·√x + 2·√max(1 − x, y) + 2·√(1 − y)` s, more than 4 s
    /// since `√` is concave (e.g. 4.43 s at `x = 0.9, y = 0.1`), though its cruise time
    /// `x + max(1 − x, y) + 1 − y` is less than 2 s: the path stays as it is. With corners
    /// blended (the planner's default) the result is never slower than the input.
    #[test]
    fn shortcuts_that_add_costly_corners_are_not_taken() {
        let corridor = |q: &[f64]| {
            (q[1] <= 0.1 && (-0.1..=1.1).contains(&q[0]))
                || (q[0] >= 0.9 && (-0.1..=1.1).contains(&q[1]))
        };
        let (vmax, amax) = ([1.0, 1.0], [1.0, 1.0]);
        let stopping = Timer {
            vmax: &vmax,
            amax: &amax,
            blend: None,
        };
        let path = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
        assert!((stopping.duration(&path) - 4.0).abs() < 1e-9);
        assert_eq!(
            random_time_shortcuts(path.clone(), &stopping, 200, 3, 0.01, &corridor),
            path
        );
        // The cruise metric alone would cut the corner.
        let cut = random_time_shortcuts(path.clone(), &cruise(&vmax), 200, 3, 0.01, &corridor);
        assert_ne!(cut, path);
        let blend = BlendSettings::default();
        let blended = Timer {
            vmax: &vmax,
            amax: &amax,
            blend: Some(&blend),
        };
        let out = random_time_shortcuts(path.clone(), &blended, 200, 3, 0.01, &corridor);
        assert!(blended.duration(&out) <= blended.duration(&path));
        assert!(first_invalid(&out, 0.01, false, &corridor).is_none());
    }

    /// The coarse-to-fine check visits exactly the states of the sequential one.
    #[test]
    fn straight_free_checks_every_state_once() {
        use std::cell::RefCell;
        let seen = RefCell::new(Vec::new());
        let record = |q: &[f64]| {
            seen.borrow_mut().push((q[0] * 1000.0).round() as i64);
            true
        };
        assert!(straight_free(&[0.0], &[0.013], 0.001, &record));
        let mut seen = seen.into_inner();
        seen.sort_unstable();
        assert_eq!(seen, (0..=13).collect::<Vec<_>>());
    }
}
