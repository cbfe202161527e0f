(** * Reduction: the search's partial-order reduction — sound and complete.

    Models [Interaction::reduced_component] (src/task/interaction.rs) and its use in
    [push_moves] (src/task/search/expand.rs, [reduced_joints]): in a state [k] whose goal is
    unmet, the search pushes only
    the moves of the joints of [C k], the component (in the dependence graph [dep]) of one
    unmet goal joint; the other moves are pruned (a stubborn set in Valmari's sense, here a
    strong stubborn set for goal reachability: a goal landmark closed under interference).

    - [dep i j]: "a move of [i] and a move of [j] may interact" ([Interaction::interacts]:
      sweep contexts (ancestors, subtree, parts within reach), and floor footprints — the
      base-pose check reads the occupancy, so every joint whose parts block floor cells at
      some lattice value interacts with every joint that has a handle);
    - [C k]: the joints whose moves the reduced search pushes in [k];
    - [reduced C feasible]: the move predicate of the reduced search: a pruned move is
      treated as an infeasible one.

    Premises (explicit):
    - [local]: the verdict of a move of joint [j] depends only on the values of [j] and of
      the joints [i] with [dep j i] (the Rust argument: every check of [Checker::evaluate]
      reads only those joints; see interaction.rs);
    - [dep_sym]: [dep] is symmetric (the Rust relation is built symmetric);
    - [dep_closed]: [C k] is closed under [dep] (a connected component is);
    - [landmark]: if [k] is not a goal state, some joint of [C k] must move before a goal
      state is reached: no state that keeps its value is a goal state (an unmet goal joint
      keeps its target unmet).

    Main results:
    - [commute_prefix]: a move of [C k] preceded by moves outside [C k] can be made first;
    - [reduction_complete]: every feasible path from a valid state to a goal state has a
      reduced counterpart (a permutation of it, so no longer), moving a joint of [C] first
      at every state;
    - [reduced_path_sound], [reduction_correct]: reduced paths are feasible paths; a goal is
      reachable with the reduction iff it is reachable without;
    - [reduced_search_run_sound], [reduced_search_run_correct]: [search_run] of Requeue.v
      run with the reduction (pruned moves as failures whose blockers are the goal joints,
      all active in every round) returns plans that are feasible paths to goal states, and
      returns a plan iff a feasible path over all joints reaches a goal state.

    Costs are not modelled: [reduction_complete] keeps the moves and only reorders them;
    whether the reordered plan costs the same is argued in interaction.rs (it does when move
    costs do not depend on where the robot stands, [travel = 0]).

    Checked on the implementation by tests/task/reduction.rs
    ([pruned_moves_commute_on_generated_kitchens]: [local] on the Rust relation, with
    [Feasibility::check]; [reduced_search_agrees_with_exhaustive_enumeration]:
    [reduced_search_run_correct] against the enumeration of brute_force.rs on scenes where
    the reduction prunes). *)

From Coq Require Import List Arith Lia Bool.
From KinScene Require Import Task.Lattice Task.Validator Task.Search Task.Rounds
  Task.Conflict Task.Requeue.
Import ListNotations.

(** ** Keys and paths *)

Lemma update_comm : forall k i j v w,
  i <> j -> update (update k i v) j w = update (update k j w) i v.
Proof.
  induction k as [|x t IH]; intros [|i] [|j] v w H; simpl; auto; try lia.
  f_equal. apply IH. lia.
Qed.

Lemma apply_comm : forall k a b,
  mv_joint a <> mv_joint b -> apply (apply k a) b = apply (apply k b) a.
Proof. intros k a b H. unfold apply. apply update_comm. exact H. Qed.

Lemma nth_apply_other : forall k m i, i <> mv_joint m -> nth i (apply k m) 0 = nth i k 0.
Proof. intros k m i H. unfold apply. apply nth_update_other. exact H. Qed.

