(** * Lattice: the finite state space of the task search (theorems 3 and 4).

    Models src/task/lattice.rs and the move relation of src/task/search/expand.rs:
    - a lattice state is a [Key]: one value index per joint (the Rust [Key = Vec<u16>]);
      joint [j] has [nth j sizes 0] values ([Lattice::values(j).len()]), so a state is
      [valid] iff it has one entry per joint and every entry is below its joint's size;
    - a [Move] changes one joint to another index of its set ([Item::Edge { joint, to }]);
      [apply] is [next[j] = to];
    - [moves sizes A k] is the successor loop of [push_moves] when a node is closed: every
      joint [j] with [active[j]], every [to] in [0..len] with [to != key[j]], in that order;
      [is_move] is the same relation as a proposition ([In_moves]);
    - [path sizes A feasible k ms k']: [ms] is a sequence of moves over the joints of [A], each
      feasible ([feasible k m = true]) in the state it is applied to, leading from [k] to [k'].

    Assumptions: [feasible] is a function of the state and the move only. That is the Rust
    [Checker::evaluate] verdict (Feasible or not) under the conditions stated in
    theories/Task/Search.v; [Feasibility::check] is the memo-free form of the same predicate.

    Main results (lemmas used by Search.v and Rounds.v):
    - [In_moves]: the enumerated successors are exactly the moves of [is_move];
    - [moves_length]: a state has at most [move_bound sizes] successors;
    - [all_keys_complete]: every valid state is in the finite list [all_keys sizes] (the
      state space is finite, [Lattice::state_count] states);
    - [apply_valid], [path_valid]: moves keep states valid;
    - [agree_*]: agreement of two states on a joint set, used by the projection lemma.

    Checked on the implementation by: the tests cited in Search.v (the BFS of
    tests/task/brute_force.rs enumerates the same successor relation). *)

From Coq Require Import List Arith Lia Bool.
Import ListNotations.

Definition Key := list nat.

Record Move := mkMove { mv_joint : nat; mv_to : nat }.

(** A set of joints, as the Rust [active: Vec<bool>] (indices past the end are unused). *)
Definition JointSet := nat -> bool.

Definition all_joints : JointSet := fun _ => true.

(** ** Keys *)

Definition key_eqb (a b : Key) : bool :=
  if list_eq_dec Nat.eq_dec a b then true else false.

(** Membership in a closed set ([HashSet<Key>::contains]). *)
Definition mem (k : Key) (l : list Key) : bool := existsb (key_eqb k) l.

Lemma key_eqb_true : forall a b, key_eqb a b = true <-> a = b.
Proof.
  intros a b. unfold key_eqb. destruct (list_eq_dec Nat.eq_dec a b); split; intro H;
    congruence.
Qed.

Lemma mem_In : forall k l, mem k l = true <-> In k l.
Proof.
  intros k l. unfold mem. rewrite existsb_exists. split.
  - intros [x [Hx He]]. apply key_eqb_true in He. subst. exact Hx.
  - intros H. exists k. split; [exact H|]. apply key_eqb_true. reflexivity.
Qed.

Lemma mem_false : forall k l, mem k l = false <-> ~ In k l.
Proof.
  intros k l. rewrite <- mem_In. destruct (mem k l); split; congruence.
Qed.

(** [k] is a lattice state: one index per joint, each below its joint's number of values. *)
Definition valid (sizes : list nat) (k : Key) : Prop := Forall2 lt k sizes.

Lemma valid_length : forall sizes k, valid sizes k -> length k = length sizes.
Proof. intros sizes k H. induction H; simpl; congruence. Qed.

(** [k[j] := v] (a no-op past the end). *)
Fixpoint update (k : Key) (j v : nat) : Key :=
  match k, j with
  | [], _ => []
  | _ :: t, 0 => v :: t
  | x :: t, S j' => x :: update t j' v
  end.

Definition apply (k : Key) (m : Move) : Key := update k (mv_joint m) (mv_to m).

Lemma update_length : forall k j v, length (update k j v) = length k.
Proof. induction k as [|x t IH]; intros [|j] v; simpl; auto. Qed.

Lemma nth_update_same : forall k j v, j < length k -> nth j (update k j v) 0 = v.
Proof.
  induction k as [|x t IH]; intros [|j] v H; simpl in *; try lia; auto.
  apply IH. lia.
Qed.

Lemma nth_update_other : forall k i j v, i <> j -> nth i (update k j v) 0 = nth i k 0.
Proof.
  induction k as [|x t IH]; intros [|i] [|j] v H; simpl; auto; try lia.
Qed.

Lemma valid_update : forall sizes k j v,
  valid sizes k -> v < nth j sizes 0 -> valid sizes (update k j v).
Proof.
  unfold valid. intros sizes k j v H. revert j.
  induction H as [|x m t ms Hx Ht IH]; intros [|j] Hv; simpl in *; constructor; auto.
Qed.

(** ** Moves *)

(** [m] is a move of an active joint of [k] to another value of its set. *)
Definition is_move (sizes : list nat) (A : JointSet) (k : Key) (m : Move) : Prop :=
  A (mv_joint m) = true /\ mv_joint m < length sizes
  /\ mv_to m < nth (mv_joint m) sizes 0 /\ mv_to m <> nth (mv_joint m) k 0.

(** The moves of joint [j]: [for to in 0..len { if to == key[j] { continue } … }]. *)
Definition moves_of (sizes : list nat) (k : Key) (j : nat) : list Move :=
  map (mkMove j) (filter (fun t => negb (t =? nth j k 0)) (seq 0 (nth j sizes 0))).

(** All successors of [k]: [for (j, is_active) in active.iter().enumerate() { … }]. *)
Definition moves (sizes : list nat) (A : JointSet) (k : Key) : list Move :=
  flat_map (fun j => if A j then moves_of sizes k j else []) (seq 0 (length sizes)).

Lemma In_moves : forall sizes A k m, In m (moves sizes A k) <-> is_move sizes A k m.
Proof.
  intros sizes A k m. unfold moves, is_move. rewrite in_flat_map. split.
  - intros [j [Hj Hm]]. apply in_seq in Hj. destruct (A j) eqn:HA; [|contradiction].
    unfold moves_of in Hm. apply in_map_iff in Hm. destruct Hm as [t [<- Ht]].
    apply filter_In in Ht. destruct Ht as [Ht Hne]. apply in_seq in Ht.
    apply negb_true_iff, Nat.eqb_neq in Hne. simpl. repeat split; auto; lia.
  - intros [HA [Hj [Ht Hne]]]. exists (mv_joint m). split; [apply in_seq; lia|].
    rewrite HA. unfold moves_of. apply in_map_iff. exists (mv_to m).
    split; [destruct m; reflexivity|]. apply filter_In.
    split; [apply in_seq; lia|]. apply negb_true_iff, Nat.eqb_neq. exact Hne.
Qed.

(** [Σ_j |L_j|]: no state has more successors. *)
Definition move_bound (sizes : list nat) : nat :=
  list_sum (map (fun j => nth j sizes 0) (seq 0 (length sizes))).

Lemma filter_length_le : forall {X} (f : X -> bool) l, length (filter f l) <= length l.
Proof. intros X f l. induction l as [|x t IH]; simpl; [lia|]. destruct (f x); simpl; lia. Qed.

Lemma moves_of_length : forall sizes k j, length (moves_of sizes k j) <= nth j sizes 0.
Proof.
  intros sizes k j. unfold moves_of. rewrite map_length.
  pose proof (filter_length_le (fun t => negb (t =? nth j k 0)) (seq 0 (nth j sizes 0))).
  rewrite seq_length in H. exact H.
Qed.

Lemma moves_length : forall sizes A k, length (moves sizes A k) <= move_bound sizes.
Proof.
  intros sizes A k. unfold moves, move_bound.
  induction (seq 0 (length sizes)) as [|j t IH]; simpl; [lia|].
  rewrite app_length. pose proof (moves_of_length sizes k j). destruct (A j); simpl; lia.
Qed.

Lemma apply_valid : forall sizes A k m, valid sizes k -> is_move sizes A k m -> valid sizes (apply k m).
Proof. intros sizes A k m Hk [_ [_ [Ht _]]]. apply valid_update; assumption. Qed.

(** ** The finite state space *)

(** Every state of [L_1 × … × L_n]. *)
Fixpoint all_keys (sizes : list nat) : list Key :=
  match sizes with
  | [] => [[]]
  | m :: rest => flat_map (fun v => map (cons v) (all_keys rest)) (seq 0 m)
  end.

Lemma all_keys_complete : forall sizes k, valid sizes k -> In k (all_keys sizes).
Proof.
  intros sizes k H. induction H as [|v m t rest Hv Ht IH]; simpl; [left; reflexivity|].
  apply in_flat_map. exists v. split; [apply in_seq; lia|]. apply in_map. exact IH.
Qed.

(** ** Agreement on a set of joints *)

Definition agree (A : JointSet) (k k' : Key) : Prop :=
  length k = length k' /\ forall j, A j = true -> nth j k 0 = nth j k' 0.

Lemma agree_refl : forall A k, agree A k k.
Proof. split; reflexivity. Qed.

Lemma agree_sym : forall A k k', agree A k k' -> agree A k' k.
Proof. intros A k k' [Hl H]. split; [congruence|]. intros j Hj. symmetry. auto. Qed.

Lemma agree_mono : forall (A B : JointSet) k k',
  (forall j, B j = true -> A j = true) -> agree A k k' -> agree B k k'.
Proof. intros A B k k' Hs [Hl H]. split; auto. Qed.

(** Both states make the same move. *)
Lemma agree_apply : forall A k k' m, agree A k k' -> agree A (apply k m) (apply k' m).
Proof.
  intros A k k' m [Hl H]. unfold apply. split; [rewrite !update_length; exact Hl|].
  intros j Hj. destruct (Nat.eq_dec j (mv_joint m)) as [->|Hne].
  - destruct (Nat.lt_ge_cases (mv_joint m) (length k)) as [Hlt|Hge].
    + rewrite !nth_update_same by lia. reflexivity.
    + rewrite !nth_overflow by (rewrite update_length; lia). reflexivity.
  - rewrite !nth_update_other by exact Hne. auto.
Qed.

(** One state moves a joint outside [A]: they still agree on [A]. *)
Lemma agree_apply_inactive : forall A k k' m,
  A (mv_joint m) = false -> agree A k k' -> agree A k (apply k' m).
Proof.
  intros A k k' m HA [Hl H]. unfold apply. split; [rewrite update_length; exact Hl|].
  intros j Hj. rewrite nth_update_other by congruence. auto.
Qed.

(** Agreement on every joint of the model is equality. *)
Lemma agree_all_eq : forall (A : JointSet) k k',
  (forall j, j < length k -> A j = true) -> agree A k k' -> k = k'.
Proof.
  intros A k k' Hall [Hl H]. apply nth_ext with (d := 0) (d' := 0); [exact Hl|].
  intros j Hj. auto.
Qed.

(** ** Feasible paths *)

(** [ms] leads from [k] to [k'] by moves of active joints, each feasible where applied. *)
Inductive path (sizes : list nat) (A : JointSet) (feasible : Key -> Move -> bool)
  : Key -> list Move -> Key -> Prop :=
  | path_nil : forall k, path sizes A feasible k [] k
  | path_cons : forall k m ms k',
      is_move sizes A k m -> feasible k m = true ->
      path sizes A feasible (apply k m) ms k' -> path sizes A feasible k (m :: ms) k'.

Lemma path_snoc : forall sizes A feasible k ms k' m,
  path sizes A feasible k ms k' -> is_move sizes A k' m -> feasible k' m = true ->
  path sizes A feasible k (ms ++ [m]) (apply k' m).
Proof.
  intros sizes A feasible k ms k' m H. induction H as [k|k m0 ms k' Hm Hf Hp IH];
    intros Hm' Hf'; simpl.
  - apply path_cons; auto. apply path_nil.
  - apply path_cons; auto.
Qed.

Lemma path_mono : forall sizes (A B : JointSet) feasible k ms k',
  (forall j, A j = true -> B j = true) ->
  path sizes A feasible k ms k' -> path sizes B feasible k ms k'.
Proof.
  intros sizes A B feasible k ms k' Hs H.
  induction H as [k|k m ms k' [HA Hm] Hf Hp IH]; constructor; auto. split; auto.
Qed.

Lemma path_valid : forall sizes A feasible k ms k',
  valid sizes k -> path sizes A feasible k ms k' -> valid sizes k'.
Proof.
  intros sizes A feasible k ms k' Hk H.
  induction H as [k|k m ms k' Hm Hf Hp IH]; auto. apply IH. eapply apply_valid; eauto.
Qed.
