(** * SweepBound: how far a point of a moving subtree travels (theorem 1).

    Models src/scene/motion/bound.rs:
    - [lipschitz], [max_displacement]: [MotionBound::lipschitz] ([L = r] revolute, [L = 1]
      prismatic) and [MotionBound::max_displacement] ([L·|δ|]);
    - [sweep_radius]: [sweep_radius] — [max(0, dist(centre, axis) + radius, dist(handle, axis))]
      over the bounding spheres of the colliders and the handles of the joint's subtree;
    - [motion_bound] / [max_displacement] of bound.rs combine the two.

    Assumptions: unit axis direction; every point of a collider lies in the collider's
    bounding sphere ([in_sphere]; parry's [bounding_sphere] contains the shape); the subtree
    moves rigidly with the joint (forward kinematics; [JointAxis::displacement]); the other
    joints do not move during a one-joint motion; exact reals.

    Main results:
    - [revolute_chord_le_arc]: rotating [p] about the axis by [φ1] and [φ2] moves it by at most
      [dist(p, axis)·|φ1 − φ2|] (chord ≤ arc);
    - [prismatic_travel_exact]: translating by [d1], [d2] along a unit axis moves it by exactly
      [|d1 − d2|];
    - [subtree_point_within_radius]: [|x − axis| <= dist(centre, axis) + radius <= r] for every
      point of every collider (and every handle) of the subtree;
    - [sweep_bound]: every subtree point travels at most [max_displacement(φ1 − φ2)];
    - [sweep_radius_invariant]: [r] computed at one value of the joint is the same at every
      value (the joint's own value does not matter);
    - [ancestors_add] / [nested_sweep_bound]: for a part nested under several joints moving
      at once, the bounds of the ancestors' motions add.

    Checked on the implementation by: tests/scene/properties.rs
    [sweep_bound_holds_for_sampled_points] (travel [<= L·|Δθ|] and distance to the axis
    [<= r] for sampled subtree points of generated scenes) and tests/scene/trajectory.rs
    [motion_bound_of_the_door] (hand-computed radius and displacements). The chain model of
    [ancestors_add] is forward kinematics as tests/scene/properties.rs
    [forward_kinematics_composes_along_the_tree] checks it; tests/scene/nested_bound.rs
    [handle_travel_within_summed_ancestor_bounds] checks [nested_sweep_bound] itself: it moves
    every joint on a handle's ancestor chain of a generated scene to a new value and checks
    the handle's travel against the sum of the [max_displacement]s, each radius computed with
    the joints below already at their new values (and each telescoping step against its own
    term, [steps_bounded]). *)

From Coq Require Import Reals Lra Psatz Nsatz List.
From KinScene Require Import Geometry.Vec3 Geometry.Trig Geometry.Rodrigues Motion.JointAxis.
Import ListNotations.
Open Scope R_scope.

(** ** One joint, one point *)

(** [|R(φ1)v − R(φ2)v|² = 2(1 − cos(φ1 − φ2))·|v × u|²]: with [a = u × v] and
    [b = u × (u × v)], [R(φ1)v − R(φ2)v = (s1 − s2) a + (c2 − c1) b] (Eq. (3)), [a·b = 0] and
    [|b| = |a| = |v × u|] for a unit [u]. *)
Lemma revolute_chord_sq : forall ax phi1 phi2 p,
  axis_unit ax -> kind ax = Revolute ->
  dot (vsub (move_point ax phi1 p) (move_point ax phi2 p))
      (vsub (move_point ax phi1 p) (move_point ax phi2 p))
  = 2 * (1 - cos (phi1 - phi2)) * (axis_dist ax p * axis_dist ax p).
Proof.
  intros [k q u] phi1 phi2 p Hu Hk. simpl in Hk; subst k.
  unfold axis_unit in Hu; simpl in Hu.
  unfold axis_dist, move_point; simpl. rewrite norm_sq.
  set (v := vsub p q). set (a := cross u v). set (b := cross u (cross u v)).
  replace (vsub (vadd q (mvec (rodrigues u phi1) v)) (vadd q (mvec (rodrigues u phi2) v)))
    with (vadd (vscale (sin phi1 - sin phi2) a) (vscale (cos phi2 - cos phi1) b))
    by (rewrite !rodrigues_apply; unfold a, b; vec_ring).
  assert (Hab : dot a b = 0) by (unfold a, b; vec_unfold; ring).
  assert (Hbb : dot b b = dot a a).
  { unfold b. fold a. rewrite lagrange, Hu.
    replace (dot u a) with 0 by (unfold a; vec_unfold; ring). ring. }
  assert (Haa : dot a a = dot (cross v u) (cross v u)).
  { unfold a. rewrite !lagrange, (dot_comm u v). ring. }
  assert (E : forall x y, dot (vadd (vscale x a) (vscale y b)) (vadd (vscale x a) (vscale y b))
                          = x * x * dot a a + y * y * dot b b + 2 * x * y * dot a b)
    by (intros; vec_unfold; ring).
  rewrite E, Hab, Hbb, <- Haa, cos_minus.
  pose proof (sin_cos_sq phi1). pose proof (sin_cos_sq phi2).
  nsatz.
Qed.

(** ** Theorem 1(a): chord ≤ arc. *)
Theorem revolute_chord_le_arc : forall ax phi1 phi2 p,
  axis_unit ax -> kind ax = Revolute ->
  dist (move_point ax phi1 p) (move_point ax phi2 p)
  <= axis_dist ax p * Rabs (phi1 - phi2).
Proof.
  intros ax phi1 phi2 p Hu Hk. unfold dist at 1.
  pose proof (axis_dist_nonneg ax p) as Hr.
  apply norm_le_of_sq; [apply Rmult_le_pos; [exact Hr | apply Rabs_pos]|].
  rewrite revolute_chord_sq by assumption.
  pose proof (two_one_minus_cos_le (phi1 - phi2)) as Hc.
  replace (axis_dist ax p * Rabs (phi1 - phi2) * (axis_dist ax p * Rabs (phi1 - phi2)))
    with ((Rabs (phi1 - phi2) * Rabs (phi1 - phi2)) * (axis_dist ax p * axis_dist ax p))
    by ring.
  rewrite <- Rabs_mult, Rabs_right by (apply Rle_ge, Rle_0_sqr).
  apply Rmult_le_compat_r; [apply Rle_0_sqr | exact Hc].
Qed.

(** ** Theorem 1(b): a prismatic motion moves every point by exactly [|d1 − d2|]. *)
Theorem prismatic_travel_exact : forall ax d1 d2 p,
  axis_unit ax -> kind ax = Prismatic ->
  dist (move_point ax d1 p) (move_point ax d2 p) = Rabs (d1 - d2).
Proof.
  intros ax d1 d2 p Hu Hk. unfold move_point, dist. rewrite Hk.
  replace (vsub (vadd p (vscale d1 (direction ax))) (vadd p (vscale d2 (direction ax))))
    with (vscale (d1 - d2) (direction ax)) by vec_ring.
  rewrite norm_scale, norm_unit by exact Hu. ring.
Qed.

(** ** The motion bound of bound.rs *)

Definition lipschitz (k : joint_kind) (r : R) : R :=
  match k with Revolute => r | Prismatic => 1 end.

Definition max_displacement (k : joint_kind) (r delta : R) : R := lipschitz k r * Rabs delta.

(** A point within [r] of the axis travels at most [max_displacement] (both kinds). *)
Theorem point_travel_bound : forall ax r phi1 phi2 p,
  axis_unit ax -> axis_dist ax p <= r ->
  dist (move_point ax phi1 p) (move_point ax phi2 p)
  <= max_displacement (kind ax) r (phi1 - phi2).
Proof.
  intros ax r phi1 phi2 p Hu Hr. unfold max_displacement, lipschitz.
  destruct (kind ax) eqn:Hk.
  - eapply Rle_trans; [apply revolute_chord_le_arc; assumption|].
    apply Rmult_le_compat_r; [apply Rabs_pos | exact Hr].
  - rewrite prismatic_travel_exact by assumption. lra.
Qed.

(** ** The sweep radius *)

(** A collider's bounding sphere in the world ([Placed] / [world_center] in
    src/scene/collision/geometry.rs). *)
Record sphere := mkSphere { centre : V3; radius : R }.

Definition in_sphere (s : sphere) (x : V3) : Prop := dist x (centre s) <= radius s.

(** [sweep_radius] of bound.rs: [r] starts at 0 and takes the maximum with
    [dist(centre, axis) + radius] for every collider and [dist(handle, axis)] for every
    handle of the subtree. The Rust loop visits parts in subtree order, colliders before
    handles of each part; [Rmax] is associative and commutative, so the order does not
    matter ([sweep_radius_is_max] characterises the value independently of it). *)
Definition sweep_radius (ax : joint_axis) (colliders : list sphere) (handles : list V3) : R :=
  fold_right (fun s r => Rmax (axis_dist ax (centre s) + radius s) r)
    (fold_right (fun h r => Rmax (axis_dist ax h) r) 0 handles)
    colliders.

(** A point of the moving subtree: a point of (the bounding sphere of) one of its colliders,
    or one of its handle points. *)
Definition subtree_point (colliders : list sphere) (handles : list V3) (x : V3) : Prop :=
  (exists s, In s colliders /\ in_sphere s x) \/ In x handles.

Lemma sweep_radius_nonneg : forall ax cs hs, 0 <= sweep_radius ax cs hs.
Proof.
  intros ax cs hs. unfold sweep_radius. induction cs as [|s cs IH]; simpl.
  - induction hs as [|h hs IHh]; simpl; [lra|].
    eapply Rle_trans; [exact IHh | apply Rmax_r].
  - eapply Rle_trans; [exact IH | apply Rmax_r].
Qed.

Lemma sweep_radius_ge_sphere : forall ax cs hs s,
  In s cs -> axis_dist ax (centre s) + radius s <= sweep_radius ax cs hs.
Proof.
  intros ax cs hs s Hin. unfold sweep_radius. induction cs as [|s' cs IH]; simpl in *.
  - contradiction.
  - destruct Hin as [<-|Hin]; [apply Rmax_l|].
    eapply Rle_trans; [exact (IH Hin) | apply Rmax_r].
Qed.

Lemma sweep_radius_ge_handle : forall ax cs hs h,
  In h hs -> axis_dist ax h <= sweep_radius ax cs hs.
Proof.
  intros ax cs hs h Hin. unfold sweep_radius. induction cs as [|s' cs IH]; simpl.
  - induction hs as [|h' hs IHh]; simpl in *; [contradiction|].
    destruct Hin as [<-|Hin]; [apply Rmax_l|].
    eapply Rle_trans; [exact (IHh Hin) | apply Rmax_r].
  - eapply Rle_trans; [exact IH | apply Rmax_r].
Qed.

(** [sweep_radius] is exactly the maximum of 0 and the listed values: an upper bound of
    them that is attained by one of them (or is 0). *)
Theorem sweep_radius_is_max : forall ax cs hs,
  0 <= sweep_radius ax cs hs
  /\ (forall s, In s cs -> axis_dist ax (centre s) + radius s <= sweep_radius ax cs hs)
  /\ (forall h, In h hs -> axis_dist ax h <= sweep_radius ax cs hs)
  /\ (sweep_radius ax cs hs = 0
      \/ (exists s, In s cs /\ sweep_radius ax cs hs = axis_dist ax (centre s) + radius s)
      \/ (exists h, In h hs /\ sweep_radius ax cs hs = axis_dist ax h)).
Proof.
  intros ax cs hs. split; [apply sweep_radius_nonneg|].
  split; [intros; apply sweep_radius_ge_sphere; assumption|].
  split; [intros; apply sweep_radius_ge_handle; assumption|].
  unfold sweep_radius. induction cs as [|s cs IH]; simpl.
  - induction hs as [|h hs IHh]; simpl; [left; reflexivity|].
    destruct (Rle_dec (axis_dist ax h) (fold_right (fun h r => Rmax (axis_dist ax h) r) 0 hs))
      as [Hle|Hgt].
    + rewrite Rmax_right by exact Hle.
      destruct IHh as [H0|[[s [[] _]]|[h' [Hh' E]]]]; [left; exact H0|].
      right; right; exists h'; split; [right; exact Hh' | exact E].
    + rewrite Rmax_left by lra. right; right; exists h; split; [left|]; reflexivity.
  - match goal with |- context [Rmax ?v ?rest] =>
      destruct (Rle_dec v rest) as [Hle|Hgt] end.
    + rewrite Rmax_right by exact Hle.
      destruct IH as [H0|[[s' [Hs' E]]|[h' [Hh' E]]]]; [left; exact H0| |].
      * right; left; exists s'; split; [right; exact Hs' | exact E].
      * right; right; exists h'; split; [exact Hh' | exact E].
    + rewrite Rmax_left by lra. right; left; exists s; split; [left|]; reflexivity.
