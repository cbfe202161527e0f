(** * Examples: the task-search model run on small lattices (sanity checks of the model).

    Evaluates [search] (Search.v), [planner] (Rounds.v), [qsearch], [qplanner] and
    [search_run] (Requeue.v) and [static_conflict] (Conflict.v) by computation, so the model is
    not vacuous: the definitions compute the plans one expects. Not a model of a specific
    Rust function beyond those of Search.v and Rounds.v; the Rust counterpart of these
    scenarios is tests/task (e.g. a door that must be opened before the goal joint can move). *)

From Coq Require Import List Arith.
From KinScene Require Import Task.Lattice Task.Search Task.Rounds Task.Conflict
  Task.Requeue.
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

(** The round with re-queue, every unbounded move re-queued once before it is evaluated
    ([raise] always true): the same plan as [search_two_joints]. *)
Example qsearch_requeues_every_move :
  qfound (qsearch [2; 3] all_joints (fun _ _ => true) (fun k => key_eqb k [1; 2]) [0; 0]
            false (fun _ => 0) (fun _ _ => true) (fun _ _ => false))
  = Some [mkMove 0 1; mkMove 1 2].
Proof. vm_compute. reflexivity. Qed.

(** The door case with re-queues and early growth ([early] always true): round 1 stops at
    its first failure (its blocker, joint 1, is inactive), round 2 opens the door first. *)
Example qplanner_opens_the_door_first :
  qplanner [2; 2] door_feasible (fun k => nth 0 k 0 =? 1) [0; 0] (fun _ => None)
    door_blockers false (fun _ _ => 0) (fun _ _ _ => true) (fun _ _ _ => true)
    (fun j => j =? 0)
  = Solved [mkMove 1 1; mkMove 0 1].
Proof. vm_compute. reflexivity. Qed.

(** Two doors on the base (parts 0 and 1, two values each) that collide when both are open
    (value 1); the goal opens both. *)
Definition doors_collide (x y : body) (k : Key) : bool :=
  match x, y with
  | Part 0, Part 1 | Part 1, Part 0 => (nth 0 k 0 =? 1) && (nth 1 k 0 =? 1)
  | _, _ => false
  end.

Definition doors_goal (k : Key) : bool := (nth 0 k 0 =? 1) && (nth 1 k 0 =? 1).

(** A move is feasible iff it does not end in the collision (the certified sweep). *)
Definition doors_feasible (k : Key) (m : Move) : bool :=
  negb (doors_collide (Part 0) (Part 1) (apply k m)).

(** The pre-check finds the conflict from the candidate contact at [q = [1; 1]]. *)
Example static_conflict_two_doors :
  static_conflict [2; 2] doors_goal [0; 0] (fun _ => None) (fun j => j <? 2)
    (fun _ v => v =? 1) doors_collide [1; 1] [(Part 0, Part 1)]
  = true.
Proof. vm_compute. reflexivity. Qed.

(** So [search::run] reports [Infeasible] before any round ... *)
Example search_run_two_doors :
  search_run [2; 2] doors_feasible doors_goal [0; 0] (fun _ => None)
    (fun _ _ _ => Some []) false (fun _ _ => 0) (fun _ _ _ => false) (fun _ _ _ => true)
    false (fun j => j <? 2) (fun _ v => v =? 1) doors_collide [1; 1] [(Part 0, Part 1)]
    (fun j => j <? 2)
  = Infeasible.
Proof. vm_compute. reflexivity. Qed.

(** ... which is what the rounds alone conclude too. *)
Example qplanner_two_doors :
  qplanner [2; 2] doors_feasible doors_goal [0; 0] (fun _ => None) (fun _ _ _ => Some [])
    false (fun _ _ => 0) (fun _ _ _ => false) (fun _ _ _ => true) (fun j => j <? 2)
  = Infeasible.
Proof. vm_compute. reflexivity. Qed.
