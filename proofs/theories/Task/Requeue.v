(** * Requeue: the round with the move re-queue and early growth, and the whole
    [search::run] with its static pre-checks (theorems 3 and 4 for the current code).

    Search.v models a round in which every popped move is evaluated at once, and Rounds.v
    rounds that run until exhausted. The Rust round (src/task/search/, [run]) does two more
    things, modelled here:
    - THE MOVE RE-QUEUE. An [Item::Edge] carries a flag [bounded]; edges are pushed with
      [bounded = (settings.cost.travel == 0.0)] ([b0] here). When an unbounded edge whose
      target is not closed is popped, its priority is tightened with
      [Checker::move_bound]; if the new key exceeds the popped one ([f > entry.f + 1e-9]) the
      same move is pushed back with [bounded: true] (same [from], [joint], [to], [g]) and not
      evaluated now; otherwise it is evaluated at once. [QEdge k p m b] is the edge with its
      flag; [qrequeue] pushes it back bounded; [qprocess] is Search.v's [process]; [qstep]
      pops ANY item and applies EITHER ([qpop r], [r] = "the tightened key is larger"), so
      every result holds whatever the bounds, the keys and the heap order are. The parallel
      sweep prefetch only peeks at the next open items (no effect in the model).
    - EARLY GROWTH. Every [GROW_CHECK] node pops (from [GROW_CHECK·2^(r−1)] on in round [r])
      the round computes the blockers of its deferred failures and leaves the [while] loop
      when some failure names a joint outside the active set, or one has unknown blockers and
      not every joint is active. In both cases [grow] over all the round's failures adds a
      joint, so the next round is larger. [qrun]'s [stop n c] (after [n] pops) models the
      break; the planner's [round_stop] is [early act n c && grows act (failed c)] with
      [early] arbitrary (the Rust counter test is a function of [n] in a deterministic run):
      a round stops early only if it will grow.
    - [search_run] is the whole of [search::run]: the two static proofs of infeasibility
      (an unreachable goal target, abstract here; the goal-conflict pre-check of Conflict.v)
      and then the rounds.

    Assumptions: those of Search.v and Rounds.v (feasibility a function of state and move,
    [blockers_contract], [goal_support act0], [ancestor_closed act0], [parents_first],
    [valid sizes start], no [Termination]), those of Conflict.v for the goal-conflict
    pre-check, and [unreachable_sound]: when [Heuristic::unreachable_targets] is non-empty
    (a goal joint whose final-move set [C_j] is empty) no feasible path reaches a goal state
    — argued in src/task/heuristic.rs, NOT proved here. Costs, keys and the heuristic are
    not modelled: they choose [pick] and [raise] only.

    Main results:
    - [qreach_sim]: every configuration the round with re-queue reaches is simulated by a
      configuration Search.v's round reaches: same closed set, failures and result, and the
      same pending moves up to order and flags (a re-queue is a stutter step of Search.v);
    - [qmeasure_decreases], [qsearch_terminates]: every step decreases
      [(3·Σ|L_j| + 2)·(unclosed states) + 3·(unbounded edges) + 2·(bounded edges) + nodes],
      so a move is re-queued at most once and every run ends (plan, nothing pending, or an
      early stop);
    - [qsearch_sound] (theorem 4), [qexhausted_round] and [qsearch_complete] /
      [qsearch_correct] (theorem 3): a round with re-queue returns only feasible paths to goal
      states, and an exhausted round is closed under feasible active moves: the re-queue loses
      no move, so completeness is kept;
    - [no_requeue_without_travel]: with [b0 = true] ([travel = 0]) no item is ever re-queued:
      the round is Search.v's;
    - [qplanner_terminates], [qplanner_sound], [qplanner_infeasible_sound],
      [qplanner_complete], [qplanner_correct]: the rounds with re-queue and early growth
      decide plan existence over the full lattice (an early-stopped round never reports
      [Infeasible]);
    - [search_run_sound], [search_run_infeasible_sound], [search_run_correct]: the same for
      [search::run] with its static pre-checks.

    Checked on the implementation by: tests/task/brute_force.rs
    [search_agrees_with_exhaustive_enumeration] (with [travel = 0], so with the pre-checks
    and early growth, not the re-queue) and tests/task/validate.rs
    [search_and_random_plans_validate_on_generated_kitchens] (default settings,
    [travel > 0]: the re-queue is exercised; every returned plan validates). *)

From Coq Require Import List Arith Lia Bool Permutation.
From KinScene Require Import Task.Lattice Task.Validator Task.Search Task.Rounds
  Task.Conflict.
Import ListNotations.

(** Heap items: [Item::Node], and [Item::Edge] with its [bounded] flag. *)
Inductive qitem : Type :=
  | QNode (k : Key) (p : list Move)
  | QEdge (k : Key) (p : list Move) (m : Move) (bounded : bool).

Record qconfig := mkQ {
  qclosed : list Key;
  qwork : list qitem;
  qfailed : list (Key * Move);
  qfound : option (list Move) }.

