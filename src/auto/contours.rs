//! Contours of plain artwork: the feature curves automatic mode makes from a drawing with no
//! control geometry.
//!
//! A filled path contributes its subpaths as closed contours, nested by containment: a subpath
//! inside an odd number of the path's other subpaths is a hole (for `evenodd`, and for `nonzero`
//! paths drawn the usual way, with holes wound against their outline). A path that is only
//! stroked (outline icons) contributes its subpaths as centre lines, open or closed. Filled
//! contours too small to matter (below 1/10,000 of the drawing's area) are left to the artwork;
//! centre lines of any visible length are kept (a short one with round caps is a dot).

use crate::artwork::{Item, Scene};
use crate::error::Result;
use crate::geometry::{polygon_area, Point};
use crate::input::{Limit, Limits};

/// What a contour outlines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContourKind {
    /// The outer outline of a filled region.
    Outline,
    /// A hole of a filled region.
    Hole,
    /// The centre line of a stroke.
    Stroke,
}

/// One contour of a drawing's artwork.
#[derive(Debug, Clone, PartialEq)]
pub struct Contour {
    /// Flattened points in root user space (closed contours do not repeat the first point).
    pub points: Vec<Point>,
    /// Whether the last point connects back to the first.
    pub closed: bool,
    /// Outline, hole or stroke.
    pub kind: ContourKind,
    /// For a hole, the index of its outline in the same list.
    pub parent: Option<usize>,
    /// Paint-order index of the artwork path it comes from.
    pub path: usize,
    /// Enclosed area (absolute), or 0 for open centre lines.
    pub area: f64,
    /// Length of the polyline.
    pub length: f64,
    /// Area centroid (closed) or mean point (open).
    pub centroid: Point,
    /// Elongation: the ratio of the small to the large principal second moment, in (0, 1].
    pub elongation: f64,
}

/// The contours of every path of `scene`, flattened at `tolerance` user units; an error when
/// they would flatten to more than [`Limits::vertices`] in all (estimated before flattening,
/// [`crate::drawing`]'s Wang bound), so that a huge path or a tiny tolerance cannot fill
/// memory. Far-away artwork should be cut first ([`crate::artwork::within_reach`]).
pub fn contours(scene: &Scene, tolerance: f64, limits: &Limits) -> Result<Vec<Contour>> {
    let mut estimate = 0.0;
    for item in scene.items() {
        if let Item::Path(p) = item {
            estimate += crate::drawing::flattened_count(
                &(scene.root_transform * p.path.clone()),
                tolerance.max(1e-9),
            );
            if estimate > limits.vertices as f64 {
                let what = format!(
                    "artwork flattening to about {} vertices",
                    crate::budget::count_text(estimate)
                );
                return Err(Limit::Vertices.exceeded(&scene.file, &what, limits));
            }
        }
    }
    Ok(contours_flattened(scene, tolerance))
}

fn contours_flattened(scene: &Scene, tolerance: f64) -> Vec<Contour> {
    let (lo, hi) = scene.view_box;
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let min_area = 1e-4 * (w * h).abs();
    // Strokes of any visible length count: a short one with round caps is a dot.
    let min_length = 1e-6 * (w * w + h * h).sqrt();
    let mut out = Vec::new();
    for (index, item) in scene.items().into_iter().enumerate() {
        let Item::Path(p) = item else { continue };
        let path = scene.root_transform * p.path.clone();
        let subs = flatten(&path, tolerance);
        if let Some(fill) = &p.fill {
            // The filled region by the path's fill rule (i_overlay): overlapping subpaths
            // merge, self-crossing rings split, and every shape is one outline with its holes.
            let rings: Vec<Vec<Point>> = subs
                .into_iter()
                .map(|(pts, _)| pts)
                .filter(|pts| pts.len() >= 3)
                .collect();
            for shape in filled_region(&rings, fill.even_odd) {
                let mut rings = shape.into_iter().map(|r| separate_pinches(r, tolerance));
                let Some(outline) = rings.next() else {
                    continue;
                };
                if outline.len() < 3 || polygon_area(&outline).abs() < min_area {
                    continue;
                }
                let parent = out.len();
                out.push(describe(outline, true, ContourKind::Outline, None, index));
                for hole in rings {
                    if hole.len() >= 3 && polygon_area(&hole).abs() >= min_area {
                        out.push(describe(hole, true, ContourKind::Hole, Some(parent), index));
                    }
                }
            }
        } else if p.stroke.is_some() {
            for (pts, closed) in subs {
                let c = describe(pts, closed, ContourKind::Stroke, None, index);
                if c.points.len() >= 2 && c.length >= min_length {
                    out.push(c);
                }
            }
        }
    }
    out
}

