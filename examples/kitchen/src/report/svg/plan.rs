//! A plan in a top view: each step's part sweep, base path, manipulation base pose and the
//! base's trail along a whole-body manipulation.

use kinscene::planner::MotionPlan;
use kinscene::scene::{SceneData, SceneModel, State, forward_kinematics};
use nalgebra::{Point2, Vector2};

use super::SvgError;
use super::check::check_finite;
use super::document::{Svg, escape, format_value, palette, px};
use super::geometry::{Bounds, Outline, part_outline};
use super::top_view::TopViewOptions;
use super::view::View;

/// One step of a plan, ready to draw.
pub(super) struct StepDrawing {
    /// The legend entry: number, joint, from → to.
    pub(super) label: String,
    /// The moved joint.
    joint: String,
    /// Outlines of the moving subtree at each sampled value (sample-major).
    sweep: Vec<Outline>,
    /// Base path (x, y) waypoints.
    path: Vec<Point2<f64>>,
    /// Manipulation base pose x, y, yaw.
    base: [f64; 3],
    /// The base's (x, y) along a whole-body manipulation (one per waypoint, from `base` to
    /// the end pose); empty when the base stands still.
    trail: Vec<Point2<f64>>,
}

/// The (x, y) of each waypoint of a path, checked finite and added to `bounds` padded by
/// `radius`; `what` names the path in errors.
fn planar_points(
    what: &str,
    positions: &[Vec<f64>],
    radius: f64,
    bounds: &mut Bounds,
) -> Result<Vec<Point2<f64>>, SvgError> {
    let mut points = Vec::with_capacity(positions.len());
    for (w, q) in positions.iter().enumerate() {
        if q.len() < 2 {
            return Err(SvgError::DimensionMismatch {
                what: format!("{what} waypoint {}", w + 1),
                expected: 3,
                got: q.len(),
            });
        }
        let x = check_finite(|| format!("{what} x"), q[0])?;
        let y = check_finite(|| format!("{what} y"), q[1])?;
        let p = Point2::new(x, y);
        bounds.add(p, radius);
        points.push(p);
    }
    Ok(points)
}

/// The steps of `plan` replayed from `start`: each step's joint is set to `sweep_samples`
/// values from its `from` to its `to` (the state then stays at `to` for the next step) and the
/// moved part and its descendants are outlined at each. Sweeps, base paths padded by the robot
/// radius and base poses are added to `bounds`; `data` is left at the last state.
///
/// # Errors
/// [`SvgError::Step`] for an unknown joint or a value outside its limits;
/// [`SvgError::NonFinite`] for a non-finite value, waypoint or base pose;
/// [`SvgError::DimensionMismatch`] for a waypoint with fewer than 2 coordinates;
/// [`SvgError::Scene`] when forward kinematics fails.
pub(super) fn replay_plan(
    model: &SceneModel,
    data: &mut SceneData,
    start: &State,
    plan: &MotionPlan,
    options: &TopViewOptions,
    bounds: &mut Bounds,
) -> Result<Vec<StepDrawing>, SvgError> {
    let mut steps: Vec<StepDrawing> = Vec::new();
    let mut state = start.clone();
    for (i, step) in plan.steps.iter().enumerate() {
        let n = i + 1;
        let step_err = |source| SvgError::Step { step: n, source };
        let joint = model.joint_id(&step.joint).map_err(step_err)?;
        check_finite(|| format!("plan step {n} from"), step.from)?;
        check_finite(|| format!("plan step {n} to"), step.to)?;
        let Some(part) = model.part(joint.part()) else {
            // A joint id from the model always has its part.
            continue;
        };
        let subtree: Vec<usize> = part.subtree().map(|p| p.index()).collect();
        let (lo, hi) = (step.from.min(step.to), step.from.max(step.to));
        let mut sweep = Vec::new();
        let samples = options.sweep_samples;
        for k in 0..samples {
            let value = if k + 1 == samples {
                step.to
            } else {
                let f = k as f64 / (samples - 1) as f64;
                (step.from + f * (step.to - step.from)).clamp(lo, hi)
            };
            state.set(model, joint, value).map_err(step_err)?;
            forward_kinematics(model, data, &state)?;
            for &index in &subtree {
                if let Some(fp) = part_outline(model, data, index) {
                    for p in fp.points() {
                        bounds.add(*p, 0.0);
                    }
                    sweep.push(fp);
                }
            }
        }
        let radius = options.robot_radius;
        let path = planar_points(
            &format!("plan step {n} base path"),
            &step.base_path.positions,
            radius,
            bounds,
        )?;
        let trail = match &step.manipulation_base {
            Some(b) => planar_points(
                &format!("plan step {n} manipulation base path"),
                &b.positions,
                radius,
                bounds,
            )?,
            None => Vec::new(),
        };
        for (c, v) in ["x", "y", "yaw"].iter().zip(step.base) {
            check_finite(|| format!("plan step {n} base {c}"), v)?;
        }
        bounds.add(
            Point2::new(step.base[0], step.base[1]),
            options.robot_radius,
        );
        steps.push(StepDrawing {
            label: format!(
                "{n}. {} {} \u{2192} {}",
                step.joint,
                format_value(step.from),
                format_value(step.to)
            ),
            joint: step.joint.clone(),
            sweep,
            path,
            base: step.base,
            trail,
        });
    }
    Ok(steps)
}

