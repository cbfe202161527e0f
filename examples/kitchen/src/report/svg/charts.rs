//! The charts of the experiments: grouped bars, stacked bars and lines.

use super::axes::{
    NiceAxis, PLOT_HEIGHT_PX, PLOT_LEFT_PX, Plot, draw_categories, draw_legend, legend_width,
};
use super::check::{check_finite, check_len, check_nonempty, check_series};
use super::document::{
    MARGIN_PX, Svg, TITLE_HEIGHT_PX, escape, format_value, palette, px, text_width,
};
use super::{Series, SvgError};

/// Grouped bar chart: one group per category, one bar per series, legend, y axis with ticks,
/// optional fixed y maximum; error bars when `errors` is Some (same shape as series values).
///
/// The y axis spans from `min(0, smallest value − error)` to `y_max` if given, else to the
/// largest value (+ error) rounded up to a nice tick. Values above `y_max` are drawn clipped at
/// the top (their printed value is the true one).
///
/// # Errors
/// [`SvgError::Empty`] without categories or series; [`SvgError::DimensionMismatch`] when a
/// series (or error series) does not have one value per category or `errors` does not have one
/// series per series; [`SvgError::NonFinite`] for NaN or infinite values, errors or `y_max`;
/// [`SvgError::OutOfRange`] for a negative error or a `y_max` not above the axis minimum.
pub fn bar_chart(
    title: &str,
    categories: &[String],
    series: &[Series],
    y_label: &str,
    y_max: Option<f64>,
    errors: Option<&[Series]>,
) -> Result<String, SvgError> {
    check_nonempty("categories", categories.len())?;
    check_nonempty("series", series.len())?;
    let n = categories.len();
    check_series("series", series, n, false)?;
    if let Some(errors) = errors {
        check_len(|| "error series".into(), series.len(), errors.len())?;
        check_series("error series", errors, n, true)?;
    }
    let err = |i: usize, j: usize| errors.map_or(0.0, |e| e[i].values[j]);
    let mut lo: f64 = 0.0;
    let mut hi: f64 = 0.0;
    for (i, s) in series.iter().enumerate() {
        for (j, &v) in s.values.iter().enumerate() {
            lo = lo.min(v - err(i, j));
            hi = hi.max(v + err(i, j));
        }
    }
    if let Some(m) = y_max {
        check_finite(|| "y_max".into(), m)?;
        if m <= lo {
            return Err(SvgError::OutOfRange {
                what: "y_max".into(),
                requirement: "above the smallest value",
                value: m,
            });
        }
    }
    let axis = NiceAxis::new(lo, hi, y_max);

    let k = series.len();
    let plot_min_width = 380.0;
    let bar_w = (plot_min_width / (n as f64 * (k as f64 + 1.0))).clamp(14.0, 48.0);
    let gap = bar_w;
    let group_w = k as f64 * bar_w + gap;
    let plot = Plot {
        left: PLOT_LEFT_PX,
        top: TITLE_HEIGHT_PX + 14.0,
        width: group_w * n as f64,
        height: PLOT_HEIGHT_PX,
        axis,
    };
    let mut svg = Svg::new();
    plot.draw_value_axis(&mut svg, y_label);
    let base_y = plot.y(plot.baseline());
    let print_values = n * k <= 48;
    for (i, s) in series.iter().enumerate() {
        let colour = palette(i);
        svg.raw(&format!(
            r#"<g class="series" data-series="{}">"#,
            escape(&s.label)
        ));
        for (j, &v) in s.values.iter().enumerate() {
            let x = plot.left + j as f64 * group_w + gap / 2.0 + i as f64 * bar_w;
            let y = plot.y(v);
            let (top, h) = if y < base_y {
                (y, base_y - y)
            } else {
                (base_y, y - base_y)
            };
            svg.raw(&format!(
                r#"<rect class="bar" x="{}" y="{}" width="{}" height="{}" fill="{colour}"><title>{}: {}</title></rect>"#,
                px(x),
                px(top),
                px(bar_w - 1.0),
                px(h),
                escape(&format!("{} / {}", s.label, categories[j])),
                escape(&format_value(v)),
            ));
            let e = err(i, j);
            if errors.is_some() && e > 0.0 {
                let cx = x + (bar_w - 1.0) / 2.0;
                let (y0, y1) = (plot.y(v - e), plot.y(v + e));
                let attrs = r##"class="error-bar" stroke="#222222" stroke-width="1.2""##;
                svg.line((cx, y0), (cx, y1), attrs);
                svg.line((cx - 4.0, y0), (cx + 4.0, y0), attrs);
                svg.line((cx - 4.0, y1), (cx + 4.0, y1), attrs);
            }
            if print_values {
                let above = if v >= plot.baseline() {
                    plot.y(v + e) - 3.0
                } else {
                    plot.y(v - e) + 11.0
                };
                svg.text(
                    x + (bar_w - 1.0) / 2.0,
                    above.max(plot.top - 2.0),
                    r##"class="value" font-size="9" text-anchor="middle" fill="#333333""##,
                    &format_value(v),
                );
            }
        }
        svg.raw("</g>");
    }
    svg.line(
        (plot.left, base_y),
        (plot.left + plot.width, base_y),
        r##"stroke="#333333""##,
    );
    let centres: Vec<f64> = (0..n)
        .map(|j| plot.left + (j as f64 + 0.5) * group_w)
        .collect();
    let label_h = draw_categories(
        &mut svg,
        categories,
        &centres,
        plot.top + plot.height,
        group_w,
    );
    let entries: Vec<(String, &str)> = series
        .iter()
        .enumerate()
        .map(|(i, s)| (s.label.clone(), palette(i)))
        .collect();
    let lx = plot.left + plot.width + 24.0;
    let legend_h = draw_legend(&mut svg, lx, plot.top, &entries);
    let width = lx + legend_width(series.iter().map(|s| &s.label)) + MARGIN_PX;
    let width = width.max(PLOT_LEFT_PX + text_width(title, 16.0) + MARGIN_PX);
    let height = (plot.top + plot.height + label_h).max(plot.top + legend_h) + MARGIN_PX;
    Ok(svg.finish(width, height, title))
}

