(** * SpanCover: the continuous motion check of the arm accepts only motions that keep
    their clearance everywhere.

    Models [ArmCheck::check_motion] with continuous motions (the default,
    [ArmCheck::with_continuous]; [certify_motion] in src/kinematics/robot/spheres/arm.rs) and
    the span of a free state ([ArmCheck::span] in src/kinematics/robot/spheres/arm/span.rs):
    - the motion's parameter [t] runs over [[0, 1]];
    - [D t] is one item's distance at [t] (a link against the scene, or a checked pair), and
      [g] the clearance it must keep (the margin plus the certified gap);
    - [v >= 0] bounds how fast [D] changes per unit of [t] (the lever sums of the module
      [levers], the speed the Rust code keeps per item): [D] is [v]-Lipschitz;
    - the oracle [span_at t] is the Rust closure of the same name: [None] when the state at
      [t] is not free (or too close, or the state budget is spent), else [Some s] with the
      state free ([D t > g]) and [v·s <= D t − g] (the span is the least over the items of
      their bound less [g], over their speed: for this item at most that);
    - [certify] is the loop over the pending closed intervals: the middle [m] of the first,
      its span [s]; when [s] exceeds the half-length the interval is covered, else the two
      pieces [[x, m − s]] and [[m + s, y]] are queued at the back;
    - [certify_motion] evaluates [t = 1], then [t = 0], then runs [certify] on what is left.

    Assumptions: exact real arithmetic (the Rust bounds subtract [CERTIFIED_GAP], which covers
    the rounding of the interpolated states and of the spans); [D] is [v]-Lipschitz along the
    motion (the lever bound). The state budget is part of the oracle ([None] once it is
    spent) and the loop's length is modelled by [fuel]: running out of either only rejects.

    Main results:
    - [span_sound]: within the open span of a free state, [D > g];
    - [certify_sound]: an accepted queue has [D > g] on every point of its intervals;
    - [certify_motion_sound]: an accepted motion has [D > g] for every [t] in [[0, 1]].

    Checked on the implementation by: tests/kinematics/continuous.rs
    [the_continuous_check_accepts_no_motion_that_touches] (dense sampling of the exact check
    never finds a contact on a motion the check accepts). *)

From Coq Require Import Reals Lra List.
Import ListNotations.
Open Scope R_scope.

Section Cover.

