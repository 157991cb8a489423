//! Artwork kept within reach of the frame: paths far outside the view are left out, paths that
//! reach far outside it are cut at the edge of a bounded region, before anything flattens,
//! locates or renders them (issue #12: work must not grow with coordinates).
//!
//! The **reach** is the view box grown on every side by [`REACH`] times its larger side. A morph
//! of a normal drawing never draws there (a view growing to hold the whole morph grows by a
//! fraction of the view), so every path inside the reach is kept exactly as read and a normal
//! drawing's output does not change. Beyond it, a vertex at x = 10⁶ in a 200-unit icon, a
//! `scale(1000)` or `skewX(89.999)` on one shape, or a control point near 3.4 × 10³⁸ would make
//! every later stage (flattening at a tolerance relative to the drawing, meshing a shape of
//! that size, locating its points) do work in proportion to the coordinates.
//!
//! - A path whose control points all lie beyond one side of the reach draws nothing inside it:
//!   it is **left out** (its geometry emptied; the item stays, so paint-order indices into
//!   [`Scene::items`] hold).
//! - A filled path (or a clip shape) partly outside is **clipped** to the reach, one half-plane
//!   at a time (Sutherland–Hodgman). Clipping a ring against a half-plane replaces each
//!   excursion beyond it with a run along its edge; the excursion and the run together lie in
//!   the outer half-plane, so they wind around no point inside: the winding number of every
//!   point in the reach is unchanged, and so is the fill under either fill rule. Curves are
//!   split (de Casteljau) until each piece's control points lie inside (kept exactly) or
//!   beyond one side (replaced by its chord, which the same argument allows), so what shows
//!   is the exact curve. `i_overlay` is not used here: it snaps to an integer grid fitted to the
//!   input's extent, which for the hostile inputs this exists for is no grid at all.
//! - A stroke-only path partly outside is **cut** where it leaves the reach, its pieces inside
//!   kept as open subpaths (their caps lie at the reach's edge, out of view).
//! - A filled and stroked path partly outside is clipped like a fill: the runs along the reach's
//!   edge are stroked too, out of view. Images are left as they are (they are placed by one
//!   point and never flattened).
//! - A path with a coordinate that is not finite is left out.

use super::{Group, Item, PathItem, Scene};
use crate::geometry::Point;
use kurbo::{Affine, BezPath, CubicBez, ParamCurve, PathEl, QuadBez};

/// How far the reach extends beyond the view box on every side, in multiples of the view box's
/// larger side.
pub const REACH: f64 = 2.0;

/// Deepest curve subdivision when clipping; a piece still straddling the edge of the reach
/// there is replaced by its chord (at 2⁻⁴⁰ of a curve's parameter range, only a curve with
/// control points some 10¹² view sizes away is visibly approximated).
const MAX_DEPTH: u32 = 40;

/// What [`within_reach`] did to one path.
#[derive(Debug, Clone, PartialEq)]
pub struct FarPath {
    /// Index of the path in [`Scene::items`].
    pub item: usize,
    /// Where the path is: the centre of its control points' box, in root user space (for the
    /// message; infinite or NaN for a path with coordinates that are not finite).
    pub at: Point,
    /// Left out (nothing of it within reach) rather than cut at the reach's edge.
    pub left_out: bool,
    /// Left out because a coordinate is not finite.
    pub not_finite: bool,
}

/// The reach as four half-planes `n · p ≤ c` in the scene's path space.
#[derive(Debug, Clone, Copy)]
struct Region {
    planes: [(Point, f64); 4],
}

impl Region {
    /// The reach of a view box `(lo, hi)` in root user space, pulled back through the root
    /// transform `m` (paths are stored before it; `m * path` is in root user space).
    fn new(view_box: (Point, Point), m: Affine) -> Region {
        let (lo, hi) = view_box;
        let grow = REACH * (hi - lo).max_element().abs();
        let (lo, hi) = (lo - Point::splat(grow), hi + Point::splat(grow));
        let [a, b, c, d, e, f] = m.as_coeffs();
        // n · (M p) ≤ k  ⇔  (Mᵀ n) · p ≤ k − n · t
        let plane = |n: Point, k: f64| {
            (
                Point::new(n.x * a + n.y * b, n.x * c + n.y * d),
                k - (n.x * e + n.y * f),
            )
        };
        Region {
            planes: [
                plane(Point::new(1.0, 0.0), hi.x),
                plane(Point::new(-1.0, 0.0), -lo.x),
                plane(Point::new(0.0, 1.0), hi.y),
                plane(Point::new(0.0, -1.0), -lo.y),
            ],
        }
    }

