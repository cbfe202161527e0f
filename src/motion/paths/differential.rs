//! Base paths for a differential-drive base: an SE(2) path turned into turn-in-place and
//! drive-straight pieces.

use std::f64::consts::{PI, TAU};

/// Below this distance (m) two base positions are the same: the segment between them is a
/// turn in place.
pub const SAME_POSITION: f64 = 1e-9;

/// Why [`differential_drive`] found no piecewise path.
#[derive(Debug, Clone, PartialEq)]
pub struct DifferentialFailure {
    /// The segment of the input path (from state `segment` to `segment + 1`) that no
    /// turn-drive-turn option follows; `path.len() − 1` for the final turn to the goal's yaw.
    pub segment: usize,
    /// The pose `[x, y, yaw]` the base was at when every option for that segment failed.
    pub at: [f64; 3],
    /// Options tried (each rejected by the caller's motion check).
    pub tried: usize,
}

impl std::fmt::Display for DifferentialFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "no turn-and-drive motion follows segment {} from ({:.3}, {:.3}, {:.3}): all {} \
             options collide",
            self.segment, self.at[0], self.at[1], self.at[2], self.tried
        )
    }
}

/// Turns the SE(2) path `path` (`[x, y, yaw]` states, yaw unwrapped as in the
/// [module conventions](super)) into a path a differential-drive base follows: consecutive
/// states differ either in yaw only (a turn in place) or along the base's heading only (a
/// straight drive, forward or backward, yaw unchanged). No piece moves sideways.
///
/// The base visits the positions of `path` in order. For each segment it turns in place to
/// face the next position, then drives straight to it; at the end it turns to the last
/// state's yaw. The yaws of the intermediate states of `path` are not kept (a differential
/// drive cannot follow them). For each segment the options are: drive forward or backward,
/// each reached by turning the short or the long way round; they are tried in order of the
/// angle turned (on the last segment, including the final turn), and the first whose pieces
/// all pass `valid_motion(from, to)` is taken. When none on the last segment does (turning
/// in place at the goal may collide), the base arrives straight in instead: to a point
/// [`STRAIGHT_IN`] behind or in front of the goal along its yaw, turning there, then straight
/// to the goal. When none on the first segment that moves does (turning in place at the start
/// may collide: the base stands close to what it just handled), the base leaves straight out
/// first: [`STRAIGHT_OUT`] backward or forward along the start's yaw, then on as above.
/// `valid_motion` receives one piece at a time, a
/// pure turn or a pure drive (turns of more than π included, the yaw unwrapped), and must
/// check the robot along the whole piece (e.g. densely with
/// [`first_invalid`](super::first_invalid)); zero-length pieces are not handed to it and not
/// kept.
///
/// The result starts at `path[0]` exactly, ends at the last state's position (exactly, unless
/// the last segment moves it by at most [`SAME_POSITION`]) and at its yaw up to a multiple of
/// 2π, and keeps the yaw unwrapped (continuous). A one-state path
/// is returned as it is.
///
/// # Errors
/// [`DifferentialFailure`] when every option of some segment fails `valid_motion` (greedy: an
/// earlier choice is not revisited; the caller may plan another SE(2) path). States must be
/// `[x, y, yaw]` and finite (the output of [`plan_base`](super::plan_base)); other states are
/// reported as a failure at that segment.
///
/// # Example
/// ```
/// use kinscene::motion::paths::differential_drive;
///
/// // From the origin facing +x to (1, 1) facing +x: turn to face (1, 1), drive, turn back.
/// let path = vec![vec![0.0, 0.0, 0.0], vec![1.0, 1.0, 0.0]];
/// let pieces = differential_drive(&path, &|_, _| true).unwrap();
/// let quarter = std::f64::consts::FRAC_PI_4;
/// assert_eq!(pieces.len(), 4);
/// assert!((pieces[1][2] - quarter).abs() < 1e-12 && pieces[1][..2] == [0.0, 0.0]);
/// assert_eq!(pieces[2][..2], [1.0, 1.0]);
/// assert!(pieces[3][2].abs() < 1e-12);
/// ```
pub fn differential_drive(
    path: &[Vec<f64>],
    valid_motion: &dyn Fn(&[f64], &[f64]) -> bool,
) -> Result<Vec<Vec<f64>>, DifferentialFailure> {
    let Some(first) = path.first() else {
        return Ok(Vec::new());
    };
    let well_formed = |q: &Vec<f64>| q.len() == 3 && q.iter().all(|v| v.is_finite());
    if !well_formed(first) {
        return Err(DifferentialFailure {
            segment: 0,
            at: [f64::NAN; 3],
            tried: 0,
        });
    }
    let mut out = vec![first.clone()];
    let mut at = [first[0], first[1], first[2]];
    let last = path.len() - 1;
    // Whether the last segment's option included the turn to the last state's yaw.
    let mut turned_to_goal = false;
    for (k, pair) in path.windows(2).enumerate() {
        let next = &pair[1];
        if !well_formed(next) {
            return Err(DifferentialFailure {
                segment: k,
                at,
                tried: 0,
            });
        }
        let (dx, dy) = (next[0] - at[0], next[1] - at[1]);
        // A segment that does not move the position: its yaw is not followed.
        if dx.hypot(dy) <= SAME_POSITION {
            continue;
        }
        let final_yaw = (k + 1 == last).then_some(next[2]);
        let mut tried = 0;
        let mut chosen = None;
        for option in options(at[2], dy.atan2(dx), final_yaw) {
            tried += 1;
            let pieces = option.pieces(at, [next[0], next[1]], final_yaw);
            if pieces.windows(2).all(|w| valid_motion(&w[0], &w[1])) {
                chosen = Some(pieces);
                break;
            }
        }
        // Turning in place at the goal may be what collides: arrive straight along its yaw.
        let chosen = match (chosen, final_yaw) {
            (None, Some(goal)) => {
                straight_in(at, [next[0], next[1]], goal, valid_motion, &mut tried)
            }
            (chosen, _) => chosen,
        };
        // Turning in place at the start may be what collides (the base was left close to
        // what it just handled): leave straight along its yaw first.
        let chosen = match chosen {
            None if out.len() == 1 => straight_out(at, next, final_yaw, valid_motion, &mut tried),
            chosen => chosen,
        };
        let Some(pieces) = chosen else {
            return Err(DifferentialFailure {
                segment: k,
                at,
                tried,
            });
        };
        if let Some(q) = pieces.last() {
            at = [q[0], q[1], q[2]];
        }
        out.extend(pieces.into_iter().skip(1));
        turned_to_goal = final_yaw.is_some();
    }
    // The last segment did not move the position (or nothing did): turn in place to the last
    // state's yaw.
    let goal_yaw = path[last][2];
    if last > 0 && !turned_to_goal && !same_yaw(at[2], goal_yaw) {
        let mut tried = 0;
        let mut done = false;
        for turn in turns(wrap(goal_yaw - at[2])) {
            tried += 1;
            let to = [at[0], at[1], at[2] + turn];
            if valid_motion(&at, &to) {
                out.push(to.to_vec());
                done = true;
                break;
            }
        }
        if !done {
            return Err(DifferentialFailure {
                segment: last,
                at,
                tried,
            });
        }
    }
    Ok(out)
}

