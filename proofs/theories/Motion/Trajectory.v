(** * Trajectory: the grasp-point trajectory of Eq. (4)/(5) (theorem 2).

    Models [grasp_trajectory] (src/scene/motion/trajectory.rs): with [p], [n] the handle's
    world point and normal at the start value [a], the joint's world axis ([pivot] q, unit
    [direction] u), step [i ∈ [0, K]] has [φᵢ = (i/K)(b − a)] and
    - revolute (Eq. (3)–(4)): [pᵢ = R(φᵢ)(p − q) + q], [nᵢ = R(φᵢ) n];
    - prismatic (Eq. (5)): [pᵢ = p + φᵢ u], [nᵢ = n].

    Assumptions: unit axis direction; [K >= 1] (the Rust function rejects [K = 0]); exact
    reals. The Rust function normalises [nᵢ] afterwards; [grasp_normal_length] shows that this
    is a no-op up to rounding for a revolute joint.

    Main results:
    - [revolute_pivot_distance]: [|R(φ)(p − q)| = |p − q|];
    - [move_axis_distance]: the distance of the grasp point to the axis is constant;
    - [revolute_in_plane]: [(R(φ)(p − q))·u = (p − q)·u], i.e. the point stays in the plane
      through [p] perpendicular to [u];
    - [grasp_trajectory_on_circle] / [grasp_trajectory_on_line]: every pose of the modelled
      [grasp_trajectory] list has these properties;
    - [grasp_trajectory_endpoints]: the first pose is [p], the last is [p] moved by [b − a].

    Checked on the implementation by: tests/scene/trajectory.rs
    [revolute_trajectory_of_a_descendant_handle] (constant axis distance and [(pᵢ − p)·u = 0]),
    [prismatic_trajectory_is_evenly_spaced_along_the_axis], and tests/scene/properties.rs
    [trajectory_endpoints_match_forward_kinematics] (endpoints equal forward kinematics). *)

From Coq Require Import Reals Lra Psatz List.
From KinScene Require Import Geometry.Vec3 Geometry.Rodrigues Motion.JointAxis.
Import ListNotations.
Open Scope R_scope.

(** [φᵢ = (i/K)(b − a)], as computed in [grasp_trajectory]. *)
Definition step_value (a b : R) (k i : nat) : R := (INR i / INR k) * (b - a).

Definition grasp_positions (ax : joint_axis) (p : V3) (a b : R) (k : nat) : list V3 :=
  map (fun i => move_point ax (step_value a b k i) p) (seq 0 (S k)).

Definition grasp_normals (ax : joint_axis) (n : V3) (a b : R) (k : nat) : list V3 :=
  map (fun i => move_vector ax (step_value a b k i) n) (seq 0 (S k)).

(** ** Theorem 2(c): [|R(φ)(p − q)| = |p − q|]: constant distance to the pivot. *)
Theorem revolute_pivot_distance : forall ax phi p,
  axis_unit ax -> kind ax = Revolute ->
  dist (move_point ax phi p) (pivot ax) = dist p (pivot ax).
Proof.
  intros ax phi p Hu Hk. unfold move_point. rewrite Hk. unfold dist.
  replace (vsub (vadd (pivot ax) (mvec (rodrigues (direction ax) phi) (vsub p (pivot ax))))
                (pivot ax))
    with (mvec (rodrigues (direction ax) phi) (vsub p (pivot ax))) by vec_ring.
  apply rodrigues_norm; exact Hu.
Qed.

(** ** Theorem 2(d): the distance of the grasp point to the axis is constant (both kinds). *)
Theorem move_axis_distance : forall ax phi p,
  axis_unit ax -> axis_dist ax (move_point ax phi p) = axis_dist ax p.
Proof. intros; apply axis_dist_move; assumption. Qed.

(** ** Theorem 2(e): [(R(φ)(p − q))·u = (p − q)·u]; equivalently [(pᵢ − p)·u = 0]: the point
    stays in the plane through [p] perpendicular to [u]. *)
Theorem revolute_axial_component : forall ax phi p,
  axis_unit ax ->
  dot (mvec (rodrigues (direction ax) phi) (vsub p (pivot ax))) (direction ax)
  = dot (vsub p (pivot ax)) (direction ax).
Proof. intros; apply rodrigues_axial; assumption. Qed.

Theorem revolute_in_plane : forall ax phi p,
  axis_unit ax -> kind ax = Revolute ->
  dot (vsub (move_point ax phi p) p) (direction ax) = 0.
