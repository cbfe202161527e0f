(** * Rodrigues: the rotation matrix of the paper's Eq. (3) is a rotation (theorem 2).

    Models: [JointAxis::rodrigues] (src/scene/motion/axis.rs),
    [R(φ) = I + sin φ [u]× + (1 − cos φ) [u]×²] with the joint's unit world direction [u]
    (normalised by [joint_axis], src/scene/kinematics.rs).

    Assumption: [u] is a unit vector ([unit u]); exact real arithmetic.

    Main results:
    - [rodrigues_orthonormal]: [R(φ)ᵀ R(φ) = I];
    - [rodrigues_orthonormal_r]: [R(φ) R(φ)ᵀ = I];
    - [rodrigues_det]: [det R(φ) = 1];
    - [rodrigues_dot], [rodrigues_norm]: [R(φ)] preserves dot products and lengths;
    - [rodrigues_fixes_axis], [rodrigues_axial]: [R(φ) u = u] and [(R(φ) v)·u = v·u].

    Checked on the implementation by: tests/scene/trajectory.rs
    [revolute_trajectory_of_a_descendant_handle] (constant axis distance, plane through p) and
    tests/scene/properties.rs [trajectory_endpoints_match_forward_kinematics] (Eq. (3) agrees
    with forward kinematics). *)

From Coq Require Import Reals Lra Psatz Nsatz.
From KinScene Require Import Geometry.Vec3.
Open Scope R_scope.

(** 3×3 matrices, row-major. *)
Record M3 := mkM3 {
  m11 : R; m12 : R; m13 : R;
  m21 : R; m22 : R; m23 : R;
  m31 : R; m32 : R; m33 : R }.

Definition mid : M3 := mkM3 1 0 0 0 1 0 0 0 1.

Definition madd (a b : M3) : M3 :=
  mkM3 (m11 a + m11 b) (m12 a + m12 b) (m13 a + m13 b)
       (m21 a + m21 b) (m22 a + m22 b) (m23 a + m23 b)
       (m31 a + m31 b) (m32 a + m32 b) (m33 a + m33 b).

Definition mscale (k : R) (a : M3) : M3 :=
  mkM3 (k * m11 a) (k * m12 a) (k * m13 a)
       (k * m21 a) (k * m22 a) (k * m23 a)
       (k * m31 a) (k * m32 a) (k * m33 a).

Definition mmul (a b : M3) : M3 :=
  mkM3 (m11 a * m11 b + m12 a * m21 b + m13 a * m31 b)
       (m11 a * m12 b + m12 a * m22 b + m13 a * m32 b)
       (m11 a * m13 b + m12 a * m23 b + m13 a * m33 b)
       (m21 a * m11 b + m22 a * m21 b + m23 a * m31 b)
       (m21 a * m12 b + m22 a * m22 b + m23 a * m32 b)
       (m21 a * m13 b + m22 a * m23 b + m23 a * m33 b)
       (m31 a * m11 b + m32 a * m21 b + m33 a * m31 b)
       (m31 a * m12 b + m32 a * m22 b + m33 a * m32 b)
       (m31 a * m13 b + m32 a * m23 b + m33 a * m33 b).

Definition mtranspose (a : M3) : M3 :=
  mkM3 (m11 a) (m21 a) (m31 a)
       (m12 a) (m22 a) (m32 a)
       (m13 a) (m23 a) (m33 a).

Definition mvec (a : M3) (v : V3) : V3 :=
  mkV3 (m11 a * vx v + m12 a * vy v + m13 a * vz v)
       (m21 a * vx v + m22 a * vy v + m23 a * vz v)
       (m31 a * vx v + m32 a * vy v + m33 a * vz v).

Definition det (a : M3) : R :=
  m11 a * (m22 a * m33 a - m23 a * m32 a)
  - m12 a * (m21 a * m33 a - m23 a * m31 a)
  + m13 a * (m21 a * m32 a - m22 a * m31 a).

