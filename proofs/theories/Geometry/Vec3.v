(** * Vec3: explicit 3-vectors over Coq's standard reals.

    Vectors are triples of reals; every identity below is checked component-wise by [ring].
    This is the vector algebra the other files use: dot and cross products, the Euclidean
    norm, Lagrange's identity, Cauchy–Schwarz and the triangle inequality.

    Models: [nalgebra::Vector3<f64>] / [Point3<f64>] as used throughout [src/scene/], over
    exact reals (no rounding). *)

From Coq Require Import Reals Lra Psatz.
Open Scope R_scope.

Record V3 := mkV3 { vx : R; vy : R; vz : R }.

Definition vadd (a b : V3) : V3 := mkV3 (vx a + vx b) (vy a + vy b) (vz a + vz b).
Definition vsub (a b : V3) : V3 := mkV3 (vx a - vx b) (vy a - vy b) (vz a - vz b).
Definition vscale (k : R) (a : V3) : V3 := mkV3 (k * vx a) (k * vy a) (k * vz a).
Definition vzero : V3 := mkV3 0 0 0.

Definition dot (a b : V3) : R := vx a * vx b + vy a * vy b + vz a * vz b.

Definition cross (a b : V3) : V3 :=
  mkV3 (vy a * vz b - vz a * vy b)
       (vz a * vx b - vx a * vz b)
       (vx a * vy b - vy a * vx b).

(** Euclidean norm and distance. *)
Definition norm (a : V3) : R := sqrt (dot a a).
Definition dist (a b : V3) : R := norm (vsub a b).

(** A unit vector: the joint axes of the scene model are normalised
    ([joint_axis] in src/scene/kinematics.rs calls [Unit::new_normalize]). *)
Definition unit (u : V3) : Prop := dot u u = 1.

Lemma V3_ext : forall a b : V3,
  vx a = vx b -> vy a = vy b -> vz a = vz b -> a = b.
Proof. intros [] [] ; simpl; intros -> -> ->; reflexivity. Qed.

(** Proves an equality of vectors component-wise with [ring]. *)
Ltac vec_ring :=
  repeat match goal with v : V3 |- _ => destruct v end;
  apply V3_ext; simpl; ring.

(** Unfolds vector operations on explicit components, for scalar goals. *)
Ltac vec_unfold :=
  repeat match goal with v : V3 |- _ => destruct v end;
  unfold dot, cross, vadd, vsub, vscale in *; simpl in *.

Lemma dot_comm : forall a b, dot a b = dot b a.
Proof. intros; vec_unfold; ring. Qed.

Lemma dot_self_nonneg : forall a, 0 <= dot a a.
Proof. intros; vec_unfold; nra. Qed.

Lemma dot_add_l : forall a b c, dot (vadd a b) c = dot a c + dot b c.
Proof. intros; vec_unfold; ring. Qed.

Lemma dot_sub_l : forall a b c, dot (vsub a b) c = dot a c - dot b c.
Proof. intros; vec_unfold; ring. Qed.

Lemma dot_scale_l : forall k a b, dot (vscale k a) b = k * dot a b.
Proof. intros; vec_unfold; ring. Qed.

