//! The `inspect` picture: the two compatible triangulations side by side, the boundary and each
//! feature curve in its own colour, the associated salient points marked (like the paper's
//! Fig.2(c) and Fig.8). This is the picture a user looks at to judge the triangulation.

use std::fmt::Write as _;

use quick_xml::events::{BytesEnd, BytesStart, BytesText, Event};
use quick_xml::Writer;

use crate::compatible::Compatible;
use crate::geometry::{bounding_box, orient2d, Point};
use crate::mesh::CurveKind;

/// Side of one panel in pixels.
const PANEL: f64 = 480.0;
/// Margin around a panel's content.
const MARGIN: f64 = 24.0;
/// Space for the caption under each panel.
const CAPTION: f64 = 28.0;

/// Colours of feature curves, in name order (boundary is drawn in near-black).
const PALETTE: [&str; 10] = [
    "#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4", "#f032e6", "#9a6324",
    "#469990", "#bfef45",
];

/// The colour used for curve number `k` (0 is the boundary).
pub fn curve_colour(k: usize, kind: CurveKind) -> &'static str {
    match kind {
        CurveKind::Boundary => "#222222",
        CurveKind::Feature => PALETTE[(k.saturating_sub(1)) % PALETTE.len()],
    }
}

struct Panel {
    offset: Point,
    scale: f64,
    lo: Point,
}

impl Panel {
    fn new(points: &[Point], index: usize) -> Panel {
        let (lo, hi) = bounding_box(points.iter().copied()).unwrap_or((Point::ZERO, Point::ONE));
        let size = (hi - lo).max_element().max(1e-300);
        let scale = (PANEL - 2.0 * MARGIN) / size;
        let content = (hi - lo) * scale;
        let offset = Point::new(index as f64 * PANEL, 0.0)
            + Point::splat(MARGIN)
            + (Point::splat(PANEL - 2.0 * MARGIN) - content) * 0.5;
        Panel { offset, scale, lo }
    }

    fn map(&self, p: Point) -> Point {
        self.offset + (p - self.lo) * self.scale
    }
}

fn fmt_xy(s: &mut String, p: Point) {
    let _ = write!(s, "{:.2} {:.2}", p.x, p.y);
}

/// Path data of separate segments, mapped into the panel.
fn segments(p: &Panel, segs: impl Iterator<Item = (Point, Point)>) -> String {
    let mut d = String::new();
    for (a, b) in segs {
        d.push('M');
        fmt_xy(&mut d, p.map(a));
        d.push('L');
        fmt_xy(&mut d, p.map(b));
    }
    d
}

fn el<'a>(name: &'a str, attrs: &[(&'a str, &'a str)]) -> BytesStart<'a> {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, *v));
    }
    e
}

/// A skeleton to draw over a panel: bones and joint positions.
type SkeletonView<'a> = Option<(&'a [[u32; 2]], &'a [Point])>;

/// A skeleton to draw over both panels: bones, source joints, target joints.
pub type SkeletonPair<'a> = Option<(&'a [[u32; 2]], &'a [Point], &'a [Point])>;