(** The skew-symmetric matrix [[u]×], nalgebra's [cross_matrix]. *)
Definition skew (u : V3) : M3 :=
  mkM3 0 (- vz u) (vy u)
       (vz u) 0 (- vx u)
       (- vy u) (vx u) 0.

(** The paper's Eq. (3), exactly as [JointAxis::rodrigues] builds it. *)
Definition rodrigues (u : V3) (phi : R) : M3 :=
  madd (madd mid (mscale (sin phi) (skew u)))
       (mscale (1 - cos phi) (mmul (skew u) (skew u))).

Lemma M3_ext : forall a b : M3,
  m11 a = m11 b -> m12 a = m12 b -> m13 a = m13 b ->
  m21 a = m21 b -> m22 a = m22 b -> m23 a = m23 b ->
  m31 a = m31 b -> m32 a = m32 b -> m33 a = m33 b -> a = b.
Proof.
  intros [] []; simpl; intros -> -> -> -> -> -> -> -> ->; reflexivity.
Qed.

Lemma skew_apply : forall u v, mvec (skew u) v = cross u v.
Proof. intros; vec_ring. Qed.

(** Eq. (3) applied to a vector:
    [R(φ) v = v + sin φ (u × v) + (1 − cos φ) u × (u × v)]. *)
Lemma rodrigues_apply : forall u phi v,
  mvec (rodrigues u phi) v =
  vadd (vadd v (vscale (sin phi) (cross u v)))
       (vscale (1 - cos phi) (cross u (cross u v))).
Proof. intros; vec_ring. Qed.

Lemma rodrigues_zero : forall u, rodrigues u 0 = mid.
Proof.
  intros u. unfold rodrigues. rewrite sin_0, cos_0.
  destruct u; apply M3_ext; simpl; ring.
Qed.

Lemma sin_cos_sq : forall x, sin x * sin x + cos x * cos x = 1.
Proof. intros x. pose proof (sin2_cos2 x). unfold Rsqr in *. lra. Qed.

(** Reduces a matrix equation about [rodrigues u phi] to nine polynomial identities in the
    components of [u], [s = sin φ] and [c = cos φ], proved by [nsatz] from [|u|² = 1] and
    [s² + c² = 1]. *)
Ltac rodrigues_nsatz Hu phi :=
  let s := fresh "s" in let c := fresh "c" in let Hsc := fresh "Hsc" in
  pose proof (sin_cos_sq phi) as Hsc;
  generalize dependent (sin phi); intros s Hsc;
  generalize dependent (cos phi); intros c Hsc;
  unfold unit, dot in Hu; simpl in Hu.

(** ** Theorem 2(a): [R(φ)ᵀ R(φ) = I]. *)
Theorem rodrigues_orthonormal : forall u phi,
  unit u -> mmul (mtranspose (rodrigues u phi)) (rodrigues u phi) = mid.
Proof.
  intros [ux uy uz] phi Hu. unfold rodrigues.
  rodrigues_nsatz Hu phi.
  apply M3_ext; simpl; nsatz.
Qed.

(** ** Theorem 2(a'): [R(φ) R(φ)ᵀ = I]. *)
Theorem rodrigues_orthonormal_r : forall u phi,
  unit u -> mmul (rodrigues u phi) (mtranspose (rodrigues u phi)) = mid.
Proof.
  intros [ux uy uz] phi Hu. unfold rodrigues.
  rodrigues_nsatz Hu phi.
  apply M3_ext; simpl; nsatz.
Qed.

(** ** Theorem 2(b): [det R(φ) = 1] (a proper rotation, not a reflection). *)
Theorem rodrigues_det : forall u phi, unit u -> det (rodrigues u phi) = 1.
Proof.
  intros [ux uy uz] phi Hu. unfold rodrigues, det.
  rodrigues_nsatz Hu phi.
  simpl; nsatz.
Qed.

Lemma mvec_mmul : forall a b v, mvec (mmul a b) v = mvec a (mvec b v).
Proof. intros [] [] []; apply V3_ext; simpl; ring. Qed.

Lemma mvec_id : forall v, mvec mid v = v.
Proof. intros []; apply V3_ext; simpl; ring. Qed.

Lemma dot_mvec_transpose : forall a v w, dot (mvec a v) w = dot v (mvec (mtranspose a) w).
Proof. intros [] [] []; unfold dot; simpl; ring. Qed.

Lemma mvec_sub : forall a v w, mvec a (vsub v w) = vsub (mvec a v) (mvec a w).
Proof. intros [] [] []; apply V3_ext; simpl; ring. Qed.

(** [R(φ)] preserves dot products: [(R v)·(R w) = v·w]. *)
Theorem rodrigues_dot : forall u phi v w,
  unit u -> dot (mvec (rodrigues u phi) v) (mvec (rodrigues u phi) w) = dot v w.
Proof.
  intros u phi v w Hu.
  rewrite dot_mvec_transpose, <- mvec_mmul, rodrigues_orthonormal, mvec_id by exact Hu.
  reflexivity.
Qed.

(** [R(φ)] preserves lengths: [|R v| = |v|]. *)
Theorem rodrigues_norm : forall u phi v,
  unit u -> norm (mvec (rodrigues u phi) v) = norm v.
Proof. intros; apply norm_eq_of_dot_eq, rodrigues_dot; assumption. Qed.

(** [R(φ)] fixes its axis (no unit assumption needed: [u × u = 0]). *)
Lemma rodrigues_fixes_axis : forall u phi, mvec (rodrigues u phi) u = u.
Proof. intros; rewrite rodrigues_apply; vec_ring. Qed.

(** The axial component is preserved: [(R v)·u = v·u]. *)
Theorem rodrigues_axial : forall u phi v,
  unit u -> dot (mvec (rodrigues u phi) v) u = dot v u.
Proof.
  intros u phi v Hu.
  rewrite <- (rodrigues_fixes_axis u phi) at 2.
  apply rodrigues_dot; exact Hu.
Qed.
