//! The hierarchical interface: a refinement layer (motion planning) can veto a task-level move.

use crate::scene::{HandleId, JointId, PartId, SceneModel, State};

/// A move the task search is about to accept, with what the task level decided for it.
#[derive(Debug, Clone, Copy)]
pub struct MoveContext<'a> {
    /// The scene.
    pub model: &'a SceneModel,
    /// The state before the move.
    pub state: &'a State,
    /// The joint moved.
    pub joint: JointId,
    /// Its value before (rad or m).
    pub from: f64,
    /// Its value after (rad or m).
    pub to: f64,
    /// The handle the task level grasps.
    pub handle: HandleId,
    /// The base pose x (m), y (m), yaw (rad) chosen by the task level (nearest admissible
    /// grid cell, facing the grasp point).
    pub base: [f64; 3],
    /// Where the robot comes from: x (m), y (m).
    pub robot_from: [f64; 2],
}

/// The refiner's answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Refinement {
    /// The move can be refined (a motion exists).
    Accept,
    /// The move cannot be refined in this state.
    Veto {
        /// Why, for the report (e.g. "no IK solution for the handle at 1.9 m").
        reason: String,
        /// The parts whose configuration causes the veto, if the refiner knows them. `None`
        /// means "unknown": the search then lets every joint move (still complete, slower);
        /// `Some(vec![])` means "no other part matters" (the move is infeasible whatever the
        /// other joints do).
        blockers: Option<Vec<PartId>>,
    },
}

/// A refinement layer consulted for every move the task search accepts, before the move's
/// successor state is opened. Implemented by the motion layer; the task layer ships
/// [`NoRefinement`] and implements the trait for closures.
///
/// The search calls `refine` at most once per (state, move) — verdicts are cached across
/// rounds — and may call it from several threads at once. A veto makes the search record the
/// failure and look for another plan; it does not retry the move from another base pose. A
/// refiner should therefore judge the move in the state (is there *any* motion that does
/// it?), not only the proposed base pose, or the search may miss plans; and its verdict must
/// depend only on the state and the move for the completeness guarantee to hold.
pub trait Refiner: Sync {
    /// Accepts or vetoes `action`.
    fn refine(&self, action: &MoveContext<'_>) -> Refinement;

    /// Whether the verdict on a move of joint `j` depends only on the values of `j` and of
    /// the joints that [interact](super::Interaction::interacts) with it (not on the rest of
    /// the state, nor on the base pose proposed or where the robot comes from). The search's
    /// partial-order reduction ([`TaskSettings::reduction`](super::TaskSettings::reduction))
    /// is sound only then, and is used only for refiners that say so. Default `false`.
    fn local(&self) -> bool {
        false
    }
}

/// Accepts every move.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoRefinement;

impl Refiner for NoRefinement {
    fn refine(&self, _: &MoveContext<'_>) -> Refinement {
        Refinement::Accept
    }

    fn local(&self) -> bool {
        true
    }
}

impl<F> Refiner for F
where
    F: Fn(&MoveContext<'_>) -> Refinement + Sync,
{
    fn refine(&self, action: &MoveContext<'_>) -> Refinement {
        self(action)
    }
}