fn panel(
    w: &mut Writer<Vec<u8>>,
    c: &Compatible,
    points: &[Point],
    index: usize,
    title: &str,
    skeleton: SkeletonView<'_>,
) {
    let m = &c.meshes;
    let p = Panel::new(points, index);
    // Mesh edges as one path.
    let d = segments(
        &p,
        crate::mesh::edges(&m.triangles)
            .into_iter()
            .map(|(a, b)| (points[a as usize], points[b as usize])),
    );
    let _ = w.write_event(Event::Empty(el(
        "path",
        &[
            ("d", &d),
            ("fill", "none"),
            ("stroke", "#9aa4b1"),
            ("stroke-width", "0.6"),
        ],
    )));
    // Inverted triangles, if any, in red: they must never appear.
    let mut bad = String::new();
    for t in &m.triangles {
        let [a, b, cc] = t.map(|i| points[i as usize]);
        if orient2d(a, b, cc) <= 0.0 {
            bad.push('M');
            fmt_xy(&mut bad, p.map(a));
            bad.push('L');
            fmt_xy(&mut bad, p.map(b));
            bad.push('L');
            fmt_xy(&mut bad, p.map(cc));
            bad.push('Z');
        }
    }
    if !bad.is_empty() {
        let _ = w.write_event(Event::Empty(el(
            "path",
            &[("d", &bad), ("fill", "#ff0000"), ("fill-opacity", "0.6")],
        )));
    }
    // Curves and their salient points.
    for (k, curve) in m.curves.iter().enumerate() {
        let colour = curve_colour(k, curve.kind);
        let mut d = String::new();
        for (i, &v) in curve.vertices.iter().enumerate() {
            d.push(if i == 0 { 'M' } else { 'L' });
            fmt_xy(&mut d, p.map(points[v as usize]));
        }
        if curve.closed {
            d.push('Z');
        }
        let mut g = el(
            "path",
            &[
                ("d", &d),
                ("fill", "none"),
                ("stroke", colour),
                ("stroke-width", "2"),
            ],
        );
        g.push_attribute(("data-curve", curve.name.as_str()));
        let _ = w.write_event(Event::Empty(g));
        if let Some(pair) = c.pairs.get(k) {
            for &s in &pair.salient {
                if let Some(&v) = curve.vertices.get(s) {
                    let q = p.map(points[v as usize]);
                    let (cx, cy) = (format!("{:.2}", q.x), format!("{:.2}", q.y));
                    let _ = w.write_event(Event::Empty(el(
                        "circle",
                        &[
                            ("cx", &cx),
                            ("cy", &cy),
                            ("r", "3.5"),
                            ("fill", colour),
                            ("stroke", "#ffffff"),
                            ("stroke-width", "1"),
                        ],
                    )));
                }
            }
        }
    }
    if let Some((bones, joints)) = skeleton {
        let d = segments(
            &p,
            bones
                .iter()
                .map(|&[a, b]| (joints[a as usize], joints[b as usize])),
        );
        let _ = w.write_event(Event::Empty(el(
            "path",
            &[
                ("d", &d),
                ("fill", "none"),
                ("stroke", "#00acc1"),
                ("stroke-width", "3"),
                ("stroke-linecap", "round"),
                ("data-skeleton", "bones"),
            ],
        )));
        for &j in joints {
            let q = p.map(j);
            let (cx, cy) = (format!("{:.2}", q.x), format!("{:.2}", q.y));
            let _ = w.write_event(Event::Empty(el(
                "circle",
                &[
                    ("cx", &cx),
                    ("cy", &cy),
                    ("r", "4"),
                    ("fill", "#ffffff"),
                    ("stroke", "#00838f"),
                    ("stroke-width", "1.5"),
                ],
            )));
        }
    }
    let (x, y) = (
        format!("{:.0}", index as f64 * PANEL + PANEL / 2.0),
        format!("{:.0}", PANEL + CAPTION / 2.0),
    );
    let _ = w.write_event(Event::Start(el(
        "text",
        &[
            ("x", &x),
            ("y", &y),
            ("text-anchor", "middle"),
            ("font-family", "DejaVu Sans, sans-serif"),
            ("font-size", "15"),
            ("fill", "#333"),
        ],
    )));
    let _ = w.write_event(Event::Text(BytesText::new(title)));
    let _ = w.write_event(Event::End(BytesEnd::new("text")));
}

/// The side-by-side SVG picture of the compatible triangulations.
pub fn inspect_svg(c: &Compatible) -> String {
    inspect_svg_with_skeleton(c, None)
}

/// [`inspect_svg`] with a skeleton drawn over both panels: `bones`, the joints on the source
/// (the reference skeleton) and on the target (the derived skeleton at t = 1), §4.2.
pub fn inspect_svg_with_skeleton(c: &Compatible, skeleton: SkeletonPair<'_>) -> String {
    let m = &c.meshes;
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 1);
    let (wd, ht) = (format!("{}", 2.0 * PANEL), format!("{}", PANEL + CAPTION));
    let vb = format!("0 0 {wd} {ht}");
    let _ = w.write_event(Event::Start(el(
        "svg",
        &[
            ("xmlns", "http://www.w3.org/2000/svg"),
            ("width", &wd),
            ("height", &ht),
            ("viewBox", &vb),
        ],
    )));
    let _ = w.write_event(Event::Empty(el(
        "rect",
        &[("width", &wd), ("height", &ht), ("fill", "#ffffff")],
    )));
    let stats = format!(
        "{} vertices, {} triangles, {} curves",
        m.source.len(),
        m.triangles.len(),
        m.curves.len()
    );
    panel(
        &mut w,
        c,
        &m.source,
        0,
        &format!("source — {stats}"),
        skeleton.map(|(b, s, _)| (b, s)),
    );
    panel(
        &mut w,
        c,
        &m.target,
        1,
        &format!("target — {} mapping steps", c.stats.steps),
        skeleton.map(|(b, _, t)| (b, t)),
    );
    let _ = w.write_event(Event::End(BytesEnd::new("svg")));
    // The writer only ever receives `&str`, so its bytes are UTF-8.
    let mut s = String::from_utf8_lossy(&w.into_inner()).into_owned();
    s.push('\n');
    s
}
