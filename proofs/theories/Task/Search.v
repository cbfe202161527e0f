(** * Search: one round of the lattice search terminates, is complete and sound
    (theorems 3 and 4).

    Models one round of [search::run] (src/task/search/pass.rs: [Search::round], i.e. the
    [while let Some(entry) = round.open.pop()] loop for a fixed active set [A]) as a generic
    worklist graph search:
    - [config]: the closed set ([closed: HashSet<Key>]), the pending items ([open]: edges
      and nodes), the failed evaluations of the round ([failures]) and the result;
    - [Node k p]: a state to close, reached by the plan [p] ([Item::Node]; the Rust node
      stores a parent pointer, [path_to] rebuilds [p]); [Edge k p m]: a move out of the
      closed state [k], not yet evaluated ([Item::Edge { from, joint, to }], lazy evaluation);
    - [process it rest c] is one iteration with [it] popped: a node already closed is
      skipped; otherwise it is closed, and if it satisfies the goal ([unmet == 0]) the round
      returns [Solved(path_to(node))], else one edge per successor of [moves] whose target is
      not closed is pushed. An edge whose target is closed is skipped; otherwise the move is
      evaluated ([Checker::evaluate]): feasible pushes the target node with the plan
      extended by the move, infeasible records a failure;
    - [step c c'] pops **any** pending item ([work c = l1 ++ it :: l2]): the A* order of the
      Rust heap (lowest [f], then highest [g], then oldest [seq]) is one choice among all, so
      every result below holds for A* and for any other priority order. [run pick] is the
      deterministic search that pops item number [pick (work c)] ([search pick] runs it with
      enough fuel); the Rust order is such a [pick], since the items' [f], [g] are functions
      of their plans and [seq] is their position in [work] (items are appended and removal
      keeps the order). The parallel sweep prefetch pops and re-pushes items unchanged.

    Assumptions (what the Rust code must satisfy for the model to apply):
    - [feasible k m] is the verdict (Feasible or not) of [Checker::evaluate] for move [m] in
      state [k]; it must be a function of [(k, m)] only:
      (a) the robot's position does not matter: the module docs of src/task/mod.rs — every
          node's robot cell lies in the start's free component of its state (the start cell
          does, and each move's base cell is required to be in the start component of the
          state after the move), so "reachable from the robot" ([Blocked::distances]) equals
          "in the start component" ([Blocked::component]; both use [Blocked::neighbours]);
          [Feasibility::check] evaluates with the robot at the start cell;
      (b) the memo is transparent: a memoised sweep, region, swept footprint or occupancy
          equals the value computed afresh (their keys hold every joint value the result
          depends on; for sweeps, the conservative reach-sphere contexts of reach.rs);
      (c) the [Refiner]'s verdict depends only on the state and the move (e.g.
          [NoRefinement]; a refiner that looks at [MoveContext::robot_from] or at the base
          pose chosen for the current robot position breaks (a));
      (d) the active set [A] only changes the reported blockers, not the verdict (true of
          [evaluate]: [active] is read only to compute blockers);
    - the start state is a lattice state ([valid sizes start]; [run] builds it with
      [Lattice::index_of], which holds the start value);
    - no early stop: [Termination::should_stop] (deadline, cancel flag → [Timeout]) is not
      modelled; the theorems are about runs that are not interrupted;
    - costs and the heuristic are not modelled: they only choose [pick].

    Main results:
    - [measure_decreases], [search_runs_bounded] (termination): every step decreases
      [measure = (2·Σ|L_j| + 2)·(unclosed lattice states) + (2·edges + nodes pending)], so
      every run has at most [measure init] steps — the closed set only grows, and a state is
      expanded once; [search_progress]: a run stops only when a plan is found or nothing is
      pending; [search_terminates]: [search pick] ends in such a configuration;
    - [search_sound] (theorem 4): a returned plan is a path of feasible moves of active
      joints, each applied in the state it is feasible in, from the start to a goal state;
      [search_plan_validates]: it passes the validator predicate of Validator.v;
    - [exhausted_round] / [search_complete] / [search_returns_plan] (theorem 3): if the round
      ends with nothing pending and no plan, the closed set contains the start, contains no
      goal state and is closed under feasible active moves (each unexplored successor of a
      closed state is a recorded failure); hence if some path of feasible moves of active
      joints leads from the start to a goal state, the search returns a plan;
    - [search_correct]: [search pick] returns a plan iff such a path exists.

    Checked on the implementation by: tests/task/validate.rs
    [search_and_random_plans_validate_on_generated_kitchens] (every plan [task::plan] returns
    on generated kitchens passes [task::validate]: theorem 4) and
    tests/task/brute_force.rs [search_agrees_with_exhaustive_enumeration] (generated
    kitchens, [NoRefinement]: [task::plan] returns [Solved] iff an exhaustive enumeration of
    the full lattice over [Feasibility::check], with every joint movable, reaches a goal
    state; every step of a returned plan starts at the current value, is feasible in the
    state it is applied in, and the plan ends in a goal state) and its larger, ignored
    variant [brute_force_up_to_eight_joints]. *)