/// Stacked bars: one bar per category, one layer per series (e.g. success / part collision /
/// path blocking / other shares; or handles passing mapping / navigation / exploration /
/// estimation), legend.
///
/// The y axis runs from 0 to the largest total rounded up to a nice tick; layers are stacked
/// in the order given, the first at the bottom. Segments tall enough show their value.
///
/// # Errors
/// [`SvgError::Empty`] without categories or layers; [`SvgError::DimensionMismatch`] when a
/// layer does not have one value per category; [`SvgError::NonFinite`] for NaN or infinite
/// values; [`SvgError::OutOfRange`] for a negative value.
pub fn stacked_bars(
    title: &str,
    categories: &[String],
    layers: &[Series],
    y_label: &str,
) -> Result<String, SvgError> {
    check_nonempty("categories", categories.len())?;
    check_nonempty("layers", layers.len())?;
    let n = categories.len();
    check_series("layer", layers, n, true)?;
    let totals: Vec<f64> = (0..n)
        .map(|j| layers.iter().map(|l| l.values[j]).sum())
        .collect();
    let max_total = totals.iter().copied().fold(0.0, f64::max);
    let axis = NiceAxis::new(0.0, max_total, None);
    let bar_w = (380.0 / (n as f64 * 1.6)).clamp(18.0, 64.0);
    let slot = bar_w * 1.6;
    let plot = Plot {
        left: PLOT_LEFT_PX,
        top: TITLE_HEIGHT_PX + 14.0,
        width: slot * n as f64,
        height: PLOT_HEIGHT_PX,
        axis,
    };
    let mut svg = Svg::new();
    plot.draw_value_axis(&mut svg, y_label);
    for (j, category) in categories.iter().enumerate() {
        let x = plot.left + j as f64 * slot + (slot - bar_w) / 2.0;
        let mut acc = 0.0;
        svg.raw(&format!(
            r#"<g class="stack" data-category="{}">"#,
            escape(category)
        ));
        for (i, layer) in layers.iter().enumerate() {
            let v = layer.values[j];
            let y_top = plot.y(acc + v);
            let y_bottom = plot.y(acc);
            acc += v;
            if v <= 0.0 {
                continue;
            }
            svg.raw(&format!(
                r##"<rect class="segment" data-layer="{}" x="{}" y="{}" width="{}" height="{}" fill="{}" stroke="#ffffff" stroke-width="0.5"><title>{}: {}</title></rect>"##,
                escape(&layer.label),
                px(x),
                px(y_top),
                px(bar_w),
                px(y_bottom - y_top),
                palette(i),
                escape(&format!("{} / {}", layer.label, category)),
                escape(&format_value(v)),
            ));
            let label = format_value(v);
            if y_bottom - y_top >= 14.0 && text_width(&label, 10.0) <= bar_w - 2.0 {
                svg.text(
                    x + bar_w / 2.0,
                    (y_top + y_bottom) / 2.0 + 3.5,
                    r##"class="value" font-size="10" text-anchor="middle" fill="#ffffff""##,
                    &label,
                );
            }
        }
        svg.raw("</g>");
    }
    let base_y = plot.y(0.0);
    svg.line(
        (plot.left, base_y),
        (plot.left + plot.width, base_y),
        r##"stroke="#333333""##,
    );
    let centres: Vec<f64> = (0..n)
        .map(|j| plot.left + (j as f64 + 0.5) * slot)
        .collect();
    let label_h = draw_categories(&mut svg, categories, &centres, plot.top + plot.height, slot);
    // The legend lists the top layer first, as the bars show it.
    let entries: Vec<(String, &str)> = layers
        .iter()
        .enumerate()
        .rev()
        .map(|(i, l)| (l.label.clone(), palette(i)))
        .collect();
    let lx = plot.left + plot.width + 24.0;
    let legend_h = draw_legend(&mut svg, lx, plot.top, &entries);
    let width = lx + legend_width(layers.iter().map(|s| &s.label)) + MARGIN_PX;
    let width = width.max(PLOT_LEFT_PX + text_width(title, 16.0) + MARGIN_PX);
    let height = (plot.top + plot.height + label_h).max(plot.top + legend_h) + MARGIN_PX;
    Ok(svg.finish(width, height, title))
}