/// The sweeps, then the base paths, then the base's trail along a whole-body manipulation
/// (dashed, a dot at its end), then the base poses (on top), one palette colour per step.
pub(super) fn draw_plan(
    svg: &mut Svg,
    view: &View,
    steps: &[StepDrawing],
    options: &TopViewOptions,
) {
    for (i, step) in steps.iter().enumerate() {
        let colour = palette(i);
        svg.raw(&format!(
            r#"<g class="sweep" data-step="{}" data-joint="{}">"#,
            i + 1,
            escape(&step.joint)
        ));
        for fp in &step.sweep {
            svg.raw(&format!(
                r#"<path class="sweep-outline" d="{}" fill="{colour}" fill-opacity="0.12" stroke="{colour}" stroke-opacity="0.7" stroke-width="1"/>"#,
                view.path(fp)
            ));
        }
        if let Some(last) = step.sweep.last() {
            let (x, y) = view.px(last.centroid());
            svg.text(
                x,
                y + 4.0,
                &format!(
                    r##"class="sweep-label" text-anchor="middle" font-size="12" font-weight="bold" fill="{colour}" stroke="#ffffff" stroke-width="2.5" paint-order="stroke""##
                ),
                &(i + 1).to_string(),
            );
        }
        svg.raw("</g>");
    }
    for (i, step) in steps.iter().enumerate() {
        let colour = palette(i);
        if step.path.is_empty() {
            continue;
        }
        svg.raw(&format!(
            r#"<polyline class="base-path" data-step="{}" points="{}" fill="none" stroke="{colour}" stroke-width="2.5" stroke-linejoin="round" stroke-linecap="round"/>"#,
            i + 1,
            view.points(&step.path)
        ));
        let (x, y) = view.px(step.path[0]);
        svg.raw(&format!(
            r##"<circle class="path-start" cx="{}" cy="{}" r="3.5" fill="#ffffff" stroke="{colour}" stroke-width="1.5"/>"##,
            px(x),
            px(y)
        ));
    }
    for (i, step) in steps.iter().enumerate() {
        let colour = palette(i);
        let Some(end) = step.trail.last() else {
            continue;
        };
        svg.raw(&format!(
            r#"<polyline class="manipulation-base" data-step="{}" points="{}" fill="none" stroke="{colour}" stroke-width="2" stroke-dasharray="4 3" stroke-linejoin="round"/>"#,
            i + 1,
            view.points(&step.trail)
        ));
        let (x, y) = view.px(*end);
        svg.raw(&format!(
            r#"<circle class="manipulation-end" data-step="{}" cx="{}" cy="{}" r="3.5" fill="{colour}"/>"#,
            i + 1,
            px(x),
            px(y)
        ));
    }
    for (i, step) in steps.iter().enumerate() {
        let colour = palette(i);
        let [bx, by, yaw] = step.base;
        let centre = Point2::new(bx, by);
        let (cx, cy) = view.px(centre);
        let tip = view.px(centre + options.robot_radius * Vector2::new(yaw.cos(), yaw.sin()));
        svg.raw(&format!(r#"<g class="robot-pose" data-step="{}">"#, i + 1));
        svg.raw(&format!(
 r#"<circle class="footprint" cx="{}" cy="{}" r="{}" fill="{colour}" fill-opacity="0.18" stroke="{colour}" stroke-width="2"/>"#,
            px(cx),
            px(cy),
            px(options.robot_radius * view.scale)
        ));
        svg.line(
            (cx, cy),
            tip,
            &format!(
                r#"class="heading" stroke="{colour}" stroke-width="2.5" stroke-linecap="round""#
            ),
        );
        svg.text(
            cx,
            cy + 4.5,
            r##"text-anchor="middle" font-size="13" font-weight="bold" fill="#222222""##,
            &(i + 1).to_string(),
        );
        svg.raw("</g>");
    }
}
