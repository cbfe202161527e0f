(** * RequeueKey: the key of a re-queued move is a lower bound.

    Models the priority arithmetic of the move re-queue in [search::run]
    (src/task/search/expand.rs) and [Checker::move_bound] (src/task/check/bound.rs), over
    real numbers:
    - [move_bound] is the loop of [Checker::move_bound] over the move's manipulation region:
      for each region entry [r] whose cell is free in the state before the move ([cands]),
      [near = aw·r.actuation + tw·|cell − robot|] and, only [if near < best],
      [best = min(best, near + extra(r.cell))]; [best] starts at INFINITY ([None] here);
      [extra] is [w·travel_of(next).at(cell)], the weighted travel heuristic of the state after
      the move with the robot at that cell;
    - the re-queued key is [requeue_key b = g + action + w·work(next) + b] ([g] of the node
      the move leaves, [settings.cost.action]);
    - a feasible evaluation chooses a region entry [c] of [cands] (its cell is free before the
      move: [clear] ⊆ [cands]), with base travel [travel] (a grid path, no shorter than the
      straight line [c_dist c]) and handle travel [c_act c]; it pushes the node of key
      [node_key = g + (action + aw·c_act c + tw·travel) + w·(work(next) + T)], [T] the travel
      heuristic at the chosen cell ([g + h(&next, choice.cell)]);
    - [key_after f f' eps] is the key with which the move is eventually evaluated: the
      popped key [f], or [f'] when it is re-queued ([f > entry.f + 1e-9]).

    Assumptions (explicit premises): [tw ≥ 0]; every [extra] is [≥ 0] (the travel heuristic
    is a weighted distance); the chosen entry's [extra] is [w·T]; [travel ≥ c_dist c] (grid
    paths are no shorter than straight lines between cell centres). Not modelled: f64
    rounding, and that [T] is the same function for the bound and for the node (both are
    [heuristic.travel_of(&next).at(cell)]).

    Main results:
    - [move_bound_le]: the loop's result is at most [near + extra] of every candidate (the
      [near < best] pruning is exact because [extra ≥ 0]);
    - [requeue_key_below_node]: the re-queued key is at most the key of the node that any
      feasible evaluation of the move pushes;
    - [key_after_below], [key_after_ge]: if the popped key is such a lower bound too, the key
      the move is evaluated with is one, and the re-queue never lowers a key. So the re-queue
      keeps every pending move's key below the keys of the nodes it can produce — the
      invariant a best-first (A* ) order needs for lazy evaluation; the existence of an
      optimal plan among the pushed keys is NOT proved (see the README: optimality).

    Checked on the implementation by: tests/task/validate.rs
    [search_and_random_plans_validate_on_generated_kitchens] exercises the re-queue
    ([travel > 0]); no test checks the keys. *)

From Coq Require Import Reals Lra List.
Import ListNotations.
Open Scope R_scope.