/// The region `rings` fill under the even-odd or non-zero rule, as shapes: each an outer ring
/// followed by its holes, every ring without self-crossings (`i_overlay`). A ring may still touch
/// itself at a vertex (a hole pinched onto its outline comes back as one ring visiting the pinch
/// twice), which [`separate_pinches`] resolves.
fn filled_region(rings: &[Vec<Point>], even_odd: bool) -> Vec<Vec<Vec<Point>>> {
    use i_overlay::core::fill_rule::FillRule;
    use i_overlay::float::simplify::SimplifyShape;
    let input: Vec<Vec<[f64; 2]>> = rings
        .iter()
        .map(|r| r.iter().map(|p| [p.x, p.y]).collect())
        .collect();
    if input
        .iter()
        .flatten()
        .any(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Vec::new();
    }
    let rule = if even_odd {
        FillRule::EvenOdd
    } else {
        FillRule::NonZero
    };
    input
        .simplify_shape(rule)
        .into_iter()
        .map(|shape| {
            shape
                .into_iter()
                .map(|ring| ring.into_iter().map(|[x, y]| Point::new(x, y)).collect())
                .collect()
        })
        .collect()
}

/// `ring` with every vertex it visits twice (a pinch) split in two: each visit moved by a
/// hair (a tenth of the flattening `tolerance`) into its own corner of the ring's interior, so
/// the ring becomes simple and can be a boundary or a feature curve.
fn separate_pinches(mut ring: Vec<Point>, tolerance: f64) -> Vec<Point> {
    let n = ring.len();
    if n < 4 {
        return ring;
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| {
        ring[a]
            .x
            .total_cmp(&ring[b].x)
            .then(ring[a].y.total_cmp(&ring[b].y))
    });
    let repeated: Vec<usize> = order
        .windows(2)
        .filter(|w| ring[w[0]] == ring[w[1]])
        .flat_map(|w| [w[0], w[1]])
        .collect();
    if repeated.is_empty() {
        return ring;
    }
    let side = polygon_area(&ring).signum();
    let step = 0.1 * tolerance.max(1e-12);
    let original = ring.clone();
    for k in repeated {
        let v = original[k];
        let (prev, next) = (original[(k + n - 1) % n], original[(k + 1) % n]);
        let (u1, u2) = (
            (prev - v).normalize_or_zero(),
            (next - v).normalize_or_zero(),
        );
        let mut d = (u1 + u2).normalize_or_zero();
        if d == Point::ZERO {
            d = Point::new(-u2.y, u2.x);
        }
        // Inside is to the left of the outgoing edge for a positive ring.
        if (next - v).perp_dot(d) * side < 0.0 {
            d = -d;
        }
        ring[k] = v + d * step;
    }
    ring
}

fn describe(
    points: Vec<Point>,
    closed: bool,
    kind: ContourKind,
    parent: Option<usize>,
    path: usize,
) -> Contour {
    let n = points.len();
    let edges = if closed { n } else { n.saturating_sub(1) };
    let length: f64 = (0..edges)
        .map(|i| points[i].distance(points[(i + 1) % n]))
        .sum();
    let (area, centroid, elongation) = if closed && n >= 3 {
        moments(&points)
    } else {
        let c = points.iter().copied().sum::<Point>() / n.max(1) as f64;
        let (mut xx, mut yy, mut xy) = (0.0, 0.0, 0.0);
        for p in &points {
            let d = *p - c;
            xx += d.x * d.x;
            yy += d.y * d.y;
            xy += d.x * d.y;
        }
        (0.0, c, elongation_of(xx, yy, xy))
    };
    Contour {
        points,
        closed,
        kind,
        parent,
        path,
        area,
        length,
        centroid,
        elongation,
    }
}

