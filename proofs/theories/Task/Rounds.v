(** * Rounds: the active-set rounds of the search — the projection lemma and the whole
    planner (theorems 3 and 4).

    Models the rounds of [search::run] (src/task/search/pass.rs) and the "Active joints"
    paragraph of src/task/mod.rs:
    - a round is the search of Search.v over the moves of the active joints [act]
      ([active: Vec<bool>]); it returns a plan, or is exhausted with its failed evaluations;
    - [blockers act k m] is what [Checker::evaluate] (called with [active = act]) reports
      for a failed move: [Some B] for [Blockers::Known(B)] (joint indices), [None] for
      [Blockers::Unknown] (a refiner veto without blockers);
    - [grow] is the end of the loop: if some failure had unknown blockers and not every joint
      is active, every joint becomes active; otherwise every named joint outside [act] (and
      its ancestors, [close_over_ancestors] with [parent]) joins; if nothing joins, [run]
      reports [Infeasible];
    - [planner pick act0] runs at most [n + 1] rounds ([n] joints; each growing round adds a
      joint, so the fuel is never the reason to stop — [planner_terminates]); [act0] is the
      goal joints closed over their ancestors.

    Assumptions (explicit premises of the theorems):
    - [blockers_contract] — THE ASSUMPTION ON THE BLOCKERS REPORTED BY [Checker::evaluate]:
      if evaluating move [m] in lattice state [k], in a round whose active set [act] is
      closed under parents and contains [m]'s joint, returns Infeasible with
      [Blockers::Known(B)], and every joint of [B] is in [act], then the move is infeasible
      in every lattice state [k'] that agrees with [k] on [act]. The Rust code argues it per
      cause: [NoHandle] and an empty manipulation region ([NoBasePose]) depend only on the
      joint and its ancestors ([B] empty); a sweep [Collision] names the joints of both
      bodies of the contacts (their ancestors are added by [close_over_ancestors]), whose
      poses along the motion are then the same in [k'], so the contact persists and no sound
      sweep check returns Free (theorem 1); for an [Inconclusive] sweep (the nearest pair
      could not be certified) the same is assumed, not argued; a failed base-pose check
      names the inactive parts with a footprint before or after the move when the check
      restricted to the active parts passes, and nothing otherwise — correct because adding
      parts only adds occupied cells and swept cells (the check is monotone); a [Vetoed]
      move names the refiner's blockers ([Refiner] must honour the same contract) or
      [Unknown]. Blockers are joint ids of the model ([< n]); [grow] ignores others.
    - [goal_support act0]: the goal test depends only on the joints of [act0] (it reads the
      goal joints' values, [Goal::is_satisfied]; [act0] contains them);
    - [ancestor_closed act0] and [parents_first] (parts are stored parents before children,
      [SceneModel::parts]); [valid sizes start];
    - the assumptions of Search.v on [feasible] (a function of state and move: robot
      position, memo, refiner, active set do not change the verdict).

    Main results:
    - [projection_lemma]: if a round with active set [act] is exhausted, every failed
      evaluation [(k, m)] of the round stays infeasible in every state agreeing with [k] on
      [act], and the goal depends only on [act], then no feasible path over ALL joints leads
      from the start to a goal state (project the path onto [act]: drop the steps of
      inactive joints; every projected state is closed in the round);
    - [failures_determined]: when [grow] adds nothing, [blockers_contract] gives the
      premise of the projection lemma for every failure of the round;
    - [planner_terminates]: the planner ends with [Solved] or [Infeasible];
    - [planner_sound] / [planner_plan_validates] (theorem 4): a [Solved] plan is a path of
      feasible moves from the start to a goal state and passes the validator;
    - [planner_infeasible_sound] / [planner_complete] (theorem 3): [Infeasible] only if no
      feasible path over all joints reaches a goal state; so if one exists, the planner
      returns a plan; [planner_correct]: the planner decides plan existence.

    Checked on the implementation by: tests/task/validate.rs
    [search_and_random_plans_validate_on_generated_kitchens] ([planner_plan_validates]) and
    tests/task/brute_force.rs [search_agrees_with_exhaustive_enumeration] (generated
    kitchens, [NoRefinement]: [task::plan] returns [Solved] iff an exhaustive enumeration of
    the full lattice over [Feasibility::check], with every joint movable, reaches a goal
    state; every step of a returned plan starts at the current value, is feasible in the
    state it is applied in, and the plan ends in a goal state) and its larger, ignored
    variant [brute_force_up_to_eight_joints]; a brute-force BFS with every joint movable
    is what [planner_correct] compares the rounds with. *)

From Coq Require Import List Arith Lia Bool.
From KinScene Require Import Task.Lattice Task.Validator Task.Search.
Import ListNotations.

Inductive outcome : Type :=
  | Solved (plan : list Move)
  | Infeasible
  | OutOfRounds.

Section Rounds.

Context (sizes : list nat) (feasible : Key -> Move -> bool) (goal : Key -> bool)
  (start : Key) (parent : nat -> option nat)
  (blockers : JointSet -> Key -> Move -> option (list nat)).

(** ** Joint sets *)

Definition ancestor_closed (act : JointSet) : Prop :=
  forall j p, act j = true -> parent j = Some p -> act p = true.

(** Parts are stored parents before children. *)
Definition parents_first : Prop := forall j p, parent j = Some p -> p < j.

(** [j] and its ancestors ([close_over_ancestors] walks [parent] up to the base). *)
Fixpoint chain (fuel j : nat) : list nat :=
  j :: match fuel with
       | 0 => []
       | S f => match parent j with Some p => chain f p | None => [] end
       end.

Definition close_over_ancestors (act : JointSet) (js : list nat) : JointSet :=
  fun j => act j || existsb (fun b => existsb (Nat.eqb j) (chain (length sizes) b)) js.

Definition all_active (act : JointSet) : bool := forallb act (seq 0 (length sizes)).

Definition unknown_blockers (act : JointSet) (fl : list (Key * Move)) : bool :=
  existsb (fun km => match blockers act (fst km) (snd km) with
                     | None => true
                     | Some _ => false
                     end) fl.

(** [new_blockers]: named joints outside [act]. *)
Definition new_blockers (act : JointSet) (fl : list (Key * Move)) : list nat :=
  flat_map (fun km => match blockers act (fst km) (snd km) with
                      | Some bs => filter (fun b => (b <? length sizes) && negb (act b)) bs
                      | None => []
                      end) fl.

(** The end of an exhausted round: the next active set, or [None] (report infeasible). *)
Definition grow (act : JointSet) (fl : list (Key * Move)) : option JointSet :=
  if unknown_blockers act fl && negb (all_active act) then Some all_joints
  else match new_blockers act fl with
       | [] => None
       | bs => Some (close_over_ancestors act bs)
       end.

(** [search::run]: rounds until a plan is found or nothing new is blocking. *)
Fixpoint rounds (pick : JointSet -> list item -> nat) (r : nat) (act : JointSet) : outcome :=
  match r with
  | 0 => OutOfRounds
  | S r' =>
      match found (search sizes act feasible goal start (pick act)) with
      | Some p => Solved p
      | None =>
          match grow act (failed (search sizes act feasible goal start (pick act))) with
          | None => Infeasible
          | Some act' => rounds pick r' act'
          end
      end
  end.

Definition planner (pick : JointSet -> list item -> nat) (act0 : JointSet) : outcome :=
  rounds pick (S (length sizes)) act0.

(** ** The assumptions *)

(** The contract of the blockers reported by [Checker::evaluate] (see the header). *)
Definition blockers_contract : Prop :=
  forall act k m B,
    ancestor_closed act -> valid sizes k -> is_move sizes act k m -> feasible k m = false ->
    blockers act k m = Some B ->
    (forall b, In b B -> b < length sizes -> act b = true) ->
    forall k', valid sizes k' -> agree act k k' -> feasible k' m = false.

(** The goal test reads only joints of [act]. *)
Definition goal_support (act : JointSet) : Prop :=
  forall k1 k2, valid sizes k1 -> valid sizes k2 -> agree act k1 k2 -> goal k1 = goal k2.

Lemma goal_support_mono : forall (act act' : JointSet),
  (forall j, act j = true -> act' j = true) -> goal_support act -> goal_support act'.
Proof.
  intros act act' Hs H k1 k2 H1 H2 Ha. apply H; auto. eapply agree_mono; [|exact Ha]. auto.
Qed.

(** ** The projection lemma *)

Theorem projection_lemma : forall act c ms k,
  valid sizes start ->
  reach sizes act feasible goal start c -> found c = None -> work c = [] ->
  (forall k0 m, In (k0, m) (failed c) ->
     forall k', valid sizes k' -> agree act k0 k' -> feasible k' m = false) ->
  goal_support act ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof.
  intros act c ms k Hs Hr Hf Hw Hdet Hgoal Hpath.
  destruct (exhausted_round sizes act feasible goal start c Hs Hr Hf Hw)
    as [Hst [Hcl [Hcov _]]].
  (* Every state of the full path has a closed projection that agrees with it on [act]. *)
  assert (Hproj : forall s ms k, path sizes all_joints feasible s ms k -> valid sizes s ->
            forall q, In q (closed c) -> agree act q s ->
            exists q', In q' (closed c) /\ agree act q' k /\ valid sizes k).
  { clear ms k Hpath. intros s ms k H.
    induction H as [s|s m ms k Hm Hfe Hp IH]; intros Hv q Hq Ha; [eauto|].
    pose proof Hm as [_ [Hj [Ht Hne]]].
    assert (Hv' : valid sizes (apply s m)) by (eapply apply_valid; eauto).
    destruct (act (mv_joint m)) eqn:Hact.
    - (* An active step: the projection makes it too; it is closed, not a failure. *)
      assert (Hmq : is_move sizes act q m).
      { destruct Ha as [_ Ha]. repeat split; auto. rewrite (Ha _ Hact). exact Hne. }
      destruct (Hcov q Hq m Hmq) as [Hin|Hfl].
      + apply (IH Hv' (apply q m) Hin). apply agree_apply. exact Ha.
      + exfalso. pose proof (Hdet q m Hfl s Hv Ha). congruence.
    - (* An inactive step: dropped from the projection. *)
      apply (IH Hv' q Hq). apply agree_apply_inactive; assumption. }
  destruct (Hproj start ms k Hpath Hs start Hst (agree_refl act start))
    as [q [Hq [Ha Hk]]].
  destruct (Hcl q Hq) as [Hvq Hgq].
  rewrite <- Hgq. symmetry. apply Hgoal; auto.
Qed.

(** ** Growing the active set *)

Definition count (act : JointSet) : nat := length (filter act (seq 0 (length sizes))).

Lemma count_le : forall act, count act <= length sizes.
Proof.
  intros act. unfold count. pose proof (filter_length_le act (seq 0 (length sizes))).
  rewrite seq_length in H. exact H.
Qed.

Lemma forallb_false : forall {X} (f : X -> bool) l,
  forallb f l = false -> exists x, In x l /\ f x = false.
Proof.
  intros X f l H. induction l as [|a t IH]; simpl in H; [discriminate|].
  destruct (f a) eqn:Fa; simpl in H.
  - destruct (IH H) as [x [Hx Fx]]. exists x. split; [right; exact Hx|exact Fx].
  - exists a. split; [left; reflexivity|exact Fa].
Qed.

Lemma In_new_blockers : forall act fl b,
  In b (new_blockers act fl) ->
  b < length sizes /\ act b = false.
Proof.
  intros act fl b H. unfold new_blockers in H. apply in_flat_map in H.
  destruct H as [km [_ H]]. destruct (blockers act (fst km) (snd km)); [|destruct H].
  apply filter_In in H. destruct H as [_ H]. apply andb_true_iff in H as [H1 H2].
  apply Nat.ltb_lt in H1. apply negb_true_iff in H2. auto.
Qed.

Lemma in_chain_head : forall fuel j, existsb (Nat.eqb j) (chain fuel j) = true.
Proof. intros [|f] j; simpl; rewrite Nat.eqb_refl; reflexivity. Qed.

(** A growing round makes a larger set. *)
Lemma grow_grows : forall act fl act',
  grow act fl = Some act' ->
  (forall j, act j = true -> act' j = true) /\ count act < count act'.
Proof.
  intros act fl act' H. unfold grow in H.
  destruct (unknown_blockers act fl && negb (all_active act)) eqn:Hu.
  - injection H as <-. split; [reflexivity|].
    apply andb_true_iff in Hu as [_ Hu]. apply negb_true_iff in Hu.
    destruct (forallb_false act _ Hu) as [j [Hj Fj]].
    unfold count. apply filter_sub_lt with (y := j); auto.
  - destruct (new_blockers act fl) as [|b bs] eqn:Hn; [discriminate|].
    injection H as <-.
    assert (Hb : In b (new_blockers act fl)) by (rewrite Hn; left; reflexivity).
    destruct (In_new_blockers act fl b Hb) as [Hlt Hnb].
    assert (Hsub : forall j, act j = true -> close_over_ancestors act (b :: bs) j = true)
      by (intros j Hj; unfold close_over_ancestors; rewrite Hj; reflexivity).
    split; [exact Hsub|]. unfold count.
    apply filter_sub_lt with (y := b); auto.
    + apply in_seq. lia.
    + unfold close_over_ancestors. simpl. rewrite in_chain_head.
      rewrite orb_true_r. reflexivity.
Qed.

Lemma chain_closed : forall fuel j,
  parents_first -> j <= fuel ->
  forall x, In x (chain fuel j) -> forall p, parent x = Some p -> In p (chain fuel j).
Proof.
  induction fuel as [|f IH]; intros j Hpf Hj x Hx p Hp.
  - simpl in Hx. destruct Hx as [<-|[]]. pose proof (Hpf j p Hp). lia.
  - simpl in Hx |- *. destruct Hx as [<-|Hx].
    + rewrite Hp. right. destruct f; simpl; left; reflexivity.
    + destruct (parent j) as [q|] eqn:Hq; [|destruct Hx].
      pose proof (Hpf j q Hq). right. exact (IH q Hpf ltac:(lia) x Hx p Hp).
Qed.

Lemma existsb_chain : forall fuel j b,
  existsb (Nat.eqb j) (chain fuel b) = true <-> In j (chain fuel b).
Proof.
  intros fuel j b. rewrite existsb_exists. split.
  - intros [x [Hx He]]. apply Nat.eqb_eq in He. subst. exact Hx.
  - intros H. exists j. split; [exact H|apply Nat.eqb_refl].
Qed.

Lemma grow_closed : forall act fl act',
  parents_first -> ancestor_closed act -> grow act fl = Some act' -> ancestor_closed act'.
Proof.
  intros act fl act' Hpf Hac H. unfold grow in H.
  destruct (unknown_blockers act fl && negb (all_active act)) eqn:Hu.
  - injection H as <-. intros j p _ _. reflexivity.
  - destruct (new_blockers act fl) as [|b bs] eqn:Hn; [discriminate|].
    injection H as <-. intros j p Hj Hp. unfold close_over_ancestors in *.
    apply orb_true_iff in Hj as [Hj|Hj]; [rewrite (Hac j p Hj Hp); reflexivity|].
    apply existsb_exists in Hj. destruct Hj as [b' [Hb' Hj]].
    apply existsb_chain in Hj.
    assert (Hin : In b' (new_blockers act fl)) by (rewrite Hn; exact Hb').
    destruct (In_new_blockers act fl b' Hin) as [Hlt _].
    apply orb_true_iff. right. apply existsb_exists. exists b'. split; [exact Hb'|].
    apply existsb_chain. exact (chain_closed (length sizes) b' Hpf ltac:(lia) j Hj p Hp).
Qed.

(** When nothing joins, every failure of the round is determined by [act]. *)
Theorem failures_determined : forall act fl,
  blockers_contract -> ancestor_closed act -> grow act fl = None ->
  (forall k m, In (k, m) fl -> valid sizes k /\ is_move sizes act k m /\ feasible k m = false) ->
  forall k m, In (k, m) fl ->
    forall k', valid sizes k' -> agree act k k' -> feasible k' m = false.
Proof.
  intros act fl Hcon Hac Hg Hfl k m Hin k' Hk' Ha.
  destruct (Hfl k m Hin) as [Hk [Hm Hf]].
  unfold grow in Hg.
  destruct (unknown_blockers act fl && negb (all_active act)) eqn:Hu; [discriminate|].
  destruct (new_blockers act fl) as [|b bs] eqn:Hn; [|discriminate].
  destruct (blockers act k m) as [B|] eqn:Hb.
  - (* Known blockers, all active: the contract. *)
    apply (Hcon act k m B Hac Hk Hm Hf Hb); auto.
    intros b HbB Hlt. destruct (act b) eqn:Hab; [reflexivity|exfalso].
    assert (Hnb : In b (new_blockers act fl)).
    { unfold new_blockers. apply in_flat_map. exists (k, m). split; [exact Hin|].
      simpl. rewrite Hb. apply filter_In. split; [exact HbB|].
      apply andb_true_iff. split; [apply Nat.ltb_lt; exact Hlt|rewrite Hab; reflexivity]. }
    rewrite Hn in Hnb. destruct Hnb.
  - (* Unknown blockers: the round had every joint active, so [k' = k]. *)
    assert (Hunk : unknown_blockers act fl = true).
    { unfold unknown_blockers. apply existsb_exists. exists (k, m). simpl. rewrite Hb. auto. }
    rewrite Hunk in Hu. simpl in Hu. apply negb_false_iff in Hu.
    unfold all_active in Hu. rewrite forallb_forall in Hu.
    assert (Heq : k = k').
    { apply (agree_all_eq act); [|exact Ha]. intros j Hj. apply Hu. apply in_seq.
      rewrite (valid_length sizes k Hk) in Hj. lia. }
    subst. exact Hf.
Qed.

(** ** The planner *)

Lemma rounds_terminate : forall pick r act,
  count act + r > length sizes -> rounds pick r act <> OutOfRounds.
Proof.
  intros pick r. induction r as [|r IH]; intros act Hc; simpl.
  - pose proof (count_le act). lia.
  - destruct (found _) as [p|]; [discriminate|].
    destruct (grow _ _) as [act'|] eqn:Hg; [|discriminate].
    destruct (grow_grows _ _ _ Hg) as [_ Hlt]. apply IH. lia.
Qed.

(** The planner ends with [Solved] or [Infeasible] (each round terminates:
    [search_terminates]; each growing round adds a joint). *)
Theorem planner_terminates : forall pick act0, planner pick act0 <> OutOfRounds.
Proof. intros pick act0. apply rounds_terminate. lia. Qed.

Lemma rounds_sound : forall pick r act p,
  valid sizes start -> rounds pick r act = Solved p ->
  exists k, path sizes all_joints feasible start p k /\ goal k = true.
Proof.
  intros pick r. induction r as [|r IH]; intros act p Hs H; simpl in H; [discriminate|].
  destruct (found (search sizes act feasible goal start (pick act))) as [p'|] eqn:Hf.
  - injection H as <-.
    destruct (search_terminates sizes act feasible goal start (pick act) Hs) as [Hr _].
    destruct (search_sound sizes act feasible goal start _ p' Hs Hr Hf) as [k [Hp Hg]].
    exists k. split; [|exact Hg]. eapply path_mono; [|exact Hp]. reflexivity.
  - destruct (grow _ _) as [act'|]; [|discriminate]. eapply IH; eauto.
Qed.

(** Theorem 4: a returned plan is a sequence of moves, each feasible in the state it is
    applied to, from the start to a goal state. *)
Theorem planner_sound : forall pick act0 p,
  valid sizes start -> planner pick act0 = Solved p ->
  exists k, path sizes all_joints feasible start p k /\ goal k = true.
Proof. intros. eapply rounds_sound; eauto. Qed.

(** Theorem 4, validator form: a returned plan passes [task::validate]'s predicate for any
    step check [ok] that accepts the moves the search's predicate accepts. *)
Theorem planner_plan_validates : forall (ok : Key -> Move -> bool) pick act0 p,
  (forall k m, valid sizes k -> is_move sizes all_joints k m -> feasible k m = true ->
     ok k m = true) ->
  valid sizes start -> planner pick act0 = Solved p ->
  validate sizes ok goal start p = true.
Proof.
  intros ok pick act0 p Hok Hs H. destruct (planner_sound pick act0 p Hs H) as [k [Hp Hg]].
  eapply path_validates; eauto.
Qed.

Lemma rounds_infeasible : forall pick r act ms k,
  valid sizes start -> parents_first -> blockers_contract ->
  ancestor_closed act -> goal_support act ->
  rounds pick r act = Infeasible ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof.
  intros pick r. induction r as [|r IH]; intros act ms k Hs Hpf Hcon Hac Hgs H Hp;
    simpl in H; [discriminate|].
  set (c := search sizes act feasible goal start (pick act)) in H.
  destruct (found c) as [p|] eqn:Hf; [discriminate|].
  destruct (grow act (failed c)) as [act'|] eqn:Hg.
  - destruct (grow_grows _ _ _ Hg) as [Hsub _].
    apply (IH act' ms k Hs Hpf Hcon); auto.
    + eapply grow_closed; eauto.
    + eapply goal_support_mono; eauto.
  - destruct (search_terminates sizes act feasible goal start (pick act) Hs) as [Hr Ht].
    fold c in Hr, Ht.
    assert (Hw : work c = []) by (destruct Ht as [Ht|Ht]; [contradiction|exact Ht]).
    destruct (exhausted_round sizes act feasible goal start c Hs Hr Hf Hw)
      as [_ [_ [_ Hfl]]].
    eapply projection_lemma; eauto.
    eapply failures_determined; eauto.
Qed.

(** Theorem 3, the report: [Infeasible] only if no feasible path over all joints leads
    from the start to a goal state. *)
Theorem planner_infeasible_sound : forall pick act0 ms k,
  valid sizes start -> parents_first -> blockers_contract ->
  ancestor_closed act0 -> goal_support act0 ->
  planner pick act0 = Infeasible ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof. intros. eapply rounds_infeasible; eauto. Qed.

(** Theorem 3, completeness: if some path of feasible moves (over all joints) leads from
    the start to a goal state, the planner returns a plan. *)
Theorem planner_complete : forall pick act0 ms k,
  valid sizes start -> parents_first -> blockers_contract ->
  ancestor_closed act0 -> goal_support act0 ->
  path sizes all_joints feasible start ms k -> goal k = true ->
  exists p, planner pick act0 = Solved p.
Proof.
  intros pick act0 ms k Hs Hpf Hcon Hac Hgs Hp Hg.
  destruct (planner pick act0) as [p| |] eqn:H; [eauto| |].
  - exfalso. pose proof (planner_infeasible_sound pick act0 ms k Hs Hpf Hcon Hac Hgs H Hp).
    congruence.
  - exfalso. exact (planner_terminates pick act0 H).
Qed.

(** The planner decides whether a plan exists in the full lattice. *)
Corollary planner_correct : forall pick act0,
  valid sizes start -> parents_first -> blockers_contract ->
  ancestor_closed act0 -> goal_support act0 ->
  (exists p, planner pick act0 = Solved p)
  <-> (exists ms k, path sizes all_joints feasible start ms k /\ goal k = true).
Proof.
  intros pick act0 Hs Hpf Hcon Hac Hgs. split.
  - intros [p Hp]. destruct (planner_sound pick act0 p Hs Hp) as [k Hk]. eauto.
  - intros [ms [k [Hp Hg]]]. eapply planner_complete; eauto.
Qed.

End Rounds.
