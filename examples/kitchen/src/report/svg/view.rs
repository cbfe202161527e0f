//! The frame of a top view: the world → pixel map, the background grid and the legend.

use nalgebra::Point2;

use super::SvgError;
use super::axes::{MAX_TICKS, nice_step};
use super::document::{
    Svg, TITLE_HEIGHT_PX, format_value, palette, part_colour, px, text_width, trim_zeros,
};
use super::geometry::{Bounds, Outline};
use super::plan::StepDrawing;
use super::top_view::TopViewOptions;

/// The world → pixel map of a top view.
pub(super) struct View {
    x_min: f64,
    y_max: f64,
    /// Pixels per metre.
    pub(super) scale: f64,
    left: f64,
    top: f64,
}

impl View {
    pub(super) fn px(&self, p: Point2<f64>) -> (f64, f64) {
        (
            self.left + (p.x - self.x_min) * self.scale,
            self.top + (self.y_max - p.y) * self.scale,
        )
    }

    pub(super) fn points(&self, outline: &[Point2<f64>]) -> String {
        outline
            .iter()
            .map(|p| {
                let (x, y) = self.px(*p);
                format!("{},{}", px(x), px(y))
            })
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// Path data with one closed subpath per piece (filled as their union).
    pub(super) fn path(&self, outline: &Outline) -> String {
        outline
            .pieces
            .iter()
            .map(|piece| format!("M {} Z", self.points(&piece.outline)))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The map of `options` for a drawing of `bounds` (the map documented on
    /// [`TopViewOptions`]), and the height of the drawing (px, margins included). Empty bounds
    /// become a 1 m square around the origin and a degenerate side is widened to 1 m, in
    /// `bounds` too.
    ///
    /// # Errors
    /// [`SvgError::OutOfRange`] when the extent of `bounds` is not finite.
    pub(super) fn fit(
        bounds: &mut Bounds,
        options: &TopViewOptions,
    ) -> Result<(View, f64), SvgError> {
        if bounds.is_empty() {
            bounds.add(Point2::origin(), 0.5);
        }
        for axis in 0..2 {
            if bounds.hi[axis] - bounds.lo[axis] < 1e-3 {
                bounds.lo[axis] -= 0.5;
                bounds.hi[axis] += 0.5;
            }
        }
        let inner_w = options.width_px - 2.0 * options.margin_px;
        let inner_h = options.max_height_px - 2.0 * options.margin_px;
        let dx = bounds.hi.x - bounds.lo.x;
        let dy = bounds.hi.y - bounds.lo.y;
        if !(dx.is_finite() && dy.is_finite()) {
            return Err(SvgError::OutOfRange {
                what: "extent of the drawing (m)".into(),
                requirement: "finite",
                value: dx.max(dy),
            });
        }
        let scale = (inner_w / dx).min(inner_h / dy);
        let view = View {
            x_min: bounds.lo.x,
            y_max: bounds.hi.y,
            scale,
            left: options.margin_px + (inner_w - dx * scale) / 2.0,
            top: TITLE_HEIGHT_PX + options.margin_px,
        };
        let drawing_h = dy * scale + 2.0 * options.margin_px;
        Ok((view, drawing_h))
    }
}

/// The legend right of the drawing: the body styles, the executed trace when `has_trace`, the
/// plan steps and the grid spacing of `bounds`. Returns its width (px, at least 230) and its
/// bottom (px).
pub(super) fn draw_legend(
    svg: &mut Svg,
    options: &TopViewOptions,
    bounds: &Bounds,
    steps: &[StepDrawing],
    has_trace: bool,
) -> (f64, f64) {
    let lx = options.width_px + 10.0;
    let mut ly = TITLE_HEIGHT_PX + options.margin_px;
    let mut legend_w: f64 = 0.0;
    let mut entry = |svg: &mut Svg, ly: &mut f64, swatch: &str, label: &str, colour: &str| {
        svg.raw(&format!(
            r#"<g class="legend-entry" transform="translate({},{})">{swatch}</g>"#,
            px(lx),
            px(*ly)
        ));
        svg.text(
            lx + 24.0,
            *ly + 10.5,
            &format!(r#"class="legend" fill="{colour}""#),
            label,
        );
        legend_w = legend_w.max(24.0 + text_width(label, 12.0));
        *ly += 18.0;
    };
    let square = |fill: &str, extra: &str| {
        format!(r#"<rect x="0" y="0" width="16" height="12" fill="{fill}" {extra}/>"#)
    };
    entry(svg, &mut ly, &square("#3a3a3a", ""), "wall", "#222222");
    entry(
        svg,
        &mut ly,
        &square("#c4c4c4", r##"stroke="#7a7a7a""##),
        "counter, carcass",
        "#222222",
    );
    entry(
        svg,
        &mut ly,
        &square("none", r##"stroke="#6a6a6a" stroke-dasharray="4 2""##),
        "overhead (above 1.2 m)",
        "#222222",
    );
    entry(
        svg,
        &mut ly,
        &square(&part_colour(0), r##"stroke="#444444""##),
        "part",
        "#222222",
    );
    entry(
        svg,
        &mut ly,
        r##"<circle cx="8" cy="6" r="3" fill="#1a1a1a"/>"##,
        "handle",
        "#222222",
    );
    if has_trace {
        entry(
            svg,
            &mut ly,
            r##"<line x1="0" y1="6" x2="16" y2="6" stroke="#111111" stroke-width="1.5" stroke-dasharray="4 2"/>"##,
            "executed base trace",
            "#222222",
        );
    }
    if !steps.is_empty() {
        ly += 8.0;
        svg.text(lx, ly + 10.0, r#"font-weight="bold""#, STEPS_HEADER);
        ly += 18.0;
        for (i, step) in steps.iter().enumerate() {
            let colour = palette(i);
            entry(
                svg,
                &mut ly,
                &square(colour, r#"fill-opacity="0.6""#),
                &step.label,
                "#222222",
            );
        }
    }
    let grid = grid_step(bounds);
    ly += 8.0;
    svg.text(
        lx,
        ly + 10.0,
        r##"fill="#555555" font-size="11""##,
        &format!("grid {} m, x right, y up", format_value(grid)),
    );
    ly += 18.0;
    // The bold header of the step list is about 10 % wider than plain text.
    let header_w = if steps.is_empty() {
        0.0
    } else {
        1.1 * text_width(STEPS_HEADER, 12.0)
    };
    (legend_w.max(header_w).max(230.0), ly)
}

/// The header of the legend's list of plan steps.
const STEPS_HEADER: &str = "Steps (sweep, base path, base pose)";

/// The spacing (m) of the background grid: a nice step giving about 6 lines across.
fn grid_step(bounds: &Bounds) -> f64 {
    let span = (bounds.hi.x - bounds.lo.x).max(bounds.hi.y - bounds.lo.y);
    nice_step(span / 6.0)
}

/// The multiples of `step` in `[lo, hi]` (at most [`MAX_TICKS`]).
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step).ceil();
    (0..MAX_TICKS)
        .map(|i| (first + i as f64) * step)
        .take_while(|v| *v <= hi + 1e-9 * step)
        .collect()
}

/// Light grid lines at whole multiples of the grid step, labelled in metres.
pub(super) fn draw_grid(svg: &mut Svg, view: &View, bounds: &Bounds) {
    let step = grid_step(bounds);
    let label = |v: f64| format!("{} m", trim_zeros(format!("{v:.3}")));
    let (x0, y0) = view.px(bounds.lo);
    let (x1, y1) = view.px(bounds.hi);
    let attrs = r##"class="grid" stroke="#ececec" stroke-width="1""##;
    svg.raw(r#"<g class="grid">"#);
    for v in multiples(bounds.lo.x, bounds.hi.x, step) {
        let (x, _) = view.px(Point2::new(v, 0.0));
        svg.line((x, y0 + 6.0), (x, y1 - 6.0), attrs);
        svg.text(
            x,
            y0 + 18.0,
            r##"font-size="10" fill="#888888" text-anchor="middle""##,
            &label(v),
        );
    }
    for v in multiples(bounds.lo.y, bounds.hi.y, step) {
        let (_, y) = view.px(Point2::new(0.0, v));
        svg.line((x0 - 6.0, y), (x1 + 6.0, y), attrs);
        svg.text(
            x0 - 8.0,
            y + 3.5,
            r##"font-size="10" fill="#888888" text-anchor="end""##,
            &label(v),
        );
    }
    svg.raw("</g>");
}
