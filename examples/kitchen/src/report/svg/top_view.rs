//! The top view of a scene and its plan: its options and the drawing, layer by layer.

use kinscene::planner::MotionPlan;
use kinscene::scene::{SceneData, SceneModel, State, forward_kinematics};
use nalgebra::{Isometry2, Point2};

use super::SvgError;
use super::bodies::Bodies;
use super::check::check_finite;
use super::document::{MARGIN_PX, Svg, TITLE_HEIGHT_PX};
use super::geometry::Bounds;
use super::plan::{draw_plan, replay_plan};
use super::view::{View, draw_grid, draw_legend};

/// How a top view is drawn. [`Default`] gives the values [`top_view`] uses.
///
/// Mapping from the world to pixels: with `[x_min, x_max] × [y_min, y_max]` the xy bounds of
/// everything drawn (every base shape including the skipped floor, every part, sweep, base
/// path, footprint and trace point), the scale is
/// `s = min((width_px − 2·margin_px) / (x_max − x_min), (max_height_px − 2·margin_px) / (y_max − y_min))`
/// px/m and a point maps to
/// `px = margin_px + ((width_px − 2·margin_px) − (x_max − x_min)·s) / 2 + (x − x_min)·s`,
/// `py = TITLE_HEIGHT_PX + margin_px + (y_max − y)·s` (y up). The legend sits to the right of
/// the `width_px` wide drawing.
#[derive(Debug, Clone, PartialEq)]
pub struct TopViewOptions {
    /// Width of the drawing (px), margins included (900).
    pub width_px: f64,
    /// Largest height of the drawing (px), margins included (1100).
    pub max_height_px: f64,
    /// Margin around the drawing (px) (40; the grid labels sit in it).
    pub margin_px: f64,
    /// Radius of the robot's footprint (m) (0.284, the Gen3 base).
    pub robot_radius: f64,
    /// Joint values drawn per step sweep, `from` and `to` included (8).
    pub sweep_samples: usize,
    /// Shapes whose top is below this height (m) are floor and not drawn (0.05).
    pub floor_top: f64,
    /// Base shapes from the floor reaching this height (m) are drawn as walls (1.95).
    pub wall_height: f64,
    /// Shapes whose bottom is above this height (m) are overhead (wall cabinets) and drawn
    /// as dashed outlines (1.2).
    pub overhead_bottom: f64,
}

impl Default for TopViewOptions {
    fn default() -> Self {
        TopViewOptions {
            width_px: 900.0,
            max_height_px: 1100.0,
            margin_px: 40.0,
            robot_radius: 0.284,
            sweep_samples: 8,
            floor_top: 0.05,
            wall_height: 1.95,
            overhead_bottom: 1.2,
        }
    }
}

impl TopViewOptions {
    /// Checks every option is finite and in its range.
    pub(super) fn validate(&self) -> Result<(), SvgError> {
        let positive = |what: &str, v: f64| -> Result<(), SvgError> {
            check_finite(|| format!("top view option {what}"), v)?;
            if v > 0.0 {
                Ok(())
            } else {
                Err(SvgError::OutOfRange {
                    what: format!("top view option {what}"),
                    requirement: "positive",
                    value: v,
                })
            }
        };
        positive("margin_px", self.margin_px)?;
        positive(
            "width_px − 2·margin_px",
            self.width_px - 2.0 * self.margin_px,
        )?;
        positive(
            "max_height_px − 2·margin_px",
            self.max_height_px - 2.0 * self.margin_px,
        )?;
        positive("robot_radius", self.robot_radius)?;
        check_finite(|| "top view option floor_top".into(), self.floor_top)?;
        check_finite(|| "top view option wall_height".into(), self.wall_height)?;
        check_finite(
            || "top view option overhead_bottom".into(),
            self.overhead_bottom,
        )?;
        if self.sweep_samples < 2 {
            return Err(SvgError::OutOfRange {
                what: "top view option sweep_samples".into(),
                requirement: "at least 2",
                value: self.sweep_samples as f64,
            });
        }
        Ok(())
    }
}

