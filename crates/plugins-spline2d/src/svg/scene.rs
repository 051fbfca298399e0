//! The drawing itself: shapes in world coordinates grouped in styled layers, their bounds, and
//! writing a panel as SVG elements (flipped y axis, two decimals, escaped text).

use super::{MARGIN, TITLE_HEIGHT};
use std::fmt::Write as _;

/// Something to draw, in world coordinates (radii in pixels).
#[derive(Debug, Clone)]
pub(super) enum SvgElement {
    Line([f64; 2], [f64; 2]),
    Polyline(Vec<[f64; 2]>),
    Polygon(Vec<[f64; 2]>),
    Circle([f64; 2], f64),
    Text([f64; 2], String),
}

impl SvgElement {
    /// Calls `f` with every point of the shape (for bounds).
    fn each_point(&self, mut f: impl FnMut(&[f64; 2])) {
        match self {
            SvgElement::Line(a, b) => {
                f(a);
                f(b);
            }
            SvgElement::Polyline(p) | SvgElement::Polygon(p) => p.iter().for_each(f),
            SvgElement::Circle(c, _) | SvgElement::Text(c, _) => f(c),
        }
    }
}

/// One group of shapes sharing a style.
#[derive(Debug, Clone)]
pub(super) struct StyledGroup {
    class: String,
    style: String,
    shapes: Vec<SvgElement>,
}

impl StyledGroup {
    pub(super) fn new(class: &str, style: &str, shapes: Vec<SvgElement>) -> Self {
        StyledGroup {
            class: class.to_string(),
            style: style.to_string(),
            shapes,
        }
    }

    /// The group's class (what it draws), for tests.
    #[cfg(test)]
    pub(super) fn name(&self) -> &str {
        &self.class
    }

    /// Its number of shapes, for tests.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.shapes.len()
    }
}

/// Axis-aligned bounds of world coordinates; empty when `lo > hi`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Bounds {
    lo: [f64; 2],
    hi: [f64; 2],
}

impl Bounds {
    fn empty() -> Self {
        Bounds {
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
        }
    }

    fn add(&mut self, p: &[f64; 2]) {
        for ((lo, hi), x) in self.lo.iter_mut().zip(self.hi.iter_mut()).zip(p) {
            *lo = lo.min(*x);
            *hi = hi.max(*x);
        }
    }

    pub(super) fn union(&self, other: &Bounds) -> Bounds {
        Bounds {
            lo: [self.lo[0].min(other.lo[0]), self.lo[1].min(other.lo[1])],
            hi: [self.hi[0].max(other.hi[0]), self.hi[1].max(other.hi[1])],
        }
    }

    /// The bounds, or the unit square at the origin when nothing was added.
    fn or_unit(self) -> Bounds {
        if self.lo[0] <= self.hi[0] && self.lo[1] <= self.hi[1] {
            self
        } else {
            Bounds {
                lo: [0.0, 0.0],
                hi: [1.0, 1.0],
            }
        }
    }

    fn extent(&self) -> [f64; 2] {
        [self.hi[0] - self.lo[0], self.hi[1] - self.lo[1]]
    }
}

/// Pixels per world unit so that the longer side of `bounds` is `size` pixels.
pub(super) fn scale_for(bounds: &Bounds, size: f64) -> f64 {
    let [w, h] = bounds.extent();
    let longest = w.max(h);
    if longest > 0.0 && longest.is_finite() {
        size / longest
    } else {
        1.0
    }
}

/// Drawn content of one panel.
#[derive(Debug, Clone)]
pub(super) struct Scene {
    pub(super) layers: Vec<StyledGroup>,
    pub(super) title: Option<String>,
}

impl Scene {
    pub(super) fn bounds(&self) -> Bounds {
        let mut b = Bounds::empty();
        for layer in &self.layers {
            for shape in &layer.shapes {
                shape.each_point(|p| b.add(p));
            }
        }
        b.or_unit()
    }

