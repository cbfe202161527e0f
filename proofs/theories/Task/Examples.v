(** * Examples: the task-search model run on small lattices (sanity checks of the model).

    Evaluates [search] (Search.v) and [planner] (Rounds.v) by computation, so the model is
    not vacuous: the definitions compute the plans one expects. Not a model of a specific
    Rust function beyond those of Search.v and Rounds.v; the Rust counterpart of these
    scenarios is tests/task (e.g. a door that must be opened before the goal joint can move). *)

From Coq Require Import List Arith.
From KinScene Require Import Task.Lattice Task.Search Task.Rounds.
Import ListNotations.

(** Two joints with 2 and 3 values, every move feasible, goal [[1; 2]]. Popping the oldest
    item first (breadth-first order) returns a two-step plan. *)
Example search_two_joints :
  found (search [2; 3] all_joints (fun _ _ => true) (fun k => key_eqb k [1; 2]) [0; 0]
           (fun _ => 0))
  = Some [mkMove 0 1; mkMove 1 2].
Proof. vm_compute. reflexivity. Qed.

(** The same with the newest item first (depth-first order): still a plan, another one. *)
Example search_two_joints_newest_first :
  exists p, found (search [2; 3] all_joints (fun _ _ => true) (fun k => key_eqb k [1; 2])
                    [0; 0] (fun w => length w - 1)) = Some p.
Proof. eexists. vm_compute. reflexivity. Qed.

(** A goal joint 0 that can move only while joint 1 (a door in the way) is at value 1.
    Round 1 (only joint 0 active) fails with blocker joint 1; round 2 moves the door first. *)
Definition door_feasible (k : Key) (m : Move) : bool :=
  match mv_joint m with
  | 0 => nth 1 k 0 =? 1
  | _ => true
  end.

Definition door_blockers (_ : JointSet) (_ : Key) (m : Move) : option (list nat) :=
  match mv_joint m with 0 => Some [1] | _ => Some [] end.

Example planner_opens_the_door_first :
  planner [2; 2] door_feasible (fun k => nth 0 k 0 =? 1) [0; 0] (fun _ => None)
    door_blockers (fun _ _ => 0) (fun j => j =? 0)
  = Solved [mkMove 1 1; mkMove 0 1].
Proof. vm_compute. reflexivity. Qed.

(** If the door blocks for good, the planner reports [Infeasible] after the second round. *)
Example planner_reports_a_blocked_goal :
  planner [2; 2] (fun k m => negb (mv_joint m =? 0)) (fun k => nth 0 k 0 =? 1) [0; 0]
    (fun _ => None) door_blockers (fun _ _ => 0) (fun j => j =? 0)
  = Infeasible.
Proof. vm_compute. reflexivity. Qed.
