//! The continuous motion check of [`ArmCheck`] (its default, [`ArmCheck::with_continuous`]):
//! the spans of the free states it evaluates cover the whole motion.
//!
//! **Loop.** The motion's end `t = 1` is evaluated, then its start, then the middle of each
//! closed interval of the parameter that no evaluated state's open span covers yet (in
//! bisection order, so a blocked motion is found early): a span longer than the interval's
//! half covers it, else the two pieces either side of the span are queued. A state that is
//! not free, a span below [`CONTACT_CLEARANCE`] over the fastest item's speed, or more than
//! [`MAX_CONTINUOUS_STATES`] states rejects the motion. Soundness (an accepted motion keeps
//! every clearance at every point) is `certify_motion_sound` of
//! `proofs/theories/Collision/SpanCover.v`, given the lever bounds (the `span` module).

use super::{ArmCheck, ArmCheckData};

/// The clearance (m) below which a continuous motion check ([`ArmCheck::with_continuous`])
/// rejects a motion: it would otherwise creep towards a contact in ever smaller spans.
pub const CONTACT_CLEARANCE: f64 = 1e-5;

/// The most states a continuous motion check evaluates before it rejects the motion (one
/// that stays within a hair of something for long). On MotionBenchMaker no motion needed
/// more than 1026 (most need at most 16).
pub const MAX_CONTINUOUS_STATES: usize = 10_000;

/// Added to an interval's half-length when capping a span: a span that reaches past the
/// interval's ends covers them (the spans are open intervals).
const CAP_SLACK: f64 = 1e-12;

/// How near (m) a link's spheres come to an obstacle, or a checked pair's spheres to each
/// other, before a continuous motion check computes their exact distance.
pub const CONTINUOUS_BAND: f64 = 0.005;

impl ArmCheck<'_> {
    /// The continuous motion check ([`ArmCheck::with_continuous`]), the motion's speeds and
    /// bounds set up in `data`: `b`, then `a`, then the middle of each interval of the
    /// parameter that no evaluated state's span covers yet.
    pub(super) fn certify_motion(&self, a: &[f64], b: &[f64], data: &mut ArmCheckData) -> bool {
        let fastest = data
            .state
            .link_speed
            .iter()
            .chain(&data.state.speed)
            .fold(0.0, |m: f64, &v| m.max(v));
        if fastest <= 0.0 {
            // The arm does not move: `a` is taken as valid, and `b` is `a`.
            return self.state_valid(b, None, &mut data.state);
        }
        let floor = CONTACT_CLEARANCE / fastest;
        // The span of the free state at `t`, capped at `cap` (`None`: not free, or too close).
        let mut evaluated = 0;
        let mut span_at = |t: f64, cap: f64, data: &mut ArmCheckData| -> Option<f64> {
            evaluated += 1;
            if evaluated > MAX_CONTINUOUS_STATES {
                return None;
            }
            data.q.clear();
            data.q.extend(a.iter().zip(b).map(|(x, y)| x + (y - x) * t));
            // Evaluated afresh even when it was the last valid one: its bounds are needed.
            data.state.last_valid.clear();
            let q = std::mem::take(&mut data.q);
            let free = self.state_valid(&q, Some(t), &mut data.state);
            data.q = q;
            if !free {
                return None;
            }
            let span = self.span(t, cap, floor, &data.state);
            (span >= floor).then_some(span)
        };
        // The open span around each evaluated state is free; `pending` holds the closed
        // intervals still to certify, in bisection order (a blocked motion is found early).
        let mut pending = std::mem::take(&mut data.intervals);
        pending.clear();
        let certified = 'walk: {
            let Some(end) = span_at(1.0, 1.0 + CAP_SLACK, data) else {
                break 'walk false;
            };
            if end <= 1.0 {
                let Some(start) = span_at(0.0, (1.0 - end) + CAP_SLACK, data) else {
                    break 'walk false;
                };
                if start <= 1.0 - end {
                    pending.push_back((start, 1.0 - end));
                }
            }
            while let Some((x, y)) = pending.pop_front() {
                let (m, half) = (0.5 * (x + y), 0.5 * (y - x));
                let Some(span) = span_at(m, half + CAP_SLACK, data) else {
                    break 'walk false;
                };
                if span <= half {
                    pending.push_back((x, m - span));
                    pending.push_back((m + span, y));
                }
            }
            true
        };
        data.intervals = pending;
        certified
    }
}
