//! An SVG document as a small element tree whose attribute values keep their numbers.
//!
//! Frames are built as trees rather than written straight to text so that the animated SVG can
//! line up the same element across keyframes and animate exactly the values that change: path
//! outlines as geometry (to fit curves through every keyframe at once), numbers as numbers (to
//! drop keyframes that their neighbours reproduce), transforms as matrices (to decompose into
//! SMIL `animateTransform`s). A single frame is the same tree serialized once.

use crate::error::{Error, Result};
pub(crate) use crate::number::{fixed, sig};
use kurbo::{Affine, BezPath, PathEl};
use quick_xml::events::{BytesEnd, BytesStart, Event};
use quick_xml::Writer;

/// How a number is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NumFormat {
    /// At most this many decimals (coordinates and lengths, rounded to the output's precision).
    Fixed(usize),
    /// Nine significant digits (scale-free values: opacities, blend weights).
    Sig,
}

impl NumFormat {
    pub(crate) fn write(self, x: f64) -> String {
        match self {
            NumFormat::Fixed(d) => fixed(x, d),
            NumFormat::Sig => sig(x),
        }
    }
}

/// An attribute value.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value {
    /// Text that is not interpolated (ids, references, keywords).
    Text(String),
    /// One or more numbers separated by spaces (`stroke-width`, `stroke-dasharray`, `k2`).
    Nums(Vec<f64>, NumFormat),
    /// Path data, coordinates with `decimals` decimals.
    Path {
        /// The outline.
        path: BezPath,
        /// Decimals of each coordinate.
        decimals: usize,
        /// `Some(tolerance)`: runs of straight segments may be replaced by cubic curves that stay
        /// within `tolerance` user units of them (warped artwork, which is flattened; never the
        /// exact input).
        fit: Option<f64>,
    },
    /// A `matrix(…)` transform.
    Matrix(Affine),
    /// An opaque colour, written `#rrggbb` (alpha goes in a separate opacity attribute).
    Color(crate::artwork::Rgba),
}

impl From<String> for Value {
    fn from(s: String) -> Self {
        Value::Text(s)
    }
}

impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::Text(s.to_string())
    }
}

impl Value {
    /// One number written with `format`.
    pub(crate) fn num(x: f64, format: NumFormat) -> Self {
        Value::Nums(vec![x], format)
    }

    /// The attribute text.
    pub(crate) fn text(&self) -> String {
        match self {
            Value::Text(s) => s.clone(),
            Value::Nums(v, f) => v.iter().map(|x| f.write(*x)).collect::<Vec<_>>().join(" "),
            Value::Path {
                path,
                decimals,
                fit: None,
            } => path_data(path, *decimals),
            Value::Path {
                path,
                decimals,
                fit: Some(tol),
            } => path_data(
                &super::fit::fit_paths(std::slice::from_ref(path), *tol)[0],
                *decimals,
            ),
            Value::Matrix(m) => matrix(*m),
            Value::Color(c) => format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b),
        }
    }
}

/// One element: name, attributes in writing order, children.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Node {
    pub(crate) name: String,
    pub(crate) attrs: Vec<(&'static str, Value)>,
    pub(crate) children: Vec<Node>,
}

impl Node {
    pub(crate) fn new(name: &str, attrs: Vec<(&'static str, Value)>) -> Self {
        Node {
            name: name.to_string(),
            attrs,
            children: Vec::new(),
        }
    }

    /// The document as text, with an XML declaration-free `<svg>` root.
    pub(crate) fn to_svg_string(&self) -> Result<String> {
        let mut w = Writer::new(Vec::new());
        self.write(&mut w)
            .map_err(|_| Error::internal("writing the SVG failed"))?;
        String::from_utf8(w.into_inner()).map_err(|_| Error::internal("the SVG is not UTF-8"))
    }

    /// The document written to `out` as it is serialized (no text of the whole file in
    /// memory).
    pub(crate) fn write_svg<W: std::io::Write>(&self, out: W) -> Result<()> {
        let mut w = Writer::new(std::io::BufWriter::new(out));
        self.write(&mut w)
            .map_err(|e| Error::internal(format!("writing the SVG failed: {e}")))?;
        std::io::Write::flush(w.get_mut())
            .map_err(|e| Error::internal(format!("writing the SVG failed: {e}")))
    }

    fn write<W: std::io::Write>(&self, w: &mut Writer<W>) -> std::io::Result<()> {
        let mut e = BytesStart::new(self.name.as_str());
        for (k, v) in &self.attrs {
            let text = v.text();
            e.push_attribute((*k, text.as_str()));
        }
        if self.children.is_empty() {
            w.write_event(Event::Empty(e))?;
        } else {
            w.write_event(Event::Start(e))?;
            for c in &self.children {
                c.write(w)?;
            }
            w.write_event(Event::End(BytesEnd::new(self.name.as_str())))?;
        }
        Ok(())
    }
}

/// Builds a tree with open/close calls in document order.
#[derive(Debug)]
pub(crate) struct Builder {
    stack: Vec<Node>,
}

impl Builder {
    /// A builder whose result is the children of a (nameless) holder node.
    pub(crate) fn new() -> Self {
        Builder {
            stack: vec![Node::default()],
        }
    }

