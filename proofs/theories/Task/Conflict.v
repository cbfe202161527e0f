(** * Conflict: the static goal-conflict pre-check is sound.

    Models [static_conflict] (src/task/conflict.rs), which [search::run] calls before the
    rounds and whose [Some] makes the search return [Infeasible] at once:
    - a body is a part [Part p] or a base shape [BaseShape s] ([Body]); part [p] is placed by
      joint [p] (a part's joint has the part's index) and its ancestors: [chain_of] is the
      Rust [chain] closure ([Rounds.chain] over [parent], which reaches the root when parts
      are stored parents first, [parents_first]); a base shape by no joint;
    - [collide x y k] is "[collisions] at the state of key [k] reports a contact between [x]
      and [y]" (in either order: the Rust [same]); it is abstract here;
    - [pair_conflict q a b] is the test the Rust loop applies to a candidate contact [(a, b)]
      of [collisions] at [q] (the start with every goal joint at the point of its target
      nearest its start value): the goal is not met at the start, the pair collides at [q]
      and not at the start, every joint of [placing a b] ([chain(a) ++ chain(b)], sorted and
      deduplicated: here [nodup]) is a goal joint ([problem.goal.target(j)?]), and the pair
      collides at every key of [combos q (placing a b)]: each of those joints set to each of
      its lattice values inside its target ([choices]: [lattice.values(j)] filtered by
      [t.contains]), every other joint as in [q] — at least one and at most
      [MAX_COMBINATIONS = 64] keys; [static_conflict q contacts] is [true] iff some
      candidate passes (the Rust function returns [Some]).

    Assumptions (explicit premises, [sweep_separates], [relative_pose], [goal_targets]):
    - [sweep_separates] — THE SWEEP GUARANTEE: after a feasible move of joint [j], no pair
      with exactly one body in [j]'s moving subtree (the parts whose chain holds [j])
      collides. Feasible moves have a [Free] sweep ([Checker::evaluate] checks the sweep
      first; a part without handles is never feasible), [check_joint_motion] certifies the
      pairs [checked_pairs(.., Some(root))] — exactly the pairs of [collisions] with one body
      in the subtree, same settings ([settings.sweep.collision] in both) — over the closed
      interval, end value included (theorem 1, [check_joint_motion_free_sound]);
    - [relative_pose]: whether [x] and [y] collide depends only on the joints that place
      exactly one of them ([splitting x y]): a joint placing both (a common ancestor) moves
      them rigidly together, and distances are invariant under rigid motions; joints
      placing neither do not move them;
    - [goal_targets]: a goal state has every goal joint inside its target ([Goal::is_satisfied],
      the search's [unmet == 0]), with [target j v] the Rust [t.contains(lattice.values(j)[v])];
    - [length q = length sizes]: [q] has one entry per joint. In Rust the entries of [q]
      outside [placing a b] are real values that need not be lattice values; by
      [relative_pose] they do not matter, which is why the model may take any key.

    Main results:
    - [collide_backward]: along a feasible path, a pair that collides at the end collides
      at the start (the last move that changes the pair's relative pose ends in a state
      where the pair does not collide);
    - [combos_cover]: every key whose [placing] joints are inside their targets agrees on
      those joints with one of the enumerated [combos];
    - [pair_conflict_sound], [static_conflict_sound]: if the pre-check reports a conflict,
      no feasible path over ALL joints (any joint may move, not only the active ones) leads
      from the start to a goal state — the [Infeasible] verdict is sound for the whole
      lattice.

    Checked on the implementation by: tests/task/brute_force.rs
    [search_agrees_with_exhaustive_enumeration] (every [Infeasible] of [task::plan],
    including those of the pre-check, is confirmed by an exhaustive enumeration of the full
    lattice). *)

From Coq Require Import List Arith Lia Bool.
From KinScene Require Import Task.Lattice Task.Rounds.
Import ListNotations.

(** [Body::Part] and [Body::Base]. *)
Inductive body : Type :=
  | Part (p : nat)
  | BaseShape (s : nat).

(** [MAX_COMBINATIONS]: value combinations tried per candidate pair. *)
Definition max_combinations : nat := 64.

(** Membership in a list of joints, as a joint set. *)
Definition in_list (J : list nat) : JointSet := fun j => existsb (Nat.eqb j) J.

Lemma in_list_In : forall J j, in_list J j = true <-> In j J.
Proof.
  intros J j. unfold in_list. rewrite existsb_exists. split.
  - intros [x [Hx He]]. apply Nat.eqb_eq in He. subst. exact Hx.
  - intros H. exists j. split; [exact H|apply Nat.eqb_refl].
Qed.

(** A lattice state has, for each joint, an index below that joint's number of values. *)
Lemma valid_nth : forall sizes k j,
  valid sizes k -> j < length sizes -> nth j k 0 < nth j sizes 0.
Proof.
  intros sizes k j H. revert j. induction H as [|x m t ms Hx Ht IH]; intros [|j] Hj;
    simpl in *; try lia; auto. apply IH. lia.
Qed.

Section Conflict.

(** The lattice, the search's move predicate, the goal test, the start key, the parts'
    parents, the goal joints, the targets ([target j v]: value index [v] of joint [j] is
    inside [j]'s target) and the collision predicate of a body pair in a state. *)
Context (sizes : list nat) (feasible : Key -> Move -> bool) (goal : Key -> bool)
  (start : Key) (parent : nat -> option nat) (is_goal : JointSet)
  (target : nat -> nat -> bool) (collide : body -> body -> Key -> bool).

(** The joints placing a body: its part's joint and the ancestors' ([chain] in conflict.rs). *)
Definition chain_of (x : body) : list nat :=
  match x with
  | Part p => chain parent (length sizes) p
  | BaseShape _ => []
  end.

(** Joint [j] moves body [x]: [x] is in the subtree of [j]'s part. *)
Definition moves_body (j : nat) (x : body) : bool := in_list (chain_of x) j.

(** The joints that place exactly one of [x], [y]: they change the pair's relative pose. *)
Definition splitting (x y : body) : JointSet := fun j => xorb (moves_body j x) (moves_body j y).

(** [joints] in conflict.rs: the chains of both bodies, without repetitions. *)
Definition placing (x y : body) : list nat := nodup Nat.eq_dec (chain_of x ++ chain_of y).

(** The lattice values of joint [j] inside its target ([choices] in conflict.rs). *)
Definition choices (j : nat) : list nat := filter (target j) (seq 0 (nth j sizes 0)).

(** Every combination of the [choices] of the joints of [J], the other joints as in [q]. *)
Fixpoint combos (q : Key) (J : list nat) : list Key :=
  match J with
  | [] => [q]
  | j :: rest => flat_map (fun v => map (fun k => update k j v) (combos q rest)) (choices j)
  end.

(** The test of one candidate contact [(a, b)] found at [q] (the body of the Rust loop). *)
Definition pair_conflict (q : Key) (a b : body) : bool :=
  negb (goal start) && collide a b q && negb (collide a b start)
  && forallb is_goal (placing a b)
  && (let cs := combos q (placing a b) in
      (0 <? length cs) && (length cs <=? max_combinations) && forallb (collide a b) cs).

(** [static_conflict] returns [Some]: some candidate contact passes the test. *)
Definition static_conflict (q : Key) (contacts : list (body * body)) : bool :=
  existsb (fun ab => pair_conflict q (fst ab) (snd ab)) contacts.

(** ** The assumptions *)

(** The certified sweep of a feasible move separates its moving subtree from every other
    body at the end value. *)
Definition sweep_separates : Prop :=
  forall k m x y,
    valid sizes k -> is_move sizes all_joints k m -> feasible k m = true ->
    splitting x y (mv_joint m) = true -> collide x y (apply k m) = false.

(** A pair's collision depends only on the joints that place exactly one of its bodies. *)
Definition relative_pose : Prop :=
  forall x y k k', agree (splitting x y) k k' -> collide x y k = collide x y k'.

(** A goal state has every goal joint inside its target. *)
Definition goal_targets : Prop :=
  forall k, valid sizes k -> goal k = true ->
    forall j, is_goal j = true -> j < length sizes -> target j (nth j k 0) = true.

(** ** The pair along a path *)

Theorem collide_backward : forall x y k ms k',
  sweep_separates -> relative_pose -> valid sizes k ->
  path sizes all_joints feasible k ms k' -> collide x y k' = true -> collide x y k = true.
Proof.
  intros x y k ms k' Hsw Hrel Hk H.
  induction H as [k|k m ms k' Hm Hf Hp IH]; intros Hc; [exact Hc|].
  assert (Hv : valid sizes (apply k m)) by (eapply apply_valid; eauto).
  specialize (IH Hv Hc).
  destruct (splitting x y (mv_joint m)) eqn:Hs.
  - (* The move changes the pair's relative pose: the sweep separated them. *)
    rewrite (Hsw k m x y Hk Hm Hf Hs) in IH. discriminate.
  - (* It does not: the pair collides before as after. *)
    rewrite <- IH. apply Hrel. apply agree_apply_inactive; [exact Hs|apply agree_refl].
Qed.

(** ** The enumeration *)

Lemma flat_map_nil : forall {X Y} (l : list X),
  flat_map (fun _ => @nil Y) l = [].
Proof. intros X Y l. induction l; simpl; auto. Qed.

Lemma combos_empty : forall q J j, In j J -> choices j = [] -> combos q J = [].
Proof.
  intros q J. induction J as [|j0 rest IH]; intros j Hj Hc; [destruct Hj|].
  simpl. destruct Hj as [<-|Hj]; [rewrite Hc; reflexivity|].
  rewrite (IH j Hj Hc). apply flat_map_nil.
Qed.

Lemma combos_length : forall q J k, In k (combos q J) -> length k = length q.
Proof.
  intros q J. induction J as [|j rest IH]; intros k Hk; simpl in Hk.
  - destruct Hk as [<-|[]]. reflexivity.
  - apply in_flat_map in Hk. destruct Hk as [v [_ Hk]]. apply in_map_iff in Hk.
    destruct Hk as [k0 [<- Hk0]]. rewrite update_length. auto.
Qed.

(** Every key whose joints of [J] take values of their [choices] agrees on [J] with an
    enumerated combination. *)
Theorem combos_cover : forall q J k,
  length k = length q -> (forall j, In j J -> In (nth j k 0) (choices j)) ->
  exists k', In k' (combos q J) /\ agree (in_list J) k' k.
Proof.
  intros q J. induction J as [|j rest IH]; intros k Hl Hin.
  - exists q. split; [left; reflexivity|]. split; [symmetry; exact Hl|].
    intros i Hi. discriminate.
  - destruct (IH k Hl (fun i Hi => Hin i (or_intror Hi))) as [k0 [Hk0 [Hl0 Ha0]]].
    exists (update k0 j (nth j k 0)). split.
    + simpl. apply in_flat_map. exists (nth j k 0). split; [apply Hin; left; reflexivity|].
      apply (in_map (fun k1 => update k1 j (nth j k 0))). exact Hk0.
    + split; [rewrite update_length; exact Hl0|]. intros i Hi.
      destruct (Nat.eq_dec i j) as [->|Hne].
      * destruct (Nat.lt_ge_cases j (length k0)) as [Hlt|Hge].
        -- rewrite nth_update_same by exact Hlt. reflexivity.
        -- rewrite !nth_overflow; [reflexivity|lia|rewrite update_length; exact Hge].
      * rewrite nth_update_other by exact Hne. apply Ha0.
        apply in_list_In in Hi. destruct Hi as [Hi|Hi]; [congruence|].
        apply in_list_In. exact Hi.
Qed.

Lemma splitting_placing : forall x y j,
  splitting x y j = true -> in_list (placing x y) j = true.
Proof.
  intros x y j H. unfold splitting, moves_body in H. apply in_list_In. unfold placing.
  apply nodup_In. apply in_or_app.
  destruct (in_list (chain_of x) j) eqn:Hx; [left; apply in_list_In; exact Hx|].
  destruct (in_list (chain_of y) j) eqn:Hy; [right; apply in_list_In; exact Hy|].
  discriminate.
Qed.

(** ** Soundness of the pre-check *)

(** A candidate pair that passes the test collides in every goal state of the lattice. *)
Lemma pair_conflict_goal : forall q a b k,
  relative_pose -> goal_targets -> length q = length sizes ->
  pair_conflict q a b = true -> valid sizes k -> goal k = true -> collide a b k = true.
Proof.
  intros q a b k Hrel Hgt Hq Hpc Hk Hg. unfold pair_conflict in Hpc.
  apply andb_true_iff in Hpc as [Hpc Hcs]. apply andb_true_iff in Hpc as [_ Hgoals].
  apply andb_true_iff in Hcs as [Hcs Hall]. apply andb_true_iff in Hcs as [Hpos _].
  apply Nat.ltb_lt in Hpos. rewrite forallb_forall in Hgoals, Hall.
  set (J := placing a b) in *.
  assert (Hin : forall j, In j J -> In (nth j k 0) (choices j)).
  { intros j Hj.
    assert (Hne : choices j <> []).
    { intros He. rewrite (combos_empty q J j Hj He) in Hpos. simpl in Hpos. lia. }
    assert (Hlt : j < length sizes).
    { destruct (Nat.lt_ge_cases j (length sizes)) as [H|H]; [exact H|exfalso].
      apply Hne. unfold choices. rewrite nth_overflow by exact H. reflexivity. }
    unfold choices. apply filter_In. split.
    - apply in_seq. pose proof (valid_nth sizes k j Hk Hlt). lia.
    - apply (Hgt k Hk Hg j); [apply Hgoals; exact Hj|exact Hlt]. }
  assert (Hl : length k = length q) by (rewrite (valid_length sizes k Hk); symmetry; exact Hq).
  destruct (combos_cover q J k Hl Hin) as [k' [Hk' Ha]].
  rewrite <- (Hall k' Hk'). symmetry. apply Hrel.
  eapply agree_mono; [|exact Ha]. apply splitting_placing.
Qed.

(** The verdict of one candidate pair is sound: no feasible path over all joints leads from
    the start to a goal state. *)
Theorem pair_conflict_sound : forall q a b ms k,
  sweep_separates -> relative_pose -> goal_targets ->
  valid sizes start -> length q = length sizes ->
  pair_conflict q a b = true ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof.
  intros q a b ms k Hsw Hrel Hgt Hs Hq Hpc Hp.
  destruct (goal k) eqn:Hg; [exfalso|reflexivity].
  assert (Hk : valid sizes k) by (eapply path_valid; eauto).
  pose proof (pair_conflict_goal q a b k Hrel Hgt Hq Hpc Hk Hg) as Hc.
  pose proof (collide_backward a b start ms k Hsw Hrel Hs Hp Hc) as Hc0.
  unfold pair_conflict in Hpc. rewrite Hc0 in Hpc. simpl in Hpc.
  rewrite !andb_false_r in Hpc. discriminate.
Qed.

(** [static_conflict] returns [Some] only if no plan in the lattice reaches the goal. *)
Theorem static_conflict_sound : forall q contacts ms k,
  sweep_separates -> relative_pose -> goal_targets ->
  valid sizes start -> length q = length sizes ->
  static_conflict q contacts = true ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof.
  intros q contacts ms k Hsw Hrel Hgt Hs Hq H Hp. unfold static_conflict in H.
  apply existsb_exists in H. destruct H as [[a b] [_ H]]. simpl in H.
  eapply pair_conflict_sound; eauto.
Qed.

End Conflict.