/// How far (m) a straight-out departure drives along the start's yaw before it turns, nearest
/// first.
pub const STRAIGHT_OUT: [f64; 2] = [0.3, 0.6];

/// A straight-out departure from `at` towards `next` (the first segment that moves): drive
/// [`STRAIGHT_OUT`] backward (then forward) along the start's yaw, with no turn at the start,
/// then follow the segment from there as any segment (turn, drive, and on the last segment
/// the final turn to `final_yaw`, or a straight-in arrival). The first whose pieces all pass
/// `valid_motion`; `tried` counts the options.
fn straight_out(
    at: [f64; 3],
    next: &[f64],
    final_yaw: Option<f64>,
    valid_motion: &dyn Fn(&[f64], &[f64]) -> bool,
    tried: &mut usize,
) -> Option<Vec<Vec<f64>>> {
    let to = [next[0], next[1]];
    for out in STRAIGHT_OUT {
        for sign in [-1.0, 1.0] {
            let via = [
                at[0] + sign * out * at[2].cos(),
                at[1] + sign * out * at[2].sin(),
                at[2],
            ];
            *tried += 1;
            if !valid_motion(&at, &via) {
                continue;
            }
            let (dx, dy) = (to[0] - via[0], to[1] - via[1]);
            let rest = if dx.hypot(dy) <= SAME_POSITION {
                None
            } else {
                options(via[2], dy.atan2(dx), final_yaw)
                    .into_iter()
                    .map(|way| {
                        *tried += 1;
                        way.pieces(via, to, final_yaw)
                    })
                    .find(|pieces| pieces.windows(2).all(|w| valid_motion(&w[0], &w[1])))
                    .or_else(|| {
                        final_yaw.and_then(|goal| straight_in(via, to, goal, valid_motion, tried))
                    })
            };
            if let Some(rest) = rest {
                let mut pieces = vec![at.to_vec()];
                pieces.extend(rest);
                return Some(pieces);
            }
        }
    }
    None
}

/// How far back from the goal (m) along its yaw a straight-in arrival starts, nearest first.
pub const STRAIGHT_IN: [f64; 2] = [0.3, 0.6];