From Coq Require Import List Arith Lia Bool.
From KinScene Require Import Task.Lattice Task.Validator.
Import ListNotations.

(** Pending work: [Item::Node] and [Item::Edge], with the plan that reached the state. *)
Inductive item : Type :=
  | Node (k : Key) (p : list Move)
  | Edge (k : Key) (p : list Move) (m : Move).

Record config := mkConfig {
  closed : list Key;
  work : list item;
  failed : list (Key * Move);
  found : option (list Move) }.

(** Removes item number [i] of [l] (the first if [i] is out of range). *)
Fixpoint extract (i : nat) (l : list item) : option (item * list item) :=
  match l with
  | [] => None
  | x :: t =>
      match i with
      | 0 => Some (x, t)
      | S i' =>
          match extract i' t with
          | Some (y, r) => Some (y, x :: r)
          | None => Some (x, t)
          end
      end
  end.

Lemma extract_split : forall i l it rest,
  extract i l = Some (it, rest) -> exists l1 l2, l = l1 ++ it :: l2 /\ rest = l1 ++ l2.
Proof.
  intros i l. revert i. induction l as [|x t IH]; intros [|i] it rest H; simpl in H;
    try discriminate.
  - injection H as <- <-. exists [], t. auto.
  - destruct (extract i t) as [[y r]|] eqn:He.
    + injection H as <- <-. destruct (IH i y r He) as [l1 [l2 [-> ->]]].
      exists (x :: l1), l2. auto.
    + injection H as <- <-. exists [], t. auto.
Qed.

Lemma extract_none : forall i l, extract i l = None -> l = [].
Proof.
  intros i [|x t] H; [reflexivity|].
  destruct i; simpl in H; [discriminate|]. destruct (extract i t) as [[y r]|]; discriminate.
Qed.

Lemma in_pick : forall {X} (x it : X) l1 l2, In x (l1 ++ it :: l2) -> x = it \/ In x (l1 ++ l2).
Proof.
  intros X x it l1 l2 H. apply in_app_or in H as [H|[H|H]]; auto using in_or_app.
Qed.

Lemma in_unpick : forall {X} (x it : X) l1 l2, In x (l1 ++ l2) -> In x (l1 ++ it :: l2).
Proof.
  intros X x it l1 l2 H. apply in_app_or in H as [H|H]; apply in_or_app; simpl; auto.
Qed.

(** ** Measure helpers *)

Fixpoint weight (w : list item) : nat :=
  match w with
  | [] => 0
  | Node _ _ :: t => 1 + weight t
  | Edge _ _ _ :: t => 2 + weight t
  end.

Lemma weight_app : forall l1 l2, weight (l1 ++ l2) = weight l1 + weight l2.
Proof. induction l1 as [|[k p|k p m] t IH]; intros l2; simpl; try rewrite IH; lia. Qed.

Lemma weight_edges : forall k p ms, weight (map (Edge k p) ms) = 2 * length ms.
Proof. induction ms as [|m t IH]; simpl; lia. Qed.

Lemma filter_sub_le : forall {X} (f g : X -> bool) l,
  (forall x, f x = true -> g x = true) -> length (filter f l) <= length (filter g l).
