//! Time shortcuts of a free arm path: OMPL's simplifier shortens the path in its Euclidean
//! metric, but the arm's time on a segment is set by its slowest joint (the largest
//! `|Δq_j| / v_j`). A path that is shortest in length can still make one joint travel far:
//! a detour through a folded arm, a wrist turned one way and back.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::motion::paths::first_invalid;

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
/// that end up on a straight line between their neighbours are dropped.
pub(super) fn time_shortcuts(
    path: Vec<Vec<f64>>,
    vmax: &[f64],
    subdivisions: usize,
    resolution: f64,
    valid: &dyn Fn(&[f64]) -> bool,
) -> Vec<Vec<f64>> {
    if subdivisions == 0 || path.len() < 2 || vmax.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return path;
    }
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
    drop_collinear(out)
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

/// Random time shortcuts (Hauser and Ng-Thow-Hing's shortcutting, timed by the slowest
/// joint): `attempts` times, two times along the path are drawn (seeded, reproducible), and
/// the path between the two points at those times is replaced by the straight motion when
/// that is quicker and free (every `resolution`, the dense re-check's rule). Where the greedy
/// [`time_shortcuts`] only jump between points it divided the path into, these also cut a
/// corner at any depth, so the path converges towards the quickest one around the same
/// obstacles. The result passes [`first_invalid`] at `resolution` whenever `path` does (else
/// `path` is returned unchanged); the ends are kept.
pub(super) fn random_time_shortcuts(
    path: Vec<Vec<f64>>,
    vmax: &[f64],
    attempts: usize,
    seed: u64,
    resolution: f64,
    valid: &dyn Fn(&[f64]) -> bool,
) -> Vec<Vec<f64>> {
    if attempts == 0 || path.len() < 3 || vmax.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return path;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = path.clone();
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
        if leg_time(&a, &b, vmax) >= (t1 - t0) * (1.0 - MIN_GAIN)
            || !straight_free(&a, &b, resolution, valid)
        {
            continue;
        }
        let mut next = out[..=k0].to_vec();
        next.push(a);
        next.push(b);
        next.extend_from_slice(&out[k1 + 1..]);
        out = next;
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
        let out = time_shortcuts(path.clone(), &vmax, 4, 0.01, &valid);
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
        let out = time_shortcuts(path.clone(), &vmax, 4, 0.01, &|_: &[f64]| true);
        assert_eq!(out, vec![vec![0.0, 0.0], vec![1.0, 1.0]]);
        // Off: unchanged.
        assert_eq!(time_shortcuts(path.clone(), &vmax, 0, 0.01, &valid), path);
    }

    /// The speed limits decide: a detour on a slow joint is cut even where the Euclidean
    /// length barely changes.
    #[test]
    fn the_slow_joint_sets_the_time() {
        let vmax = [10.0, 0.1];
        // Joint 1 goes out 0.5 and back: 10 s at 0.1 rad/s; straight, 0.1 s.
        let path = vec![vec![0.0, 0.0], vec![0.5, 0.5], vec![1.0, 0.0]];
        let out = time_shortcuts(path, &vmax, 2, 0.01, &|_: &[f64]| true);
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
        let out = random_time_shortcuts(detour.clone(), &vmax, 200, 7, 0.01, &valid);
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
            random_time_shortcuts(detour.clone(), &vmax, 200, 7, 0.01, &valid)
        );
        // Off, or nothing to cut: unchanged.
        assert_eq!(
            random_time_shortcuts(detour.clone(), &vmax, 0, 7, 0.01, &valid),
            detour
        );
        let straight = vec![vec![0.0, 0.0], vec![1.0, 0.0]];
        assert_eq!(
            random_time_shortcuts(straight.clone(), &vmax, 50, 7, 0.01, &valid),
            straight
        );
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