Proof.
  intros ax phi p Hu Hk. unfold move_point. rewrite Hk.
  replace (vsub (vadd (pivot ax) (mvec (rodrigues (direction ax) phi) (vsub p (pivot ax)))) p)
    with (vsub (mvec (rodrigues (direction ax) phi) (vsub p (pivot ax))) (vsub p (pivot ax)))
    by vec_ring.
  rewrite dot_sub_l, rodrigues_axial by exact Hu. ring.
Qed.

(** The normals of a revolute trajectory keep their length. *)
Lemma grasp_normal_length : forall ax phi n,
  axis_unit ax -> norm (move_vector ax phi n) = norm n.
Proof.
  intros [[] q u] phi n Hu; unfold move_vector; simpl.
  - apply rodrigues_norm; exact Hu.
  - reflexivity.
Qed.

Lemma in_grasp_positions : forall ax p a b k x,
  In x (grasp_positions ax p a b k) ->
  exists i, (i <= k)%nat /\ x = move_point ax (step_value a b k i) p.
Proof.
  intros ax p a b k x Hin. unfold grasp_positions in Hin.
  apply in_map_iff in Hin. destruct Hin as [i [Hx Hi]].
  apply in_seq in Hi. exists i. split; [lia | symmetry; exact Hx].
Qed.

(** Every pose of a revolute grasp trajectory lies on the circle about the axis through [p]:
    same distance to the axis and to the pivot, and in the plane through [p] perpendicular
    to [u]. *)
Theorem grasp_trajectory_on_circle : forall ax p a b k x,
  axis_unit ax -> kind ax = Revolute ->
  In x (grasp_positions ax p a b k) ->
  axis_dist ax x = axis_dist ax p
  /\ dist x (pivot ax) = dist p (pivot ax)
  /\ dot (vsub x p) (direction ax) = 0.
Proof.
  intros ax p a b k x Hu Hk Hin.
  destruct (in_grasp_positions _ _ _ _ _ _ Hin) as [i [_ ->]].
  split; [apply move_axis_distance; exact Hu|].
  split; [apply revolute_pivot_distance; assumption|].
  apply revolute_in_plane; assumption.
Qed.

(** Every pose of a prismatic grasp trajectory lies on the line through [p] along [u], at
    distance [|φᵢ|] from [p] (Eq. (5)), and at the same distance from the axis. *)
Theorem grasp_trajectory_on_line : forall ax p a b k x,
  axis_unit ax -> kind ax = Prismatic ->
  In x (grasp_positions ax p a b k) ->
  exists i, (i <= k)%nat
  /\ x = vadd p (vscale (step_value a b k i) (direction ax))
  /\ dist x p = Rabs (step_value a b k i)
  /\ axis_dist ax x = axis_dist ax p.
Proof.
  intros ax p a b k x Hu Hk Hin.
  destruct (in_grasp_positions _ _ _ _ _ _ Hin) as [i [Hi ->]].
  exists i. split; [exact Hi|].
  assert (E : move_point ax (step_value a b k i) p
              = vadd p (vscale (step_value a b k i) (direction ax)))
    by (unfold move_point; rewrite Hk; reflexivity).
  split; [exact E|]. split.
  - rewrite E. unfold dist.
    replace (vsub (vadd p (vscale (step_value a b k i) (direction ax))) p)
      with (vscale (step_value a b k i) (direction ax)) by vec_ring.
    rewrite norm_scale, norm_unit by exact Hu. ring.
  - apply axis_dist_move; exact Hu.
Qed.

(** The first pose is [p] (the handle at [a]) and the last is [p] moved by [b − a] (the
    handle at [b]), for [K >= 1]. *)
Theorem grasp_trajectory_endpoints : forall ax p a b k,
  (1 <= k)%nat ->
  nth 0 (grasp_positions ax p a b k) vzero = p
  /\ nth k (grasp_positions ax p a b k) vzero = move_point ax (b - a) p.
Proof.
  intros ax p a b k Hk. unfold grasp_positions. split.
  - simpl. unfold step_value. replace (INR 0 / INR k * (b - a)) with 0
      by (simpl; unfold Rdiv; ring).
    apply move_point_zero.
  - set (f := fun i => move_point ax (step_value a b k i) p).
    rewrite nth_indep with (d' := f 0%nat) by (rewrite map_length, seq_length; lia).
    rewrite map_nth, seq_nth by lia. unfold f, step_value. simpl.
    f_equal. field. apply not_0_INR. lia.
Qed.

Lemma grasp_positions_length : forall ax p a b k,
  length (grasp_positions ax p a b k) = S k.
Proof. intros; unfold grasp_positions; rewrite map_length, seq_length; reflexivity. Qed.