    fn title_height(&self) -> f64 {
        if self.title.is_some() {
            TITLE_HEIGHT
        } else {
            0.0
        }
    }

    pub(super) fn panel_size(&self, bounds: &Bounds, scale: f64) -> (f64, f64) {
        let [w, h] = bounds.extent();
        (
            w * scale + 2.0 * MARGIN,
            h * scale + 2.0 * MARGIN + self.title_height(),
        )
    }

    /// Writes the panel with its top left corner at `offset`; `width` is the panel's width.
    pub(super) fn render(
        &self,
        out: &mut String,
        bounds: &Bounds,
        scale: f64,
        offset: [f64; 2],
        width: f64,
    ) {
        let top = offset[1] + self.title_height() + MARGIN;
        let to_screen = |p: &[f64; 2]| -> [f64; 2] {
            [
                offset[0] + MARGIN + (p[0] - bounds.lo[0]) * scale,
                top + (bounds.hi[1] - p[1]) * scale,
            ]
        };
        if let Some(title) = &self.title {
            let _ = writeln!(
                out,
                r#"<text class="title" x="{}" y="{}" font-family="sans-serif" font-size="14" text-anchor="middle">{}</text>"#,
                num(offset[0] + width / 2.0),
                num(offset[1] + 17.0),
                escape(title)
            );
        }
        for layer in &self.layers {
            if layer.shapes.is_empty() {
                continue;
            }
            let _ = writeln!(out, r#"<g class="{}" {}>"#, layer.class, layer.style);
            for shape in &layer.shapes {
                match shape {
                    SvgElement::Line(a, b) => {
                        let (a, b) = (to_screen(a), to_screen(b));
                        let _ = writeln!(
                            out,
                            r#"<line x1="{}" y1="{}" x2="{}" y2="{}"/>"#,
                            num(a[0]),
                            num(a[1]),
                            num(b[0]),
                            num(b[1])
                        );
                    }
                    SvgElement::Polyline(points) | SvgElement::Polygon(points) => {
                        let tag = if matches!(shape, SvgElement::Polygon(_)) {
                            "polygon"
                        } else {
                            "polyline"
                        };
                        let _ = write!(out, r#"<{tag} points=""#);
                        for (i, p) in points.iter().enumerate() {
                            let s = to_screen(p);
                            if i > 0 {
                                out.push(' ');
                            }
                            let _ = write!(out, "{},{}", num(s[0]), num(s[1]));
                        }
                        out.push_str("\"/>\n");
                    }
                    SvgElement::Circle(c, r) => {
                        let c = to_screen(c);
                        let _ = writeln!(
                            out,
                            r#"<circle cx="{}" cy="{}" r="{}"/>"#,
                            num(c[0]),
                            num(c[1]),
                            num(*r)
                        );
                    }
                    SvgElement::Text(p, text) => {
                        let p = to_screen(p);
                        let _ = writeln!(
                            out,
                            r#"<text x="{}" y="{}">{}</text>"#,
                            num(p[0] + 6.0),
                            num(p[1] - 6.0),
                            escape(text)
                        );
                    }
                }
            }
            out.push_str("</g>\n");
        }
    }
}

pub(super) fn header(width: f64, height: f64) -> String {
    let (w, h) = (num(width), num(height));
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n"
    )
}

/// A coordinate with two decimals; `-0.00` is written `0.00`.
pub(super) fn num(x: f64) -> String {
    let s = format!("{x:.2}");
    if s == "-0.00" {
        "0.00".to_string()
    } else {
        s
    }
}

/// Escapes text for SVG content and attribute values.
pub(super) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            // Control characters other than tab and newlines are not allowed in XML 1.0.
            c if c.is_control() && !matches!(c, '\t' | '\n' | '\r') => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}
/// Whether both coordinates are finite (drawable).
pub(super) fn finite(p: &[f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}
