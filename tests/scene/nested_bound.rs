//! The nested sweep bound on generated scenes: moving every joint on a handle's ancestor chain
//! at once moves the handle by at most the sum of the per-joint
//! [`max_displacement`](kinscene::scene::motion::max_displacement)s, each computed with the
//! joints below it already at their new values.
//!
//! This is the implementation-side check of `nested_sweep_bound` (and its per-joint steps,
//! `steps_bounded` / `point_travel_bound`) in proofs/theories/Motion/SweepBound.v. The proof
//! telescopes the motion root-last: joint `i` moves from its old to its new value while the
//! joints below it are at their new values and the joints above at their old ones; each such
//! one-joint step moves the point by at most that joint's bound (its radius taken in that
//! intermediate state), and the ancestors above are rigid, so the steps add (triangle
//! inequality). The test replays the same intermediate states with forward kinematics.

use kinscene::scene::motion::max_displacement;
use kinscene::scene::{
    HandleId, Parent, SceneData, SceneModel, State, forward_kinematics, world_from_handle,
};
use nalgebra::Point3;
use proptest::prelude::*;

use super::generators::{scene_and_state, state};

/// Rounding slack (m): poses with coordinates of a few metres, depth ≤ 4, as in
/// `properties::sweep_bound_holds_for_sampled_points`.
const SLACK: f64 = 1e-9;

/// The handle's world position at `state`.
fn handle_at(model: &SceneModel, data: &mut SceneData, state: &State, h: HandleId) -> Point3<f64> {
    forward_kinematics(model, data, state).unwrap();
    world_from_handle(model, data, h).unwrap().position
}

/// A generated scene with two independent random states (old and new values).
fn scene_and_two_states() -> impl Strategy<Value = (SceneModel, State, State)> {
    scene_and_state(30).prop_flat_map(|(m, old)| {
        let new = state(&m);
        (Just(m), Just(old), new)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Moving all joints on a handle's ancestor chain from their old to their new values moves
    /// the handle by at most Σ max_displacement (models `nested_sweep_bound`), and each
    /// telescoping step by at most its own term (models `steps_bounded`).
    #[test]
    fn handle_travel_within_summed_ancestor_bounds(
        (model, old, new) in scene_and_two_states(),
        pick in any::<prop::sample::Index>(),
    ) {
        let handles: Vec<HandleId> = model.handles().map(|(id, _)| id).collect();
        prop_assume!(!handles.is_empty());
        let handle = handles[pick.index(handles.len())];
        // The handle's part and its ancestors, deepest first.
        let mut chain = vec![handle.part()];
        while let Parent::Part(p) = model.part(*chain.last().unwrap()).unwrap().parent() {
            chain.push(p);
        }
        let mut data = SceneData::new(&model);
        let start = handle_at(&model, &mut data, &old, handle);

        // Telescoping, deepest joint first: `now` has the joints below the current one at
        // their new values, the current one and those above at their old values.
        let mut now = old.clone();
        let mut total = 0.0;
        for part in &chain {
            let joint = part.joint();
            let (a, b) = (old.value(joint).unwrap(), new.value(joint).unwrap());
            // The bound at `now` (max_displacement runs forward kinematics of `now`; the
            // joint's own value does not change the radius: `sweep_radius_invariant`).
            let bound = max_displacement(&model, &mut data, &now, joint, a, b).unwrap();
            let before = handle_at(&model, &mut data, &now, handle);
            now.set(&model, joint, b).unwrap();
            let after = handle_at(&model, &mut data, &now, handle);
            prop_assert!(
                (after - before).norm() <= bound + SLACK,
                "joint {}: step moved the handle {} > bound {bound}",
                joint.index(),
                (after - before).norm()
            );
            total += bound;
        }
        // `now` is the old state with the whole chain at its new values.
        let end = handle_at(&model, &mut data, &now, handle);
        let travel = (end - start).norm();
        prop_assert!(
            travel <= total + SLACK,
            "handle moved {travel} > summed bounds {total} over {} joints",
            chain.len()
        );
    }
}