/// A top view (x right, y up, metres) of `model` at `start`: base-map shapes and parts as
/// filled outlines (projections of their colliders), handles as dots; for a plan, each step's
/// part sweep (the moving part's outline at several values from `from` to `to`, one colour per
/// step, numbered), the planned base path of each step (polyline) and the base pose of each
/// manipulation (robot footprint circle with heading), and for a whole-body manipulation the
/// base's trail along it (dashed, a dot at the end pose); `trace` (executed base poses) as a
/// dashed line. Returns a standalone SVG document.
///
/// Uses [`TopViewOptions::default`]; see [`top_view_with`].
///
/// # Errors
/// As [`top_view_with`].
pub fn top_view(
    model: &SceneModel,
    start: &State,
    plan: Option<&MotionPlan>,
    trace: &[Isometry2<f64>],
    title: &str,
) -> Result<String, SvgError> {
    top_view_with(model, start, plan, trace, title, &TopViewOptions::default())
}

/// [`top_view`] with explicit options.
///
/// Each body is drawn as the convex hulls of its colliders' floor projections: one `<polygon>`
/// per base shape whose top is at least `floor_top` (walls dark, counters grey, overhead shapes
/// dashed) and one `<path>` per part with colliders (coloured; one closed subpath per collider).
/// For plan step `i` the state is set to `sweep_samples` values from the step's `from` to its
/// `to` and the moved part and its descendants are outlined at each (one `<path>` per part and
/// value, in a `<g class="sweep">` per step); the state then stays at `to` for the next step.
///
/// # Errors
/// [`SvgError::Scene`] when `start` does not fit the model; [`SvgError::Step`] when a step
/// names an unknown joint or a value outside its limits; [`SvgError::NonFinite`] for a
/// non-finite base pose, path waypoint or trace pose; [`SvgError::DimensionMismatch`] for a
/// base-path waypoint with fewer than 2 coordinates; [`SvgError::OutOfRange`] and
/// [`SvgError::NonFinite`] for invalid options.
pub fn top_view_with(
    model: &SceneModel,
    start: &State,
    plan: Option<&MotionPlan>,
    trace: &[Isometry2<f64>],
    title: &str,
    options: &TopViewOptions,
) -> Result<String, SvgError> {
    options.validate()?;
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, start)?;
    let mut bounds = Bounds::empty();

    // The scene at the start state, then the plan replayed from it.
    let bodies = Bodies::collect(model, &data, options, &mut bounds)?;
    let steps = match plan {
        Some(plan) => replay_plan(model, &mut data, start, plan, options, &mut bounds)?,
        None => Vec::new(),
    };

    // The executed trace.
    let mut trace_points = Vec::with_capacity(trace.len());
    for (k, pose) in trace.iter().enumerate() {
        let t = pose.translation.vector;
        let x = check_finite(|| format!("trace pose {} x", k + 1), t.x)?;
        let y = check_finite(|| format!("trace pose {} y", k + 1), t.y)?;
        check_finite(
            || format!("trace pose {} yaw", k + 1),
            pose.rotation.angle(),
        )?;
        let p = Point2::new(x, y);
        bounds.add(p, 0.0);
        trace_points.push(p);
    }

    // The world → pixel map, then the layers: grid, scene, plan, trace and legend.
    let (view, drawing_h) = View::fit(&mut bounds, options)?;
    let mut svg = Svg::new();
    draw_grid(&mut svg, &view, &bounds);
    bodies.draw(&mut svg, &view, model, options);
    draw_plan(&mut svg, &view, &steps, options);
    if !trace_points.is_empty() {
        svg.raw(&format!(
            r##"<polyline class="trace" points="{}" fill="none" stroke="#111111" stroke-width="1.5" stroke-dasharray="5 4"/>"##,
            view.points(&trace_points)
        ));
    }
    let (legend_w, legend_bottom) =
        draw_legend(&mut svg, options, &bounds, &steps, !trace_points.is_empty());
    let width = options.width_px + 10.0 + legend_w + MARGIN_PX;
    let height = (TITLE_HEIGHT_PX + drawing_h).max(legend_bottom + MARGIN_PX);
    Ok(svg.finish(width, height, title))
}
