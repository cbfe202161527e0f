//! PlanBase: base poses in front of a handle that are free in the navigation grid, and the
//! Reposition shifts.

use nalgebra::{Isometry2, Point2, Point3, Vector2, Vector3};

use super::error::DiscoveryError;
use crate::scene::nav::{NavGrid, occupancy};
use crate::scene::{SceneData, SceneModel, State, forward_kinematics};

/// A normal whose horizontal part is shorter than this is treated as vertical.
const MIN_HORIZONTAL: f64 = 0.2;
/// Angular step (rad) of the candidate search around the handle (10°).
const ANGLE_STEP: f64 = std::f64::consts::PI / 18.0;
/// Radial step (m) of the candidate search.
const RADIAL_STEP: f64 = 0.05;

/// The free space of the base: the occupancy of the (discovered) scene at a state, inflated by
/// the robot radius.
#[derive(Debug, Clone)]
pub(crate) struct FreeSpace {
    grid: NavGrid,
}

impl FreeSpace {
    /// Free space of `model` at `state` for a disc robot of `robot_radius`.
    pub(crate) fn new(
        model: &SceneModel,
        state: &State,
        robot_radius: f64,
    ) -> Result<Self, DiscoveryError> {
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, state)?;
        let grid = occupancy(model, &data)?.inflate(robot_radius)?;
        Ok(FreeSpace { grid })
    }

    /// Whether a disc robot centred at `p` is free. Outside the grid counts as free: the grid
    /// covers every shape plus its padding.
    pub(crate) fn is_free(&self, p: &Point2<f64>) -> bool {
        match self.grid.cell_of(*p) {
            Some((i, j)) => !self.grid.is_occupied(i, j),
            None => true,
        }
    }
}

/// The pose at `position` facing `target` (yaw towards it).
pub(crate) fn facing(position: Point2<f64>, target: &Point3<f64>) -> Isometry2<f64> {
    let d = Point2::new(target.x, target.y) - position;
    Isometry2::new(position.coords, d.y.atan2(d.x))
}

/// The horizontal outward direction of `normal`, or `fallback` (normalised) when the normal is
/// nearly vertical; `None` if both are degenerate.
pub(crate) fn horizontal(normal: &Vector3<f64>, fallback: &Vector2<f64>) -> Option<Vector2<f64>> {
    let h = Vector2::new(normal.x, normal.y);
    if h.norm() >= MIN_HORIZONTAL {
        Some(h.normalize())
    } else {
        fallback.try_normalize(1e-9)
    }
}

/// PlanBase: a base pose facing `target` at horizontal `distance` along `direction` (unit,
/// horizontal, pointing away from the surface), free in `free`.
///
/// The nominal position `target + distance · direction` is used if free. Otherwise candidates
/// on rings around the target are searched: directions turned by multiples of 10° up to ±60°
/// and distances changed by multiples of 5 cm, no closer than half the nominal distance, all
/// within `search_radius` of the nominal position. The free candidate whose distance to the
/// handle is nearest the nominal one wins (ties: the smaller turn, then the nearer to the
/// nominal position): the arm's reach depends on that distance, not on the heading, so in a
/// narrow passage a pose turned to the side at the right distance beats a frontal one too close
/// to the front for the arm. `None` if none is free.
pub(crate) fn plan_base(
    free: &FreeSpace,
    target: &Point3<f64>,
    direction: &Vector2<f64>,
    distance: f64,
    search_radius: f64,
) -> Option<Isometry2<f64>> {
    plan_base_where(target, direction, distance, search_radius, |p| {
        free.is_free(p)
    })
}

/// [`plan_base`] keeping `keep_off` (m) from every position in `refused`: the goals the
/// robot's own navigation refused (something the map does not hold stands there), so that
/// the next attempt goes elsewhere instead of to the same refused goal.
pub(crate) fn plan_base_avoiding(
    free: &FreeSpace,
    target: &Point3<f64>,
    direction: &Vector2<f64>,
    distance: f64,
    search_radius: f64,
    refused: &[Point2<f64>],
    keep_off: f64,
) -> Option<Isometry2<f64>> {
    plan_base_where(target, direction, distance, search_radius, |p| {
        free.is_free(p) && refused.iter().all(|r| (p - r).norm() >= keep_off)
    })
}

/// [`plan_base`] with `is_free` deciding which positions are free.
fn plan_base_where(
    target: &Point3<f64>,
    direction: &Vector2<f64>,
    distance: f64,
    search_radius: f64,
    is_free: impl Fn(&Point2<f64>) -> bool,
) -> Option<Isometry2<f64>> {
    let t = Point2::new(target.x, target.y);
    let nominal = t + direction * distance;
    if is_free(&nominal) {
        return Some(facing(nominal, target));
    }
    let radial = (search_radius / RADIAL_STEP).floor() as i64;
    // (distance error, turn, offset from the nominal position), compared in that order.
    let mut best: Option<(f64, f64, f64, Point2<f64>)> = None;
    for a in -6i64..=6 {
        let angle = a as f64 * ANGLE_STEP;
        let dir = nalgebra::Rotation2::new(angle) * direction;
        for r in -radial..=radial {
            let dist = distance + r as f64 * RADIAL_STEP;
            if dist < distance / 2.0 {
                continue;
            }
            let p = t + dir * dist;
            let off = (p - nominal).norm();
            if off > search_radius || !is_free(&p) {
                continue;
            }
            let key = ((dist - distance).abs(), angle.abs(), off);
            let better = match best {
                None => true,
                Some((e, turn, o, _)) => {
                    key.0 < e - 1e-12
                        || (key.0 <= e + 1e-12
                            && (key.1 < turn - 1e-12 || (key.1 <= turn + 1e-12 && key.2 < o)))
                }
            };
            if better {
                best = Some((key.0, key.1, key.2, p));
            }
        }
    }
    best.map(|(_, _, _, p)| facing(p, target))
}

/// Reposition's move: `from` translated by `shift` (world frame, horizontal), re-aimed at
/// `target`. If the shifted position is occupied, the shift is shortened to 3/4, 1/2 and 1/4
/// of its length; `None` if all are occupied.
pub(crate) fn shifted(
    free: &FreeSpace,
    from: &Isometry2<f64>,
    shift: &Vector2<f64>,
    target: &Point3<f64>,
) -> Option<Isometry2<f64>> {
    let p0 = Point2::from(from.translation.vector);
    [1.0, 0.75, 0.5, 0.25]
        .iter()
        .map(|f| p0 + shift * *f)
        .find(|p| free.is_free(p))
        .map(|p| facing(p, target))
}
