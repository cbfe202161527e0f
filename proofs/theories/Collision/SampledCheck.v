(** * SampledCheck: the sampled sweep check cannot miss a collision (theorem 1,
    corollary).

    Models [check_joint_motion] (src/scene/collision/sweep.rs) and its interval search
    [Search::run], [Search::search], [Search::refine] (src/scene/collision/search.rs):
    - [L] is [MotionBound::lipschitz] (the sweep radius for a revolute joint, 1 for a
      prismatic one), [c] is [contact_distance], [mm] is [SweepSettings::min_margin];
    - [ell θ] is the computed clearance lower bound of [Search::sample] (exact parry
      distances, or bounding-sphere gaps for pairs farther than the cutoff), minimised over
      the checked pairs;
    - the first samples split [[a, b]] into [n] equal intervals, [n = ⌈L·|b − a| / (2·margin)⌉]
      at least 1 ([initial_samples]);
    - the certificate of an interval [[s, e]] ([certifies]) is exactly the Rust test
      [le > c && ls + le − travel > 2c] with [travel = L·|e − s|];
    - an interval that fails it is halved while [travel > 2·min_margin] ([refine]); a finest
      interval that still fails reports a collision if [ell e <= c], else it is unresolved and
      the search goes on; [then_] is the Rust control flow (stop at the first collision,
      remember the first unresolved interval);
    - [run] first rejects [ell a <= c], then scans the intervals from [a] to [b]; the status is
      [Free] iff every interval was certified.

    Assumptions: exact real arithmetic (no rounding; the Rust [splittable] test only matters
    in floating point: over the reals a split interval has [s ≠ e], and [s = e] has travel 0);
    [ell θ] is a lower bound on the separation at [θ]; the separation is [L]-Lipschitz in the
    joint value (proved from the motion bound in [check_joint_motion_free_sound] and
    [check_free_set_distance]). The sample budget ([max_samples]) is not modelled: running out
    of it only turns a result into [Inconclusive], never into [Free], so every [Free] verdict
    of the Rust function is a [Free] verdict of this model. The recursion depth is modelled by
    [fuel]; [refine_terminates] shows that enough fuel makes the result independent of it,
    i.e. equal to the unbounded Rust recursion.

    Main results:
    - [certified_interval_sound]: a certified interval has [D(θ) > c] everywhere on it;
    - [margin_certifies], [initial_interval_travel]: with the Rust spacing, each first interval
      has travel [<= 2·margin], so samples with clearance [> c + margin] certify it;
    - [run_free_sound]: [Free] implies [D(θ) > c] for every [θ] between [a] and [b];
    - [check_joint_motion_free_sound]: for a one-joint motion of a subtree with the
      [sweep_radius] bound, [Free] implies that no point of the moving colliders comes within
      [contact_distance] of a point of a checked fixed body at any [θ] between [a] and [b];
    - [check_free_set_distance]: the same for the exact separation ([glb] over point pairs).

    Checked on the implementation by: tests/scene/sweep_soundness.rs
    [sampled_check_never_misses_a_brute_force_collision] (dense brute-force sampling never
    finds a collision in an interval certified free), tests/scene/sweep.rs
    [thin_plate_missed_by_six_samples_is_caught] and
    [grazing_contact_is_inconclusive_and_budget_is_respected]. *)

From Coq Require Import Reals Lra Psatz List.
From KinScene Require Import Geometry.Vec3 Motion.JointAxis Motion.SweepBound
  Collision.SetDistance.
Import ListNotations.
Open Scope R_scope.

(** [θ] lies in the closed interval between [s] and [e] (in either order: motions may go
    down, [b < a]). *)
Definition between (s e theta : R) : Prop := Rmin s e <= theta <= Rmax s e.

Lemma between_split : forall s m e theta,
  between s e theta -> between s m theta \/ between m e theta.
Proof.
  intros s m e theta. unfold between, Rmin, Rmax.
  destruct (Rle_dec s e), (Rle_dec s m), (Rle_dec m e); intros; lra.