Qed.

(** Every point of the subtree is within [r] of the axis:
    [|x − axis| <= dist(centre, axis) + |x − centre| <= dist(centre, axis) + radius <= r]. *)
Theorem subtree_point_within_radius : forall ax cs hs x,
  axis_unit ax -> subtree_point cs hs x -> axis_dist ax x <= sweep_radius ax cs hs.
Proof.
  intros ax cs hs x Hu [[s [Hin Hs]]|Hin].
  - eapply Rle_trans; [apply (axis_dist_le ax x (centre s) Hu)|].
    eapply Rle_trans; [|apply (sweep_radius_ge_sphere ax cs hs s Hin)].
    unfold in_sphere in Hs. lra.
  - apply sweep_radius_ge_handle; exact Hin.
Qed.

(** ** Theorem 1(c): the motion bound of a one-joint motion. With [r] the sweep radius at the
    state where the subtree points [x] were placed (joint value [θ0]), the subtree point at
    joint value [θ] is [move_point ax (θ − θ0) x]; between any two values it travels at most
    [L·|θ − θ'|]. *)
Theorem sweep_bound : forall ax cs hs x phi1 phi2,
  axis_unit ax -> subtree_point cs hs x ->
  dist (move_point ax phi1 x) (move_point ax phi2 x)
  <= max_displacement (kind ax) (sweep_radius ax cs hs) (phi1 - phi2).
Proof.
  intros. apply point_travel_bound; [assumption|].
  apply subtree_point_within_radius; assumption.
Qed.

Definition move_sphere (ax : joint_axis) (delta : R) (s : sphere) : sphere :=
  mkSphere (move_point ax delta (centre s)) (radius s).

(** The subtree moves rigidly, so its points stay in the moved spheres ... *)
Lemma in_sphere_move : forall ax delta s x,
  axis_unit ax -> in_sphere s x -> in_sphere (move_sphere ax delta s) (move_point ax delta x).
Proof.
  intros ax delta s x Hu Hs. unfold in_sphere, move_sphere in *; simpl.
  rewrite move_point_rigid by exact Hu. exact Hs.
Qed.

(** ... and the sweep radius computed from the moved geometry is the same: [r] does not
    depend on the joint's own value. *)
Theorem sweep_radius_invariant : forall ax delta cs hs,
  axis_unit ax ->
  sweep_radius ax (map (move_sphere ax delta) cs) (map (move_point ax delta) hs)
  = sweep_radius ax cs hs.
Proof.
  intros ax delta cs hs Hu. unfold sweep_radius.
  induction cs as [|s cs IH]; simpl.
  - induction hs as [|h hs IHh]; simpl; [reflexivity|].
    rewrite IHh, axis_dist_move by exact Hu. reflexivity.
  - rewrite IH, axis_dist_move by exact Hu. reflexivity.
Qed.

(** Every moved subtree point stays within [r] of the axis. *)
Corollary moved_point_within_radius : forall ax cs hs x delta,
  axis_unit ax -> subtree_point cs hs x ->
  axis_dist ax (move_point ax delta x) <= sweep_radius ax cs hs.
Proof.
  intros. rewrite axis_dist_move by assumption. apply subtree_point_within_radius; assumption.
Qed.

(** ** Theorem 1(d): nested parts — the bounds of the ancestors' motions add.

    Forward kinematics (src/scene/kinematics.rs) places a point [x] of a part nested under
    joints [j1 … jn] (root first) at [M1(θ1) (M2(θ2) (… Mn(θn) x))], where
    [Mi(θ) = parent_from_jointᵢ ∘ (joint i's motion by θ)] is rigid for every [θ]. A [link]
    is one such [Mi] with its start value, end value and a bound on the travel it causes. *)

Definition rigid (f : V3 -> V3) : Prop := forall a b, dist (f a) (f b) = dist a b.

Record link := mkLink {
  motion : R -> V3 -> V3;
  start : R;
  finish : R;
  bound : R }.

(** The world position of [x] with every joint of the chain at [sel] of its link. *)
Fixpoint place (sel : link -> R) (chain : list link) (x : V3) : V3 :=
  match chain with
  | [] => x
  | l :: rest => motion l (sel l) (place sel rest x)
  end.

(** Each joint's own step is bounded: moving joint [i] from [start] to [finish], with the
    joints below it already at [finish] (those above do not matter: they are rigid). This is
    what [max_displacement] bounds for a one-joint motion at that state. *)
Fixpoint steps_bounded (chain : list link) (x : V3) : Prop :=
  match chain with
  | [] => True
  | l :: rest =>
      dist (motion l (start l) (place finish rest x)) (motion l (finish l) (place finish rest x))
        <= bound l
      /\ steps_bounded rest x
  end.

Fixpoint total_bound (chain : list link) : R :=
  match chain with [] => 0 | l :: rest => bound l + total_bound rest end.

Theorem ancestors_add : forall chain x,
  (forall l, In l chain -> forall t, rigid (motion l t)) ->
  steps_bounded chain x ->
  dist (place start chain x) (place finish chain x) <= total_bound chain.
Proof.
  induction chain as [|l rest IH]; intros x Hrigid Hsteps; simpl in *.
  - unfold dist. replace (vsub x x) with vzero by vec_ring.
    unfold norm, dot; simpl. replace (0 * 0 + 0 * 0 + 0 * 0) with 0 by ring.
    rewrite sqrt_0. lra.
  - destruct Hsteps as [Hl Hrest].
    eapply Rle_trans; [apply dist_triangle with
      (b := motion l (start l) (place finish rest x))|].
    rewrite (Hrigid l (or_introl eq_refl)).
    pose proof (IH x (fun l' H => Hrigid l' (or_intror H)) Hrest). lra.
Qed.

(** The chain of forward kinematics: link [i] is a rigid placement [P] (parent_from_joint)
    after the motion about joint [i]'s axis, with the [max_displacement] bound of radius [r]. *)
Definition fk_link (P : V3 -> V3) (ax : joint_axis) (t t' r : R) : link :=
  mkLink (fun theta y => P (move_point ax theta y)) t t' (max_displacement (kind ax) r (t - t')).

Fixpoint fk_links (js : list ((V3 -> V3) * joint_axis * R * R * R)) : list link :=
  match js with
  | [] => []
  | (P, ax, t, t', r) :: rest => fk_link P ax t t' r :: fk_links rest
  end.

(** The conditions of [nested_sweep_bound]: every placement is rigid, every axis is unit, and
    the point (placed by the joints below at their end values) is within each joint's radius
    — which [subtree_point_within_radius] gives for [r] the joint's [sweep_radius]. *)
Fixpoint within_radii (js : list ((V3 -> V3) * joint_axis * R * R * R)) (x : V3) : Prop :=
  match js with
  | [] => True
  | (P, ax, t, t', r) :: rest =>
      rigid P /\ axis_unit ax
      /\ axis_dist ax (place finish (fk_links rest) x) <= r
      /\ within_radii rest x
  end.

Fixpoint total_displacement (js : list ((V3 -> V3) * joint_axis * R * R * R)) : R :=
  match js with
  | [] => 0
  | (P, ax, t, t', r) :: rest => max_displacement (kind ax) r (t - t') + total_displacement rest
  end.

Lemma total_bound_fk_links : forall js, total_bound (fk_links js) = total_displacement js.
Proof.
  induction js as [|[[[[P ax] t] t'] r] rest IH]; simpl; [reflexivity|]. rewrite IH. reflexivity.
Qed.

(** A point of a nested part, with all its ancestor joints moving from [t] to [t'] at once,
    travels at most the sum of the ancestors' [max_displacement]s. *)
Theorem nested_sweep_bound : forall js x,
  within_radii js x ->
  dist (place start (fk_links js) x) (place finish (fk_links js) x) <= total_displacement js.
Proof.
  intros js x H. rewrite <- total_bound_fk_links.
  apply ancestors_add.
  - induction js as [|[[[[P ax] t] t'] r] rest IH]; simpl; [contradiction|].
    destruct H as [HP [Hu [_ Hrest]]].
    intros l [<-|Hin] theta a b; simpl.
    + rewrite HP. apply move_point_rigid; exact Hu.
    + apply (IH Hrest l Hin).
  - induction js as [|[[[[P ax] t] t'] r] rest IH]; simpl; [exact I|].
    destruct H as [HP [Hu [Hr Hrest]]]. split; [|apply IH; exact Hrest].
    rewrite HP. apply point_travel_bound; assumption.
Qed.
