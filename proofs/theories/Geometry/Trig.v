(** * Trig: [|sin x| <= |x|] and [2(1 − cos x) <= x²] (chord ≤ arc).

    Proved from the standard library's Taylor bound [pre_sin_bound] (Rtrigo_alt) rather than
    the mean value theorem: [MVT] and [sin_lt_x] depend on [Classical_Prop.classic], which is
    not among the axioms proofs/check.sh allows. *)

From Coq Require Import Reals Lra Psatz.
Open Scope R_scope.

(** [sin x <= x] for [x >= 0]: on [0, 4] from [sin x <= x − x³/6 + x⁵/120 <= x]
    ([x² <= 20]); beyond, [sin x <= 1 < x]. *)
Lemma sin_le_id : forall x, 0 <= x -> sin x <= x.
Proof.
  intros x Hx. destruct (Rle_dec x 4) as [H4|H4].
  - destruct (pre_sin_bound x 0 Hx H4) as [_ H].
    assert (E : sin_approx x (2 * (0 + 1)) = x - x^3/6 + x^5/120).
    { unfold sin_approx, sin_term; simpl; field. }
    rewrite E in H.
    assert (0 <= x^3 * (20 - x^2)).
    { apply Rmult_le_pos; [apply pow_le; lra | nra]. }
    nra.
  - pose proof (SIN_bound x); lra.
Qed.

(** [−x <= sin x] for [x >= 0]: on [0, 4] from [sin x >= x − x³/6 >= −x] when [x² <= 12];
    the case [x > 3] from [sin x >= −1]. *)
Lemma neg_id_le_sin : forall x, 0 <= x -> - x <= sin x.
Proof.
  intros x Hx. destruct (Rle_dec x 3) as [H3|H3].
  - destruct (pre_sin_bound x 0 Hx ltac:(lra)) as [H _].
    assert (E : sin_approx x (2 * 0 + 1) = x - x^3/6).
    { unfold sin_approx, sin_term; simpl; field. }
    rewrite E in H.
    assert (0 <= x * (12 - x^2)) by (apply Rmult_le_pos; nra).
    nra.
  - pose proof (SIN_bound x); lra.
Qed.

Lemma sin_sq_le : forall x, sin x * sin x <= x * x.
Proof.
  intros x. destruct (Rle_dec 0 x) as [Hx|Hx].
  - pose proof (sin_le_id x Hx). pose proof (neg_id_le_sin x Hx). nra.
  - assert (Hn : 0 <= - x) by lra.
    pose proof (sin_le_id (- x) Hn). pose proof (neg_id_le_sin (- x) Hn).
    rewrite sin_neg in *. nra.
Qed.

(** [|sin x| <= |x|]. *)
Lemma abs_sin_le : forall x, Rabs (sin x) <= Rabs x.
Proof.
  intros x. apply Rsqr_le_abs_0. unfold Rsqr. apply sin_sq_le.
Qed.

(** Chord ≤ arc in squared form: [2(1 − cos x) = 4 sin²(x/2) <= x²]. *)
Lemma two_one_minus_cos_le : forall x, 2 * (1 - cos x) <= x * x.
Proof.
  intros x.
  replace x with (2 * (x / 2)) at 1 by field.
  rewrite cos_2a_sin.
  pose proof (sin_sq_le (x / 2)).
  nra.
Qed.