    fn inside(&self, p: Point) -> bool {
        self.planes.iter().all(|&(n, c)| n.dot(p) <= c)
    }

    /// Whether all of `pts` lie strictly beyond one of the half-planes.
    fn beyond_one_side(&self, pts: &[Point]) -> bool {
        self.planes
            .iter()
            .any(|&(n, c)| pts.iter().all(|p| n.dot(*p) > c))
    }
}

fn pt(p: kurbo::Point) -> Point {
    Point::new(p.x, p.y)
}

fn kp(p: Point) -> kurbo::Point {
    kurbo::Point::new(p.x, p.y)
}

/// Every control point of a path.
fn control_points(path: &BezPath) -> impl Iterator<Item = Point> + '_ {
    path.elements().iter().flat_map(|el| {
        let (a, b, c, n) = match *el {
            PathEl::MoveTo(p) | PathEl::LineTo(p) => (p, p, p, 1),
            PathEl::QuadTo(p, q) => (p, q, q, 2),
            PathEl::CurveTo(p, q, r) => (p, q, r, 3),
            PathEl::ClosePath => return Vec::new().into_iter(),
        };
        [a, b, c][..n]
            .iter()
            .map(|&p| pt(p))
            .collect::<Vec<_>>()
            .into_iter()
    })
}

/// The scene with every path (and clip shape) within reach of its view (module docs), and
/// what was cut or left out, by item index. A scene already within reach comes back equal.
pub fn within_reach(scene: &Scene) -> (Scene, Vec<FarPath>) {
    let region = Region::new(scene.view_box, scene.root_transform);
    let mut far = Vec::new();
    let mut next = 0;
    let root = group(
        &scene.root,
        &region,
        scene.root_transform,
        &mut next,
        &mut far,
    );
    (
        Scene {
            root,
            ..scene.clone()
        },
        far,
    )
}

fn group(g: &Group, r: &Region, m: Affine, next: &mut usize, far: &mut Vec<FarPath>) -> Group {
    let clip = g.clip.as_ref().map(|c| super::Clip {
        shapes: c
            .shapes
            .iter()
            .map(|s| super::ClipShape {
                // A shape within reach as it is stays as it is.
                path: bound(&s.path, r, true).map_or_else(|| s.path.clone(), |(p, _)| p),
                even_odd: s.even_odd,
            })
            .collect(),
    });
    let mut children = Vec::with_capacity(g.children.len());
    for c in &g.children {
        let index = *next;
        *next += 1;
        children.push(match c {
            Item::Group(sub) => Item::Group(group(sub, r, m, next, far)),
            Item::Path(p) => Item::Path(path_item(p, index, r, m, far)),
            Item::Image(i) => Item::Image(i.clone()),
        });
    }
    Group {
        id: g.id.clone(),
        opacity: g.opacity,
        clip,
        children,
    }
}