/// A straight-in arrival at `to` with yaw `goal`: to a point [`STRAIGHT_IN`] behind (or in
/// front of) the goal along its yaw, as any segment (turn, drive), turn there to the goal's
/// yaw, then drive forward (or backward) to the goal, with no turn at the goal. The first
/// whose pieces all pass `valid_motion`; `tried` counts the options.
fn straight_in(
    at: [f64; 3],
    to: [f64; 2],
    goal: f64,
    valid_motion: &dyn Fn(&[f64], &[f64]) -> bool,
    tried: &mut usize,
) -> Option<Vec<Vec<f64>>> {
    for back in STRAIGHT_IN {
        for sign in [1.0, -1.0] {
            let via = [
                to[0] - sign * back * goal.cos(),
                to[1] - sign * back * goal.sin(),
            ];
            let (dx, dy) = (via[0] - at[0], via[1] - at[1]);
            if dx.hypot(dy) <= SAME_POSITION {
                continue;
            }
            for way in options(at[2], dy.atan2(dx), Some(goal)) {
                *tried += 1;
                let mut pieces = way.pieces(at, via, Some(goal));
                let yaw = pieces.last().map_or(goal, |q| q[2]);
                pieces.push(vec![to[0], to[1], yaw]);
                if pieces.windows(2).all(|w| valid_motion(&w[0], &w[1])) {
                    return Some(pieces);
                }
            }
        }
    }
    None
}

fn same_yaw(a: f64, b: f64) -> bool {
    wrap(b - a).abs() <= 1e-12
}

/// An angle wrapped into `[-π, π]`.
fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

/// The short turn `short` (in `[-π, π]`) and the long way round to the same heading.
fn turns(short: f64) -> [f64; 2] {
    let long = if short >= 0.0 {
        short - TAU
    } else {
        short + TAU
    };
    [short, long]
}

/// One way to follow a segment: turn by `turn` (rad, signed), drive (forward or backward),
/// and on the last segment turn by `final_turn` to the goal's yaw.
#[derive(Debug, Clone, Copy)]
struct Way {
    turn: f64,
    final_turn: f64,
}

impl Way {
    /// The states of this option from `at`: after the turn (if any), after the drive, after
    /// the final turn (if any).
    fn pieces(&self, at: [f64; 3], to: [f64; 2], final_yaw: Option<f64>) -> Vec<Vec<f64>> {
        let mut out = vec![at.to_vec()];
        let heading = at[2] + self.turn;
        if self.turn != 0.0 {
            out.push(vec![at[0], at[1], heading]);
        }
        out.push(vec![to[0], to[1], heading]);
        if final_yaw.is_some() && self.final_turn != 0.0 {
            out.push(vec![to[0], to[1], heading + self.final_turn]);
        }
        out
    }
}

