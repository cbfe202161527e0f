//! Shared geometry: axis-aligned walls, robots, an independent implementation of the spaces'
//! distance and interpolation, and dense re-validation of returned paths.

use std::f64::consts::PI;
use std::sync::{Mutex, MutexGuard};

use kinscene_ompl::StateSpace;

static SERIAL: Mutex<()> = Mutex::new(());

/// Serialises tests that plan (see the crate doc of tests/lib.rs).
pub fn serial() -> MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// An axis-aligned rectangle `[min, max]` (metres).
#[derive(Debug, Clone, Copy)]
pub struct Rect {
    pub min: [f64; 2],
    pub max: [f64; 2],
}

impl Rect {
    /// Euclidean distance from `p` to the rectangle (0 inside).
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        let dx = (self.min[0] - p[0]).max(p[0] - self.max[0]).max(0.0);
        let dy = (self.min[1] - p[1]).max(p[1] - self.max[1]).max(0.0);
        dx.hypot(dy)
    }
}

/// Distance from `p` to the nearest wall.
pub fn clearance(walls: &[Rect], p: [f64; 2]) -> f64 {
    walls
        .iter()
        .map(|w| w.distance(p))
        .fold(f64::INFINITY, f64::min)
}

/// The shortest signed angle from `a` to `b`, in [-π, π].
pub fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (b - a).rem_euclid(2.0 * PI);
    if d > PI { d - 2.0 * PI } else { d }
}

/// OMPL's distance, re-implemented: Euclidean for a real vector space, `‖Δxy‖ + 0.5·|Δyaw|`
/// (shortest angle) for SE(2).
pub fn distance(space: &StateSpace, a: &[f64], b: &[f64]) -> f64 {
    match space {
        StateSpace::Se2 { .. } => {
            (b[0] - a[0]).hypot(b[1] - a[1]) + 0.5 * angle_diff(a[2], b[2]).abs()
        }
        StateSpace::RealVector { .. } => a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x) * (y - x))
            .sum::<f64>()
            .sqrt(),
    }
}

/// The state at fraction `t` of the straight motion `a → b` (shortest angle for yaw).
pub fn interpolate(space: &StateSpace, a: &[f64], b: &[f64], t: f64) -> Vec<f64> {
    let mut q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect();
    if let StateSpace::Se2 { .. } = space {
        q[2] = a[2] + t * angle_diff(a[2], b[2]);
    }
    q
}

/// OMPL's maximum extent of the space: the bounds' diagonal, plus 0.5·π for SE(2)'s yaw.
pub fn extent(space: &StateSpace) -> f64 {
    let (lower, upper) = space.bounds();
    let diagonal = lower
        .iter()
        .zip(&upper)
        .map(|(l, u)| (u - l) * (u - l))
        .sum::<f64>()
        .sqrt();
    match space {
        StateSpace::Se2 { .. } => diagonal + 0.5 * PI,
        StateSpace::RealVector { .. } => diagonal,
    }
}

/// Path length in the space's distance.
pub fn length(space: &StateSpace, path: &[Vec<f64>]) -> f64 {
    path.windows(2).map(|w| distance(space, &w[0], &w[1])).sum()
}

/// Re-validates every state and every motion of `path` with `valid`, stepping at most
/// `1e-3 × extent` along each segment, and checks the bounds. Panics with the first failure.
pub fn assert_path_valid(space: &StateSpace, path: &[Vec<f64>], valid: impl Fn(&[f64]) -> bool) {
    if let Some(failure) = first_violation(space, path, valid) {
        panic!("{failure}");
    }
}

/// The first invalid state, out-of-bounds state or invalid motion of `path`, described.
pub fn first_violation(
    space: &StateSpace,
    path: &[Vec<f64>],
    valid: impl Fn(&[f64]) -> bool,
) -> Option<String> {
    let step = 1e-3 * extent(space);
    let (lower, upper) = space.bounds();
    for (i, q) in path.iter().enumerate() {
        if !valid(q) {
            return Some(format!("state {i} {q:?} is invalid"));
        }
        if lower
            .iter()
            .zip(&upper)
            .enumerate()
            .any(|(k, (l, u))| q[k] < *l || q[k] > *u)
        {
            return Some(format!("state {i} {q:?} is out of bounds"));
        }
        if matches!(space, StateSpace::Se2 { .. }) && q[2].abs() > PI {
            return Some(format!("state {i}: yaw {} outside [-π, π]", q[2]));
        }
    }
    for (i, w) in path.windows(2).enumerate() {
        let n = (distance(space, &w[0], &w[1]) / step).ceil().max(1.0) as usize;
        for j in 0..=n {
            let q = interpolate(space, &w[0], &w[1], j as f64 / n as f64);
            if !valid(&q) {
                return Some(format!("motion {i} -> {} is invalid at {q:?}", i + 1));
            }
        }
    }
    None
}
