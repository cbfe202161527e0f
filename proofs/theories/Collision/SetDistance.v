(** * SetDistance: the distance between point sets is 1-Lipschitz in point displacement.

    Models the collision predicate of [CollisionSettings] (src/scene/collision/settings.rs):
    two bodies collide iff the exact separation between them is [<= contact_distance]; the
    separation of two shapes is the greatest lower bound of the distances between their
    points (parry's [distance], 0 when they touch or overlap). The sweep check
    ([check_joint_motion], src/scene/collision/sweep.rs) takes the minimum over the checked
    pairs of bodies, which is the greatest lower bound over all point pairs of checked bodies
    ([clearances] below).

    Main results:
    - [glb_exists]: a non-empty set of reals bounded below has a greatest lower bound (from the
      standard library's [completeness] axiom), so the separations are well defined;
    - [set_dist_lipschitz]: moving every point of [A] by at most [δ] changes the distance
      between [A] and [B] by at most [δ];
    - [clearance_lipschitz]: if every moving point travels at most [L·|θ − θ'|], the minimum
      separation [D(θ)] over the checked pairs is [L]-Lipschitz in the joint value — the
      fact [check_joint_motion]'s certificate relies on.

    Checked on the implementation by: tests/scene/sweep_soundness.rs
    [sampled_check_never_misses_a_brute_force_collision] (the consequence: no brute-force
    collision inside an interval the check certified). *)

From Coq Require Import Reals Lra Psatz.
From KinScene Require Import Geometry.Vec3.
Open Scope R_scope.

Definition lower_bound (S : R -> Prop) (d : R) : Prop := forall r, S r -> d <= r.

Definition is_glb (S : R -> Prop) (d : R) : Prop :=
  lower_bound S d /\ forall d', lower_bound S d' -> d' <= d.

Lemma glb_unique : forall S d1 d2, is_glb S d1 -> is_glb S d2 -> d1 = d2.
Proof.
  intros S d1 d2 [L1 G1] [L2 G2]. apply Rle_antisym; [apply G2 | apply G1]; assumption.
Qed.

Lemma glb_exists : forall S : R -> Prop,
  (exists r, S r) -> (exists m, lower_bound S m) -> exists d, is_glb S d.
Proof.
  intros S [r Hr] [m Hm].
  destruct (completeness (fun x => S (- x))) as [l [Hub Hleast]].
  - exists (- m). intros x Hx. specialize (Hm _ Hx). lra.
  - exists (- r). rewrite Ropp_involutive. exact Hr.
  - exists (- l). split.
    + intros y Hy. assert (S (- - y)) by (rewrite Ropp_involutive; exact Hy).
      specialize (Hub (- y) H). lra.
    + intros d' Hd'. assert (l <= - d').
      { apply Hleast. intros x Hx. specialize (Hd' _ Hx). lra. }
      lra.
Qed.

(** Two sets whose elements are pairwise within [δ] (each element of one has an element of
    the other at most [δ] above it) have greatest lower bounds within [δ]. *)
Lemma glb_close : forall (S1 S2 : R -> Prop) d1 d2 delta,
  (forall r1, S1 r1 -> exists r2, S2 r2 /\ r2 <= r1 + delta) ->
  (forall r2, S2 r2 -> exists r1, S1 r1 /\ r1 <= r2 + delta) ->
  is_glb S1 d1 -> is_glb S2 d2 -> Rabs (d1 - d2) <= delta.
Proof.
  intros S1 S2 d1 d2 delta H12 H21 [L1 G1] [L2 G2].
  assert (d2 - delta <= d1).
  { apply G1. intros r1 Hr1. destruct (H12 r1 Hr1) as [r2 [Hr2 Hle]].
    specialize (L2 r2 Hr2). lra. }
  assert (d1 - delta <= d2).
  { apply G2. intros r2 Hr2. destruct (H21 r2 Hr2) as [r1 [Hr1 Hle]].
    specialize (L1 r1 Hr1). lra. }
  unfold Rabs; destruct (Rcase_abs (d1 - d2)); lra.
Qed.

(** ** Sets of points *)

Definition pair_dists (A B : V3 -> Prop) : R -> Prop :=
  fun r => exists a b, A a /\ B b /\ r = dist a b.

(** [d] is the distance between the point sets [A] and [B]. *)
Definition set_dist (A B : V3 -> Prop) (d : R) : Prop := is_glb (pair_dists A B) d.

Lemma set_dist_exists : forall A B : V3 -> Prop,
  (exists a, A a) -> (exists b, B b) -> exists d, set_dist A B d.
Proof.
  intros A B [a Ha] [b Hb]. apply glb_exists.
  - exists (dist a b), a, b. auto.
  - exists 0. intros r [x [y [_ [_ ->]]]]. apply dist_nonneg.
Qed.

Definition image (f : V3 -> V3) (A : V3 -> Prop) : V3 -> Prop :=
  fun y => exists x, A x /\ y = f x.

(** ** Distance between sets is 1-Lipschitz in point displacement. *)
Theorem set_dist_lipschitz : forall (A B : V3 -> Prop) (f : V3 -> V3) d d' delta,
  (forall x, A x -> dist (f x) x <= delta) ->
  set_dist A B d -> set_dist (image f A) B d' -> Rabs (d' - d) <= delta.
Proof.
  intros A B f d d' delta Hf Hd Hd'.
  eapply glb_close; [| | exact Hd' | exact Hd].
  - intros r [y [b [[x [Hx ->]] [Hb ->]]]]. exists (dist x b). split.
    + exists x, b. auto.
    + pose proof (dist_triangle x (f x) b). rewrite (dist_sym x (f x)) in H.
      specialize (Hf x Hx). lra.
  - intros r [x [b [Hx [Hb ->]]]]. exists (dist (f x) b). split.
    + exists (f x), b. split; [exists x; auto | auto].
    + pose proof (dist_triangle (f x) x b). specialize (Hf x Hx). lra.
Qed.

(** ** The clearance of a one-joint motion

    [X θ i] is the world position at joint value [θ] of the moving point [i] (a point of a
    collider of the moving subtree), [Y j] a point of a fixed body, [checked i j] says the
    pair of bodies they belong to is checked ([checked_pairs]: not allowed, not parent–child
    unless asked, not both in the moving subtree). *)
Definition clearances {I J : Type} (X : R -> I -> V3) (Y : J -> V3)
    (checked : I -> J -> Prop) (theta : R) : R -> Prop :=
  fun r => exists i j, checked i j /\ r = dist (X theta i) (Y j).

(** The minimum separation over the checked pairs, [D(θ)], is [L]-Lipschitz in [θ] when
    every moving point travels at most [L·|θ − θ'|] (the motion bound, [sweep_bound]). *)
Theorem clearance_lipschitz : forall {I J : Type} (X : R -> I -> V3) (Y : J -> V3)
    (checked : I -> J -> Prop) (L : R) (D : R -> R) theta theta',
  (forall i, dist (X theta i) (X theta' i) <= L * Rabs (theta - theta')) ->
  is_glb (clearances X Y checked theta) (D theta) ->
  is_glb (clearances X Y checked theta') (D theta') ->
  Rabs (D theta - D theta') <= L * Rabs (theta - theta').
Proof.
  intros I J X Y checked L D t t' Hmove Ht Ht'.
  eapply glb_close; [| | exact Ht | exact Ht'].
  - intros r [i [j [Hc ->]]]. exists (dist (X t' i) (Y j)). split.
    + exists i, j. auto.
    + pose proof (dist_triangle (X t' i) (X t i) (Y j)). rewrite (dist_sym (X t' i) (X t i)) in H.
      specialize (Hmove i). lra.
  - intros r [i [j [Hc ->]]]. exists (dist (X t i) (Y j)). split.
    + exists i, j. auto.
    + pose proof (dist_triangle (X t i) (X t' i) (Y j)). specialize (Hmove i). lra.
Qed.
