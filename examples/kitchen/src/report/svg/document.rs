//! Writing SVG as text: XML escaping, number and colour formats, the palette, and the `Svg`
//! document builder every picture uses.

/// `text` with the five XML special characters escaped (safe in text and attribute values).
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Control characters other than tab and newline are not allowed in XML 1.0.
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// A pixel coordinate (two decimals: 0.01 px).
pub(super) fn px(v: f64) -> String {
    let s = format!("{v:.2}");
    if s == "-0.00" { "0.00".into() } else { s }
}

/// A value for a label: about three significant digits, trailing zeros dropped.
pub fn format_value(v: f64) -> String {
    let a = v.abs();
    let decimals = if a >= 100.0 || a == 0.0 {
        0
    } else if a >= 10.0 {
        1
    } else if a >= 1.0 {
        2
    } else {
        3
    };
    trim_zeros(format!("{v:.decimals$}"))
}

pub(super) fn trim_zeros(s: String) -> String {
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".into() } else { s }
}

/// The categorical palette of series and plan steps (Tableau 10).
const PALETTE: [&str; 10] = [
    "#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f", "#edc948", "#b07aa1", "#ff9da7",
    "#9c755f", "#bab0ac",
];

/// Colour `i` of the categorical palette (cycling).
pub fn palette(i: usize) -> &'static str {
    PALETTE[i % PALETTE.len()]
}

/// A soft colour for part `i`: hues spaced by the golden angle, light and desaturated.
pub(super) fn part_colour(i: usize) -> String {
    let hue = (i as f64 * 137.508 + 200.0) % 360.0;
    hsl_hex(hue, 0.45, 0.72)
}

fn hsl_hex(h: f64, s: f64, l: f64) -> String {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = h / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    let byte = |v: f64| ((v + m).clamp(0.0, 1.0) * 255.0).round() as u8;
    format!("#{:02x}{:02x}{:02x}", byte(r), byte(g), byte(b))
}

/// Rough width (px) of `text` at `font_px` in a sans-serif font.
pub(super) fn text_width(text: &str, font_px: f64) -> f64 {
    text.chars().count() as f64 * font_px * 0.58
}

// ---------------------------------------------------------------------------------------------
// The document.

/// An SVG document being written.
pub(super) struct Svg {
    body: String,
}

impl Svg {
    pub(super) fn new() -> Self {
        Svg {
            body: String::new(),
        }
    }

    pub(super) fn raw(&mut self, s: &str) {
        self.body.push_str(s);
        self.body.push('\n');
    }

    /// Text at (x, y) with extra attributes (already escaped).
    pub(super) fn text(&mut self, x: f64, y: f64, attrs: &str, text: &str) {
        self.raw(&format!(
            r#"<text x="{}" y="{}" {attrs}>{}</text>"#,
            px(x),
            px(y),
            escape(text)
        ));
    }

    pub(super) fn line(&mut self, a: (f64, f64), b: (f64, f64), attrs: &str) {
        self.raw(&format!(
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" {attrs}/>"#,
            px(a.0),
            px(a.1),
            px(b.0),
            px(b.1)
        ));
    }

    pub(super) fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, attrs: &str) {
        self.raw(&format!(
            r#"<rect x="{}" y="{}" width="{}" height="{}" {attrs}/>"#,
            px(x),
            px(y),
            px(w.max(0.0)),
            px(h.max(0.0))
        ));
    }

    /// The standalone document of the given size with a white background and a title.
    pub(super) fn finish(self, width: f64, height: f64, title: &str) -> String {
        let mut out = String::with_capacity(self.body.len() + 512);
        out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        out.push_str(&format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="Helvetica, Arial, sans-serif" font-size="12">"#,
            w = px(width.ceil()),
            h = px(height.ceil()),
        ));
        out.push('\n');
        out.push_str(&format!("<title>{}</title>\n", escape(title)));
        out.push_str(&format!(
            r##"<rect x="0" y="0" width="{}" height="{}" fill="#ffffff"/>"##,
            px(width.ceil()),
            px(height.ceil())
        ));
        out.push('\n');
        out.push_str(&format!(
            r#"<text class="title" x="{}" y="24" font-size="16" font-weight="bold">{}</text>"#,
            px(MARGIN_PX),
            escape(title)
        ));
        out.push('\n');
        out.push_str(&self.body);
        out.push_str("</svg>\n");
        out
    }
}

/// Left/right margin of every picture (px).
pub(super) const MARGIN_PX: f64 = 16.0;

/// Height of the title band at the top of every picture (px); the drawing starts below it.
pub const TITLE_HEIGHT_PX: f64 = 36.0;