fn path_item(
    p: &PathItem,
    index: usize,
    r: &Region,
    m: Affine,
    far: &mut Vec<FarPath>,
) -> PathItem {
    let filled = p.fill.is_some() || p.stroke.is_none();
    match bound(&p.path, r, filled) {
        None => p.clone(),
        Some((path, how)) => {
            let (lo, hi) = control_points(&p.path).fold(
                (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY)),
                |(lo, hi), q| (lo.min(q), hi.max(q)),
            );
            let c = m * kp((lo + hi) * 0.5);
            far.push(FarPath {
                item: index,
                at: pt(c),
                left_out: how != How::Cut,
                not_finite: how == How::NotFinite,
            });
            PathItem { path, ..p.clone() }
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum How {
    Cut,
    LeftOut,
    NotFinite,
}

/// `path` within reach: `None` when it is within reach as it is; else the cut or clipped path
/// (empty when left out) and what was done.
fn bound(path: &BezPath, r: &Region, filled: bool) -> Option<(BezPath, How)> {
    let mut all_inside = true;
    for p in control_points(path) {
        if !p.is_finite() {
            return Some((BezPath::new(), How::NotFinite));
        }
        all_inside &= r.inside(p);
    }
    if all_inside {
        return None;
    }
    let pts: Vec<Point> = control_points(path).collect();
    if r.beyond_one_side(&pts) {
        return Some((BezPath::new(), How::LeftOut));
    }
    let out = if filled {
        clip_fill(path, r)
    } else {
        cut_stroke(path, r)
    };
    if out.elements().is_empty() {
        Some((out, How::LeftOut))
    } else {
        Some((out, How::Cut))
    }
}

/// One segment of a subpath, by its end point: a line, or a curve wholly within reach.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Seg {
    Line(Point),
    Quad(Point, Point),
    Cubic(Point, Point, Point),
}

impl Seg {
    fn end(&self) -> Point {
        match *self {
            Seg::Line(p) | Seg::Quad(_, p) | Seg::Cubic(_, _, p) => p,
        }
    }

    fn push_to(&self, out: &mut BezPath) {
        match *self {
            Seg::Line(p) => out.line_to(kp(p)),
            Seg::Quad(a, p) => out.quad_to(kp(a), kp(p)),
            Seg::Cubic(a, b, p) => out.curve_to(kp(a), kp(b), kp(p)),
        }
    }
}

/// A subpath as a start point and segments, curves split so that each is a line or lies
/// wholly within reach.
struct Sub {
    start: Point,
    segs: Vec<Seg>,
    closed: bool,
}

fn subpaths(path: &BezPath, r: &Region) -> Vec<Sub> {
    let mut out: Vec<Sub> = Vec::new();
    let mut last = Point::ZERO;
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                last = pt(p);
                out.push(Sub {
                    start: last,
                    segs: Vec::new(),
                    closed: false,
                });
            }
            PathEl::ClosePath => {
                if let Some(s) = out.last_mut() {
                    s.closed = true;
                    last = s.start;
                }
            }
            el => {
                if out.is_empty() {
                    out.push(Sub {
                        start: last,
                        segs: Vec::new(),
                        closed: false,
                    });
                }
                let Some(s) = out.last_mut() else { continue };
                match el {
                    PathEl::LineTo(p) => s.segs.push(Seg::Line(pt(p))),
                    PathEl::QuadTo(a, p) => {
                        quad_pieces(QuadBez::new(kp(last), a, p), r, 0, &mut s.segs)
                    }
                    PathEl::CurveTo(a, b, p) => {
                        cubic_pieces(CubicBez::new(kp(last), a, b, p), r, 0, &mut s.segs)
                    }
                    _ => {}
                }
                last = s.segs.last().map_or(last, Seg::end);
            }
        }
    }
    out
}

fn quad_pieces(q: QuadBez, r: &Region, depth: u32, out: &mut Vec<Seg>) {
    let pts = [pt(q.p0), pt(q.p1), pt(q.p2)];
    if pts.iter().all(|&p| r.inside(p)) {
        out.push(Seg::Quad(pts[1], pts[2]));
    } else if depth >= MAX_DEPTH || r.beyond_one_side(&pts) {
        out.push(Seg::Line(pts[2]));
    } else {
        let (a, b) = q.subdivide();
        quad_pieces(a, r, depth + 1, out);
        quad_pieces(b, r, depth + 1, out);
    }
}

fn cubic_pieces(c: CubicBez, r: &Region, depth: u32, out: &mut Vec<Seg>) {
    let pts = [pt(c.p0), pt(c.p1), pt(c.p2), pt(c.p3)];
    if pts.iter().all(|&p| r.inside(p)) {
        out.push(Seg::Cubic(pts[1], pts[2], pts[3]));
    } else if depth >= MAX_DEPTH || r.beyond_one_side(&pts) {
        out.push(Seg::Line(pts[3]));
    } else {
        let (a, b) = c.subdivide();
        cubic_pieces(a, r, depth + 1, out);
        cubic_pieces(b, r, depth + 1, out);
    }
}

/// Where the segment from `a` to `b` crosses the line `n · p = c`, put exactly on the line
/// (an end point far away leaves the interpolated point off it by rounding).
fn crossing(a: Point, b: Point, n: Point, c: f64) -> Point {
    let (da, db) = (n.dot(a) - c, n.dot(b) - c);
    let t = da / (da - db);
    let x = if t.is_finite() {
        a.lerp(b, t.clamp(0.0, 1.0))
    } else {
        a
    };
    let nn = n.dot(n);
    let y = x - n * ((n.dot(x) - c) / nn);
    if y.is_finite() {
        y
    } else {
        x
    }
}