(** Forgets the flag: the item of Search.v. *)
Definition erase (it : qitem) : item :=
  match it with
  | QNode k p => Node k p
  | QEdge k p m _ => Edge k p m
  end.

(** Removes item number [i] of [l] (the first if [i] is out of range), as [extract]. *)
Fixpoint qextract (i : nat) (l : list qitem) : option (qitem * list qitem) :=
  match l with
  | [] => None
  | x :: t =>
      match i with
      | 0 => Some (x, t)
      | S i' =>
          match qextract i' t with
          | Some (y, r) => Some (y, x :: r)
          | None => Some (x, t)
          end
      end
  end.

Lemma qextract_split : forall i l it rest,
  qextract i l = Some (it, rest) -> exists l1 l2, l = l1 ++ it :: l2 /\ rest = l1 ++ l2.
Proof.
  intros i l. revert i. induction l as [|x t IH]; intros [|i] it rest H; simpl in H;
    try discriminate.
  - injection H as <- <-. exists [], t. auto.
  - destruct (qextract i t) as [[y r]|] eqn:He.
    + injection H as <- <-. destruct (IH i y r He) as [l1 [l2 [-> ->]]].
      exists (x :: l1), l2. auto.
    + injection H as <- <-. exists [], t. auto.
Qed.

Lemma qextract_none : forall i l, qextract i l = None -> l = [].
Proof.
  intros i [|x t] H; [reflexivity|].
  destruct i; simpl in H; [discriminate|]. destruct (qextract i t) as [[y r]|]; discriminate.
Qed.

(** Pending nodes count 1, bounded edges 2, unbounded edges 3. *)
Fixpoint qweight (w : list qitem) : nat :=
  match w with
  | [] => 0
  | QNode _ _ :: t => 1 + qweight t
  | QEdge _ _ _ b :: t => (if b then 2 else 3) + qweight t
  end.

Lemma qweight_app : forall l1 l2, qweight (l1 ++ l2) = qweight l1 + qweight l2.
Proof. induction l1 as [|[k p|k p m [|]] t IH]; intros l2; simpl; try rewrite IH; lia. Qed.

Lemma qweight_edges : forall k p b ms,
  qweight (map (fun m => QEdge k p m b) ms) <= 3 * length ms.
Proof. intros k p b ms. induction ms as [|m t IH]; simpl; [lia|]. destruct b; lia. Qed.

Section Round.

(** As in Search.v, and [b0]: the flag new edges get ([settings.cost.travel == 0.0]). *)
Context (sizes : list nat) (A : JointSet) (feasible : Key -> Move -> bool)
  (goal : Key -> bool) (start : Key) (b0 : bool).

Definition qinit : qconfig := mkQ [] [QNode start []] [] None.

(** The edges pushed when [k] is closed, with the flag [b0]. *)
Definition qedges (k : Key) (p : list Move) (cl : list Key) : list qitem :=
  map (fun m => QEdge k p m b0) (filter (fun m => negb (mem (apply k m) cl)) (moves sizes A k)).