(** Lagrange's identity: [|a × b|² = |a|²|b|² − (a·b)²]. *)
Lemma lagrange : forall a b,
  dot (cross a b) (cross a b) = dot a a * dot b b - dot a b * dot a b.
Proof. intros; vec_unfold; ring. Qed.

Lemma cauchy_schwarz_sq : forall a b, dot a b * dot a b <= dot a a * dot b b.
Proof.
  intros a b. pose proof (lagrange a b). pose proof (dot_self_nonneg (cross a b)). lra.
Qed.

Lemma norm_nonneg : forall a, 0 <= norm a.
Proof. intros; apply sqrt_pos. Qed.

Lemma norm_sq : forall a, norm a * norm a = dot a a.
Proof. intros; apply sqrt_sqrt, dot_self_nonneg. Qed.

Lemma dist_nonneg : forall a b, 0 <= dist a b.
Proof. intros; apply norm_nonneg. Qed.

(** [sqrt x <= y] from [x <= y²]. *)
Lemma sqrt_le_of_sq : forall x y, 0 <= y -> x <= y * y -> sqrt x <= y.
Proof.
  intros x y Hy Hxy. rewrite <- (sqrt_square y Hy). apply sqrt_le_1_alt; exact Hxy.
Qed.

(** [norm a <= y] from [a·a <= y²]. *)
Lemma norm_le_of_sq : forall a y, 0 <= y -> dot a a <= y * y -> norm a <= y.
Proof. intros; apply sqrt_le_of_sq; assumption. Qed.

(** [norm a <= norm b] from [a·a <= b·b]. *)
Lemma norm_le_of_dot_le : forall a b, dot a a <= dot b b -> norm a <= norm b.
Proof. intros; apply sqrt_le_1_alt; assumption. Qed.

Lemma norm_eq_of_dot_eq : forall a b, dot a a = dot b b -> norm a = norm b.
Proof. intros a b H; unfold norm; rewrite H; reflexivity. Qed.

Lemma dot_le_norm : forall a b, dot a b <= norm a * norm b.
Proof.
  intros a b.
  pose proof (cauchy_schwarz_sq a b) as Hcs.
  pose proof (norm_sq a) as Ha. pose proof (norm_sq b) as Hb.
  pose proof (norm_nonneg a). pose proof (norm_nonneg b).
  destruct (Rle_dec (dot a b) 0) as [Hle|Hgt].
  - apply Rle_trans with 0; [exact Hle | apply Rmult_le_pos; assumption].
  - rewrite <- Ha, <- Hb in Hcs.
    set (x := dot a b) in *. set (y := norm a * norm b).
    assert (Hy : 0 <= y) by (apply Rmult_le_pos; assumption).
    replace (norm a * norm a * (norm b * norm b)) with (y * y) in Hcs by (unfold y; ring).
    destruct (Rle_dec x y) as [Hxy|Hxy]; [exact Hxy|].
    exfalso. assert (y < x) by lra. nra.
Qed.

Lemma norm_triangle : forall a b, norm (vadd a b) <= norm a + norm b.
Proof.
  intros a b. apply norm_le_of_sq.
  - pose proof (norm_nonneg a); pose proof (norm_nonneg b); lra.
  - assert (E : dot (vadd a b) (vadd a b) = dot a a + 2 * dot a b + dot b b)
      by (vec_unfold; ring).
    rewrite E, <- (norm_sq a), <- (norm_sq b).
    pose proof (dot_le_norm a b). nra.
Qed.

Lemma dist_sym : forall a b, dist a b = dist b a.
Proof. intros; unfold dist; apply norm_eq_of_dot_eq; vec_unfold; ring. Qed.

Lemma dist_triangle : forall a b c, dist a c <= dist a b + dist b c.
Proof.
  intros a b c. unfold dist.
  replace (vsub a c) with (vadd (vsub a b) (vsub b c)) by vec_ring.
  apply norm_triangle.
Qed.

Lemma norm_scale : forall k a, norm (vscale k a) = Rabs k * norm a.
Proof.
  intros k a. unfold norm.
  replace (dot (vscale k a) (vscale k a)) with ((k * k) * dot a a) by (vec_unfold; ring).
  rewrite sqrt_mult_alt by (apply Rle_0_sqr).
  change (k * k) with (Rsqr k). rewrite sqrt_Rsqr_abs. reflexivity.
Qed.

Lemma norm_unit : forall u, unit u -> norm u = 1.
Proof. intros u Hu; unfold norm; rewrite Hu; apply sqrt_1. Qed.

(** Crossing with a unit vector does not lengthen: [|a × u| <= |a|]. *)
Lemma norm_cross_unit_le : forall a u, unit u -> norm (cross a u) <= norm a.
Proof.
  intros a u Hu. apply norm_le_of_dot_le.
  rewrite lagrange, Hu. pose proof (Rle_0_sqr (dot a u)). unfold Rsqr in *. lra.
Qed.

(** Translation invariance and linearity facts used for rigid motions. *)
Lemma dist_add_same : forall q a b, dist (vadd q a) (vadd q b) = dist a b.
Proof. intros; unfold dist; f_equal; vec_ring. Qed.

Lemma dist_add_r_same : forall q a b, dist (vadd a q) (vadd b q) = dist a b.
Proof. intros; unfold dist; f_equal; vec_ring. Qed.