/// Filled subpaths clipped to the reach, one half-plane at a time (module docs); every subpath
/// comes out closed, as a fill draws it.
fn clip_fill(path: &BezPath, r: &Region) -> BezPath {
    let mut out = BezPath::new();
    for sub in subpaths(path, r) {
        // The ring as vertices, each with the segment that enters it; the first is entered by
        // the closing line.
        let mut ring: Vec<(Point, Seg)> = Vec::with_capacity(sub.segs.len() + 1);
        ring.push((sub.start, Seg::Line(sub.start)));
        ring.extend(sub.segs.iter().map(|s| (s.end(), *s)));
        for &(n, c) in &r.planes {
            let len = ring.len();
            if len < 2 {
                break;
            }
            let inside = |p: Point| n.dot(p) <= c;
            let mut next = Vec::with_capacity(len + 4);
            for i in 0..len {
                let (prev, _) = ring[(i + len - 1) % len];
                let (cur, seg) = ring[i];
                match (inside(prev), inside(cur)) {
                    (true, true) => next.push((cur, seg)),
                    (true, false) => {
                        let x = crossing(prev, cur, n, c);
                        next.push((x, Seg::Line(x)));
                    }
                    (false, true) => {
                        let x = crossing(prev, cur, n, c);
                        next.push((x, Seg::Line(x)));
                        next.push((cur, Seg::Line(cur)));
                    }
                    (false, false) => {}
                }
            }
            ring = next;
        }
        if ring.len() < 3 {
            continue;
        }
        out.move_to(kp(ring[0].0));
        for (_, seg) in &ring[1..] {
            seg.push_to(&mut out);
        }
        // The segment entering the first vertex closes the ring (a curve is drawn; a line is
        // what the close draws).
        if let s @ (Seg::Quad(..) | Seg::Cubic(..)) = ring[0].1 {
            s.push_to(&mut out);
        }
        out.close_path();
    }
    out
}

/// The parameter range `[t0, t1]` of the segment from `a` to `b` within reach (Cyrus–Beck), or
/// `None`.
fn visible(a: Point, b: Point, r: &Region) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for &(n, c) in &r.planes {
        let (da, db) = (n.dot(a) - c, n.dot(b) - c);
        match (da <= 0.0, db <= 0.0) {
            (true, true) => {}
            (false, false) => return None,
            (true, false) => t1 = t1.min(da / (da - db)),
            (false, true) => t0 = t0.max(da / (da - db)),
        }
    }
    (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some((t0, t1))
}