Lemma apply_length : forall k m, length (apply k m) = length k.
Proof. intros k m. unfold apply. apply update_length. Qed.

Lemma path_app : forall sizes A f s ms u ms' t,
  path sizes A f s ms u -> path sizes A f u ms' t -> path sizes A f s (ms ++ ms') t.
Proof.
  intros sizes A f s ms u ms' t H. induction H as [k|k m ms k' Hm Hf Hp IH]; intros H';
    simpl; [exact H'|]. apply path_cons; auto.
Qed.

Lemma path_app_inv : forall sizes A f pre s a post t,
  path sizes A f s (pre ++ a :: post) t ->
  exists u, path sizes A f s pre u /\ is_move sizes A u a /\ f u a = true
    /\ path sizes A f (apply u a) post t.
Proof.
  intros sizes A f pre. induction pre as [|b pre IH]; intros s a post t H; simpl in H.
  - inversion H; subst. exists s. split; [apply path_nil|]. auto.
  - inversion H as [|k0 m0 ms0 k1 Hm Hf Hp]; subst.
    destruct (IH _ _ _ _ Hp) as [u [H1 [H2 [H3 H4]]]].
    exists u. split; [apply path_cons; auto|]. auto.
Qed.

(** A path none of whose moves is of joint [i] keeps [i]'s value. *)
Lemma path_keeps : forall sizes A f s ms t i,
  path sizes A f s ms t -> (forall m, In m ms -> mv_joint m <> i) -> nth i s 0 = nth i t 0.
Proof.
  intros sizes A f s ms t i H. induction H as [k|k m ms k' Hm Hf Hp IH]; intros Hne;
    [reflexivity|].
  rewrite <- IH by (intros m' Hm'; apply Hne; right; exact Hm').
  symmetry. apply nth_apply_other. intros E. exact (Hne m (or_introl eq_refl) (eq_sym E)).
Qed.

(** The first element of a list that satisfies [p]. *)
Lemma split_first : forall {X} (p : X -> bool) l, existsb p l = true ->
  exists pre a post, l = pre ++ a :: post /\ p a = true /\ forall b, In b pre -> p b = false.
Proof.
  intros X p l. induction l as [|x t IH]; simpl; intros H; [discriminate|].
  apply orb_true_iff in H. destruct (p x) eqn:Px.
  - exists [], x, t. split; [reflexivity|]. split; [exact Px|]. intros b [].
  - destruct H as [H|H]; [discriminate|].
    destruct (IH H) as [pre [a [post [-> [Ha Hb]]]]]. exists (x :: pre), a, post.
    split; [reflexivity|]. split; [exact Ha|]. intros b [<-|Hb']; auto.
Qed.

Section Reduction.

(** The lattice, the search's move predicate, the goal test, the dependence relation of
    joints and the reduced search's joint set per state. *)
Context (sizes : list nat) (feasible : Key -> Move -> bool) (goal : Key -> bool)
  (dep : nat -> nat -> bool) (C : Key -> JointSet).

(** The reduced search's predicate: a move outside [C k] is pruned. *)
Definition reduced (k : Key) (m : Move) : bool := C k (mv_joint m) && feasible k m.

(** ** The premises *)

Definition local : Prop :=
  forall k k' m, length k = length k' ->
    (forall i, i = mv_joint m \/ dep (mv_joint m) i = true -> nth i k 0 = nth i k' 0) ->
    feasible k m = feasible k' m.

Definition dep_sym : Prop := forall i j, dep i j = dep j i.

Definition dep_closed : Prop := forall k i j, C k i = true -> dep i j = true -> C k j = true.

Definition landmark : Prop :=
  forall k, valid sizes k -> goal k = false ->
    exists g, C k g = true /\
      forall k', valid sizes k' -> nth g k' 0 = nth g k 0 -> goal k' = false.

(** ** Commutation *)

(** Moving [a] first does not change the verdict of a move [m] that does not depend on
    [a]'s joint. *)
Lemma local_apply : forall k m a,
  local -> mv_joint a <> mv_joint m -> dep (mv_joint m) (mv_joint a) = false ->
  feasible (apply k a) m = feasible k m.
Proof.
  intros k m a Hloc Hne Hd. apply Hloc; [apply apply_length|].
  intros i [Hi|Hi]; apply nth_apply_other.
  - intros E. apply Hne. congruence.
  - intros E. subst i. congruence.
Qed.

(** A move [a] of a joint of a [dep]-closed set [D], preceded by moves of joints outside
    [D], can be made first: it is feasible at the start of the prefix, and the prefix is
    still feasible after it, ending in the same state. *)
Lemma commute_prefix : forall (D : JointSet) s pre u a,
  local -> dep_sym ->
  (forall i j, D i = true -> dep i j = true -> D j = true) ->
  path sizes all_joints feasible s pre u ->
  (forall b, In b pre -> D (mv_joint b) = false) -> D (mv_joint a) = true ->
  is_move sizes all_joints u a -> feasible u a = true ->
  is_move sizes all_joints s a /\ feasible s a = true
  /\ path sizes all_joints feasible (apply s a) pre (apply u a).
Proof.
  intros D s pre u a Hloc Hsym Hcl H.
  induction H as [k|k b ms k' Hm Hf Hp IH]; intros Hpre Ha Hmu Hfu.
  - split; [exact Hmu|]. split; [exact Hfu|]. apply path_nil.
  - destruct (IH (fun b' Hb' => Hpre b' (or_intror Hb')) Ha Hmu Hfu) as [Hm1 [Hf1 Hp1]].
    assert (Hb : D (mv_joint b) = false) by (apply Hpre; left; reflexivity).
    assert (Hne : mv_joint a <> mv_joint b) by congruence.
    assert (Hdab : dep (mv_joint a) (mv_joint b) = false).
    { destruct (dep (mv_joint a) (mv_joint b)) eqn:E; [|reflexivity].
      rewrite (Hcl _ _ Ha E) in Hb. discriminate. }
    assert (Hdba : dep (mv_joint b) (mv_joint a) = false) by (rewrite Hsym; exact Hdab).
    split; [|split].
    + destruct Hm1 as [HA [Hj [Ht Hn]]].
      split; [exact HA|]. split; [exact Hj|]. split; [exact Ht|].
      rewrite nth_apply_other in Hn by exact Hne. exact Hn.
    + rewrite (local_apply k a b Hloc (not_eq_sym Hne) Hdab) in Hf1. exact Hf1.
    + apply path_cons.
      * destruct Hm as [HA [Hj [Ht Hn]]].
        split; [exact HA|]. split; [exact Hj|]. split; [exact Ht|].
        rewrite nth_apply_other by exact (not_eq_sym Hne). exact Hn.
      * rewrite (local_apply k b a Hloc Hne Hdba). exact Hf.
      * rewrite apply_comm by exact Hne. exact Hp1.
Qed.

(** ** Completeness and soundness of the reduction *)

Theorem reduction_complete : forall n s ms t,
  local -> dep_sym -> dep_closed -> landmark ->
  length ms <= n -> valid sizes s ->
  path sizes all_joints feasible s ms t -> goal t = true ->
  exists ms' t', path sizes all_joints reduced s ms' t' /\ goal t' = true
    /\ length ms' <= length ms.
Proof.
  intros n. induction n as [|n IH]; intros s ms t Hloc Hsym Hcl Hlm Hlen Hs Hp Hg;
    (destruct (goal s) eqn:Gs;
     [exists [], s; split; [apply path_nil|]; simpl; split; [exact Gs|lia]|]).
  - destruct ms; [|simpl in Hlen; lia]. inversion Hp; subst. congruence.
  - destruct (Hlm s Hs Gs) as [g [Hgc Hgk]].
    destruct (existsb (fun m => C s (mv_joint m)) ms) eqn:Ex.
    + destruct (split_first _ ms Ex) as [pre [a [post [-> [Ha Hpre]]]]].
      destruct (path_app_inv _ _ _ _ _ _ _ _ Hp) as [u [Hpu [Hmu [Hfu Hpt]]]].
      destruct (commute_prefix (C s) s pre u a Hloc Hsym (Hcl s) Hpu Hpre Ha Hmu Hfu)
        as [Hms [Hfs Hpa]].
      assert (Hrest : path sizes all_joints feasible (apply s a) (pre ++ post) t)
        by (eapply path_app; eauto).
      assert (Hva : valid sizes (apply s a)) by (eapply apply_valid; eauto).
      rewrite app_length in Hlen. simpl in Hlen.
      assert (Hl : length (pre ++ post) <= n) by (rewrite app_length; lia).
      destruct (IH (apply s a) (pre ++ post) t Hloc Hsym Hcl Hlm Hl Hva Hrest Hg)
        as [ms' [t' [Hp' [Hg' Hl']]]].
      exists (a :: ms'), t'. split; [|split; [exact Hg'|]].
      * apply path_cons; auto. unfold reduced. rewrite Ha, Hfs. reflexivity.
      * rewrite app_length in *. simpl. lia.
    + exfalso. assert (Hkeep : nth g s 0 = nth g t 0).
      { eapply path_keeps; [exact Hp|]. intros m Hm E. subst g.
        assert (existsb (fun m => C s (mv_joint m)) ms = true)
          by (apply existsb_exists; eauto).
        congruence. }
      assert (Hvt : valid sizes t) by (eapply path_valid; eauto).
      rewrite (Hgk t Hvt (eq_sym Hkeep)) in Hg. discriminate.
Qed.

Lemma reduced_true : forall k m, reduced k m = true -> feasible k m = true.
Proof. intros k m H. unfold reduced in H. apply andb_true_iff in H. tauto. Qed.

Theorem reduced_path_sound : forall A s ms t,
  path sizes A reduced s ms t -> path sizes A feasible s ms t.
Proof.
  intros A s ms t H. induction H as [k|k m ms k' Hm Hf Hp IH]; [apply path_nil|].
  apply path_cons; auto. apply reduced_true. exact Hf.
Qed.

(** A goal state is reachable with the reduction iff it is reachable without. *)
Corollary reduction_correct : forall s,
  local -> dep_sym -> dep_closed -> landmark -> valid sizes s ->
  (exists ms t, path sizes all_joints reduced s ms t /\ goal t = true)
  <-> (exists ms t, path sizes all_joints feasible s ms t /\ goal t = true).
Proof.
  intros s Hloc Hsym Hcl Hlm Hs. split.
  - intros [ms [t [Hp Hg]]]. exists ms, t. split; [apply reduced_path_sound|]; assumption.
  - intros [ms [t [Hp Hg]]].
    destruct (reduction_complete (length ms) s ms t Hloc Hsym Hcl Hlm (le_n _) Hs Hp Hg)
      as [ms' [t' [Hp' [Hg' _]]]]. eauto.
Qed.

(** ** The reduction inside [search::run] *)

(** The parts' parents, the blockers of [Checker::evaluate], and the goal joints
    ([support]): [C k] depends only on their values (which goal targets are unmet). *)
Context (start : Key) (parent : nat -> option nat)
  (blockers : JointSet -> Key -> Move -> option (list nat)) (support : list nat).

(** A pruned move is a failure whose blockers are the goal joints (active in every round,
    so it never grows the active set: the Rust search does not push it at all). *)
Definition rblockers (act : JointSet) (k : Key) (m : Move) : option (list nat) :=
  if C k (mv_joint m) then blockers act k m else Some support.

Definition in_support (j : nat) : bool := existsb (Nat.eqb j) support.

Definition C_support : Prop :=
  (forall j, In j support -> j < length sizes) /\
  forall k k', agree in_support k k' -> forall j, C k j = C k' j.

Lemma rblockers_contract :
  blockers_contract sizes feasible parent blockers -> C_support ->
  blockers_contract sizes reduced parent rblockers.
Proof.
  intros Hcon [Hsl Hsup] act k m B Hac Hk Hm Hf Hb Hin k' Hk' Ha.
  unfold reduced in *. unfold rblockers in Hb.
  destruct (C k (mv_joint m)) eqn:Ck.
  - simpl in Hf. rewrite (Hcon act k m B Hac Hk Hm Hf Hb Hin k' Hk' Ha).
    apply andb_false_r.
  - injection Hb as <-.
    assert (Hag : agree in_support k k').
    { eapply agree_mono; [|exact Ha]. intros j Hj. unfold in_support in Hj.
      apply existsb_exists in Hj. destruct Hj as [x [Hx E]]. apply Nat.eqb_eq in E.
      subst x. apply Hin; auto. }
    rewrite <- (Hsup k k' Hag (mv_joint m)), Ck. reflexivity.
Qed.

Lemma reduced_sweep_separates : forall collide,
  sweep_separates sizes feasible parent collide ->
  sweep_separates sizes reduced parent collide.
Proof.
  intros collide H k m x y Hk Hm Hf. apply H; auto. apply reduced_true. exact Hf.
Qed.

Context (b0 : bool) (pick : JointSet -> list qitem -> nat)
  (raise : JointSet -> qitem -> qconfig -> bool) (early : JointSet -> nat -> qconfig -> bool)
  (unreachable : bool) (is_goal : JointSet) (target : nat -> nat -> bool)
  (collide : body -> body -> Key -> bool) (q : Key) (contacts : list (body * body)).

(** [search::run] with the reduction. *)
Definition reduced_search_run (act0 : JointSet) : outcome :=
  search_run sizes reduced goal start parent rblockers b0 pick raise early unreachable
    is_goal target collide q contacts act0.

(** Theorem 4 with the reduction: a returned plan is a feasible path to a goal state. *)
Theorem reduced_search_run_sound : forall act0 p,
  valid sizes start -> reduced_search_run act0 = Solved p ->
  exists k, path sizes all_joints feasible start p k /\ goal k = true.
Proof.
  intros act0 p Hs H. destruct (search_run_sound _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ _ act0 p Hs H)
    as [k [Hp Hg]].
  exists k. split; [apply reduced_path_sound|]; assumption.
Qed.

(** Theorem 3 with the reduction: under the premises of [search::run] and of the
    reduction, the reduced search returns a plan iff a feasible path over all joints
    reaches a goal state (so its [Infeasible] is sound). *)
Theorem reduced_search_run_correct : forall act0,
  run_premises sizes feasible goal start parent blockers unreachable is_goal target collide
    q act0 ->
  local -> dep_sym -> dep_closed -> landmark -> C_support ->
  (exists p, reduced_search_run act0 = Solved p)
  <-> (exists ms k, path sizes all_joints feasible start ms k /\ goal k = true).
Proof.
  intros act0 Hpre Hloc Hsym Hcl Hlm Hsup.
  destruct Hpre as [Hs [Hpf [Hcon [Hac [Hgs [Hun [Hsw [Hrel [Hgt Hq]]]]]]]]].
  assert (Hpre' : run_premises sizes reduced goal start parent rblockers unreachable is_goal
                    target collide q act0).
  { repeat split; auto.
    - apply rblockers_contract; auto.
    - intros Hu ms k Hp. apply (Hun Hu ms k). apply reduced_path_sound. exact Hp.
    - apply reduced_sweep_separates. exact Hsw. }
  rewrite <- (reduction_correct start Hloc Hsym Hcl Hlm Hs).
  apply search_run_correct. exact Hpre'.
Qed.

End Reduction.