    pub(crate) fn open(&mut self, name: &str, attrs: Vec<(&'static str, Value)>) {
        self.stack.push(Node::new(name, attrs));
    }

    pub(crate) fn empty(&mut self, name: &str, attrs: Vec<(&'static str, Value)>) {
        self.push(Node::new(name, attrs));
    }

    pub(crate) fn push(&mut self, node: Node) {
        if let Some(top) = self.stack.last_mut() {
            top.children.push(node);
        }
    }

    pub(crate) fn close(&mut self) {
        if self.stack.len() > 1 {
            if let Some(n) = self.stack.pop() {
                self.push(n);
            }
        }
    }

    /// Whether nothing was added.
    pub(crate) fn is_empty(&self) -> bool {
        self.stack.len() == 1 && self.stack[0].children.is_empty()
    }

    /// The top-level nodes built (closing any still open).
    pub(crate) fn finish(mut self) -> Vec<Node> {
        while self.stack.len() > 1 {
            self.close();
        }
        self.stack.pop().map(|n| n.children).unwrap_or_default()
    }
}

/// Compact path data with `decimals` decimals per coordinate: relative commands (`m l q c z`),
/// no leading zeros, no separator before a minus sign. Every point is rounded in absolute
/// coordinates first and the relative steps are taken between rounded points, so rounding
/// never accumulates along the path. Keyframes of one outline keep the same commands.
pub(crate) fn path_data(path: &BezPath, decimals: usize) -> String {
    let unit = 10f64.powi(decimals as i32);
    // Rounded absolute coordinates as integers of 10^-decimals.
    let round = |q: kurbo::Point| ((q.x * unit).round() as i64, (q.y * unit).round() as i64);
    let mut d = String::new();
    let mut cur = (0i64, 0i64);
    let mut start = (0i64, 0i64);
    let push = |d: &mut String, v: i64| {
        let text = scaled(v, decimals);
        let after_number = d
            .as_bytes()
            .last()
            .is_some_and(|c| c.is_ascii_digit() || *c == b'.');
        let self_delimiting =
            text.starts_with('-') || (text.starts_with('.') && last_number_has_point(d));
        if after_number && !self_delimiting {
            d.push(' ');
        }
        d.push_str(&text);
    };
    for el in path.elements() {
        let points = |d: &mut String, cmd: char, pts: &[kurbo::Point], cur: &mut (i64, i64)| {
            d.push(cmd);
            let base = *cur;
            for q in pts {
                let r = round(*q);
                push(d, r.0 - base.0);
                push(d, r.1 - base.1);
                *cur = r;
            }
        };
        match *el {
            PathEl::MoveTo(q) => {
                points(&mut d, 'm', &[q], &mut cur);
                start = cur;
            }
            PathEl::LineTo(q) => points(&mut d, 'l', &[q], &mut cur),
            PathEl::QuadTo(a, q) => points(&mut d, 'q', &[a, q], &mut cur),
            PathEl::CurveTo(a, b, q) => points(&mut d, 'c', &[a, b, q], &mut cur),
            PathEl::ClosePath => {
                d.push('z');
                cur = start;
            }
        }
    }
    d
}

/// Whether the number at the end of `d` already has a decimal point (so a following `.5`
/// starts a new number without a separator).
fn last_number_has_point(d: &str) -> bool {
    d.bytes()
        .rev()
        .take_while(|c| c.is_ascii_digit() || *c == b'.')
        .any(|c| c == b'.')
}

/// `v · 10^-decimals` written without trailing zeros or a leading zero: `-.5`, `12.25`, `3`.
fn scaled(v: i64, decimals: usize) -> String {
    let neg = v < 0;
    let a = v.unsigned_abs();
    let unit = 10u64.pow(decimals as u32);
    let (int, frac) = (a / unit, a % unit);
    let mut s = String::new();
    if neg && a != 0 {
        s.push('-');
    }
    if frac == 0 {
        s.push_str(&int.to_string());
        return s;
    }
    if int != 0 {
        s.push_str(&int.to_string());
    }
    let f = format!("{frac:0decimals$}");
    s.push('.');
    s.push_str(f.trim_end_matches('0'));
    s
}

/// A `matrix(a b c d e f)` transform attribute. Coefficients that are rounding noise (below
/// 1e-12 of the largest linear coefficient, or 1e-9 for a translation) are written as 0.
pub(crate) fn matrix(m: Affine) -> String {
    let mut c = m.as_coeffs();
    let scale = c[..4].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for (i, x) in c.iter_mut().enumerate() {
        let floor = if i < 4 { 1e-12 * scale } else { 1e-9 };
        if x.abs() < floor {
            *x = 0.0;
        }
    }
    format!(
        "matrix({} {} {} {} {} {})",
        sig(c[0]),
        sig(c[1]),
        sig(c[2]),
        sig(c[3]),
        sig(c[4]),
        sig(c[5])
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_formats() {
        assert_eq!(fixed(1.23456, 2), "1.23");
        assert_eq!(fixed(-0.001, 2), "0");
        assert_eq!(fixed(10.0, 2), "10");
        assert_eq!(fixed(3.5, 0), "4");
        assert_eq!(sig(0.1 + 0.2), "0.3");
        assert_eq!(sig(-1.0), "-1");
        assert_eq!(sig(123456789.123), "123456789");
    }

    #[test]
    fn path_data_is_compact_relative_and_does_not_drift() {
        let mut p = BezPath::new();
        p.move_to((10.0, 20.0));
        p.line_to((10.5, 19.25));
        p.curve_to((11.0, 19.0), (12.0, 19.0), (13.0, 20.0));
        p.close_path();
        p.move_to((0.0, 0.0));
        p.line_to((-0.05, 0.5));
        assert_eq!(
            path_data(&p, 2),
            "m10 20l.5-.75c.5-.25 1.5-.25 2.5.75zm-10-20l-.05.5"
        );
        // 1000 steps of 0.0049 rounded to 0.01 would drift by 4.9 if rounded step by step.
        let mut q = BezPath::new();
        q.move_to((0.0, 0.0));
        for i in 1..=1000 {
            q.line_to((i as f64 * 0.0049, 0.0));
        }
        let d = path_data(&q, 2);
        let total: f64 = d
            .split('l')
            .skip(1)
            .map(|s| s.split([' ', '-']).next().unwrap())
            .map(|x| {
                if x.is_empty() {
                    0.0
                } else {
                    x.parse::<f64>().unwrap()
                }
            })
            .sum();
        assert!((total - 4.9).abs() < 0.006, "{total}");
        // Parses back (usvg via svgtypes) to the rounded points.
        let parsed: Vec<_> = svgtypes::SimplifyingPathParser::from(d.as_str())
            .map(|s| s.unwrap())
            .collect();
        assert_eq!(parsed.len(), 1001);
        assert_eq!(scaled(-5, 1), "-.5");
        assert_eq!(scaled(1200, 2), "12");
        assert_eq!(scaled(-1205, 2), "-12.05");
        assert_eq!(scaled(0, 3), "0");
    }

    #[test]
    fn builder_nests_and_serializes() {
        let mut b = Builder::new();
        assert!(b.is_empty());
        b.open("g", vec![("opacity", Value::num(0.5, NumFormat::Sig))]);
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.line_to((1.25, -0.004));
        p.close_path();
        b.empty(
            "path",
            vec![(
                "d",
                Value::Path {
                    path: p,
                    decimals: 2,
                    fit: None,
                },
            )],
        );
        b.close();
        let nodes = b.finish();
        assert_eq!(nodes.len(), 1);
        assert_eq!(
            nodes[0].to_svg_string().unwrap(),
            r#"<g opacity="0.5"><path d="m0 0l1.25 0z"/></g>"#
        );
        assert_eq!(
            Value::Nums(vec![1.0, 2.5], NumFormat::Fixed(1)).text(),
            "1 2.5"
        );
        assert_eq!(
            Value::Matrix(Affine::translate((3.0, 4.0))).text(),
            "matrix(1 0 0 1 3 4)"
        );
        assert_eq!(
            matrix(Affine::new([2.0, -3e-16, 1e-15, 2.0, 1e-12, 5.0])),
            "matrix(2 0 0 2 0 5)"
        );
    }
}