/// Stroked subpaths cut where they leave the reach: the pieces within reach, open.
fn cut_stroke(path: &BezPath, r: &Region) -> BezPath {
    let mut out = BezPath::new();
    for sub in subpaths(path, r) {
        let mut segs = sub.segs.clone();
        if sub.closed && sub.segs.last().map(Seg::end) != Some(sub.start) {
            segs.push(Seg::Line(sub.start));
        }
        let mut from = sub.start;
        // Whether the pen is down at `from` (the current piece continues there).
        let mut down = false;
        if r.inside(from) {
            out.move_to(kp(from));
            down = true;
        }
        for seg in segs {
            match seg {
                Seg::Line(b) => match visible(from, b, r) {
                    Some((t0, t1)) => {
                        if !down || t0 > 0.0 {
                            out.move_to(kp(from.lerp(b, t0)));
                        }
                        out.line_to(kp(from.lerp(b, t1)));
                        down = t1 >= 1.0;
                    }
                    None => down = false,
                },
                curve => {
                    // Curves here lie within reach, so the pen is down at their start.
                    if !down {
                        out.move_to(kp(from));
                    }
                    curve.push_to(&mut out);
                    down = true;
                }
            }
            from = seg.end();
        }
        // A closed subpath wholly within reach stays closed (it cannot be, or it would not be
        // cut; kept for completeness).
    }
    // Lone move-tos draw nothing; drop them.
    let mut clean = BezPath::new();
    let els = out.elements();
    for (i, el) in els.iter().enumerate() {
        if matches!(el, PathEl::MoveTo(_))
            && !matches!(
                els.get(i + 1),
                Some(PathEl::LineTo(_) | PathEl::QuadTo(..) | PathEl::CurveTo(..))
            )
        {
            continue;
        }
        clean.push(*el);
    }
    clean
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Shape;

    fn region() -> Region {
        // View 0..100: reach −200..300.
        Region::new((Point::ZERO, Point::new(100.0, 100.0)), Affine::IDENTITY)
    }

    fn winding(path: &BezPath, p: (f64, f64)) -> i32 {
        path.winding(kurbo::Point::new(p.0, p.1))
    }

    #[test]
    fn paths_within_reach_are_untouched() {
        let mut p = BezPath::new();
        p.move_to((-150.0, 10.0));
        p.curve_to((290.0, -190.0), (50.0, 290.0), (10.0, 10.0));
        p.close_path();
        assert!(bound(&p, &region(), true).is_none());
    }

    #[test]
    fn a_scene_within_reach_comes_back_equal_clips_included() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
          <clipPath id="c"><circle cx="0" cy="0" r="19"/></clipPath>
          <g transform="translate(70 50)" clip-path="url(#c)"><rect x="-20" y="-12" width="40" height="24"/></g>
          <rect x="5" y="5" width="50" height="50" fill="red"/></svg>"#;
        let scene = Scene::from_svg("a.svg", svg, "controls").unwrap();
        let (within, far) = within_reach(&scene);
        assert!(far.is_empty());
        assert_eq!(within.root, scene.root);
    }

    #[test]
    fn a_fill_is_clipped_with_the_winding_inside_unchanged() {
        // A triangle reaching to x = 10⁶ and a curve with a control point near f32::MAX.
        let mut p = BezPath::new();
        p.move_to((10.0, 80.0));
        p.line_to((1e6, 85.0));
        p.line_to((20.0, 95.0));
        p.close_path();
        p.move_to((10.0, 10.0));
        p.curve_to((3.4e38, 10.0), (10.0, 3.4e38), (50.0, 50.0));
        p.close_path();
        let (c, how) = bound(&p, &region(), true).unwrap();
        assert_eq!(how, How::Cut);
        let bb = c.bounding_box();
        assert!(bb.x1 <= 300.0 + 1e-9 && bb.y1 <= 300.0 + 1e-9, "{bb:?}");
        // The triangle's winding as kurbo computes it on the original; the curve, which kurbo
        // cannot handle at that size, leaves (10, 10) along y = 10 and comes back down x = 50
        // to (50, 50): it encloses the quadrant beyond and the wedge under y = x.
        let mut tri = BezPath::new();
        tri.move_to((10.0, 80.0));
        tri.line_to((1e6, 85.0));
        tri.line_to((20.0, 95.0));
        tri.close_path();
        for q in [(30.0, 86.0), (5.0, 86.0), (40.0, 60.0)] {
            assert_eq!(winding(&c, q), winding(&tri, q), "at {q:?}");
        }
        let (w0, w1) = (winding(&c, (60.0, 20.0)), winding(&c, (30.0, 20.0)));
        assert!(w0 != 0 && w0 == w1 && w0 == winding(&c, (250.0, 250.0)));
        assert_eq!(winding(&c, (30.0, 40.0)), 0);
        assert_eq!(winding(&c, (90.0, 86.0)), w0 + winding(&tri, (90.0, 86.0)));
    }

    #[test]
    fn far_paths_are_left_out_and_strokes_cut() {
        let mut far = BezPath::new();
        far.move_to((1e4, 1e5));
        far.line_to((6e4, 1.5e5));
        far.line_to((2e4, 2e5));
        assert_eq!(bound(&far, &region(), true).unwrap().1, How::LeftOut);
        let mut s = BezPath::new();
        s.move_to((20.0, 50.0));
        s.line_to((1e5, 60.0));
        s.line_to((30.0, 70.0));
        let (c, how) = bound(&s, &region(), false).unwrap();
        assert_eq!(how, How::Cut);
        assert_eq!(crate::artwork::subpath_count(&c), 2);
        let bb = c.bounding_box();
        assert!(bb.x1 <= 300.0 + 1e-9 && bb.x0 >= 20.0 - 1e-9, "{bb:?}");
        let mut nan = BezPath::new();
        nan.move_to((0.0, f64::NAN));
        nan.line_to((1.0, 1.0));
        assert_eq!(bound(&nan, &region(), true).unwrap().1, How::NotFinite);
    }
}