(** One item's distance along the motion, the clearance it keeps and its speed bound. *)
Variable D : R -> R.
Variable g v : R.

(** [D] changes by at most [v] per unit of the parameter. *)
Definition lipschitz : Prop := 0 <= v /\ forall t u, Rabs (D t - D u) <= v * Rabs (t - u).

(** A span [s] at [t] is sound: the state is free and [v·s] stays within its clearance. *)
Definition sound_span (t s : R) : Prop := D t > g /\ v * s <= D t - g.

(** Within the open span of a free state the item keeps its clearance. *)
Lemma span_sound : forall t s u,
  lipschitz -> sound_span t s -> Rabs (u - t) < s -> D u > g.
Proof.
  intros t s u [Hv HL] [Hfree Hspan] Hu.
  specialize (HL u t).
  assert (Hneg : -(D u - D t) <= Rabs (D u - D t)) by (rewrite <- Rabs_Ropp; apply Rle_abs).
  destruct (Req_dec v 0) as [H0 | H0].
  - subst v. rewrite Rmult_0_l in HL. lra.
  - assert (Hvpos : 0 < v) by lra.
    assert (v * Rabs (u - t) < v * s) by (apply Rmult_lt_compat_l; lra).
    lra.
Qed.

(** The oracle of the loop: the span of the free state at a parameter, or [None]. *)
Variable span_at : R -> option R.

Definition sound_oracle : Prop :=
  forall t s, span_at t = Some s -> sound_span t s.

(** The loop over the pending closed intervals [(x, y)], in queue order. *)
Fixpoint certify (fuel : nat) (pending : list (R * R)) : bool :=
  match fuel with
  | O => false
  | S fuel' =>
      match pending with
      | [] => true
      | (x, y) :: rest =>
          let m := (x + y) / 2 in
          let h := (y - x) / 2 in
          match span_at m with
          | None => false
          | Some s =>
              if Rlt_dec h s then certify fuel' rest
              else certify fuel' (rest ++ [(x, m - s); (m + s, y)])
          end
      end
  end.

(** [t] lies in one of the pending intervals. *)
Definition pending_at (pending : list (R * R)) (t : R) : Prop :=
  exists x y, In (x, y) pending /\ x <= t <= y.

Theorem certify_sound : forall fuel pending,
  lipschitz -> sound_oracle -> certify fuel pending = true ->
  forall t, pending_at pending t -> D t > g.
Proof.
  intros fuel. induction fuel as [| fuel IH]; intros pending HL HO Hc t Ht.
  - discriminate.
  - destruct pending as [| [x y] rest].
    + destruct Ht as (x & y & Hin & _). destruct Hin.
    + simpl in Hc.
      destruct (span_at ((x + y) / 2)) as [s |] eqn:Hs; [| discriminate].
      pose proof (HO _ _ Hs) as Hsound.
      destruct Ht as (x' & y' & Hin & Hxy).
      destruct (Rlt_dec ((y - x) / 2) s) as [Hcover | Hsplit].
      * destruct Hin as [Heq | Hin].
        -- injection Heq as <- <-.
           apply (span_sound ((x + y) / 2) s t HL Hsound).
           apply Rabs_def1; lra.
        -- apply (IH rest HL HO Hc t). exists x', y'. auto.
      * destruct Hin as [Heq | Hin].
        -- injection Heq as <- <-.
           destruct (Rle_lt_dec t ((x + y) / 2 - s)) as [Hlo | Hlo].
           ++ apply (IH _ HL HO Hc t). exists x, ((x + y) / 2 - s).
              split; [apply in_or_app; right; left; reflexivity | lra].
           ++ destruct (Rle_lt_dec ((x + y) / 2 + s) t) as [Hhi | Hhi].
              ** apply (IH _ HL HO Hc t). exists ((x + y) / 2 + s), y.
                 split; [apply in_or_app; right; right; left; reflexivity | lra].
              ** apply (span_sound ((x + y) / 2) s t HL Hsound).
                 apply Rabs_def1; lra.
        -- apply (IH _ HL HO Hc t). exists x', y'.
           split; [apply in_or_app; left; exact Hin | exact Hxy].
Qed.

(** The whole check: the end, then the start, then the loop on what their spans leave. *)
Definition certify_motion (fuel : nat) : bool :=
  match span_at 1 with
  | None => false
  | Some e =>
      if Rle_dec e 1 then
        match span_at 0 with
        | None => false
        | Some s0 =>
            if Rle_dec s0 (1 - e) then certify fuel [(s0, 1 - e)] else true
        end
      else true
  end.

Theorem certify_motion_sound : forall fuel,
  lipschitz -> sound_oracle -> certify_motion fuel = true ->
  forall t, 0 <= t <= 1 -> D t > g.
Proof.
  intros fuel HL HO Hc t Ht.
  unfold certify_motion in Hc.
  destruct (span_at 1) as [e |] eqn:He; [| discriminate].
  pose proof (HO _ _ He) as Hend.
  destruct (Rlt_le_dec (1 - e) t) as [Hnear1 | Hfar1].
  { apply (span_sound 1 e t HL Hend). apply Rabs_def1; lra. }
  destruct (Rle_dec e 1) as [He1 | He1]; [| lra].
  destruct (span_at 0) as [s0 |] eqn:Hs0; [| discriminate].
  pose proof (HO _ _ Hs0) as Hstart.
  destruct (Rlt_le_dec t s0) as [Hnear0 | Hfar0].
  { apply (span_sound 0 s0 t HL Hstart). apply Rabs_def1; lra. }
  destruct (Rle_dec s0 (1 - e)) as [Hgap | Hgap]; [| lra].
  apply (certify_sound fuel [(s0, 1 - e)] HL HO Hc t).
  exists s0, (1 - e). split; [left; reflexivity | lra].
Qed.

End Cover.