(** One iteration that evaluates what it pops (Search.v's [process]; the flag is ignored). *)
Definition qprocess (it : qitem) (rest : list qitem) (c : qconfig) : qconfig :=
  match it with
  | QNode k p =>
      if mem k (qclosed c) then mkQ (qclosed c) rest (qfailed c) None
      else if goal k then mkQ (k :: qclosed c) rest (qfailed c) (Some p)
      else mkQ (k :: qclosed c) (rest ++ qedges k p (k :: qclosed c)) (qfailed c) None
  | QEdge k p m _ =>
      if mem (apply k m) (qclosed c) then mkQ (qclosed c) rest (qfailed c) None
      else if feasible k m
      then mkQ (qclosed c) (rest ++ [QNode (apply k m) (p ++ [m])]) (qfailed c) None
      else mkQ (qclosed c) rest ((k, m) :: qfailed c) None
  end.

(** The re-queue: an unbounded edge whose target is not closed goes back, bounded, without
    being evaluated; every other item is processed as usual. *)
Definition qrequeue (it : qitem) (rest : list qitem) (c : qconfig) : qconfig :=
  match it with
  | QEdge k p m false =>
      if mem (apply k m) (qclosed c) then qprocess it rest c
      else mkQ (qclosed c) (rest ++ [QEdge k p m true]) (qfailed c) None
  | _ => qprocess it rest c
  end.

(** [r]: the tightened key of a popped unbounded edge exceeds the popped key. *)
Definition qpop (r : bool) : qitem -> list qitem -> qconfig -> qconfig :=
  if r then qrequeue else qprocess.

(** Pop any pending item; re-queue it or process it. *)
Inductive qstep : qconfig -> qconfig -> Prop :=
  | qstep_pick : forall c l1 it l2 r,
      qfound c = None -> qwork c = l1 ++ it :: l2 -> qstep c (qpop r it (l1 ++ l2) c).

Inductive qreach : qconfig -> Prop :=
  | qreach_init : qreach qinit
  | qreach_step : forall c c', qreach c -> qstep c c' -> qreach c'.

(** ** Simulation by Search.v's round *)

(** Same closed set, failures and result; the same pending items up to order and flags. *)
Definition sim (c : qconfig) (c0 : config) : Prop :=
  qclosed c = closed c0 /\ qfailed c = failed c0 /\ qfound c = found c0
  /\ Permutation (map erase (qwork c)) (work c0).

Lemma erase_qedges : forall k p cl, map erase (qedges k p cl) = edges sizes A k p cl.
Proof. intros k p cl. unfold qedges, edges. rewrite map_map. reflexivity. Qed.

Lemma qprocess_sim : forall it rest c rest0 c0,
  qclosed c = closed c0 -> qfailed c = failed c0 -> Permutation (map erase rest) rest0 ->
  sim (qprocess it rest c) (process sizes A feasible goal (erase it) rest0 c0).
Proof.
  intros it rest c rest0 c0 Hc Hf Hp.
  destruct it as [k p|k p m b]; unfold qprocess, process; simpl; rewrite Hc, Hf.
  - destruct (mem k (closed c0)); [repeat split; simpl; auto|].
    destruct (goal k); repeat split; simpl; auto.
    rewrite map_app, erase_qedges. apply Permutation_app_tail. exact Hp.
  - destruct (mem (apply k m) (closed c0)); [repeat split; simpl; auto|].
    destruct (feasible k m); repeat split; simpl; auto.
    rewrite map_app. simpl. apply Permutation_app_tail. exact Hp.
Qed.

(** A step is a step of Search.v's round, or (a re-queue) leaves its image unchanged. *)
Lemma qstep_sim : forall c c0 c',
  sim c c0 -> qstep c c' ->
  sim c' c0 \/ exists c0', step sizes A feasible goal c0 c0' /\ sim c' c0'.
Proof.
  intros c c0 c' [Hc [Hfl [Hfo Hp]]] Hstep.
  destruct Hstep as [c l1 it l2 r Hf Hw].
  rewrite Hw, map_app in Hp. simpl in Hp.
  assert (Hin : In (erase it) (work c0)).
  { eapply Permutation_in; [exact Hp|]. apply in_or_app. right. left. reflexivity. }
  apply in_split in Hin. destruct Hin as [w1 [w2 Hw0]].
  rewrite Hw0 in Hp. apply Permutation_app_inv in Hp. rewrite <- map_app in Hp.
  assert (Hproc : exists c0', step sizes A feasible goal c0 c0'
                              /\ sim (qprocess it (l1 ++ l2) c) c0').
  { exists (process sizes A feasible goal (erase it) (w1 ++ w2) c0). split.
    - apply step_pick; [congruence|exact Hw0].
    - apply qprocess_sim; assumption. }
  destruct r; simpl; [|right; exact Hproc].
  destruct it as [k p|k p m [|]]; simpl; try (right; exact Hproc).
  destruct (mem (apply k m) (qclosed c)) eqn:Hm.
  { right. unfold qprocess in Hproc. rewrite Hm in Hproc. exact Hproc. }
  (* The re-queue proper: the same edge, now bounded, at the end of the heap. *)
  left. simpl in Hw0. unfold sim; simpl. repeat split; try congruence.
  rewrite Hw0, map_app. simpl.
  eapply perm_trans; [apply Permutation_app_comm|]. simpl.
  eapply perm_trans; [apply perm_skip; exact Hp|].
  apply Permutation_middle.
Qed.

Theorem qreach_sim : forall c,
  qreach c -> exists c0, reach sizes A feasible goal start c0 /\ sim c c0.
Proof.
  intros c H. induction H as [|c c' Hr IH Hstep].
  - exists (init start). split; [apply reach_init|]. repeat split; simpl; auto.
  - destruct IH as [c0 [Hr0 Hs]].
    destruct (qstep_sim c c0 c' Hs Hstep) as [H|[c0' [H1 H2]]].
    + exists c0. auto.
    + exists c0'. split; [eapply reach_step; eauto|exact H2].
Qed.

(** ** Soundness and completeness (theorems 3 and 4, one round) *)

Theorem qsearch_sound : forall c p,
  valid sizes start -> qreach c -> qfound c = Some p ->
  exists k, path sizes A feasible start p k /\ goal k = true.
Proof.
  intros c p Hs Hr Hf. destruct (qreach_sim c Hr) as [c0 [Hr0 [_ [_ [Hfo _]]]]].
  eapply search_sound; eauto. congruence.
Qed.

Lemma qwork_nil : forall c c0, sim c c0 -> qwork c = [] -> work c0 = [].
Proof.
  intros c c0 [_ [_ [_ Hp]]] Hw. rewrite Hw in Hp. apply Permutation_nil. exact Hp.
Qed.

(** An exhausted round with re-queue has the properties of Search.v's [exhausted_round]. *)
Theorem qexhausted_round : forall c,
  valid sizes start -> qreach c -> qfound c = None -> qwork c = [] ->
  In start (qclosed c)
  /\ (forall k, In k (qclosed c) -> valid sizes k /\ goal k = false)
  /\ (forall k, In k (qclosed c) -> forall m, is_move sizes A k m ->
        In (apply k m) (qclosed c) \/ In (k, m) (qfailed c))
  /\ (forall k m, In (k, m) (qfailed c) ->
        valid sizes k /\ is_move sizes A k m /\ feasible k m = false).
Proof.
  intros c Hs Hr Hf Hw. destruct (qreach_sim c Hr) as [c0 [Hr0 Hsim]].
  pose proof (qwork_nil c c0 Hsim Hw) as Hw0.
  destruct Hsim as [Hc [Hfl [Hfo _]]]. rewrite Hc, Hfl.
  apply exhausted_round; auto. congruence.
Qed.

(** ** Termination *)

(** [(3·Σ|L_j| + 2)·(unclosed states) + 3·(unbounded edges) + 2·(bounded) + (nodes)]. *)
Definition qmeasure (c : qconfig) : nat :=
  (3 * move_bound sizes + 2) * unclosed sizes (qclosed c) + qweight (qwork c).

Lemma qitem_ok : forall c it,
  valid sizes start -> qreach c -> In it (qwork c) -> item_ok sizes A feasible start (erase it).
Proof.
  intros c it Hs Hr Hin. destruct (qreach_sim c Hr) as [c0 [Hr0 [_ [_ [_ Hp]]]]].
  destruct (reach_inv sizes A feasible goal start c0 Hs Hr0) as [Hwork _].
  apply Hwork. eapply Permutation_in; [exact Hp|]. apply in_map. exact Hin.
Qed.

Lemma qprocess_measure : forall it rest c,
  item_ok sizes A feasible start (erase it) ->
  qmeasure (qprocess it rest c)
  < (3 * move_bound sizes + 2) * unclosed sizes (qclosed c) + (qweight [it] + qweight rest).
Proof.
  intros it rest c Hit. unfold qmeasure.
  set (B := 3 * move_bound sizes + 2).
  destruct it as [k p|k p m b]; simpl in Hit |- *.
  - destruct Hit as [Hk _].
    destruct (mem k (qclosed c)) eqn:Hmem; simpl; [lia|].
    apply mem_false in Hmem.
    pose proof (unclosed_cons_lt sizes k (qclosed c) Hk Hmem) as Hu.
    assert (HB : B * unclosed sizes (k :: qclosed c) + B <= B * unclosed sizes (qclosed c)).
    { rewrite <- Nat.mul_succ_r. apply Nat.mul_le_mono_l. lia. }
    destruct (goal k); simpl; rewrite ?qweight_app; [lia|].
    unfold qedges.
    pose proof (qweight_edges k p b0
                  (filter (fun m => negb (mem (apply k m) (k :: qclosed c)))
                     (moves sizes A k))) as He.
    pose proof (filter_length_le (fun m => negb (mem (apply k m) (k :: qclosed c)))
                  (moves sizes A k)) as Hle.
    pose proof (moves_length sizes A k). unfold B in *. lia.
  - destruct (mem (apply k m) (qclosed c)); simpl; [destruct b; lia|].
    destruct (feasible k m); simpl; rewrite ?qweight_app; simpl; destruct b; lia.
Qed.

Theorem qmeasure_decreases : forall c c',
  valid sizes start -> qreach c -> qstep c c' -> qmeasure c' < qmeasure c.
Proof.
  intros c c' Hs Hr Hstep. revert Hr. destruct Hstep as [c l1 it l2 r Hf Hw]. intros Hr.
  assert (Hit : item_ok sizes A feasible start (erase it)).
  { apply (qitem_ok c it Hs Hr). rewrite Hw. apply in_or_app. right. left. reflexivity. }
  assert (Hsplit : qweight (qwork c) = qweight [it] + qweight (l1 ++ l2)).
  { rewrite Hw, !qweight_app. destruct it as [k p|k p m [|]]; simpl; lia. }
  pose proof (qprocess_measure it (l1 ++ l2) c Hit) as Hp.
  unfold qmeasure at 2. rewrite Hsplit.
  destruct r; [change (qpop true) with qrequeue|exact Hp].
  destruct it as [k p|k p m [|]]; try exact Hp.
  unfold qrequeue. destruct (mem (apply k m) (qclosed c)); [exact Hp|].
  unfold qmeasure. simpl. rewrite !qweight_app. simpl. lia.
Qed.

(** The deterministic round: pops item [pick (work c)], re-queues it if [raise] says so
    (Rust: the tightened key is larger), and stops early when [stop n c] (after [n] pops). *)
Fixpoint qrun (pick : list qitem -> nat) (raise : qitem -> qconfig -> bool)
  (stop : nat -> qconfig -> bool) (fuel n : nat) (c : qconfig) : qconfig :=
  match fuel with
  | 0 => c
  | S f =>
      match qfound c with
      | Some _ => c
      | None =>
          if stop n c then c
          else match qextract (pick (qwork c)) (qwork c) with
               | None => c
               | Some (it, rest) => qrun pick raise stop f (S n) (qpop (raise it c) it rest c)
               end
      end
  end.

Definition qsearch pick raise stop : qconfig := qrun pick raise stop (qmeasure qinit) 0 qinit.

(** The round has ended: a plan, nothing pending, or an early stop. *)
Definition qended (stop : nat -> qconfig -> bool) (c : qconfig) : Prop :=
  qfound c <> None \/ qwork c = [] \/ exists n, stop n c = true.

Lemma qrun_reach : forall pick raise stop fuel n c,
  qreach c -> qreach (qrun pick raise stop fuel n c).
Proof.
  intros pick raise stop fuel. induction fuel as [|f IH]; intros n c Hr; simpl; [exact Hr|].
  destruct (qfound c) eqn:Hf; [exact Hr|]. destruct (stop n c); [exact Hr|].
  destruct (qextract (pick (qwork c)) (qwork c)) as [[it rest]|] eqn:He; [|exact Hr].
  apply IH. destruct (qextract_split _ _ _ _ He) as [l1 [l2 [Hw ->]]].
  eapply qreach_step; [exact Hr|]. apply qstep_pick; assumption.
Qed.

Lemma qrun_ended : forall pick raise stop fuel n c,
  valid sizes start -> qreach c -> qmeasure c <= fuel ->
  qended stop (qrun pick raise stop fuel n c).
Proof.
  intros pick raise stop fuel. induction fuel as [|f IH]; intros n c Hs Hr Hm; simpl.
  - right. left. unfold qmeasure in Hm.
    destruct (qwork c) as [|[k p|k p m [|]] t]; simpl in Hm; auto; lia.
  - destruct (qfound c) eqn:Hf; [left; rewrite Hf; discriminate|].
    destruct (stop n c) eqn:Hst; [right; right; exists n; exact Hst|].
    destruct (qextract (pick (qwork c)) (qwork c)) as [[it rest]|] eqn:He.
    + destruct (qextract_split _ _ _ _ He) as [l1 [l2 [Hw ->]]].
      assert (Hstep : qstep c (qpop (raise it c) it (l1 ++ l2) c))
        by (apply qstep_pick; assumption).
      pose proof (qmeasure_decreases _ _ Hs Hr Hstep).
      apply IH; [exact Hs|eapply qreach_step; eauto|lia].
    + right. left. apply qextract_none in He. exact He.
Qed.

(** Termination: for any order, any re-queue decisions and any early stops, the round ends
    with a plan, with nothing pending, or by an early stop. *)
Theorem qsearch_terminates : forall pick raise stop,
  valid sizes start -> qreach (qsearch pick raise stop) /\ qended stop (qsearch pick raise stop).
Proof.
  intros pick raise stop Hs. split.
  - apply qrun_reach. apply qreach_init.
  - apply qrun_ended; [exact Hs|apply qreach_init|lia].
Qed.

(** Completeness: a round that has ended without an early stop has returned a plan if some
    feasible path over the active joints reaches a goal state. *)
Theorem qsearch_complete : forall c ms k,
  valid sizes start -> qreach c -> (qfound c <> None \/ qwork c = []) ->
  path sizes A feasible start ms k -> goal k = true ->
  exists p, qfound c = Some p.
Proof.
  intros c ms k Hs Hr Ht Hp Hg. destruct (qreach_sim c Hr) as [c0 [Hr0 Hsim]].
  assert (Hterm : terminal c0).
  { destruct Ht as [Ht|Ht]; [left; destruct Hsim as [_ [_ [Hfo _]]]; congruence|].
    right. exact (qwork_nil c c0 Hsim Ht). }
  destruct (search_complete sizes A feasible goal start c0 ms k Hs Hr0 Hterm Hp Hg) as [p Hf].
  exists p. destruct Hsim as [_ [_ [Hfo _]]]. congruence.
Qed.

(** Without early stops the round decides plan existence over the active joints, whatever
    it re-queues. *)
Corollary qsearch_correct : forall pick raise,
  valid sizes start ->
  (exists p, qfound (qsearch pick raise (fun _ _ => false)) = Some p)
  <-> (exists ms k, path sizes A feasible start ms k /\ goal k = true).
Proof.
  intros pick raise Hs.
  destruct (qsearch_terminates pick raise (fun _ _ => false) Hs) as [Hr Ht]. split.
  - intros [p Hp]. destruct (qsearch_sound _ p Hs Hr Hp) as [k Hk]. eauto.
  - intros [ms [k [Hp Hg]]]. eapply qsearch_complete; eauto.
    destruct Ht as [H|[H|[n H]]]; auto. discriminate.
Qed.

(** ** Without travel cost nothing is re-queued *)

Definition all_bounded (c : qconfig) : Prop :=
  forall k p m b, In (QEdge k p m b) (qwork c) -> b = true.

Lemma qrequeue_bounded : forall it rest c,
  (match it with QEdge _ _ _ b => b = true | QNode _ _ => True end) ->
  qrequeue it rest c = qprocess it rest c.
Proof. intros [k p|k p m b] rest c H; simpl; [reflexivity|]. subst b. reflexivity. Qed.

(** With [b0 = true] every pending edge is bounded, so every step processes what it pops:
    the round is Search.v's round (its configurations are Search.v's, flags aside). *)
Theorem no_requeue_without_travel : forall c,
  b0 = true -> qreach c ->
  all_bounded c
  /\ forall l1 it l2 r, qwork c = l1 ++ it :: l2 ->
       qpop r it (l1 ++ l2) c = qprocess it (l1 ++ l2) c.
Proof.
  intros c Hb H.
  assert (Hall : all_bounded c).
  { induction H as [|c c' Hr IH Hstep].
    - intros k p m b [He|[]]. discriminate.
    - destruct Hstep as [c l1 it l2 r Hf Hw].
      assert (Hit : match it with QEdge _ _ _ b => b = true | QNode _ _ => True end).
      { destruct it as [k p|k p m b]; [exact I|]. apply (IH k p m b). rewrite Hw.
        apply in_or_app. right. left. reflexivity. }
      assert (Hrest : forall k p m b, In (QEdge k p m b) (l1 ++ l2) -> b = true).
      { intros k p m b Hin. apply (IH k p m b). rewrite Hw. apply in_unpick. exact Hin. }
      assert (Hq : qpop r it (l1 ++ l2) c = qprocess it (l1 ++ l2) c)
        by (destruct r; simpl; [apply qrequeue_bounded; exact Hit|reflexivity]).
      rewrite Hq. intros k p m b Hin.
      destruct it as [k0 p0|k0 p0 m0 b1]; unfold qprocess in Hin.
      + destruct (mem k0 (qclosed c)); [exact (Hrest k p m b Hin)|].
        destruct (goal k0); [exact (Hrest k p m b Hin)|].
        simpl in Hin. apply in_app_or in Hin as [Hin|Hin]; [exact (Hrest k p m b Hin)|].
        unfold qedges in Hin. apply in_map_iff in Hin. destruct Hin as [m1 [He _]].
        injection He as _ _ _ <-. exact Hb.
      + destruct (mem (apply k0 m0) (qclosed c)); [exact (Hrest k p m b Hin)|].
        destruct (feasible k0 m0); simpl in Hin; [|exact (Hrest k p m b Hin)].
        apply in_app_or in Hin as [Hin|[He|[]]]; [exact (Hrest k p m b Hin)|discriminate]. }
  split; [exact Hall|]. intros l1 it l2 r Hw. destruct r; [|reflexivity]. simpl.
  apply qrequeue_bounded. destruct it as [k p|k p m b]; [exact I|].
  apply (Hall k p m b). rewrite Hw. apply in_or_app. right. left. reflexivity.
Qed.

End Round.

(** ** The rounds with re-queue and early growth, and [search::run] *)

Section Planner.

(** As in Rounds.v; [b0] as above; per active set, the pop order [pick], the re-queue
    decisions [raise] and the early-growth test [early] (all arbitrary). For the pre-checks:
    [unreachable] ([Heuristic::unreachable_targets] is non-empty), and the data of
    Conflict.v ([is_goal], [target], [collide], the state [q] and the candidate [contacts]
    of [collisions] at [q]). *)
Context (sizes : list nat) (feasible : Key -> Move -> bool) (goal : Key -> bool)
  (start : Key) (parent : nat -> option nat)
  (blockers : JointSet -> Key -> Move -> option (list nat)) (b0 : bool)
  (pick : JointSet -> list qitem -> nat) (raise : JointSet -> qitem -> qconfig -> bool)
  (early : JointSet -> nat -> qconfig -> bool).

(** [grow] adds a joint. *)
Definition grows (act : JointSet) (fl : list (Key * Move)) : bool :=
  match grow sizes parent blockers act fl with Some _ => true | None => false end.

(** The round leaves its loop early only when its failures so far make it grow. *)
Definition round_stop (act : JointSet) (n : nat) (c : qconfig) : bool :=
  early act n c && grows act (qfailed c).

Definition round (act : JointSet) : qconfig :=
  qsearch sizes act feasible goal start b0 (pick act) (raise act) (round_stop act).

(** The outer [loop] of [search::run]. *)
Fixpoint qrounds (r : nat) (act : JointSet) : outcome :=
  match r with
  | 0 => OutOfRounds
  | S r' =>
      match qfound (round act) with
      | Some p => Solved p
      | None =>
          match grow sizes parent blockers act (qfailed (round act)) with
          | None => Infeasible
          | Some act' => qrounds r' act'
          end
      end
  end.

Definition qplanner (act0 : JointSet) : outcome := qrounds (S (length sizes)) act0.

Lemma qrounds_terminate : forall r act,
  count sizes act + r > length sizes -> qrounds r act <> OutOfRounds.
Proof.
  intros r. induction r as [|r IH]; intros act Hc; simpl.
  - pose proof (count_le sizes act). lia.
  - destruct (qfound _) as [p|]; [discriminate|].
    destruct (grow _ _ _ _ _) as [act'|] eqn:Hg; [|discriminate].
    destruct (grow_grows _ _ _ _ _ _ Hg) as [_ Hlt]. apply IH. lia.
Qed.

Theorem qplanner_terminates : forall act0, qplanner act0 <> OutOfRounds.
Proof. intros act0. apply qrounds_terminate. lia. Qed.

Lemma qrounds_sound : forall r act p,
  valid sizes start -> qrounds r act = Solved p ->
  exists k, path sizes all_joints feasible start p k /\ goal k = true.
Proof.
  intros r. induction r as [|r IH]; intros act p Hs H; simpl in H; [discriminate|].
  destruct (qfound (round act)) as [p'|] eqn:Hf.
  - injection H as <-.
    destruct (qsearch_terminates sizes act feasible goal start b0 (pick act) (raise act)
                (round_stop act) Hs) as [Hr _].
    destruct (qsearch_sound sizes act feasible goal start b0 _ p' Hs Hr Hf) as [k [Hp Hg]].
    exists k. split; [|exact Hg]. eapply path_mono; [|exact Hp]. reflexivity.
  - destruct (grow _ _ _ _ _) as [act'|]; [|discriminate]. eapply IH; eauto.
Qed.

(** Theorem 4: a [Solved] plan is a feasible path from the start to a goal state. *)
Theorem qplanner_sound : forall act0 p,
  valid sizes start -> qplanner act0 = Solved p ->
  exists k, path sizes all_joints feasible start p k /\ goal k = true.
Proof. intros. eapply qrounds_sound; eauto. Qed.

(** A round that reports no plan and does not grow was exhausted: an early stop implies
    growth. *)
Lemma round_exhausted : forall act,
  valid sizes start -> qfound (round act) = None ->
  grow sizes parent blockers act (qfailed (round act)) = None ->
  qwork (round act) = [].
Proof.
  intros act Hs Hf Hg.
  destruct (qsearch_terminates sizes act feasible goal start b0 (pick act) (raise act)
              (round_stop act) Hs) as [_ [H|[H|[n H]]]]; fold (round act) in H.
  - contradiction.
  - exact H.
  - unfold round_stop, grows in H. rewrite Hg, andb_false_r in H. discriminate.
Qed.

Lemma qrounds_infeasible : forall r act ms k,
  valid sizes start -> parents_first parent -> blockers_contract sizes feasible parent blockers ->
  ancestor_closed parent act -> goal_support sizes goal act ->
  qrounds r act = Infeasible ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof.
  intros r. induction r as [|r IH]; intros act ms k Hs Hpf Hcon Hac Hgs H Hp;
    simpl in H; [discriminate|].
  destruct (qfound (round act)) as [p|] eqn:Hf; [discriminate|].
  destruct (grow sizes parent blockers act (qfailed (round act))) as [act'|] eqn:Hg.
  - destruct (grow_grows _ _ _ _ _ _ Hg) as [Hsub _].
    apply (IH act' ms k Hs Hpf Hcon); auto.
    + eapply grow_closed; eauto.
    + eapply goal_support_mono; eauto.
  - pose proof (round_exhausted act Hs Hf Hg) as Hw.
    destruct (qsearch_terminates sizes act feasible goal start b0 (pick act) (raise act)
                (round_stop act) Hs) as [Hr _]. fold (round act) in Hr.
    destruct (qreach_sim sizes act feasible goal start b0 _ Hr) as [c0 [Hr0 Hsim]].
    pose proof (qwork_nil _ c0 Hsim Hw) as Hw0.
    destruct Hsim as [_ [Hfl [Hfo _]]].
    destruct (exhausted_round sizes act feasible goal start c0 Hs Hr0 ltac:(congruence) Hw0)
      as [_ [_ [_ Hfail]]].
    assert (Hdet := failures_determined sizes feasible parent blockers act
                      (qfailed (round act)) Hcon Hac Hg ltac:(rewrite Hfl; exact Hfail)).
    refine (projection_lemma sizes feasible goal start act c0 ms k Hs Hr0
              ltac:(congruence) Hw0 _ Hgs Hp).
    intros k0 m Hin. rewrite <- Hfl in Hin. exact (Hdet k0 m Hin).
Qed.

(** Theorem 3, the report: [Infeasible] only if no feasible path over all joints reaches a
    goal state. *)
Theorem qplanner_infeasible_sound : forall act0 ms k,
  valid sizes start -> parents_first parent -> blockers_contract sizes feasible parent blockers ->
  ancestor_closed parent act0 -> goal_support sizes goal act0 ->
  qplanner act0 = Infeasible ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof. intros. eapply qrounds_infeasible; eauto. Qed.

(** Theorem 3, completeness. *)
Theorem qplanner_complete : forall act0 ms k,
  valid sizes start -> parents_first parent -> blockers_contract sizes feasible parent blockers ->
  ancestor_closed parent act0 -> goal_support sizes goal act0 ->
  path sizes all_joints feasible start ms k -> goal k = true ->
  exists p, qplanner act0 = Solved p.
Proof.
  intros act0 ms k Hs Hpf Hcon Hac Hgs Hp Hg.
  destruct (qplanner act0) as [p| |] eqn:H; [eauto| |].
  - exfalso. pose proof (qplanner_infeasible_sound act0 ms k Hs Hpf Hcon Hac Hgs H Hp).
    congruence.
  - exfalso. exact (qplanner_terminates act0 H).
Qed.

Corollary qplanner_correct : forall act0,
  valid sizes start -> parents_first parent -> blockers_contract sizes feasible parent blockers ->
  ancestor_closed parent act0 -> goal_support sizes goal act0 ->
  (exists p, qplanner act0 = Solved p)
  <-> (exists ms k, path sizes all_joints feasible start ms k /\ goal k = true).
Proof.
  intros act0 Hs Hpf Hcon Hac Hgs. split.
  - intros [p Hp]. destruct (qplanner_sound act0 p Hs Hp) as [k Hk]. eauto.
  - intros [ms [k [Hp Hg]]]. eapply qplanner_complete; eauto.
Qed.

(** *** The whole [search::run] *)

Context (unreachable : bool) (is_goal : JointSet) (target : nat -> nat -> bool)
  (collide : body -> body -> Key -> bool) (q : Key) (contacts : list (body * body)).

(** The static proofs of infeasibility, then the rounds from [act0] (the goal joints closed
    over their ancestors). *)
Definition search_run (act0 : JointSet) : outcome :=
  if unreachable then Infeasible
  else if static_conflict sizes goal start parent is_goal target collide q contacts
  then Infeasible
  else qplanner act0.

(** The assumption on the unreachable-target test (argued in heuristic.rs, not proved). *)
Definition unreachable_sound : Prop :=
  unreachable = true ->
  forall ms k, path sizes all_joints feasible start ms k -> goal k = false.

(** The premises of every result below. *)
Definition run_premises (act0 : JointSet) : Prop :=
  valid sizes start /\ parents_first parent /\ blockers_contract sizes feasible parent blockers
  /\ ancestor_closed parent act0 /\ goal_support sizes goal act0
  /\ unreachable_sound
  /\ sweep_separates sizes feasible parent collide /\ relative_pose sizes parent collide
  /\ goal_targets sizes goal is_goal target /\ length q = length sizes.

Theorem search_run_terminates : forall act0, search_run act0 <> OutOfRounds.
Proof.
  intros act0. unfold search_run. destruct unreachable; [discriminate|].
  destruct (static_conflict _ _ _ _ _ _ _ _ _); [discriminate|]. apply qplanner_terminates.
Qed.

(** Theorem 4 for [search::run]. *)
Theorem search_run_sound : forall act0 p,
  valid sizes start -> search_run act0 = Solved p ->
  exists k, path sizes all_joints feasible start p k /\ goal k = true.
Proof.
  intros act0 p Hs H. unfold search_run in H. destruct unreachable; [discriminate|].
  destruct (static_conflict _ _ _ _ _ _ _ _ _); [discriminate|].
  eapply qplanner_sound; eauto.
Qed.

(** Theorem 3 for [search::run]: every [Infeasible] — of a pre-check or of the rounds — is
    sound for the full lattice. *)
Theorem search_run_infeasible_sound : forall act0 ms k,
  run_premises act0 -> search_run act0 = Infeasible ->
  path sizes all_joints feasible start ms k -> goal k = false.
Proof.
  intros act0 ms k [Hs [Hpf [Hcon [Hac [Hgs [Hun [Hsw [Hrel [Hgt Hq]]]]]]]]] H Hp.
  unfold search_run in H. destruct unreachable eqn:Hu; [exact (Hun Hu ms k Hp)|].
  destruct (static_conflict _ _ _ _ _ _ _ _ _) eqn:Hc.
  - eapply static_conflict_sound; eauto.
  - eapply qplanner_infeasible_sound; eauto.
Qed.

(** [search::run] returns a plan iff a feasible path over all joints reaches a goal state. *)
Corollary search_run_correct : forall act0,
  run_premises act0 ->
  (exists p, search_run act0 = Solved p)
  <-> (exists ms k, path sizes all_joints feasible start ms k /\ goal k = true).
Proof.
  intros act0 Hpre. pose proof Hpre as [Hs _]. split.
  - intros [p Hp]. destruct (search_run_sound act0 p Hs Hp) as [k Hk]. eauto.
  - intros [ms [k [Hp Hg]]].
    destruct (search_run act0) as [p| |] eqn:H; [eauto| |].
    + exfalso. pose proof (search_run_infeasible_sound act0 ms k Hpre H Hp). congruence.
    + exfalso. exact (search_run_terminates act0 H).
Qed.

End Planner.
