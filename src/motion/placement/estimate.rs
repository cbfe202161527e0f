//! A quick estimate of how long a sampled placement takes to execute, for ranking samples
//! ([`TieBreak::ExecutionTime`](super::TieBreak::ExecutionTime)).
//!
//! Every phase is timed as straight lines under the robot's own velocity and acceleration
//! limits (a rest-to-rest minimum-time profile along each line, the slowest coordinate
//! deciding): the base from where it stands to the sample, the arm from its start (the
//! stow) to the first waypoint, along the waypoints, and back to the start. The planner's
//! real paths go around obstacles and its timing blends the waypoints, so this is neither an
//! upper nor a lower bound of the executed time; it ranks the candidates by what the robot
//! spends, where the path-length rule adds radians to metres.

use nalgebra::DVector;

use super::plan::ManipulationPlan;
use super::sampled::wrap;
use crate::kinematics::robot::{BaseKind, RobotModel};
use crate::motion::timing::rest_to_rest_time;

/// Minimum time (s) of a straight line, rest to rest, whose coordinates move `d[i]` under
/// limits `v[i]`, `a[i]`: the path parameter's limits are the tightest of `v[i] / d[i]` and
/// `a[i] / d[i]`.
fn line(d: impl IntoIterator<Item = (f64, f64, f64)>) -> f64 {
    let (mut v, mut a) = (f64::INFINITY, f64::INFINITY);
    for (d, vi, ai) in d {
        if d > 0.0 {
            v = v.min(vi / d);
            a = a.min(ai / d);
        }
    }
    if v.is_finite() {
        rest_to_rest_time(1.0, v, a)
    } else {
        0.0
    }
}

/// Time (s) of the arm's straight line from `from` to `to`.
fn arm_line(robot: &RobotModel, from: &DVector<f64>, to: &DVector<f64>) -> f64 {
    line(
        robot
            .arm_joints()
            .iter()
            .zip(from.iter().zip(to.iter()))
            .map(|(j, (a, b))| ((b - a).abs(), j.max_velocity, j.max_acceleration)),
    )
}

/// Time (s) of the base from `from` to `to`: a holonomic base along the straight line (the
/// translation's speed bounded by the slower of its x and y limits), a differential drive
/// turning towards the goal, driving, and turning to the goal's heading (the shorter way
/// round, forwards or backwards).
pub(crate) fn base_time(robot: &RobotModel, from: [f64; 3], to: [f64; 3]) -> f64 {
    let base = robot.base();
    let [v, a] = [base.max_velocity, base.max_acceleration];
    let distance = (to[0] - from[0]).hypot(to[1] - from[1]);
    match base.kind {
        BaseKind::Holonomic => line([
            (distance, v[0].min(v[1]), a[0].min(a[1])),
            (wrap(to[2] - from[2]).abs(), v[2], a[2]),
        ]),
        BaseKind::DifferentialDrive => {
            let turn = |angle: f64| rest_to_rest_time(wrap(angle).abs(), v[2], a[2]);
            if distance < 1e-9 {
                return turn(to[2] - from[2]);
            }
            let heading = (to[1] - from[1]).atan2(to[0] - from[0]);
            // Forwards, or backwards (heading turned by π): whichever turns less.
            let by = |h: f64| turn(h - from[2]) + turn(to[2] - h);
            by(heading).min(by(heading + std::f64::consts::PI))
                + rest_to_rest_time(distance, v[0], a[0])
        }
    }
}

/// The estimated execution time (s) of `plan` for a robot at `robot_from` with its arm at
/// `arm_start`: the base drive, the arm to the first waypoint, along every waypoint (one
/// straight line each, as if the arm stopped at each: the same overestimate for every
/// sample), and back to `arm_start`.
pub(crate) fn execution_time(
    robot: &RobotModel,
    robot_from: [f64; 3],
    arm_start: &DVector<f64>,
    plan: &ManipulationPlan,
) -> f64 {
    let (Some(first), Some(last)) = (plan.arm.first(), plan.arm.last()) else {
        return base_time(robot, robot_from, plan.base);
    };
    base_time(robot, robot_from, plan.base)
        + arm_line(robot, arm_start, first)
        + plan
            .arm
            .windows(2)
            .map(|w| arm_line(robot, &w[0], &w[1]))
            .sum::<f64>()
        + arm_line(robot, last, arm_start)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-derived: 1 m at 0.5 m/s, 0.5 m/s²: 1/0.5 + 0.5/0.5 = 3 s (trapezoid); 0.25 m:
    /// 0.25 · 0.5 < 0.25, a triangle of 2·√(0.25/0.5) = 1.414 s.
    #[test]
    fn rest_to_rest_is_the_trapezoid_or_the_triangle() {
        assert!((rest_to_rest_time(1.0, 0.5, 0.5) - 3.0).abs() < 1e-12);
        assert!((rest_to_rest_time(0.25, 0.5, 0.5) - 2.0 * 0.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(rest_to_rest_time(0.0, 0.5, 0.5), 0.0);
    }

    /// The slowest coordinate decides: 1 m at (0.5, 0.5) beside 0.1 m at (1, 1) is the 1 m
    /// alone.
    #[test]
    fn a_line_is_as_slow_as_its_slowest_coordinate() {
        let t = line([(1.0, 0.5, 0.5), (0.1, 1.0, 1.0)]);
        assert!((t - 3.0).abs() < 1e-12);
        assert_eq!(line([(0.0, 1.0, 1.0)]), 0.0);
    }

    /// The shipped Gen3 base (holonomic, 0.5 m/s, 0.5 m/s², 1 rad/s, 1 rad/s²): 1 m straight
    /// ahead is 3 s; turning π/2 in place is a trapezoid (π/2 · 1 > 1²) of π/2 + 1 = 2.571 s.
    /// A differential drive with the same limits going 1 m sideways turns π/2 (2.571 s),
    /// drives 1 m (3 s) and turns back (2.571 s), or the same backwards.
    #[test]
    fn base_times_follow_the_base_kind() {
        let robot = RobotModel::kinova_gen3_mobile();
        assert!((base_time(&robot, [0.0; 3], [1.0, 0.0, 0.0]) - 3.0).abs() < 1e-12);
        let quarter = std::f64::consts::FRAC_PI_2 + 1.0;
        let turned = base_time(&robot, [0.0; 3], [0.0, 0.0, std::f64::consts::FRAC_PI_2]);
        assert!((turned - quarter).abs() < 1e-12, "{turned}");
        let diff = robot
            .clone()
            .with_base(robot.base().to_differential_drive())
            .unwrap();
        let sideways = base_time(&diff, [0.0; 3], [0.0, 1.0, 0.0]);
        assert!(
            (sideways - (2.0 * quarter + 3.0)).abs() < 1e-12,
            "{sideways}"
        );
    }
}