Proof.
  intros X f g l Hfg. induction l as [|a t IH]; simpl; [lia|].
  destruct (f a) eqn:Fa; [rewrite (Hfg a Fa)|destruct (g a)]; simpl; lia.
Qed.

Lemma filter_sub_lt : forall {X} (f g : X -> bool) l y,
  (forall x, f x = true -> g x = true) -> In y l -> g y = true -> f y = false ->
  length (filter f l) < length (filter g l).
Proof.
  intros X f g l y Hfg. induction l as [|a t IH]; intros Hy Gy Fy; [destruct Hy|].
  simpl. destruct Hy as [<-|Hy].
  - rewrite Fy, Gy. simpl. pose proof (filter_sub_le f g t Hfg). lia.
  - specialize (IH Hy Gy Fy).
    destruct (f a) eqn:Fa; [rewrite (Hfg a Fa)|destruct (g a)]; simpl; lia.
Qed.

Section Round.

(** The lattice ([sizes]), the active joints of the round, the move predicate
    ([Checker::evaluate]), the goal test ([unmet == 0]) and the start key. *)
Context (sizes : list nat) (A : JointSet) (feasible : Key -> Move -> bool)
  (goal : Key -> bool) (start : Key).

Definition init : config := mkConfig [] [Node start []] [] None.

(** The edges pushed when [k] is closed: successors whose target is not closed. *)
Definition edges (k : Key) (p : list Move) (cl : list Key) : list item :=
  map (Edge k p) (filter (fun m => negb (mem (apply k m) cl)) (moves sizes A k)).

(** One iteration of the [while let Some(entry) = round.open.pop()] loop, [it] popped. *)
Definition process (it : item) (rest : list item) (c : config) : config :=
  match it with
  | Node k p =>
      if mem k (closed c) then mkConfig (closed c) rest (failed c) None
      else if goal k then mkConfig (k :: closed c) rest (failed c) (Some p)
      else mkConfig (k :: closed c) (rest ++ edges k p (k :: closed c)) (failed c) None
  | Edge k p m =>
      if mem (apply k m) (closed c) then mkConfig (closed c) rest (failed c) None
      else if feasible k m
      then mkConfig (closed c) (rest ++ [Node (apply k m) (p ++ [m])]) (failed c) None
      else mkConfig (closed c) rest ((k, m) :: failed c) None
  end.

(** Pop any pending item. *)
Inductive step : config -> config -> Prop :=
  | step_pick : forall c l1 it l2,
      found c = None -> work c = l1 ++ it :: l2 -> step c (process it (l1 ++ l2) c).

Inductive reach : config -> Prop :=
  | reach_init : reach init
  | reach_step : forall c c', reach c -> step c c' -> reach c'.

Inductive steps : nat -> config -> config -> Prop :=
  | steps_0 : forall c, steps 0 c c
  | steps_S : forall n c c' c'', step c c' -> steps n c' c'' -> steps (S n) c c''.

(** The round has ended: a plan was found, or the heap is empty (exhausted). *)
Definition terminal (c : config) : Prop := found c <> None \/ work c = [].

(** ** The invariant *)

Definition item_ok (it : item) : Prop :=
  match it with
  | Node k p => valid sizes k /\ path sizes A feasible start p k
  | Edge k p m => valid sizes k /\ is_move sizes A k m /\ path sizes A feasible start p k
  end.

(** Every successor of a closed state is closed, pending, or a recorded failure. *)
Definition covered (c : config) (k : Key) (m : Move) : Prop :=
  In (apply k m) (closed c) \/ (exists p, In (Edge k p m) (work c))
  \/ (exists p, In (Node (apply k m) p) (work c)) \/ In (k, m) (failed c).

Definition frontier (c : config) : Prop :=
  forall k, In k (closed c) -> forall m, is_move sizes A k m -> covered c k m.

Definition start_ok (c : config) : Prop :=
  In start (closed c) \/ exists p, In (Node start p) (work c).

Definition inv (c : config) : Prop :=
  (forall it, In it (work c) -> item_ok it)
  /\ (forall p, found c = Some p -> exists k, path sizes A feasible start p k /\ goal k = true)
  /\ (forall k m, In (k, m) (failed c) ->
        valid sizes k /\ is_move sizes A k m /\ feasible k m = false)
  /\ (found c = None ->
        (forall k, In k (closed c) -> valid sizes k /\ goal k = false)
        /\ start_ok c /\ frontier c).

