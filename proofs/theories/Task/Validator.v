(** * Validator: the predicate a returned plan must satisfy (theorem 4).

    Models [task::validate] (src/task/validate.rs): replay the plan from [problem.start];
    each step must name a joint and a value of it (check 1, [InvalidStep] otherwise; here: a
    joint index below [length sizes] and a value index below its size), start from the
    current value (check 2: in this model a step carries no [from], it is always the replayed
    value, which is what the search writes into [Step::from]), and pass the step checks
    (checks 3–4: dense sweep, base pose) — an abstract predicate [ok]; after the last step the
    goal must hold (check 5). [validate] is [Validation::valid].

    Assumptions: the validator's step checks [ok] accept every move that the search's
    predicate [feasible] accepts (the first premise of [path_validates]). The module docs
    of validate.rs argue this for the Rust checks (a certified-free sweep passes every dense
    sample; the validator's swept footprint is covered by the search's); it is not proved
    here. With [ok = feasible] it holds trivially ([path_validates_self]). Refinement vetoes
    are not replayed by the Rust validator, so a refiner only makes [feasible] stricter.

    Main results:
    - [path_validates]: a feasible path from the start to a goal state passes the validator;
    - [validate_path]: conversely, a plan the validator accepts with [ok = feasible] is a
      feasible path (over all joints, for moves that change their joint) to a goal state.

    Checked on the implementation by: tests/task/validate.rs
    [search_and_random_plans_validate_on_generated_kitchens] (plans of the search pass the
    validator), [accepts_the_plan_of_the_one_door_case], [rejects_a_wrong_from],
    [rejects_a_plan_that_misses_the_goal] (the replay, continuity and goal checks). *)

From Coq Require Import List Arith Lia Bool.
From KinScene Require Import Task.Lattice.
Import ListNotations.

(** The state after replaying [ms] from [k], or [None] at the first failing step. *)
Fixpoint replay (sizes : list nat) (ok : Key -> Move -> bool) (k : Key) (ms : list Move)
  : option Key :=
  match ms with
  | [] => Some k
  | m :: rest =>
      if (mv_joint m <? length sizes) && (mv_to m <? nth (mv_joint m) sizes 0) && ok k m
      then replay sizes ok (apply k m) rest
      else None
  end.

(** [Validation::valid]: every step passes and the final state satisfies the goal. *)
Definition validate (sizes : list nat) (ok : Key -> Move -> bool) (goal : Key -> bool)
  (start : Key) (plan : list Move) : bool :=
  match replay sizes ok start plan with
  | Some k => goal k
  | None => false
  end.

Lemma path_replay : forall sizes A feasible ok k ms k',
  (forall k m, valid sizes k -> is_move sizes A k m -> feasible k m = true -> ok k m = true) ->
  valid sizes k -> path sizes A feasible k ms k' -> replay sizes ok k ms = Some k'.
Proof.
  intros sizes A feasible ok k ms k' Hok Hk H.
  induction H as [k|k m ms k' Hm Hf Hp IH]; simpl; [reflexivity|].
  pose proof Hm as [_ [Hj [Ht _]]].
  rewrite (Hok k m Hk Hm Hf).
  apply Nat.ltb_lt in Hj. apply Nat.ltb_lt in Ht. rewrite Hj, Ht. simpl.
  apply IH. eapply apply_valid; eauto.
Qed.

Theorem path_validates : forall sizes A feasible ok goal start plan k,
  (forall k m, valid sizes k -> is_move sizes A k m -> feasible k m = true -> ok k m = true) ->
  valid sizes start -> path sizes A feasible start plan k -> goal k = true ->
  validate sizes ok goal start plan = true.
Proof.
  intros sizes A feasible ok goal start plan k Hok Hs Hp Hg. unfold validate.
  rewrite (path_replay sizes A feasible ok start plan k Hok Hs Hp). exact Hg.
Qed.

Corollary path_validates_self : forall sizes A feasible goal start plan k,
  valid sizes start -> path sizes A feasible start plan k -> goal k = true ->
  validate sizes feasible goal start plan = true.
Proof. intros. eapply path_validates; eauto. Qed.

(** Every step changes its joint's value ([Step::from != Step::to]), as in every plan of the
    search. *)
Fixpoint changes (k : Key) (ms : list Move) : Prop :=
  match ms with
  | [] => True
  | m :: rest => mv_to m <> nth (mv_joint m) k 0 /\ changes (apply k m) rest
  end.

Lemma replay_path : forall sizes feasible k ms k',
  replay sizes feasible k ms = Some k' -> changes k ms ->
  path sizes all_joints feasible k ms k'.
Proof.
  intros sizes feasible k ms. revert k.
  induction ms as [|m rest IH]; intros k k' H Hc; simpl in H.
  - injection H as <-. apply path_nil.
  - destruct Hc as [Hne Hc].
    destruct (mv_joint m <? length sizes) eqn:Hj; [|discriminate].
    destruct (mv_to m <? nth (mv_joint m) sizes 0) eqn:Ht; [|discriminate].
    destruct (feasible k m) eqn:Hf; [|discriminate]. simpl in H.
    apply Nat.ltb_lt in Hj. apply Nat.ltb_lt in Ht.
    apply path_cons; auto. repeat split; auto.
Qed.

(** Conversely, a plan of changing steps that the validator accepts with [ok = feasible] is
    a feasible path over all joints from the start to a goal state: [path] and [validate] are
    the same predicate. *)
Theorem validate_path : forall sizes feasible goal start plan,
  validate sizes feasible goal start plan = true -> changes start plan ->
  exists k, path sizes all_joints feasible start plan k /\ goal k = true.
Proof.
  intros sizes feasible goal start plan H Hc. unfold validate in H.
  destruct (replay sizes feasible start plan) as [k|] eqn:Hr; [|discriminate].
  exists k. split; [apply replay_path; assumption | exact H].
Qed.
