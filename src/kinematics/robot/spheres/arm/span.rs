//! The certified span of a free state along a motion: how many neighbouring states of the
//! discrete motion check are free without being checked.
//!
//! **Bound.** Along the straight motion `q(t) = a + t·(b − a)` no point of link `l` moves
//! faster than `link_speed[l]` (m per unit of `t`) in the world, and no point of link `k`
//! faster than `speed[p]` relative to link `i` for the checked pair `p = (i, k)` (the lever
//! bounds of [`levers`](super::levers)). At a free state `t` let `D_l` be a lower bound on
//! the distance from link `l`'s exact shapes to the scene less the margin, and `D_p` one on
//! the distance between the pair's exact shapes. Then at every `t'` with
//! `|t' − t|·link_speed[l] < D_l` for every link and `|t' − t|·speed[p] < D_p` for every
//! pair, each link still keeps more than the margin from the scene and each pair is apart:
//! the state at `t'` is free, exactly as the exact check would find it. So the discrete check
//! of the motion gives the same answer when it skips such states. With a self-clearance
//! ([`ArmCheck::with_self_margin`]) a pair's `D_p` is its distance less that clearance.
//!
//! **Lower bounds.** For a link whose spheres reach no obstacle, the least sphere clearance
//! ([`SphereObstacles::link_clearance`]: the spheres cover the exact shapes, the obstacles'
//! reach includes the margin and the `f32` slack), or the clearance of the ball enclosing
//! them where that alone keeps the span. For a link whose spheres reach some
//! obstacles, the least of the sphere clearance to the others and, for each reached one, the
//! certified bound its exact distance check left (`scene_bound`, carried to `t` with the
//! link's speed). For a pair whose spheres are apart, the larger of the enclosing balls' gap
//! and the least sphere gap; for a pair whose spheres meet, its certified exact bound
//! (`bound`). A bound missing (a state checked outside a motion) gives a span of 0. Every
//! bound is reduced by [`CERTIFIED_GAP`], which absorbs the rounding of the interpolated
//! states and of this arithmetic.

use super::{ArmCheck, CERTIFIED_GAP, StateScratch};

impl ArmCheck<'_> {
    /// The number `k` of states on either side of the free state `t = j / n` (the scratch
    /// holds its poses, spheres and broad phase, and the motion's speeds and bounds) that
    /// are certified free (see the module's bound): states `j ± 1 ..= j ± k`, at most `cap`
    /// (the states still to check lie within `cap` steps: a longer span skips nothing more,
    /// and bounds that already keep `cap` steps need not be made precise).
    pub(super) fn span_steps(&self, t: f64, n: usize, cap: usize, s: &StateScratch) -> usize {
        // Spans under one step certify nothing: stop as soon as the span drops below it.
        let step = 1.0 / n as f64;
        // `cap + 1` steps: the rounding below then gives at most `cap`.
        let span = self.span(t, (cap as f64 + 1.0) * step, step, s);
        // Strictly inside the span; the quotient rounded down by a relative hair.
        let k = (span / step * (1.0 - 1e-9)).floor();
        if k.is_finite() {
            (k as usize).min(cap)
        } else {
            cap
        }
    }

    /// The certified span of the free state `t` in the motion's parameter (see the module's
    /// bound): every state `t'` with `|t' − t|` below it is free. At most `cap` (bounds that
    /// already keep `cap` need not be made precise); 0 as soon as it drops below `floor`.
    pub(super) fn span(&self, t: f64, cap: f64, floor: f64, s: &StateScratch) -> f64 {
        let mut span = cap;
        // The far links first: they move fastest and come nearest to the scene.
        let links = s.poses.len().min(self.balls.len()).min(s.link_speed.len());
        for l in (0..links).rev() {
            let v = s.link_speed[l];
            if self.balls[l].is_none() || v <= 0.0 {
                continue;
            }
            span = narrowed(span, self.link_bound(l, t, s, span * v), v);
            if span < floor {
                return 0.0;
            }
        }
        for (p, &(i, k)) in self.spheres.checked_pairs().iter().enumerate() {
            let v = s.speed.get(p).copied().unwrap_or(f64::INFINITY);
            if v <= 0.0 {
                continue;
            }
            // The pair's distance bound less the clearance it must keep.
            let margin = self.self_margin;
            let d = if s.pairs.contains(&p) {
                s.bound.at(p, t, v).unwrap_or(0.0)
            } else {
                let ball = match (self.ball(i, s), self.ball(k, s)) {
                    (Some((ci, ri)), Some((ck, rk))) => (ci - ck).norm() - ri - rk,
                    _ => f64::INFINITY,
                };
                // The balls' gap alone keeps the span: the spheres need not be compared.
                if ball - margin - CERTIFIED_GAP >= span * v {
                    ball
                } else {
                    ball.max(f64::from(self.spheres.pair_clearance(&s.spheres, i, k)))
                }
            };
            span = narrowed(span, d - margin, v);
            if span < floor {
                return 0.0;
            }
        }
        span
    }

    /// Link `l`'s enclosing ball in the world at the scratch's poses (placed by the broad
    /// phase).
    fn ball(&self, l: usize, s: &StateScratch) -> Option<(nalgebra::Point3<f64>, f64)> {
        s.world_balls.get(l).copied().flatten()
    }

    /// A lower bound (m) on the distance from link `l`'s exact shapes to the scene less the
    /// margin at the state `t` in the scratch (see the module's lower bounds).
    /// A bound of at least `enough` may be returned without comparing the link's spheres.
    fn link_bound(&self, l: usize, t: f64, s: &StateScratch, enough: f64) -> f64 {
        // The sphere gaps are to the obstacles grown by the band.
        let band = self.band;
        let Some(m) = s.links.iter().position(|&x| x == l) else {
            // Computed by the broad phase (`+∞` without a ball).
            let ball = f64::from(s.ball_gaps.get(l).copied().unwrap_or(f32::INFINITY)) + band;
            if ball - CERTIFIED_GAP >= enough {
                return ball;
            }
            // Compared by the broad phase where the ball is close.
            let spheres = match s.link_gaps.get(l) {
                Some(g) if !g.is_nan() => *g,
                _ => self.obstacles.link_clearance(&s.spheres, l, &[]),
            };
            return ball.max(f64::from(spheres) + band);
        };
        let reached = &s.reached[m];
        let margin = self.margin.max(0.0);
        // The broad phase's gap to the obstacles the link's spheres do not reach.
        let mut d = f64::from(s.link_gaps[l]) + band;
        for (o, _) in reached.iter().enumerate().filter(|(_, r)| **r) {
            let slot = l * self.obstacles.len() + o;
            d = d.min(
                s.scene_bound
                    .at(slot, t, s.link_speed[l])
                    .map_or(0.0, |b| b - margin),
            );
        }
        d
    }
}

/// The span `span` narrowed by an item with distance bound `d` (m) closing in at speed `v`
/// (m per unit of the motion's parameter, `> 0`): `d` less [`CERTIFIED_GAP`] over `v`, 0
/// when that is not positive.
fn narrowed(span: f64, d: f64, v: f64) -> f64 {
    let d = d - CERTIFIED_GAP;
    if d > 0.0 { span.min(d / v) } else { 0.0 }
}
