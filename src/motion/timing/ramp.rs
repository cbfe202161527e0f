//! The scalar rest-to-rest profile: a path parameter `s` from 0 to 1 in minimum time under
//! `|ṡ| ≤ v`, `|s̈| ≤ a` (bang–coast–bang: a trapezoid in `ṡ`, or a triangle).

/// The minimum time (s) to move `distance` (>= 0) from rest to rest under speed `v` and
/// acceleration `a`: [`Ramp::rest_to_rest`]'s duration for the path parameter
/// `s = x / distance`, whose limits are `v / distance` and `a / distance`. 0 for no distance.
pub(crate) fn rest_to_rest_time(distance: f64, v: f64, a: f64) -> f64 {
    if distance > 0.0 {
        Ramp::rest_to_rest(0.0, v / distance, a / distance).duration
    } else {
        0.0
    }
}

/// A rest-to-rest profile of `s ∈ [0, 1]`, starting at time `start`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Ramp {
    /// Start time (s).
    pub start: f64,
    /// Duration (s), `T`.
    pub duration: f64,
    /// Length of the acceleration (and of the deceleration) phase (s), `τ`.
    pub ramp: f64,
    /// `|s̈|` during the ramps (1/s²), `a`.
    pub accel: f64,
    /// `ṡ` while coasting (1/s), `a·τ`.
    pub peak: f64,
}

impl Ramp {
    /// The minimum-time profile under `ṡ ≤ v`, `s̈ ≤ a` (both positive; `v = ∞` allowed):
    /// - trapezoid when the speed limit is reached (`v²/a < 1`): `τ = v/a`, `T = 1/v + v/a`;
    /// - triangle otherwise: `τ = 1/√a`, `T = 2/√a`.
    ///
    /// `s(T) = 1`: trapezoid `2·½aτ² + v(T − 2τ) = v²/a + 1 − v²/a`; triangle `aτ² = 1`.
    pub fn rest_to_rest(start: f64, v: f64, a: f64) -> Ramp {
        let (ramp, duration) = if v * v / a < 1.0 {
            (v / a, 1.0 / v + v / a)
        } else {
            let tau = 1.0 / a.sqrt();
            (tau, 2.0 * tau)
        };
        Ramp {
            start,
            duration,
            ramp,
            accel: a,
            peak: a * ramp,
        }
    }

    /// A profile of zero duration (nothing to move).
    pub fn empty(start: f64) -> Ramp {
        Ramp {
            start,
            duration: 0.0,
            ramp: 0.0,
            accel: 0.0,
            peak: 0.0,
        }
    }

    /// End time.
    pub fn end(&self) -> f64 {
        self.start + self.duration
    }

    /// `(s, ṡ)` at absolute time `t` (clamped to the profile).
    pub fn eval(&self, t: f64) -> (f64, f64) {
        if self.duration <= 0.0 {
            return (1.0, 0.0);
        }
        let t = (t - self.start).clamp(0.0, self.duration);
        let (a, tau, big_t) = (self.accel, self.ramp, self.duration);
        if t <= tau {
            (0.5 * a * t * t, a * t)
        } else if t < big_t - tau {
            (0.5 * a * tau * tau + self.peak * (t - tau), self.peak)
        } else {
            let r = big_t - t;
            (1.0 - 0.5 * a * r * r, a * r)
        }
    }

    /// The absolute time at which the profile reaches `s ∈ [0, 1]` (inverse of `eval`).
    pub fn time_at(&self, s: f64) -> f64 {
        if self.duration <= 0.0 {
            return self.start;
        }
        let s = s.clamp(0.0, 1.0);
        let (a, tau) = (self.accel, self.ramp);
        let s_ramp = 0.5 * a * tau * tau;
        let t = if s <= s_ramp {
            (2.0 * s / a).sqrt()
        } else if s < 1.0 - s_ramp {
            tau + (s - s_ramp) / self.peak
        } else {
            self.duration - (2.0 * (1.0 - s) / a).sqrt()
        };
        self.start + t.clamp(0.0, self.duration)
    }
}
