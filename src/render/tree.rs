//! An SVG document as a small element tree whose attribute values keep their numbers.
//!
//! Frames are built as trees rather than written straight to text so that the animated SVG can
//! line up the same element across keyframes and animate exactly the values that change: path
//! outlines as geometry (to fit curves through every keyframe at once), numbers as numbers (to
//! drop keyframes that their neighbours reproduce), transforms as matrices (to decompose into
//! SMIL `animateTransform`s). A single frame is the same tree serialized once.

use crate::error::{Error, Result};
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

    fn write(&self, w: &mut Writer<Vec<u8>>) -> std::io::Result<()> {
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

/// Path data with `decimals` decimals per coordinate.
pub(crate) fn path_data(path: &BezPath, decimals: usize) -> String {
    let mut d = String::new();
    let pt = |q: kurbo::Point| format!("{} {}", fixed(q.x, decimals), fixed(q.y, decimals));
    for el in path.elements() {
        if !d.is_empty() {
            d.push(' ');
        }
        match *el {
            PathEl::MoveTo(q) => d.push_str(&format!("M{}", pt(q))),
            PathEl::LineTo(q) => d.push_str(&format!("L{}", pt(q))),
            PathEl::QuadTo(q1, q) => d.push_str(&format!("Q{} {}", pt(q1), pt(q))),
            PathEl::CurveTo(q1, q2, q) => d.push_str(&format!("C{} {} {}", pt(q1), pt(q2), pt(q))),
            PathEl::ClosePath => d.push('Z'),
        }
    }
    d
}

/// `x` with at most `decimals` decimals, trailing zeros dropped, no negative zero.
pub(crate) fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// `x` to 9 significant digits (for scale-free values: opacities, gradient geometry, matrices).
pub(crate) fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return "0".into();
    }
    let r: f64 = format!("{x:.8e}").parse().unwrap_or(x);
    let s = format!("{r}");
    if s == "-0" {
        "0".into()
    } else {
        s
    }
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
            r#"<g opacity="0.5"><path d="M0 0 L1.25 0 Z"/></g>"#
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