/// The options from yaw `yaw` to drive along the direction `direction` (rad): forward or
/// backward, each turning the short or the long way; with `final_yaw`, each also with the
/// short or the long final turn. Sorted by the total angle turned (stable: forward first on
/// ties).
fn options(yaw: f64, direction: f64, final_yaw: Option<f64>) -> Vec<Way> {
    let mut out = Vec::with_capacity(8);
    for heading in [direction, direction + PI] {
        for turn in turns(wrap(heading - yaw)) {
            match final_yaw {
                None => out.push(Way {
                    turn,
                    final_turn: 0.0,
                }),
                Some(goal) => {
                    for final_turn in turns(wrap(goal - (yaw + turn))) {
                        out.push(Way { turn, final_turn });
                    }
                }
            }
        }
    }
    for o in &mut out {
        if o.turn.abs() <= 1e-15 {
            o.turn = 0.0;
        }
        if o.final_turn.abs() <= 1e-12 {
            o.final_turn = 0.0;
        }
    }
    out.sort_by(|a, b| {
        let cost = |o: &Way| o.turn.abs() + o.final_turn.abs();
        cost(a).total_cmp(&cost(b))
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each piece is a pure turn or a drive along the heading.
    fn no_sideways(path: &[Vec<f64>]) {
        for w in path.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            if dx.hypot(dy) > SAME_POSITION {
                assert_eq!(a[2], b[2], "a drive keeps the yaw");
                let lateral = -a[2].sin() * dx + a[2].cos() * dy;
                assert!(lateral.abs() < 1e-12, "{a:?} -> {b:?}");
            }
        }
    }

    /// No turn within 0.1 m of the start (a base left close to a cabinet whose corners sweep
    /// into it when it turns): the base backs out 0.3 m along its yaw first, then turns there.
    /// By hand, from (−0.3, 0) to (0, 1): direction atan2(1, 0.3) = 1.2793 rad; forward with
    /// the short turns (1.2793 there, −1.2793 at the goal) is the least turned.
    #[test]
    fn a_base_that_cannot_turn_at_the_start_backs_out_first() {
        let path = vec![vec![0.0, 0.0, 0.0], vec![0.0, 1.0, 0.0]];
        let no_turn_at_start = |a: &[f64], b: &[f64]| !(a[2] != b[2] && a[0].hypot(a[1]) < 0.1);
        let out = differential_drive(&path, &no_turn_at_start).unwrap();
        no_sideways(&out);
        let d = 1.0f64.atan2(0.3);
        let expected = [
            [0.0, 0.0, 0.0],
            [-0.3, 0.0, 0.0],
            [-0.3, 0.0, d],
            [0.0, 1.0, d],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(out.len(), expected.len(), "{out:?}");
        for (got, want) in out.iter().zip(expected) {
            assert!(
                got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-12),
                "{got:?} against {want:?}"
            );
        }
        // Where it cannot drive either, nothing: the failure counts every option.
        let stuck = |a: &[f64], _: &[f64]| a[0].hypot(a[1]) >= 0.1;
        let e = differential_drive(&path, &stuck).unwrap_err();
        assert_eq!(e.segment, 0);
        assert!(e.tried > 4, "{e}");
    }

    #[test]
    fn a_segment_behind_is_driven_backward() {
        // Facing +x, the next position is 1 m behind: no turn, a backward drive.
        let path = vec![vec![0.0, 0.0, 0.0], vec![-1.0, 0.0, 0.0]];
        let out = differential_drive(&path, &|_, _| true).unwrap();
        assert_eq!(out, vec![vec![0.0, 0.0, 0.0], vec![-1.0, 0.0, 0.0]]);
    }

    #[test]
    fn a_blocked_short_turn_takes_the_long_way() {
        // Turning by a negative angle is refused: the quarter turn to -y goes the long way.
        let path = vec![
            vec![0.0, 0.0, 0.0],
            vec![0.0, 0.0, -1.0],
            vec![1.0, -1.0, 0.0],
        ];
        let valid = |a: &[f64], b: &[f64]| b[2] >= a[2];
        let out = differential_drive(&path, &valid).unwrap();
        no_sideways(&out);
        let turned: f64 = out.windows(2).map(|w| w[1][2] - w[0][2]).sum();
        // Never a negative turn; ends at yaw 0 up to 2π.
        assert!(out.windows(2).all(|w| w[1][2] >= w[0][2]));
        assert!((turned / TAU - (turned / TAU).round()).abs() < 1e-12);
        assert_eq!(out.last().unwrap()[..2], [1.0, -1.0]);
    }

    #[test]
    fn no_turn_at_the_goal_arrives_straight_in() {
        // No turn within 0.1 m of the goal (1, 1), yaw 0: the base reaches (1, 1) driving
        // along x, having turned 0.3 m before it (at (0.7, 1), the nearest straight-in start).
        let path = vec![vec![0.0, 0.0, 0.0], vec![1.0, 1.0, 0.0]];
        let near = |q: &[f64]| (q[0] - 1.0).hypot(q[1] - 1.0) < 0.1;
        let valid = |a: &[f64], b: &[f64]| !(a[2] != b[2] && near(a));
        let out = differential_drive(&path, &valid).unwrap();
        no_sideways(&out);
        let last = out.len() - 1;
        assert_eq!(out[last][..2], [1.0, 1.0]);
        assert!((out[last][2] / TAU - (out[last][2] / TAU).round()).abs() < 1e-12);
        assert_eq!(out[last - 1][2], out[last][2]);
        assert!((out[last - 1][0] - 0.7).abs() < 1e-12 && (out[last - 1][1] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_pure_turn_and_failures_are_reported() {
        let path = vec![vec![1.0, 2.0, 0.0], vec![1.0, 2.0, 3.0]];
        let out = differential_drive(&path, &|_, _| true).unwrap();
        assert_eq!(out, vec![vec![1.0, 2.0, 0.0], vec![1.0, 2.0, 3.0]]);
        let err = differential_drive(&path, &|_, _| false).unwrap_err();
        assert_eq!((err.segment, err.tried), (1, 2));
        let moving = vec![
            vec![0.0, 0.0, 0.0],
            vec![0.0, 1.0, 0.0],
            vec![2.0, 1.0, 0.0],
        ];
        let err = differential_drive(&moving, &|_, b| b[1] < 0.5).unwrap_err();
        // The 4 options, then 4 straight-out departures (along x: valid), each with its 4.
        assert_eq!((err.segment, err.tried), (0, 4 + 4 * (1 + 4)));
    }
}
