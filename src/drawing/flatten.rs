//! Flattening exact curves into polylines with lyon, in f64, at a given tolerance.

use kurbo::{BezPath, PathEl};
use lyon_geom::{point, CubicBezierSegment, QuadraticBezierSegment};

use crate::geometry::Point;

/// One flattened subpath.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Subpath {
    /// Points, consecutive duplicates removed; for closed subpaths the first point is not
    /// repeated at the end.
    pub(crate) points: Vec<Point>,
    /// Closed by `Z`, or ending where it started.
    pub(crate) closed: bool,
    /// The on-curve end points of the original segments (used for skeleton joints).
    pub(crate) nodes: Vec<Point>,
}

fn lp(p: kurbo::Point) -> lyon_geom::Point<f64> {
    point(p.x, p.y)
}

/// About how many points flattening `path` at `tolerance` makes, computed from its control
/// points before any is made: one per line, and per curve the segment count of Wang's formula
/// (`⌈√(n(n−1)/8 · max‖Pᵢ − 2Pᵢ₊₁ + Pᵢ₊₂‖ / tolerance)⌉` for degree n), the number of uniform
/// pieces that keeps the curve within `tolerance` — an upper bound for the adaptive flatteners
/// of lyon and kurbo, which place their points where the curve bends. Infinite when a
/// coordinate is not finite or the tolerance is not positive, so that a check against a budget
/// refuses the path before it is flattened.
pub(crate) fn flattened_count(path: &BezPath, tolerance: f64) -> f64 {
    if tolerance.is_nan() || tolerance <= 0.0 {
        return f64::INFINITY;
    }
    let wang = |degree: f64, dd: f64| {
        (degree * (degree - 1.0) / 8.0 * dd / tolerance)
            .sqrt()
            .ceil()
            .max(1.0)
    };
    let mut last = kurbo::Point::ORIGIN;
    let mut count = 0.0;
    for el in path.elements() {
        count += match *el {
            PathEl::MoveTo(p) | PathEl::LineTo(p) => {
                if !p.is_finite() {
                    return f64::INFINITY;
                }
                last = p;
                1.0
            }
            PathEl::QuadTo(c, p) => {
                let dd = (last - 2.0 * c.to_vec2() + p.to_vec2()).to_vec2().hypot();
                last = p;
                wang(2.0, dd)
            }
            PathEl::CurveTo(c1, c2, p) => {
                let d1 = (last - 2.0 * c1.to_vec2() + c2.to_vec2()).to_vec2().hypot();
                let d2 = (c1 - 2.0 * c2.to_vec2() + p.to_vec2()).to_vec2().hypot();
                last = p;
                wang(3.0, d1.max(d2))
            }
            PathEl::ClosePath => 0.0,
        };
    }
    if count.is_nan() {
        f64::INFINITY
    } else {
        count
    }
}

