//! Chart axes and frames: "nice" value axes, the plot rectangle with its value axis, category
//! labels and legends.

use super::document::{Svg, escape, px, text_width};

/// A value axis with "nice" ticks (steps of 1, 2, 2.5 or 5 times a power of ten).
#[derive(Debug, Clone, PartialEq)]
pub struct NiceAxis {
    /// The axis minimum.
    pub lo: f64,
    /// The axis maximum.
    pub hi: f64,
    /// The tick step.
    pub step: f64,
    /// The tick values, from `lo` to `hi`.
    pub ticks: Vec<f64>,
    /// Decimals that print every tick exactly.
    pub decimals: usize,
}

impl NiceAxis {
    /// An axis covering `[lo, hi]` with about 5 ticks; the ends are rounded out to whole
    /// steps unless `fixed_hi` fixes the maximum. Expects finite input with `lo <= hi`
    /// (callers validate); an empty range becomes `[lo, lo + 1]`.
    pub fn new(lo: f64, hi: f64, fixed_hi: Option<f64>) -> Self {
        let hi = fixed_hi.unwrap_or(hi);
        let (lo, hi) = if hi > lo { (lo, hi) } else { (lo, lo + 1.0) };
        // hi/5 − lo/5 stays finite for any finite input (hi − lo may overflow).
        let step = nice_step(hi / 5.0 - lo / 5.0);
        let lo = (lo / step).floor() * step;
        let hi = if fixed_hi.is_some() {
            hi
        } else {
            (hi / step - 1e-9).ceil() * step
        };
        let first = (lo / step).round() as i64;
        let last = (hi / step + 1e-9).floor() as i64;
        // At most MAX_TICKS, whatever the rounding did at extreme magnitudes.
        let ticks = (first..=last)
            .take(MAX_TICKS)
            .map(|k| k as f64 * step)
            .collect();
        let decimals = (0..=9)
            .find(|&d| {
                let scaled = step * 10f64.powi(d as i32);
                (scaled - scaled.round()).abs() < 1e-6 * scaled.max(1.0)
            })
            .unwrap_or(9);
        NiceAxis {
            lo,
            hi,
            step,
            ticks,
            decimals,
        }
    }

    /// A tick label.
    pub fn label(&self, v: f64) -> String {
        let s = format!("{:.*}", self.decimals, v);
        if s.trim_start_matches('-')
            .chars()
            .all(|c| c == '0' || c == '.')
        {
            format!("{:.*}", self.decimals, 0.0)
        } else {
            s
        }
    }
}

/// The most ticks an axis or grid gets.
pub(super) const MAX_TICKS: usize = 50;

/// The smallest of 1, 2, 2.5, 5, 10 times a power of ten that is at least `raw` (> 0).
pub(super) fn nice_step(raw: f64) -> f64 {
    if !(raw > 0.0 && raw.is_finite()) {
        return 1.0;
    }
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let n = [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .find(|&n| f <= n * (1.0 + 1e-9))
        .unwrap_or(10.0);
    n * mag
}

/// The rectangle of a chart's plot area and its value axis (pixels grow downwards).
pub(super) struct Plot {
    pub(super) left: f64,
    pub(super) top: f64,
    pub(super) width: f64,
    pub(super) height: f64,
    pub(super) axis: NiceAxis,
}

impl Plot {
    /// Pixel y of value `v` (clamped into the axis).
    pub(super) fn y(&self, v: f64) -> f64 {
        let v = v.clamp(self.axis.lo, self.axis.hi);
        self.top + self.height * (self.axis.hi - v) / (self.axis.hi - self.axis.lo)
    }

    /// Grid lines, tick labels and the rotated y label.
    pub(super) fn draw_value_axis(&self, svg: &mut Svg, y_label: &str) {
        for &t in &self.axis.ticks {
            let y = self.y(t);
            svg.line(
                (self.left, y),
                (self.left + self.width, y),
                r##"stroke="#e3e3e3" stroke-width="1""##,
            );
            svg.line(
                (self.left - 4.0, y),
                (self.left, y),
                r##"stroke="#333333""##,
            );
            svg.text(
                self.left - 7.0,
                y + 4.0,
                r#"class="tick" text-anchor="end" font-size="11""#,
                &self.axis.label(t),
            );
        }
        svg.line(
            (self.left, self.top),
            (self.left, self.top + self.height),
            r##"stroke="#333333""##,
        );
        let cx = 18.0;
        let cy = self.top + self.height / 2.0;
        svg.raw(&format!(
            r#"<text x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text>"#,
            escape(y_label),
            x = px(cx),
            y = px(cy),
        ));
    }

    /// The baseline (value 0 if on the axis, else the axis minimum).
    pub(super) fn baseline(&self) -> f64 {
        if self.axis.lo <= 0.0 && 0.0 <= self.axis.hi {
            0.0
        } else {
            self.axis.lo
        }
    }
}

/// Category labels centred at `centres`, below `y`; rotated when they do not fit `slot` px.
/// Returns the height they take.
pub(super) fn draw_categories(
    svg: &mut Svg,
    categories: &[String],
    centres: &[f64],
    y: f64,
    slot: f64,
) -> f64 {
    let widest = categories
        .iter()
        .map(|c| text_width(c, 11.0))
        .fold(0.0, f64::max);
    let rotate = widest > slot - 4.0;
    for (c, &x) in categories.iter().zip(centres) {
        if rotate {
            let ty = y + 14.0;
            svg.raw(&format!(
                r#"<text class="category" x="{x}" y="{y}" font-size="11" text-anchor="end" transform="rotate(-35 {x} {y})">{}</text>"#,
                escape(c),
                x = px(x),
                y = px(ty),
            ));
        } else {
            svg.text(
                x,
                y + 15.0,
                r#"class="category" font-size="11" text-anchor="middle""#,
                c,
            );
        }
    }
    if rotate {
        widest * (35f64.to_radians()).sin() + 22.0
    } else {
        24.0
    }
}

/// A vertical legend of colour swatches at (x, y); returns its height.
pub(super) fn draw_legend(svg: &mut Svg, x: f64, y: f64, entries: &[(String, &str)]) -> f64 {
    for (i, (label, colour)) in entries.iter().enumerate() {
        let ey = y + i as f64 * 18.0;
        svg.rect(
            x,
            ey,
            12.0,
            12.0,
            &format!(r#"class="legend-swatch" fill="{colour}""#),
        );
        svg.text(x + 18.0, ey + 10.5, r#"class="legend""#, label);
    }
    entries.len() as f64 * 18.0
}

pub(super) fn legend_width(labels: impl Iterator<Item = impl AsRef<str>>) -> f64 {
    labels
        .map(|l| text_width(l.as_ref(), 12.0))
        .fold(0.0, f64::max)
        + 40.0
}

/// Chart plot height (px).
pub(super) const PLOT_HEIGHT_PX: f64 = 320.0;
/// Chart plot left edge (px): room for tick labels and the y label.
pub(super) const PLOT_LEFT_PX: f64 = 72.0;