(** A region entry of [Checker::move_bound]'s loop: handle travel, straight-line distance from
    the robot's cell, and [extra] at its cell. *)
Record cand := mkCand { c_act : R; c_dist : R; c_extra : R }.

Section Bound.

(** The actuation and travel weights ([CostWeights::actuation], [CostWeights::travel]). *)
Context (aw tw : R).

Definition near (r : cand) : R := aw * c_act r + tw * c_dist r.

(** One iteration: [if near < best { best = best.min(near + extra(r.cell)) }] ([None] is
    INFINITY, which every finite [near] is below). *)
Definition bound_step (best : option R) (r : cand) : option R :=
  match best with
  | None => Some (near r + c_extra r)
  | Some b => if Rlt_dec (near r) b then Some (Rmin b (near r + c_extra r)) else Some b
  end.

Definition move_bound (cands : list cand) : option R := fold_left bound_step cands None.

(** [x] is a finite value [≤ y]. *)
Definition le_opt (x : option R) (y : R) : Prop :=
  match x with Some b => b <= y | None => False end.

Lemma bound_step_mono : forall best r y, le_opt best y -> le_opt (bound_step best r) y.
Proof.
  intros [b|] r y H; simpl in *; [|contradiction].
  destruct (Rlt_dec (near r) b); simpl; [pose proof (Rmin_l b (near r + c_extra r))|]; lra.
Qed.

Lemma bound_step_here : forall best r,
  0 <= c_extra r -> le_opt (bound_step best r) (near r + c_extra r).
Proof.
  intros [b|] r He; simpl; [|lra].
  destruct (Rlt_dec (near r) b) as [H|H]; simpl.
  - apply Rmin_r.
  - apply Rnot_lt_le in H. lra.
Qed.

Lemma fold_bound_mono : forall l acc y,
  le_opt acc y -> le_opt (fold_left bound_step l acc) y.
Proof.
  induction l as [|r t IH]; intros acc y H; simpl; [exact H|].
  apply IH. apply bound_step_mono. exact H.
Qed.

Lemma fold_bound_le : forall l acc c,
  (forall r, In r l -> 0 <= c_extra r) -> In c l ->
  le_opt (fold_left bound_step l acc) (near c + c_extra c).
Proof.
  induction l as [|r t IH]; intros acc c He Hc; [destruct Hc|]. simpl.
  destruct Hc as [<-|Hc].
  - apply fold_bound_mono. apply bound_step_here. apply He. left. reflexivity.
  - apply IH; [intros x Hx; apply He; right; exact Hx|exact Hc].
Qed.

(** The bound is finite and at most [near + extra] of every candidate. *)
Theorem move_bound_le : forall cands c,
  (forall r, In r cands -> 0 <= c_extra r) -> In c cands ->
  exists b, move_bound cands = Some b /\ b <= near c + c_extra c.
Proof.
  intros cands c He Hc. pose proof (fold_bound_le cands None c He Hc) as H.
  unfold move_bound. destruct (fold_left bound_step cands None) as [b|]; [|contradiction].
  exists b. split; [reflexivity|exact H].
Qed.

End Bound.

Section Keys.

(** [settings.cost.action], the weights, [heuristic_weight], the [g] of the node the move
    leaves and [heuristic.work(&next)]. *)
Context (action aw tw w g work_next : R).

(** [nodes[from].g + settings.cost.action + w·heuristic.work(&next) + b]. *)
Definition requeue_key (b : R) : R := g + action + w * work_next + b.

(** [g' + h(&next, choice.cell)] with [g' = g + action + aw·actuation + tw·travel] and
    [h = w·(work(next) + T)]. *)
Definition node_key (act travel T : R) : R :=
  (g + (action + aw * act + tw * travel)) + w * (work_next + T).

(** The re-queued key is at most the key of the node that a feasible evaluation of the move
    pushes, whichever candidate it chooses. *)
Theorem requeue_key_below_node : forall cands c travel T b,
  0 <= tw -> (forall r, In r cands -> 0 <= c_extra r) -> In c cands ->
  c_extra c = w * T -> c_dist c <= travel ->
  move_bound aw tw cands = Some b ->
  requeue_key b <= node_key (c_act c) travel T.
Proof.
  intros cands c travel T b Htw He Hc HT Hd Hb.
  destruct (move_bound_le aw tw cands c He Hc) as [b' [Hb' Hle]].
  rewrite Hb in Hb'. injection Hb' as <-.
  unfold requeue_key, node_key. unfold near in Hle.
  assert (tw * c_dist c <= tw * travel) by (apply Rmult_le_compat_l; assumption).
  rewrite Rmult_plus_distr_l. lra.
Qed.

(** The key the move is evaluated with: the popped key [f], or the tightened [f'] when it
    exceeds [f + eps] and the move is re-queued. *)
Definition key_after (f f' eps : R) : R := if Rlt_dec (f + eps) f' then f' else f.

(** If the popped key and the tightened key are both lower bounds of [K], so is the key the
    move is evaluated with. *)
Theorem key_after_below : forall f f' eps K,
  f <= K -> f' <= K -> key_after f f' eps <= K.
Proof. intros f f' eps K H1 H2. unfold key_after. destruct (Rlt_dec (f + eps) f'); lra. Qed.

(** The re-queue never lowers a key ([eps ≥ 0]). *)
Theorem key_after_ge : forall f f' eps, 0 <= eps -> f <= key_after f f' eps.
Proof. intros f f' eps He. unfold key_after. destruct (Rlt_dec (f + eps) f'); lra. Qed.

End Keys.
