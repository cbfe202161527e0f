(** * JointAxis: the world-frame motion of a one-joint change, Eq. (3)–(5).

    Models [JointAxis] (src/scene/kinematics.rs: [kind], [pivot], unit [direction]) and its
    methods in src/scene/motion/axis.rs:
    - [move_point]: [x ↦ q + R(δ)(x − q)] (revolute, Eq. (3)–(4)), [x ↦ x + δ u] (prismatic,
      Eq. (5)) — [JointAxis::move_point], and [JointAxis::displacement] as a map on points;
    - [move_vector]: [n ↦ R(δ) n] / [n ↦ n] — [JointAxis::move_vector];
    - [axis_dist]: [|(x − q) × u|] — [JointAxis::distance_to_axis].

    Assumption everywhere: the direction is a unit vector ([axis_unit]). *)

From Coq Require Import Reals Lra Psatz.
From KinScene Require Import Geometry.Vec3 Geometry.Rodrigues.
Open Scope R_scope.

Inductive joint_kind := Revolute | Prismatic.

Record joint_axis := mkAxis { kind : joint_kind; pivot : V3; direction : V3 }.

Definition axis_unit (ax : joint_axis) : Prop := unit (direction ax).

Definition move_point (ax : joint_axis) (delta : R) (p : V3) : V3 :=
  match kind ax with
  | Revolute =>
      vadd (pivot ax) (mvec (rodrigues (direction ax) delta) (vsub p (pivot ax)))
  | Prismatic => vadd p (vscale delta (direction ax))
  end.

Definition move_vector (ax : joint_axis) (delta : R) (n : V3) : V3 :=
  match kind ax with
  | Revolute => mvec (rodrigues (direction ax) delta) n
  | Prismatic => n
  end.

Definition axis_dist (ax : joint_axis) (p : V3) : R :=
  norm (cross (vsub p (pivot ax)) (direction ax)).

Lemma move_point_zero : forall ax p, move_point ax 0 p = p.
Proof.
  intros [[] q u] p; unfold move_point; simpl.
  - rewrite rodrigues_zero, mvec_id. vec_ring.
  - vec_ring.
Qed.

(** Every joint motion is rigid: it preserves distances between points. *)
Lemma move_point_rigid : forall ax delta a b,
  axis_unit ax -> dist (move_point ax delta a) (move_point ax delta b) = dist a b.
Proof.
  intros [[] q u] delta a b Hu; unfold move_point, axis_unit in *; simpl in *.
  - rewrite dist_add_same. unfold dist. rewrite <- mvec_sub, rodrigues_norm by exact Hu.
    f_equal; vec_ring.
  - apply dist_add_r_same.
Qed.

(** Motions preserve the distance to the axis (the axis line is invariant). *)
Lemma axis_dist_move : forall ax delta p,
  axis_unit ax -> axis_dist ax (move_point ax delta p) = axis_dist ax p.
Proof.
  intros [[] q u] delta p Hu; unfold axis_dist, move_point, axis_unit in *; simpl in *.
  - apply norm_eq_of_dot_eq.
    replace (vsub (vadd q (mvec (rodrigues u delta) (vsub p q))) q)
      with (mvec (rodrigues u delta) (vsub p q)) by vec_ring.
    rewrite !lagrange, rodrigues_dot, rodrigues_axial by exact Hu. reflexivity.
  - f_equal. vec_ring.
Qed.

(** A point at distance [ρ] from the axis, translated by at most [d], is at most [ρ + d]
    from the axis: [axis_dist] is 1-Lipschitz. *)
Lemma axis_dist_le : forall ax x c,
  axis_unit ax -> axis_dist ax x <= axis_dist ax c + dist x c.
Proof.
  intros ax x c Hu. unfold axis_dist.
  replace (cross (vsub x (pivot ax)) (direction ax))
    with (vadd (cross (vsub c (pivot ax)) (direction ax)) (cross (vsub x c) (direction ax)))
    by vec_ring.
  eapply Rle_trans; [apply norm_triangle|].
  apply Rplus_le_compat_l. apply norm_cross_unit_le; exact Hu.
Qed.

Lemma axis_dist_nonneg : forall ax p, 0 <= axis_dist ax p.
Proof. intros; apply norm_nonneg. Qed.

(** [|(x − q) × u|² = |x − q|² − ((x − q)·u)²] for a unit [u]. *)
Lemma axis_dist_sq : forall ax p,
  axis_unit ax ->
  axis_dist ax p * axis_dist ax p =
  dot (vsub p (pivot ax)) (vsub p (pivot ax))
  - dot (vsub p (pivot ax)) (direction ax) * dot (vsub p (pivot ax)) (direction ax).
Proof.
  intros ax p Hu. unfold axis_dist. rewrite norm_sq, lagrange, Hu. ring.
Qed.
