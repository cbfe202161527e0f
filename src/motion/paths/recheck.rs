//! The independent dense re-check of a path: fixed-spacing samples, the caller's closure.

/// The first invalid state along `path`, sampling every segment densely: `Some((k, q))` with
/// `k` the segment (from state `k` to `k + 1`; 0 for a one-state path) and `q` the rejected
/// sample, or `None` when every sample is valid (and for an empty path).
///
/// Segment `k` is sampled at `a + (j / n)·Δ`, `j = 0..=n` (its first state only for `k = 0`;
/// its last state is `path[k + 1]` exactly), with `n = ⌈‖Δ‖ / resolution⌉`, so consecutive
/// samples are at most `resolution` apart in the Euclidean norm of the coordinates and no
/// single coordinate moves more than `resolution` between them. With `wrap_yaw`, states are
/// `[x, y, yaw]` and the yaw component of `Δ` is the shortest angle (in `[-π, π]`), as in
/// SE(2) interpolation. (OMPL's SE(2) distance `‖Δxy‖ + ½|Δyaw|` is at most √2 times the
/// Euclidean one, so `resolution ≤ PathSettings::resolution / √2` samples at least as densely
/// as OMPL's motion check did.)
///
/// This shares no code with OMPL's motion validator: it is a second opinion on a planned path.
///
/// The check fails closed: when it cannot be carried out it reports the first state where it
/// cannot, as if that state were invalid. That is the case for a `resolution` that is not
/// positive and finite (`(0, path[0])`), a state containing NaN or an infinity, a state whose
/// length differs from the first state's, and, with `wrap_yaw`, a state of length other
/// than 3.
///
/// # Example
/// ```
/// use kinscene::motion::paths::first_invalid;
///
/// // Valid outside the disc of radius 0.1 around (0.5, 0): both waypoints are valid, the
/// // straight segment between them is not.
/// let valid = |q: &[f64]| (q[0] - 0.5).hypot(q[1]) > 0.1;
/// let path = vec![vec![0.0, 0.0], vec![1.0, 0.0]];
/// let (segment, q) = first_invalid(&path, 0.01, false, &valid).unwrap();
/// assert_eq!(segment, 0);
/// assert!(q[0] > 0.39 && q[0] < 0.41); // the first sample inside, 0.01 apart
/// ```
pub fn first_invalid(
    path: &[Vec<f64>],
    resolution: f64,
    wrap_yaw: bool,
    valid: &dyn Fn(&[f64]) -> bool,
) -> Option<(usize, Vec<f64>)> {
    let first = path.first()?;
    let checkable = |q: &[f64]| {
        q.len() == first.len() && (!wrap_yaw || q.len() == 3) && q.iter().all(|v| v.is_finite())
    };
    let usable = resolution.is_finite() && resolution > 0.0;
    if !(usable && checkable(first) && valid(first)) {
        return Some((0, first.clone()));
    }
    for (k, pair) in path.windows(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        if !checkable(b) {
            return Some((k, b.clone()));
        }
        let delta: Vec<f64> = a
            .iter()
            .zip(b)
            .enumerate()
            .map(|(i, (x, y))| {
                let d = y - x;
                if wrap_yaw && i == 2 {
                    d.sin().atan2(d.cos())
                } else {
                    d
                }
            })
            .collect();
        let length = delta.iter().map(|d| d * d).sum::<f64>().sqrt();
        // At least one step; `as` saturates for absurdly small resolutions.
        let steps = ((length / resolution).ceil() as usize).max(1);
        let mut q = a.clone();
        for j in 1..steps {
            let t = j as f64 / steps as f64;
            for ((qi, ai), di) in q.iter_mut().zip(a).zip(&delta) {
                *qi = ai + t * di;
            }
            if !valid(&q) {
                return Some((k, q));
            }
        }
        if !valid(b) {
            return Some((k, b.clone()));
        }
    }
    None
}
