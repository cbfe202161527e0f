//! The two-view estimator's final segmentation (step 6), and its score and details.

use nalgebra::Isometry3;

use super::TwoViewSettings;
use super::change::{Changes, grow};
use super::fit::Selection;
use crate::articulation::estimate::{Interaction, unit_score};
use crate::articulation::icp::Registration;
use crate::articulation::screw::Screw;
use crate::articulation::visibility::RangeImage;

/// Step 6: the moving pre points, grown from the seed `seeds_pre` over the pre points that the
/// fitted `motion` explains better than the static hypothesis (or as well, near the hinge),
/// and over those that left a place the post sensor saw through (see
/// [`estimate`](super::estimate)).
pub(super) fn final_segment(
    s: &TwoViewSettings,
    i: &Interaction<'_>,
    c: &Changes<'_>,
    motion: &Isometry3<f64>,
    seeds_pre: &[usize],
) -> Vec<usize> {
    let tau = c.tau;
    let post_view = RangeImage::new(c.post, i.post.origin, s.visibility_bin);
    let eligible: Vec<bool> = c
        .pre
        .iter()
        .zip(&c.d_pre)
        .map(|(p, &d_static)| {
            let q = motion * p;
            let d_part = c.to_post(&q);
            let margin = tau / 4.0;
            let hinge = (q - p).norm() < 2.0 * tau;
            let vacated = d_part > tau && d_static > tau && post_view.seen_through(p, tau);
            (d_part <= tau
                && (d_part + margin < d_static || (hinge && d_part <= d_static + margin)))
                || vacated
        })
        .collect();
    grow(&c.pre_tree, c.pre, &eligible, seeds_pre, s.neighbor_radius)
}

/// The estimate's score: the inlier fraction times the model-selection confidence
/// `margin / (margin + 10)`. An infinite margin (only one model could be registered) is a
/// certain selection (the quotient itself would be ∞/∞ = NaN); an undefined one (NaN, ∞ − ∞)
/// is no confidence. Finite and in [0, 1] for every input ([`unit_score`]).
pub(super) fn score_of(inliers: f64, margin: f64) -> f64 {
    let selection = if margin.is_nan() {
        0.0
    } else if margin == f64::INFINITY {
        1.0
    } else {
        let margin = margin.max(0.0);
        margin / (margin + 10.0)
    };
    unit_score(unit_score(inliers) * selection)
}

/// The estimate's details: the change threshold, the segment sizes (`part` pre points,
/// `part_post` post points), the rigid registration, the model selection and the inliers.
pub(super) fn details(
    c: &Changes<'_>,
    part: usize,
    part_post: usize,
    rigid: &Registration,
    selection: &Selection,
    inliers: f64,
) -> String {
    let Selection {
        bic_r,
        bic_p,
        path_r,
        path_p,
        forced,
        n_eff,
        ..
    } = *selection;
    let tau = c.tau;
    format!(
        "two-view: tau {tau:.4} m, {} seed points, {} post points, rigid cost {:.3e}, \
         BIC revolute {bic_r:.1} prismatic {bic_p:.1}, path residual revolute {path_r:.4} m \
         prismatic {path_p:.4} m{}, screw angle {:.2} deg, axial {:.4} m, \
         inliers {:.3}, n_eff {n_eff}",
        part,
        part_post,
        rigid.cost,
        if forced { " (path decided)" } else { "" },
        Screw::from_isometry(&rigid.motion).angle.to_degrees(),
        Screw::from_isometry(&rigid.motion).translation,
        inliers,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed rotation fit (BIC ∞) makes the margin infinite: the score is then the inlier
    /// fraction, finite, not ∞/∞ = NaN.
    #[test]
    fn an_infinite_margin_scores_the_inliers() {
        assert_eq!(score_of(0.8, f64::INFINITY), 0.8);
        // 10 / (10 + 10) = half the inliers.
        assert!((score_of(0.8, 10.0) - 0.4).abs() < 1e-12);
    }

    /// Whatever the inputs (NaN, ±∞, out of range), the score is finite and in [0, 1].
    #[test]
    fn every_score_is_finite_and_in_the_unit_interval() {
        let values = [
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -1.0,
            0.0,
            0.5,
            1.0,
            7.0,
        ];
        for inliers in values {
            for margin in values {
                let s = score_of(inliers, margin);
                assert!((0.0..=1.0).contains(&s), "{inliers} {margin}: {s}");
            }
        }
        // ∞ − ∞ = NaN (both models unregistered) is no confidence.
        assert_eq!(score_of(0.8, f64::INFINITY - f64::INFINITY), 0.0);
    }
}