/// Area, centroid and elongation of a simple polygon from its area moments (Green's theorem).
fn moments(p: &[Point]) -> (f64, Point, f64) {
    let n = p.len();
    let (mut a, mut cx, mut cy, mut ixx, mut iyy, mut ixy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        let (q, r) = (p[i], p[(i + 1) % n]);
        let c = q.x * r.y - r.x * q.y;
        a += c;
        cx += (q.x + r.x) * c;
        cy += (q.y + r.y) * c;
        ixx += (q.y * q.y + q.y * r.y + r.y * r.y) * c;
        iyy += (q.x * q.x + q.x * r.x + r.x * r.x) * c;
        ixy += (q.x * r.y + 2.0 * q.x * q.y + 2.0 * r.x * r.y + r.x * q.y) * c;
    }
    a *= 0.5;
    if a.abs() < 1e-300 {
        return (0.0, p[0], 1.0);
    }
    let c = Point::new(cx / (6.0 * a), cy / (6.0 * a));
    // Central second moments.
    let yy = ixx / 12.0 - a * c.y * c.y;
    let xx = iyy / 12.0 - a * c.x * c.x;
    let xy = ixy / 24.0 - a * c.x * c.y;
    (a.abs(), c, elongation_of(xx, yy, xy))
}

/// Small over large eigenvalue of the 2×2 moment matrix `[[xx, xy], [xy, yy]]`.
fn elongation_of(xx: f64, yy: f64, xy: f64) -> f64 {
    let m = 0.5 * (xx + yy);
    let d = (0.25 * (xx - yy) * (xx - yy) + xy * xy).sqrt();
    let (l1, l2) = (m + d, m - d);
    if l1.abs() > 1e-300 {
        (l2 / l1).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Subpaths of `path` as polylines (closed ones without the repeated first point).
fn flatten(path: &kurbo::BezPath, tolerance: f64) -> Vec<(Vec<Point>, bool)> {
    let mut out: Vec<(Vec<Point>, bool)> = Vec::new();
    let mut cur: Vec<Point> = Vec::new();
    let mut closed = false;
    // Ends closer than a few flattening tolerances meet: icon paths often end a hair away from
    // where they began instead of closing with `Z`.
    let meet = 4.0 * tolerance.max(1e-9);
    let mut finish = |cur: &mut Vec<Point>, closed: &mut bool| {
        if cur.len() > 2 && crate::geometry::ends_meet(cur, meet) {
            cur.pop();
            *closed = true;
        }
        if cur.len() >= 2 {
            out.push((std::mem::take(cur), *closed));
        }
        cur.clear();
        *closed = false;
    };
    kurbo::flatten(path, tolerance.max(1e-9), |el| match el {
        kurbo::PathEl::MoveTo(p) => {
            finish(&mut cur, &mut closed);
            cur.push(Point::new(p.x, p.y));
        }
        kurbo::PathEl::LineTo(p) => {
            let q = Point::new(p.x, p.y);
            if cur.last().is_none_or(|l| l.distance(q) > 1e-9) {
                cur.push(q);
            }
        }
        kurbo::PathEl::ClosePath => {
            closed = true;
            finish(&mut cur, &mut closed);
        }
        _ => {}
    });
    finish(&mut cur, &mut closed);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(body: &str) -> Scene {
        let svg = format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100">{body}</svg>"#
        );
        Scene::from_svg("a.svg", &svg, "controls").unwrap()
    }

    #[test]
    fn a_ring_is_an_outline_with_a_hole() {
        let s = scene(
            r##"<path fill-rule="evenodd" fill="#000" d="M10 10H90V90H10Z M30 30H70V70H30Z"/>"##,
        );
        let c = contours(&s, 0.05, &Limits::default()).unwrap();
        assert_eq!(c.len(), 2);
        assert_eq!(c[0].kind, ContourKind::Outline);
        assert_eq!(c[1].kind, ContourKind::Hole);
        assert_eq!(c[1].parent, Some(0));
        assert!((c[0].area - 6400.0).abs() < 1e-6);
        assert!((c[0].centroid - Point::new(50.0, 50.0)).length() < 1e-9);
        assert!((c[0].elongation - 1.0).abs() < 1e-9);
    }

    #[test]
    fn strokes_give_centre_lines_and_specks_are_skipped() {
        let s = scene(
            r##"<path fill="none" stroke="#000" stroke-width="2" d="M10 50 L90 50"/>
                <circle cx="50" cy="20" r="0.2" fill="red"/>
                <ellipse cx="50" cy="80" rx="20" ry="5" fill="blue"/>"##,
        );
        let c = contours(&s, 0.05, &Limits::default()).unwrap();
        assert_eq!(c.len(), 2, "{c:?}");
        assert_eq!(c[0].kind, ContourKind::Stroke);
        assert!(!c[0].closed && (c[0].length - 80.0).abs() < 1e-9);
        assert_eq!(c[1].kind, ContourKind::Outline);
        assert!(
            (c[1].elongation - 1.0 / 16.0).abs() < 0.01,
            "{}",
            c[1].elongation
        );
    }
}