/// Flattens `path` so that no point of a curve is farther than `tolerance` from the polyline.
/// Points closer than `snap` to their predecessor are dropped.
pub(crate) fn flatten(path: &BezPath, tolerance: f64, snap: f64) -> Vec<Subpath> {
    let mut out: Vec<Subpath> = Vec::new();
    let mut cur: Option<Subpath> = None;
    let mut last = kurbo::Point::ORIGIN;
    let push = |sp: &mut Subpath, p: Point| {
        if sp.points.last().is_none_or(|q| q.distance(p) > snap) {
            sp.points.push(p);
        }
    };
    let finish = |sp: Option<Subpath>, out: &mut Vec<Subpath>| {
        if let Some(mut sp) = sp {
            if crate::geometry::ends_meet(&sp.points, snap) {
                sp.points.pop();
                sp.closed = true;
            }
            out.push(sp);
        }
    };
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                finish(cur.take(), &mut out);
                let q = Point::new(p.x, p.y);
                cur = Some(Subpath {
                    points: vec![q],
                    closed: false,
                    nodes: vec![q],
                });
                last = p;
            }
            PathEl::LineTo(p) => {
                if let Some(sp) = cur.as_mut() {
                    push(sp, Point::new(p.x, p.y));
                    sp.nodes.push(Point::new(p.x, p.y));
                }
                last = p;
            }
            PathEl::QuadTo(c, p) => {
                if let Some(sp) = cur.as_mut() {
                    let seg = QuadraticBezierSegment {
                        from: lp(last),
                        ctrl: lp(c),
                        to: lp(p),
                    };
                    seg.for_each_flattened(tolerance, &mut |l| {
                        push(sp, Point::new(l.to.x, l.to.y))
                    });
                    sp.nodes.push(Point::new(p.x, p.y));
                }
                last = p;
            }
            PathEl::CurveTo(c1, c2, p) => {
                if let Some(sp) = cur.as_mut() {
                    let seg = CubicBezierSegment {
                        from: lp(last),
                        ctrl1: lp(c1),
                        ctrl2: lp(c2),
                        to: lp(p),
                    };
                    seg.for_each_flattened(tolerance, &mut |l| {
                        push(sp, Point::new(l.to.x, l.to.y))
                    });
                    sp.nodes.push(Point::new(p.x, p.y));
                }
                last = p;
            }
            PathEl::ClosePath => {
                if let Some(mut sp) = cur.take() {
                    sp.closed = true;
                    if crate::geometry::ends_meet(&sp.points, snap) {
                        sp.points.pop();
                    }
                    last = kurbo::Point::new(sp.points[0].x, sp.points[0].y);
                    out.push(sp);
                }
            }
        }
    }
    finish(cur, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::Shape;

    #[test]
    fn circle_flattens_within_tolerance() {
        let c = kurbo::Circle::new((0.0, 0.0), 100.0).to_path(1e-9);
        let tol = 0.05;
        let sp = flatten(&c, tol, 1e-9);
        assert_eq!(sp.len(), 1);
        assert!(sp[0].closed);
        for p in &sp[0].points {
            assert!((p.length() - 100.0).abs() < 1e-6);
        }
        // chord sagitta bounded by the tolerance
        let n = sp[0].points.len();
        for i in 0..n {
            let mid = (sp[0].points[i] + sp[0].points[(i + 1) % n]) * 0.5;
            assert!(
                100.0 - mid.length() <= tol * 1.01,
                "sagitta {}",
                100.0 - mid.length()
            );
        }
        // finer tolerance, more points
        assert!(flatten(&c, tol / 10.0, 1e-9)[0].points.len() > n);
    }

    #[test]
    fn the_estimate_bounds_the_flattened_count() {
        for (r, tol) in [(100.0, 0.05), (1e6, 0.2), (3.0, 1e-4)] {
            let c = kurbo::Circle::new((10.0, -5.0), r).to_path(1e-9);
            let n = flatten(&c, tol, 0.0)[0].points.len() as f64;
            let est = flattened_count(&c, tol);
            assert!(
                est >= n && est <= 4.0 * n + 8.0,
                "r {r}: {n} points, estimated {est}"
            );
        }
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.curve_to((3.4e38, 0.0), (0.0, 3.4e38), (1.0, 1.0));
        assert!(flattened_count(&p, 0.2) > 1e18);
        p.line_to((f64::NAN, 0.0));
        assert_eq!(flattened_count(&p, 0.2), f64::INFINITY);
    }

    #[test]
    fn open_and_explicitly_closed_subpaths() {
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.line_to((1.0, 0.0));
        p.line_to((1.0, 0.0));
        p.move_to((5.0, 5.0));
        p.line_to((6.0, 5.0));
        p.line_to((6.0, 6.0));
        p.line_to((5.0, 5.0));
        let sp = flatten(&p, 0.1, 1e-9);
        assert_eq!(sp.len(), 2);
        assert!(!sp[0].closed);
        assert_eq!(sp[0].points.len(), 2);
        assert!(sp[1].closed);
        assert_eq!(sp[1].points.len(), 3);
    }
}