/// Line chart: one polyline with point markers per series over the numeric `x` values (for
/// example a noise level), both axes with nice ticks, legend; `y_max` fixes the top of the y
/// axis (values above it are drawn at the top).
///
/// # Errors
/// [`SvgError::Empty`] without x values or series; [`SvgError::DimensionMismatch`] when a
/// series does not have one value per x value; [`SvgError::NonFinite`] for NaN or infinite x,
/// values or `y_max`; [`SvgError::OutOfRange`] for a `y_max` not above the axis minimum.
pub fn line_chart(
    title: &str,
    x_label: &str,
    x: &[f64],
    series: &[Series],
    y_label: &str,
    y_max: Option<f64>,
) -> Result<String, SvgError> {
    check_nonempty("x values", x.len())?;
    check_nonempty("series", series.len())?;
    for (j, &v) in x.iter().enumerate() {
        check_finite(|| format!("x value {}", j + 1), v)?;
    }
    check_series("series", series, x.len(), false)?;
    let values = || series.iter().flat_map(|s| s.values.iter().copied());
    let lo = values().fold(0.0, f64::min);
    let hi = values().fold(0.0, f64::max);
    if let Some(m) = y_max {
        check_finite(|| "y_max".into(), m)?;
        if m <= lo {
            return Err(SvgError::OutOfRange {
                what: "y_max".into(),
                requirement: "above the smallest value",
                value: m,
            });
        }
    }
    let x_lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let x_hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let x_axis = NiceAxis::new(x_lo, x_hi, None);
    let plot = Plot {
        left: PLOT_LEFT_PX,
        top: TITLE_HEIGHT_PX + 14.0,
        width: 480.0,
        height: PLOT_HEIGHT_PX,
        axis: NiceAxis::new(lo, hi, y_max),
    };
    let x_px = |v: f64| plot.left + plot.width * (v - x_axis.lo) / (x_axis.hi - x_axis.lo);
    let mut svg = Svg::new();
    plot.draw_value_axis(&mut svg, y_label);
    let bottom = plot.top + plot.height;
    svg.line(
        (plot.left, bottom),
        (plot.left + plot.width, bottom),
        r##"stroke="#333333""##,
    );
    for &t in &x_axis.ticks {
        let tx = x_px(t);
        svg.line((tx, bottom), (tx, bottom + 4.0), r##"stroke="#333333""##);
        svg.text(
            tx,
            bottom + 16.0,
            r#"class="tick" font-size="11" text-anchor="middle""#,
            &x_axis.label(t),
        );
    }
    svg.text(
        plot.left + plot.width / 2.0,
        bottom + 36.0,
        r#"text-anchor="middle""#,
        x_label,
    );
    for (i, s) in series.iter().enumerate() {
        let colour = palette(i);
        let points: Vec<String> = x
            .iter()
            .zip(&s.values)
            .map(|(&xv, &yv)| format!("{},{}", px(x_px(xv)), px(plot.y(yv))))
            .collect();
        svg.raw(&format!(
            r#"<g class="series" data-series="{}">"#,
            escape(&s.label)
        ));
        svg.raw(&format!(
            r#"<polyline class="line" points="{}" fill="none" stroke="{colour}" stroke-width="2"/>"#,
            points.join(" ")
        ));
        for (&xv, &yv) in x.iter().zip(&s.values) {
            svg.raw(&format!(
                r#"<circle class="point" cx="{}" cy="{}" r="3.5" fill="{colour}"><title>{}: {} at {}</title></circle>"#,
                px(x_px(xv)),
                px(plot.y(yv)),
                escape(&s.label),
                escape(&format_value(yv)),
                escape(&format_value(xv)),
            ));
        }
        svg.raw("</g>");
    }
    let entries: Vec<(String, &str)> = series
        .iter()
        .enumerate()
        .map(|(i, s)| (s.label.clone(), palette(i)))
        .collect();
    let lx = plot.left + plot.width + 24.0;
    let legend_h = draw_legend(&mut svg, lx, plot.top, &entries);
    let width = lx + legend_width(series.iter().map(|s| &s.label)) + MARGIN_PX;
    let width = width.max(PLOT_LEFT_PX + text_width(title, 16.0) + MARGIN_PX);
    let height = (bottom + 46.0).max(plot.top + legend_h) + MARGIN_PX;
    Ok(svg.finish(width, height, title))
}