Lemma inv_init : valid sizes start -> inv init.
Proof.
  intros Hs. unfold inv, init; simpl. split; [|split; [|split]].
  - intros it [<-|[]]. simpl. split; [exact Hs|apply path_nil].
  - intros p H. discriminate.
  - intros k m [].
  - intros _. split; [|split].
    + intros k [].
    + right. exists []. left. reflexivity.
    + intros k [].
Qed.

(** The frontier survives an iteration that keeps the closed set, the failures and every
    other pending item, and discharges the popped item's obligations. *)
Lemma frontier_keep : forall c c' it,
  frontier c ->
  (forall k, In k (closed c) -> In k (closed c')) ->
  (forall x, In x (failed c) -> In x (failed c')) ->
  (forall x, In x (work c) -> x = it \/ In x (work c')) ->
  match it with
  | Node k _ => In k (closed c')
  | Edge k _ m =>
      In (apply k m) (closed c') \/ (exists p, In (Node (apply k m) p) (work c'))
      \/ In (k, m) (failed c')
  end ->
  (forall k, In k (closed c') -> ~ In k (closed c) -> forall m, is_move sizes A k m ->
     covered c' k m) ->
  frontier c'.
Proof.
  intros c c' it Hfr Hcl Hfl Hw Hit Hnew k Hk m Hm.
  destruct (In_dec (list_eq_dec Nat.eq_dec) k (closed c)) as [Hold|Hnot];
    [|exact (Hnew k Hk Hnot m Hm)].
  unfold covered. destruct (Hfr k Hold m Hm) as [H|[[p H]|[[p H]|H]]].
  - left. auto.
  - destruct (Hw _ H) as [<-|H'].
    + destruct Hit as [H1|[H1|H1]]; auto.
    + right. left. eauto.
  - destruct (Hw _ H) as [<-|H'].
    + left. exact Hit.
    + right. right. left. eauto.
  - right. right. right. auto.
Qed.

Lemma start_keep : forall c c' it,
  start_ok c ->
  (forall k, In k (closed c) -> In k (closed c')) ->
  (forall x, In x (work c) -> x = it \/ In x (work c')) ->
  match it with Node k _ => In k (closed c') | Edge _ _ _ => True end ->
  start_ok c'.
Proof.
  intros c c' it [H|[p H]] Hcl Hw Hit; [left; auto|].
  destruct (Hw _ H) as [<-|H']; [left; exact Hit|right; eauto].
Qed.

(** [inv] of a configuration whose round goes on. *)
Lemma inv_none : forall c,
  found c = None ->
  (forall it, In it (work c) -> item_ok it) ->
  (forall k m, In (k, m) (failed c) ->
     valid sizes k /\ is_move sizes A k m /\ feasible k m = false) ->
  (forall k, In k (closed c) -> valid sizes k /\ goal k = false) ->
  start_ok c -> frontier c -> inv c.
Proof.
  intros c Hf Hw Hfl Hcl Hst Hfr. unfold inv. rewrite Hf.
  split; [exact Hw|split; [discriminate|split; [exact Hfl|auto]]].
Qed.

Lemma inv_step : forall c c', inv c -> step c c' -> inv c'.
Proof.
  intros c c' [Hwork [Hfound [Hfail Hnone]]] Hstep.
  destruct Hstep as [c l1 it l2 Hf Hw].
  destruct (Hnone Hf) as [Hcl [Hst Hfr]].
  assert (Hit : item_ok it) by (apply Hwork; rewrite Hw; apply in_or_app; simpl; auto).
  assert (Hrest : forall x, In x (l1 ++ l2) -> item_ok x)
    by (intros x Hx; apply Hwork; rewrite Hw; apply in_unpick; exact Hx).
  assert (Hsplit : forall x, In x (work c) -> x = it \/ In x (l1 ++ l2))
    by (intros x Hx; rewrite Hw in Hx; apply in_pick; exact Hx).
  assert (Hsame : forall x : Key, In x (closed c) -> In x (closed c)) by auto.
  assert (Hsamef : forall x, In x (failed c) -> In x (failed c)) by auto.
  assert (Hnonew : forall c' : config, closed c' = closed c ->
            forall k, In k (closed c') -> ~ In k (closed c) ->
            forall m, is_move sizes A k m -> covered c' k m)
    by (intros c' Hc k0 H0 H1; rewrite Hc in H0; contradiction).
  destruct it as [k p|k p m]; simpl.
  - (* A node. *)
    destruct Hit as [Hk Hp].
    destruct (mem k (closed c)) eqn:Hmem.
    + (* Already closed: skipped. *)
      apply mem_In in Hmem.
      set (c' := mkConfig (closed c) (l1 ++ l2) (failed c) None).
      apply inv_none; simpl; auto.
      * exact (start_keep c c' (Node k p) Hst Hsame Hsplit Hmem).
      * exact (frontier_keep c c' (Node k p) Hfr Hsame Hsamef Hsplit Hmem
                 (Hnonew c' eq_refl)).
    + apply mem_false in Hmem.
      destruct (goal k) eqn:Hg.
      * (* A goal state: the round returns its plan. *)
        unfold inv; simpl. split; [exact Hrest|split; [|split; [exact Hfail|discriminate]]].
        intros p' Hp'. injection Hp' as <-. eauto.
      * (* Expanded: one edge per successor whose target is not closed. *)
        set (c' := mkConfig (k :: closed c) ((l1 ++ l2) ++ edges k p (k :: closed c))
                     (failed c) None).
        assert (Hw' : forall x, In x (work c) -> x = Node k p \/ In x (work c')).
        { intros x Hx. destruct (Hsplit x Hx) as [->|H]; [auto|right; simpl].
          apply in_or_app. auto. }
        assert (Hsub : forall x, In x (closed c) -> In x (closed c'))
          by (intros x Hx; simpl; right; exact Hx).
        assert (Hin : In k (closed c')) by (simpl; left; reflexivity).
        apply inv_none; simpl; auto.
        -- intros x Hx. apply in_app_or in Hx as [Hx|Hx]; auto.
           unfold edges in Hx. apply in_map_iff in Hx. destruct Hx as [m [<- Hm]].
           apply filter_In in Hm. destruct Hm as [Hm _]. apply In_moves in Hm.
           exact (conj Hk (conj Hm Hp)).
        -- intros k0 [<-|H0]; [exact (conj Hk Hg)|apply Hcl; exact H0].
        -- exact (start_keep c c' (Node k p) Hst Hsub Hw' Hin).
        -- apply (frontier_keep c c' (Node k p) Hfr Hsub Hsamef Hw' Hin).
           intros k0 [<-|H0] Hn m Hm; [|contradiction].
           unfold covered; simpl.
           destruct (mem (apply k m) (k :: closed c)) eqn:Ht.
           ++ left. apply mem_In in Ht. exact Ht.
           ++ right. left. exists p. apply in_or_app. right.
              unfold edges. apply in_map. apply filter_In. split.
              ** apply In_moves. exact Hm.
              ** rewrite Ht. reflexivity.
  - (* An edge. *)
    destruct Hit as [Hk [Hm Hp]].
    destruct (mem (apply k m) (closed c)) eqn:Hmem.
    + (* Target closed: skipped. *)
      apply mem_In in Hmem.
      set (c' := mkConfig (closed c) (l1 ++ l2) (failed c) None).
      apply inv_none; simpl; auto.
      * exact (start_keep c c' (Edge k p m) Hst Hsame Hsplit I).
      * exact (frontier_keep c c' (Edge k p m) Hfr Hsame Hsamef Hsplit (or_introl Hmem)
                 (Hnonew c' eq_refl)).
    + destruct (feasible k m) eqn:Hfe.
      * (* Feasible: the target node is pushed with the extended plan. *)
        set (c' := mkConfig (closed c) ((l1 ++ l2) ++ [Node (apply k m) (p ++ [m])])
                     (failed c) None).
        assert (Hw' : forall x, In x (work c) -> x = Edge k p m \/ In x (work c')).
        { intros x Hx. destruct (Hsplit x Hx) as [->|H]; [auto|right; simpl].
          apply in_or_app. auto. }
        assert (Hnode : In (Node (apply k m) (p ++ [m])) (work c'))
          by (simpl; apply in_or_app; simpl; auto).
        apply inv_none; simpl; auto.
        -- intros x Hx. apply in_app_or in Hx as [Hx|[<-|[]]]; auto. simpl. split.
           ++ eapply apply_valid; eauto.
           ++ apply path_snoc; assumption.
        -- exact (start_keep c c' (Edge k p m) Hst Hsame Hw' I).
        -- exact (frontier_keep c c' (Edge k p m) Hfr Hsame Hsamef Hw'
                    (or_intror (or_introl (ex_intro _ (p ++ [m]) Hnode)))
                    (Hnonew c' eq_refl)).
      * (* Infeasible: recorded as a failure of the round. *)
        set (c' := mkConfig (closed c) (l1 ++ l2) ((k, m) :: failed c) None).
        assert (Hfl : forall x, In x (failed c) -> In x (failed c'))
          by (intros x Hx; simpl; right; exact Hx).
        assert (Hnew : In (k, m) (failed c')) by (simpl; left; reflexivity).
        apply inv_none; simpl; auto.
        -- intros k0 m0 [He|H]; [injection He as <- <-; auto|apply Hfail; auto].
        -- exact (start_keep c c' (Edge k p m) Hst Hsame Hsplit I).
        -- exact (frontier_keep c c' (Edge k p m) Hfr Hsame Hfl Hsplit
                    (or_intror (or_intror Hnew)) (Hnonew c' eq_refl)).
Qed.

Lemma reach_inv : forall c, valid sizes start -> reach c -> inv c.
Proof.
  intros c Hs H. induction H as [|c c' Hr IH Hstep]; [apply inv_init; exact Hs|].
  eapply inv_step; eauto.
Qed.

(** ** Termination *)

(** Lattice states not yet closed. *)
Definition unclosed (cl : list Key) : nat :=
  length (filter (fun k => negb (mem k cl)) (all_keys sizes)).

(** [(2·Σ|L_j| + 2)·(unclosed states) + 2·(pending edges) + (pending nodes)]. *)
Definition measure (c : config) : nat :=
  (2 * move_bound sizes + 2) * unclosed (closed c) + weight (work c).

Lemma unclosed_cons_lt : forall k cl,
  valid sizes k -> ~ In k cl -> unclosed (k :: cl) < unclosed cl.
Proof.
  intros k cl Hk Hn. unfold unclosed.
  apply filter_sub_lt with (y := k).
  - intros x Hx. unfold mem in *. simpl in Hx.
    destruct (key_eqb x k); simpl in *; [discriminate|exact Hx].
  - apply all_keys_complete. exact Hk.
  - apply negb_true_iff, mem_false. exact Hn.
  - apply negb_false_iff, mem_In. left. reflexivity.
Qed.

Theorem measure_decreases : forall c c',
  valid sizes start -> reach c -> step c c' -> measure c' < measure c.
Proof.
  intros c c' Hs Hr Hstep. pose proof (reach_inv c Hs Hr) as [Hwork _].
  destruct Hstep as [c l1 it l2 Hf Hw].
  assert (Hit : item_ok it) by (apply Hwork; rewrite Hw; apply in_or_app; simpl; auto).
  unfold measure. rewrite Hw, !weight_app.
  set (B := 2 * move_bound sizes + 2).
  destruct it as [k p|k p m]; simpl.
  - destruct Hit as [Hk _].
    destruct (mem k (closed c)) eqn:Hmem; simpl; [rewrite weight_app; lia|].
    apply mem_false in Hmem.
    pose proof (unclosed_cons_lt k (closed c) Hk Hmem) as Hu.
    assert (HB : B * unclosed (k :: closed c) + B <= B * unclosed (closed c)).
    { rewrite <- Nat.mul_succ_r. apply Nat.mul_le_mono_l. lia. }
    destruct (goal k); simpl; rewrite ?weight_app; [lia|].
    unfold edges. rewrite weight_edges.
    pose proof (filter_length_le (fun m => negb (mem (apply k m) (k :: closed c)))
                  (moves sizes A k)) as Hle.
    pose proof (moves_length sizes A k). unfold B in *. lia.
  - destruct (mem (apply k m) (closed c)); simpl; [rewrite weight_app; lia|].
    destruct (feasible k m); simpl; rewrite !weight_app; simpl; lia.
Qed.

(** Every run of the round has at most [measure c] steps from [c]. *)
Theorem search_runs_bounded : forall n c c',
  valid sizes start -> reach c -> steps n c c' -> n <= measure c.
Proof.
  intros n c c' Hs Hr H. induction H as [c|n c c1 c' Hstep Hsteps IH]; [lia|].
  pose proof (measure_decreases c c1 Hs Hr Hstep).
  assert (reach c1) by (eapply reach_step; eauto). specialize (IH H0). lia.
Qed.

(** A round that has not ended can always take a step. *)
Theorem search_progress : forall c, ~ terminal c -> exists c', step c c'.
Proof.
  intros c Ht. unfold terminal in Ht.
  destruct (found c) eqn:Hf; [exfalso; apply Ht; left; discriminate|].
  destruct (work c) as [|it rest] eqn:Hw; [exfalso; apply Ht; right; reflexivity|].
  exists (process it ([] ++ rest) c). apply step_pick; [exact Hf|rewrite Hw; reflexivity].
Qed.

(** The deterministic search that pops item [pick (work c)]. *)
Fixpoint run (pick : list item -> nat) (fuel : nat) (c : config) : config :=
  match fuel with
  | 0 => c
  | S f =>
      match found c with
      | Some _ => c
      | None =>
          match extract (pick (work c)) (work c) with
          | None => c
          | Some (it, rest) => run pick f (process it rest c)
          end
      end
  end.

Definition search (pick : list item -> nat) : config := run pick (measure init) init.

Lemma run_reach : forall pick fuel c, reach c -> reach (run pick fuel c).
Proof.
  intros pick fuel. induction fuel as [|f IH]; intros c Hr; simpl; [exact Hr|].
  destruct (found c) eqn:Hf; [exact Hr|].
  destruct (extract (pick (work c)) (work c)) as [[it rest]|] eqn:He; [|exact Hr].
  apply IH. destruct (extract_split _ _ _ _ He) as [l1 [l2 [Hw ->]]].
  eapply reach_step; [exact Hr|]. apply step_pick; assumption.
Qed.

Lemma run_terminal : forall pick fuel c,
  valid sizes start -> reach c -> measure c <= fuel -> terminal (run pick fuel c).
Proof.
  intros pick fuel. induction fuel as [|f IH]; intros c Hs Hr Hm; simpl.
  - right. unfold measure in Hm. destruct (work c) as [|[k p|k p m] t]; simpl in Hm; auto; lia.
  - destruct (found c) eqn:Hf; [left; rewrite Hf; discriminate|].
    destruct (extract (pick (work c)) (work c)) as [[it rest]|] eqn:He.
    + destruct (extract_split _ _ _ _ He) as [l1 [l2 [Hw ->]]].
      assert (Hstep : step c (process it (l1 ++ l2) c)) by (apply step_pick; assumption).
      pose proof (measure_decreases _ _ Hs Hr Hstep).
      apply IH; [exact Hs|eapply reach_step; eauto|lia].
    + right. apply extract_none in He. exact He.
Qed.

(** Theorem 3, termination: for any order of popping, the search ends with a plan or with
    nothing pending. *)
Theorem search_terminates : forall pick,
  valid sizes start -> reach (search pick) /\ terminal (search pick).
Proof.
  intros pick Hs. split.
  - apply run_reach. apply reach_init.
  - apply run_terminal; [exact Hs|apply reach_init|lia].
Qed.

(** ** Soundness (theorem 4) *)

Theorem search_sound : forall c p,
  valid sizes start -> reach c -> found c = Some p ->
  exists k, path sizes A feasible start p k /\ goal k = true.
Proof.
  intros c p Hs Hr Hf. destruct (reach_inv c Hs Hr) as [_ [Hfound _]]. auto.
Qed.

(** A returned plan passes the validator, for any step check [ok] that accepts the moves the
    search's predicate accepts (in particular [ok = feasible]). *)
Theorem search_plan_validates : forall (ok : Key -> Move -> bool) c p,
  (forall k m, valid sizes k -> is_move sizes A k m -> feasible k m = true -> ok k m = true) ->
  valid sizes start -> reach c -> found c = Some p ->
  validate sizes ok goal start p = true.
Proof.
  intros ok c p Hok Hs Hr Hf. destruct (search_sound c p Hs Hr Hf) as [k [Hp Hg]].
  eapply path_validates; eauto.
Qed.

(** ** Completeness (theorem 3) *)

(** An exhausted round: the closed set holds the start and no goal state, and every
    successor of a closed state is closed or a recorded (infeasible) failure. *)
Theorem exhausted_round : forall c,
  valid sizes start -> reach c -> found c = None -> work c = [] ->
  In start (closed c)
  /\ (forall k, In k (closed c) -> valid sizes k /\ goal k = false)
  /\ (forall k, In k (closed c) -> forall m, is_move sizes A k m ->
        In (apply k m) (closed c) \/ In (k, m) (failed c))
  /\ (forall k m, In (k, m) (failed c) ->
        valid sizes k /\ is_move sizes A k m /\ feasible k m = false).
Proof.
  intros c Hs Hr Hf Hw.
  destruct (reach_inv c Hs Hr) as [_ [_ [Hfail Hnone]]].
  destruct (Hnone Hf) as [Hcl [Hst Hfr]]. unfold start_ok in Hst. rewrite Hw in Hst.
  split; [destruct Hst as [H|[p []]]; exact H|].
  split; [exact Hcl|]. split; [|exact Hfail].
  intros k Hk m Hm. destruct (Hfr k Hk m Hm) as [H|[[p H]|[[p H]|H]]]; auto;
    rewrite Hw in H; destruct H.
Qed.

Lemma closed_under_paths : forall c,
  valid sizes start -> reach c -> found c = None -> work c = [] ->
  forall k ms k', path sizes A feasible k ms k' -> In k (closed c) -> In k' (closed c).
Proof.
  intros c Hs Hr Hf Hw. destruct (exhausted_round c Hs Hr Hf Hw) as [_ [_ [Hcov Hfail]]].
  intros k ms k' H. induction H as [k|k m ms k' Hm Hfe Hp IH]; intros Hk; [exact Hk|].
  apply IH. destruct (Hcov k Hk m Hm) as [H|H]; [exact H|].
  destruct (Hfail k m H) as [_ [_ Hno]]. congruence.
Qed.

(** Theorem 3, completeness: if some path of feasible moves of active joints leads from the
    start to a goal state, every run that has ended has returned a plan. *)
Theorem search_complete : forall c ms k,
  valid sizes start -> reach c -> terminal c ->
  path sizes A feasible start ms k -> goal k = true ->
  exists p, found c = Some p.
Proof.
  intros c ms k Hs Hr Ht Hp Hg.
  destruct (found c) as [p|] eqn:Hf; [eauto|exfalso].
  destruct Ht as [Ht|Hw]; [contradiction|].
  destruct (exhausted_round c Hs Hr Hf Hw) as [Hst [Hcl _]].
  pose proof (closed_under_paths c Hs Hr Hf Hw start ms k Hp Hst) as Hk.
  destruct (Hcl k Hk) as [_ Hng]. congruence.
Qed.

Corollary search_returns_plan : forall pick ms k,
  valid sizes start -> path sizes A feasible start ms k -> goal k = true ->
  exists p, found (search pick) = Some p.
Proof.
  intros pick ms k Hs Hp Hg. destruct (search_terminates pick Hs) as [Hr Ht].
  eapply search_complete; eauto.
Qed.

(** The search decides the existence of a plan over the active joints. *)
Corollary search_correct : forall pick,
  valid sizes start ->
  (exists p, found (search pick) = Some p)
  <-> (exists ms k, path sizes A feasible start ms k /\ goal k = true).
Proof.
  intros pick Hs. split.
  - intros [p Hp]. destruct (search_terminates pick Hs) as [Hr _].
    destruct (search_sound _ p Hs Hr Hp) as [k Hk]. eauto.
  - intros [ms [k [Hp Hg]]]. eapply search_returns_plan; eauto.
Qed.

End Round.