Qed.

Lemma between_abs : forall s e theta,
  between s e theta -> Rabs (theta - s) + Rabs (e - theta) = Rabs (e - s).
Proof.
  intros s e theta. unfold between, Rmin, Rmax. destruct (Rle_dec s e); intros H;
  unfold Rabs; repeat destruct Rcase_abs; lra.
Qed.

Lemma between_refl : forall s, between s s s.
Proof. intros s. unfold between, Rmin, Rmax. destruct (Rle_dec s s); lra. Qed.

Lemma between_same : forall s theta, between s s theta -> theta = s.
Proof. intros s theta. unfold between, Rmin, Rmax. destruct (Rle_dec s s); lra. Qed.

Lemma between_r : forall s e, between s e e.
Proof. intros s e. unfold between, Rmin, Rmax. destruct (Rle_dec s e); lra. Qed.

Lemma abs_le_between : forall x y, Rabs x <= y -> - y <= x <= y.
Proof. intros x y. unfold Rabs; destruct (Rcase_abs x); lra. Qed.

(** [D] is [L]-Lipschitz. *)
Definition lipschitz_fn (L : R) (D : R -> R) : Prop :=
  forall theta theta', Rabs (D theta - D theta') <= L * Rabs (theta - theta').

(** ** The certificate of one interval *)

(** [Search::refine]'s acceptance test, with [ls = ell s], [le = ell e]. *)
Definition certifies (c L s e ls le : R) : Prop :=
  c < le /\ 2 * c < ls + le - L * Rabs (e - s).

Definition certifies_dec (c L s e ls le : R) : {certifies c L s e ls le} + {~ certifies c L s e ls le}.
Proof.
  unfold certifies.
  destruct (Rlt_dec c le), (Rlt_dec (2 * c) (ls + le - L * Rabs (e - s))); tauto.
Defined.

(** If the separation at the samples exceeds what travel across the interval can consume,
    there is no collision anywhere in it:
    [D(θ) >= max(ℓ(s) − L|θ − s|, ℓ(e) − L|e − θ|) >= (ℓ(s) + ℓ(e) − L|e − s|)/2 > c]. *)
Theorem certified_interval_sound : forall (c L : R) (ell D : R -> R) s e,
  (forall theta, ell theta <= D theta) -> lipschitz_fn L D ->
  certifies c L s e (ell s) (ell e) ->
  forall theta, between s e theta -> c < D theta.
Proof.
  intros c L ell D s e Hlow Hlip [_ Hcert] theta Hbt.
  pose proof (between_abs _ _ _ Hbt) as Habs.
  pose proof (Hlip theta s) as H1. pose proof (Hlip e theta) as H2.
  pose proof (Hlow s). pose proof (Hlow e).
  apply abs_le_between in H1. apply abs_le_between in H2.
  assert (L * Rabs (e - s) = L * Rabs (theta - s) + L * Rabs (e - theta))
    by (rewrite <- Habs; ring).
  lra.
Qed.

(** ** The margin rule. With margin [m >= 0]: samples no farther apart than a travel of [2m],
    each with clearance [> c + m], pass the certificate. *)
Theorem margin_certifies : forall c L m s e ls le,
  0 <= m -> L * Rabs (e - s) <= 2 * m -> c + m < ls -> c + m < le ->
  certifies c L s e ls le.
Proof. intros; unfold certifies; lra. Qed.

(** The first samples of [Search::run]: [a + k·h] for [k = 1 … n − 1], then [b], with
    [h = (b − a)/n]. *)
Definition initial_samples (a b : R) (n : nat) : list R :=
  map (fun k => a + INR k * ((b - a) / INR n)) (seq 1 (n - 1)) ++ [b].

(** Consecutive samples, starting from [prev]. *)
Fixpoint intervals (prev : R) (ts : list R) : list (R * R) :=
  match ts with [] => [] | t :: rest => (prev, t) :: intervals t rest end.

Lemma intervals_spacing_aux : forall a h m k0,
  Forall (fun '(s, e) => e - s = h)
    (intervals (a + INR k0 * h)
       (map (fun k => a + INR k * h) (seq (S k0) m) ++ [a + INR (S k0 + m) * h])).
Proof.
  intros a h m. induction m as [|m IH]; intros k0; cbn [intervals map seq app].
  - constructor; [|constructor]. rewrite Nat.add_0_r, S_INR. ring.
  - constructor.
    + rewrite S_INR. ring.
    + replace (S k0 + S m)%nat with (S (S k0) + m)%nat by lia. apply IH.
Qed.

(** The first intervals all have length exactly [h = (b − a)/n]. *)
Theorem initial_samples_spacing : forall a b n,
  (1 <= n)%nat ->
  Forall (fun '(s, e) => e - s = (b - a) / INR n) (intervals a (initial_samples a b n)).
Proof.
  intros a b n Hn. unfold initial_samples.
  assert (Hn0 : INR n <> 0) by (apply not_0_INR; lia).
  pose proof (intervals_spacing_aux a ((b - a) / INR n) (n - 1) 0) as H.
  replace (a + INR 0 * ((b - a) / INR n)) with a in H by (simpl; ring).
  replace (a + INR (S 0 + (n - 1)) * ((b - a) / INR n)) with b in H.
  - exact H.
  - replace (S 0 + (n - 1))%nat with n by lia. field. exact Hn0.
Qed.

(** With [n >= L·|b − a| / (2·margin)] (true of [⌈·⌉] in the Rust code), every first interval
    has travel [L·|h| <= 2·margin]. *)
Theorem initial_interval_travel : forall L margin a b n,
  0 < margin -> (1 <= n)%nat -> L * Rabs (b - a) / (2 * margin) <= INR n ->
  L * Rabs ((b - a) / INR n) <= 2 * margin.
Proof.
  intros L margin a b n Hm Hn Hcount.
  assert (Hpos : 0 < INR n) by (apply lt_0_INR; lia).
  unfold Rdiv at 1. rewrite Rabs_mult, Rabs_inv, (Rabs_right (INR n)) by lra.
  apply Rmult_le_reg_r with (INR n); [exact Hpos|].
  replace (L * (Rabs (b - a) * / INR n) * INR n) with (L * Rabs (b - a)) by (field; lra).
  apply Rmult_le_compat_l with (r := 2 * margin) in Hcount; [|lra].
  replace (2 * margin * (L * Rabs (b - a) / (2 * margin))) with (L * Rabs (b - a))
    in Hcount by (field; lra).
  lra.
Qed.

(** ** The interval search *)

(** The outcome of refining one interval ([Ok(())] with or without a recorded unresolved
    interval, or [Err(collision)] in the Rust code). *)
Inductive verdict := Certified | Collision (value : R) | Unresolved (value : R).

(** Explore one interval, then the next: stop at a collision, keep the first unresolved. *)
Definition then_ (first next : verdict) : verdict :=
  match first with
  | Collision v => Collision v
  | Certified => next
  | Unresolved u => match next with Collision v => Collision v | _ => Unresolved u end
  end.

(** A finest interval that fails the certificate. *)
Definition finest (c : R) (ell : R -> R) (s e : R) : verdict :=
  if Rle_dec (ell e) c then Collision e
  else Unresolved (if Rle_dec (ell s) (ell e) then s else e).

Fixpoint refine (c L mm : R) (ell : R -> R) (fuel : nat) (s e : R) : verdict :=
  if certifies_dec c L s e (ell s) (ell e) then Certified
  else match fuel with
  | O => finest c ell s e
  | S f =>
      if Rle_dec (L * Rabs (e - s)) (2 * mm) then finest c ell s e
      else then_ (refine c L mm ell f s ((s + e) / 2)) (refine c L mm ell f ((s + e) / 2) e)
  end.

Fixpoint scan (c L mm : R) (ell : R -> R) (fuel : nat) (prev : R) (ts : list R) : verdict :=
  match ts with
  | [] => Certified
  | t :: rest => then_ (refine c L mm ell fuel prev t) (scan c L mm ell fuel t rest)
  end.

(** [SweepStatus]: [Free], [Collision { value }], [Inconclusive { value }]. *)
Inductive status := Free | Collides (value : R) | Inconclusive (value : R).

Definition run (c L mm : R) (ell : R -> R) (fuel : nat) (a b : R) (n : nat) : status :=
  if Rle_dec (ell a) c then Collides a
  else match scan c L mm ell fuel a (initial_samples a b n) with
       | Certified => Free
       | Collision v => Collides v
       | Unresolved u => Inconclusive u
       end.

Lemma then_certified : forall o1 o2, then_ o1 o2 = Certified -> o1 = Certified /\ o2 = Certified.
Proof. intros [] [] H; simpl in H; try discriminate; auto. Qed.

Lemma finest_not_certified : forall c ell s e, finest c ell s e <> Certified.
Proof.
  intros. unfold finest. destruct (Rle_dec (ell e) c); [|destruct (Rle_dec (ell s) (ell e))];
  discriminate.
Qed.

(** A [Certified] refinement certified every leaf interval, and the leaves cover [[s, e]]. *)
Lemma refine_certified_sound : forall c L mm ell D fuel s e,
  (forall theta, ell theta <= D theta) -> lipschitz_fn L D ->
  refine c L mm ell fuel s e = Certified ->
  forall theta, between s e theta -> c < D theta.
Proof.
  intros c L mm ell D fuel. induction fuel as [|f IH]; intros s e Hlow Hlip Href theta Hbt;
  simpl in Href; destruct (certifies_dec c L s e (ell s) (ell e)) as [Hc|Hc].
  - eapply certified_interval_sound; eassumption.
  - exfalso; eapply finest_not_certified; exact Href.
  - eapply certified_interval_sound; eassumption.
  - destruct (Rle_dec (L * Rabs (e - s)) (2 * mm)).
    + exfalso; eapply finest_not_certified; exact Href.
    + apply then_certified in Href. destruct Href as [H1 H2].
      destruct (between_split s ((s + e) / 2) e theta Hbt) as [Hb|Hb].
      * exact (IH _ _ Hlow Hlip H1 theta Hb).
      * exact (IH _ _ Hlow Hlip H2 theta Hb).
Qed.

Lemma last_cons_default : forall (l : list R) t d, last (t :: l) d = last l t.
Proof.
  induction l as [|x l IH]; intros t d; [reflexivity|].
  change (last (t :: x :: l) d) with (last (x :: l) d).
  rewrite !IH. reflexivity.
Qed.

Lemma scan_certified_sound : forall c L mm ell D fuel ts prev,
  (forall theta, ell theta <= D theta) -> lipschitz_fn L D ->
  c < D prev ->
  scan c L mm ell fuel prev ts = Certified ->
  forall theta, between prev (last ts prev) theta -> c < D theta.
Proof.
  intros c L mm ell D fuel ts. induction ts as [|t rest IH]; intros prev Hlow Hlip Hprev Hscan
    theta Hbt.
  - simpl in Hbt. rewrite (between_same _ _ Hbt). exact Hprev.
  - cbn [scan] in Hscan. apply then_certified in Hscan. destruct Hscan as [Hr Hs].
    rewrite last_cons_default in Hbt.
    pose proof (refine_certified_sound c L mm ell D fuel prev t Hlow Hlip Hr) as Hseg.
    destruct (between_split prev t (last rest t) theta Hbt) as [Hb|Hb].
    + exact (Hseg theta Hb).
    + exact (IH t Hlow Hlip (Hseg t (between_r prev t)) Hs theta Hb).
Qed.

Lemma last_initial_samples : forall a b n, last (initial_samples a b n) a = b.
Proof. intros; unfold initial_samples; apply last_last. Qed.

(** ** The corollary for the abstract separation [D]: a [Free] verdict leaves no [θ] between
    [a] and [b] with [D(θ) <= c], for any number of first intervals and any fuel. *)
Theorem run_free_sound : forall c L mm ell D fuel a b n,
  (forall theta, ell theta <= D theta) -> lipschitz_fn L D ->
  run c L mm ell fuel a b n = Free ->
  forall theta, between a b theta -> c < D theta.
Proof.
  intros c L mm ell D fuel a b n Hlow Hlip Hrun theta Hbt. unfold run in Hrun.
  destruct (Rle_dec (ell a) c) as [|Ha]; [discriminate|].
  destruct (scan c L mm ell fuel a (initial_samples a b n)) eqn:Hs; try discriminate.
  eapply scan_certified_sound; try eassumption.
  - pose proof (Hlow a). lra.
  - rewrite last_initial_samples. exact Hbt.
Qed.

(** ** Termination: the recursion depth is bounded. Once [L·|e − s| <= 2ⁿ·2·min_margin],
    [n] levels of halving reach the finest resolution and more fuel changes nothing. *)
Lemma refine_fuel_stable : forall c L mm ell n s e,
  L * Rabs (e - s) <= 2 ^ n * (2 * mm) ->
  forall k, refine c L mm ell (n + k) s e = refine c L mm ell n s e.
Proof.
  intros c L mm ell n. induction n as [|n IH]; intros s e Htr k.
  - destruct k as [|k]; [reflexivity|]. cbn [refine Nat.add].
    destruct (certifies_dec c L s e (ell s) (ell e)); [reflexivity|].
    destruct (Rle_dec (L * Rabs (e - s)) (2 * mm)); [reflexivity | simpl in Htr; lra].
  - cbn [refine Nat.add].
    destruct (certifies_dec c L s e (ell s) (ell e)); [reflexivity|].
    destruct (Rle_dec (L * Rabs (e - s)) (2 * mm)); [reflexivity|].
    simpl in Htr.
    assert (Hhalf1 : L * Rabs ((s + e) / 2 - s) <= 2 ^ n * (2 * mm)).
    { replace ((s + e) / 2 - s) with ((e - s) / 2) by field.
      unfold Rdiv. rewrite Rabs_mult, (Rabs_right (/ 2)) by lra. lra. }
    assert (Hhalf2 : L * Rabs (e - (s + e) / 2) <= 2 ^ n * (2 * mm)).
    { replace (e - (s + e) / 2) with ((e - s) / 2) by field.
      unfold Rdiv. rewrite Rabs_mult, (Rabs_right (/ 2)) by lra. lra. }
    rewrite (IH _ _ Hhalf1), (IH _ _ Hhalf2). reflexivity.
Qed.

Theorem refine_terminates : forall c L mm ell s e,
  0 < mm -> exists n, forall k, refine c L mm ell (n + k) s e = refine c L mm ell n s e.
Proof.
  intros c L mm ell s e Hmm.
  destruct (Pow_x_infinity 2 ltac:(rewrite Rabs_right; lra) (L * Rabs (e - s) / (2 * mm)))
    as [n Hn].
  exists n. apply refine_fuel_stable.
  specialize (Hn n (le_n n)).
  rewrite Rabs_right in Hn by (apply Rle_ge, pow_le; lra).
  apply Rge_le in Hn.
  apply Rmult_le_compat_r with (r := 2 * mm) in Hn; [|lra].
  replace (L * Rabs (e - s) / (2 * mm) * (2 * mm)) with (L * Rabs (e - s)) in Hn
    by (field; lra).
  lra.
Qed.

(** ** Tied to the geometry *)

(** For each checked pair of points, the separation is a Lipschitz function bounded below by
    [ell]; so a [Free] verdict keeps every pair apart by more than [c] everywhere. *)
Theorem run_free_no_contact : forall {I J : Type} (X : R -> I -> V3) (Y : J -> V3)
    (checked : I -> J -> Prop) c L mm ell fuel a b n,
  (forall theta theta' i, dist (X theta i) (X theta' i) <= L * Rabs (theta - theta')) ->
  (forall theta i j, checked i j -> ell theta <= dist (X theta i) (Y j)) ->
  run c L mm ell fuel a b n = Free ->
  forall theta, between a b theta ->
  forall i j, checked i j -> c < dist (X theta i) (Y j).
Proof.
  intros I J X Y checked c L mm ell fuel a b n Hmove Hlow Hrun theta Hbt i j Hc.
  apply (run_free_sound c L mm ell (fun t => dist (X t i) (Y j)) fuel a b n); auto.
  intros t t'. apply Rabs_le. split.
  - pose proof (dist_triangle (X t' i) (X t i) (Y j)).
    rewrite (dist_sym (X t' i) (X t i)) in H. specialize (Hmove t t' i). lra.
  - pose proof (dist_triangle (X t i) (X t' i) (Y j)). specialize (Hmove t t' i). lra.
Qed.

(** [check_joint_motion] is sound. The moving points are the points of the colliders of the
    joint's subtree placed at the state's joint value [θ0] ([X0], each within a collider's
    bounding sphere); at joint value [θ] they are at [move_point ax (θ − θ0) (X0 i)]; the
    Lipschitz constant is [MotionBound::lipschitz] of the [sweep_radius]. If the verdict is
    [Free], then for every [θ] between [a] and [b] every moving point is farther than
    [contact_distance] from every point of every checked fixed body. *)
Theorem check_joint_motion_free_sound :
  forall {I J : Type} (ax : joint_axis) (cs : list sphere) (hs : list V3)
    (X0 : I -> V3) (Y : J -> V3) (checked : I -> J -> Prop)
    (theta0 c mm : R) (ell : R -> R) fuel a b n,
  axis_unit ax ->
  (forall i, subtree_point cs hs (X0 i)) ->
  (forall theta i j, checked i j ->
     ell theta <= dist (move_point ax (theta - theta0) (X0 i)) (Y j)) ->
  run c (lipschitz (kind ax) (sweep_radius ax cs hs)) mm ell fuel a b n = Free ->
  forall theta, between a b theta ->
  forall i j, checked i j -> c < dist (move_point ax (theta - theta0) (X0 i)) (Y j).
Proof.
  intros I J ax cs hs X0 Y checked theta0 c mm ell fuel a b n Hu Hpts Hlow Hrun.
  apply (run_free_no_contact (fun t i => move_point ax (t - theta0) (X0 i)) Y checked c
           (lipschitz (kind ax) (sweep_radius ax cs hs)) mm ell fuel a b n); try assumption.
  intros t t' i.
  pose proof (sweep_bound ax cs hs (X0 i) (t - theta0) (t' - theta0) Hu (Hpts i)) as H.
  unfold max_displacement in H.
  replace (t - theta0 - (t' - theta0)) with (t - t') in H by ring. exact H.
Qed.

(** The same for the exact separation [D(θ)] (the greatest lower bound of the distances over
    the checked point pairs): [Free] implies [D(θ) > contact_distance] on the interval. *)
Theorem check_free_set_distance :
  forall {I J : Type} (X : R -> I -> V3) (Y : J -> V3) (checked : I -> J -> Prop)
    (D : R -> R) c L mm ell fuel a b n,
  (forall theta theta' i, dist (X theta i) (X theta' i) <= L * Rabs (theta - theta')) ->
  (forall theta, is_glb (clearances X Y checked theta) (D theta)) ->
  (forall theta i j, checked i j -> ell theta <= dist (X theta i) (Y j)) ->
  run c L mm ell fuel a b n = Free ->
  forall theta, between a b theta -> c < D theta.
Proof.
  intros I J X Y checked D c L mm ell fuel a b n Hmove Hglb Hlow Hrun.
  apply (run_free_sound c L mm ell D fuel a b n); try assumption.
  - intros theta. apply (proj2 (Hglb theta)). intros r [i [j [Hc ->]]]. apply Hlow; exact Hc.
  - intros t t'. apply (clearance_lipschitz X Y checked L D t t'); auto.
Qed.
