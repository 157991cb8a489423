//! Fitting cubic curves to warped polylines, with one segmentation shared by every keyframe.
//!
//! Warped artwork is flattened (it must bend with the mesh), so written as is it is a dense
//! polyline: large files, the top complaint about shape tweens' SVG output. Here every run of
//! straight segments is cut into spans, and each span becomes one cubic (or one line) that stays
//! within a tolerance of the polyline. For an animation all keyframes of a path share the *same*
//! spans — browsers only interpolate `d` between keyframes with equal segment counts and types —
//! so a span is accepted only if its fit holds in every keyframe.
//!
//! A span's cubic keeps the span's end points and fits its two inner control points by least
//! squares at chord-length parameters, refined by one Newton step of the parameters
//! (Schneider's scheme, without tangent constraints: the kinks this allows at span ends are
//! within the tolerance). The error is checked at every polyline vertex and segment midpoint.

use kurbo::{BezPath, PathEl, Point};

/// The polylines of `paths` with curve fits where they hold within `tol` in every path. All paths
/// must have the same elements in the same order (keyframes of one element); if they do not, or
/// `tol` is not positive, they are returned unchanged. The results again share one structure.
pub(crate) fn fit_paths(paths: &[BezPath], tol: f64) -> Vec<BezPath> {
    let Some(first) = paths.first() else {
        return Vec::new();
    };
    let same_structure = paths.iter().all(|p| {
        p.elements().len() == first.elements().len()
            && p.elements()
                .iter()
                .zip(first.elements())
                .all(|(a, b)| std::mem::discriminant(a) == std::mem::discriminant(b))
    });
    if !(same_structure && tol > 0.0 && tol.is_finite()) {
        return paths.to_vec();
    }
    let els = first.elements();
    let mut out: Vec<BezPath> = vec![BezPath::new(); paths.len()];
    let mut i = 0;
    while i < els.len() {
        if let PathEl::LineTo(_) = els[i] {
            // A run of line segments from the previous end point.
            let mut j = i;
            while j < els.len() && matches!(els[j], PathEl::LineTo(_)) {
                j += 1;
            }
            let runs: Vec<Vec<Point>> = paths
                .iter()
                .map(|p| {
                    let e = p.elements();
                    let mut pts = vec![e[i - 1].end_point().unwrap_or_default()];
                    pts.extend(e[i..j].iter().filter_map(|el| el.end_point()));
                    pts
                })
                .collect();
            let mut spans = Vec::new();
            segment(&runs, 0, runs[0].len() - 1, tol, &mut 0, &mut spans);
            for span in spans {
                for (k, o) in out.iter_mut().enumerate() {
                    match span {
                        Span::Line(b) => o.line_to(runs[k][b]),
                        Span::Curve(b, ref ctrl) => o.curve_to(ctrl[k].0, ctrl[k].1, runs[k][b]),
                    }
                }
            }
            i = j;
        } else {
            for (k, o) in out.iter_mut().enumerate() {
                o.push(paths[k].elements()[i]);
            }
            i += 1;
        }
    }
    out
}

/// One output span ending at a run index: a line, or a cubic with per-keyframe inner controls.
enum Span {
    Line(usize),
    Curve(usize, Vec<(Point, Point)>),
}

/// Cuts run indices `a..=b` into spans that hold `tol` in every keyframe. `miss` is the
/// keyframe whose fit missed last: it is tried first, since a span that fails mostly fails in
/// the same keyframes as its neighbours (which keyframes are tried first changes only how soon a
/// failing span is given up, not the spans or their curves).
fn segment(
    runs: &[Vec<Point>],
    a: usize,
    b: usize,
    tol: f64,
    miss: &mut usize,
    out: &mut Vec<Span>,
) {
    if b - a <= 1 || runs.iter().all(|r| straight(&r[a..=b], tol)) {
        out.push(Span::Line(b));
        return;
    }
    if b - a >= 3 {
        let fit = |r: &[Point]| match fit_cubic(&r[a..=b]) {
            Some((c1, c2, err)) if err <= tol => Some((c1, c2)),
            _ => None,
        };
        // Fit every keyframe; the first that misses the tolerance decides a split.
        let first = *miss;
        if let Some(held) = fit(&runs[first]) {
            let ctrls: Option<Vec<(Point, Point)>> = runs
                .iter()
                .enumerate()
                .map(|(k, r)| {
                    if k == first {
                        return Some(held);
                    }
                    let f = fit(r);
                    if f.is_none() {
                        *miss = k;
                    }
                    f
                })
                .collect();
            if let Some(ctrls) = ctrls {
                out.push(Span::Curve(b, ctrls));
                return;
            }
        }
    }
    // Halving (rather than cutting at the worst point) keeps spans even and the count low.
    let mid = (a + b) / 2;
    segment(runs, a, mid, tol, miss, out);
    segment(runs, mid, b, tol, miss, out);
}

/// Whether every point lies within `tol` of the chord from the first to the last.
fn straight(pts: &[Point], tol: f64) -> bool {
    let (p, q) = (pts[0], pts[pts.len() - 1]);
    pts.iter()
        .all(|&x| crate::geometry::point_segment_distance(v(x), v(p), v(q)).0 <= tol)
}

fn v(p: Point) -> crate::geometry::Point {
    crate::geometry::Point::new(p.x, p.y)
}

/// The least-squares cubic through `pts` with fixed ends: its inner control points and the
/// largest error (at vertices and segment midpoints). `None` when the fit is singular.
fn fit_cubic(pts: &[Point]) -> Option<(Point, Point, f64)> {
    let n = pts.len();
    let mut u = vec![0.0; n];
    for i in 1..n {
        u[i] = u[i - 1] + pts[i].distance(pts[i - 1]);
    }
    let total = u[n - 1];
    if total.is_nan() || total <= 0.0 {
        return None;
    }
    for x in &mut u {
        *x /= total;
    }
    let (mut c1, mut c2) = solve_controls(pts, &u)?;
    // One Newton step moving each parameter to the closest point, then refit.
    for i in 1..n - 1 {
        let t = u[i];
        let (p0, p3) = (pts[0].to_vec2(), pts[n - 1].to_vec2());
        let (a, b) = (c1.to_vec2(), c2.to_vec2());
        let s = 1.0 - t;
        let q = p0 * (s * s * s) + a * (3.0 * s * s * t) + b * (3.0 * s * t * t) + p3 * (t * t * t);
        let d1 = (a - p0) * (3.0 * s * s) + (b - a) * (6.0 * s * t) + (p3 - b) * (3.0 * t * t);
        let d2 = (b - a * 2.0 + p0) * (6.0 * s) + (p3 - b * 2.0 + a) * (6.0 * t);
        let diff = q - pts[i].to_vec2();
        let den = d1.dot(d1) + diff.dot(d2);
        if den.abs() > 1e-12 {
            u[i] = (t - diff.dot(d1) / den).clamp(0.0, 1.0);
        }
    }
    if u.windows(2).all(|w| w[0] <= w[1]) {
        if let Some((a, b)) = solve_controls(pts, &u) {
            c1 = a;
            c2 = b;
        }
    }
    let curve = kurbo::CubicBez::new(pts[0], c1, c2, pts[n - 1]);
    let eval = |t: f64| kurbo::ParamCurve::eval(&curve, t);
    let mut worst = 0.0f64;
    for i in 1..n - 1 {
        worst = worst.max(eval(u[i]).distance(pts[i]));
    }
    for i in 0..n - 1 {
        let m = eval(0.5 * (u[i] + u[i + 1]));
        let e = crate::geometry::point_segment_distance(v(m), v(pts[i]), v(pts[i + 1])).0;
        worst = worst.max(e);
    }
    Some((c1, c2, worst))
}

/// Inner control points minimizing the squared error at parameters `u` with fixed ends.
fn solve_controls(pts: &[Point], u: &[f64]) -> Option<(Point, Point)> {
    let n = pts.len();
    let (p0, p3) = (pts[0].to_vec2(), pts[n - 1].to_vec2());
    let (mut a11, mut a12, mut a22) = (0.0, 0.0, 0.0);
    let (mut r1, mut r2) = (kurbo::Vec2::ZERO, kurbo::Vec2::ZERO);
    for (p, &t) in pts.iter().zip(u) {
        let s = 1.0 - t;
        let (b0, b1, b2, b3) = (s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
        let r = p.to_vec2() - p0 * b0 - p3 * b3;
        a11 += b1 * b1;
        a12 += b1 * b2;
        a22 += b2 * b2;
        r1 += r * b1;
        r2 += r * b2;
    }
    let det = a11 * a22 - a12 * a12;
    if det.is_nan() || det.abs() <= 1e-12 * (a11 * a22).max(1e-300) {
        return None;
    }
    let c1 = (r1 * a22 - r2 * a12) / det;
    let c2 = (r2 * a11 - r1 * a12) / det;
    (c1.x.is_finite() && c1.y.is_finite() && c2.x.is_finite() && c2.y.is_finite())
        .then(|| (c1.to_point(), c2.to_point()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::{ParamCurveNearest, Shape};

    fn circle_polyline(n: usize, r: f64, c: (f64, f64)) -> BezPath {
        let mut p = BezPath::new();
        for i in 0..n {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let q = (c.0 + r * a.cos(), c.1 + r * a.sin());
            if i == 0 {
                p.move_to(q);
            } else {
                p.line_to(q);
            }
        }
        p.close_path();
        p
    }

    /// Largest distance from the polyline's vertices to the fitted path.
    fn max_deviation(poly: &BezPath, fitted: &BezPath) -> f64 {
        let segs: Vec<_> = fitted.segments().collect();
        poly.elements()
            .iter()
            .filter_map(|e| e.end_point())
            .map(|p| {
                segs.iter()
                    .map(|s| s.nearest(p, 1e-9).distance_sq.sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_dense_circle_becomes_a_few_curves_within_tolerance() {
        let poly = circle_polyline(400, 100.0, (0.0, 0.0));
        let tol = 0.05;
        let fitted = fit_paths(std::slice::from_ref(&poly), tol).remove(0);
        let curves = fitted
            .elements()
            .iter()
            .filter(|e| matches!(e, PathEl::CurveTo(..)))
            .count();
        assert!((4..=16).contains(&curves), "{curves} curves");
        assert!(fitted.elements().len() < 30);
        let dev = max_deviation(&poly, &fitted);
        assert!(dev <= tol, "deviation {dev}");
        assert!((fitted.area() - poly.area()).abs() < 1e-3 * poly.area().abs());
    }

    #[test]
    fn corners_and_straight_runs_stay_lines() {
        // A square flattened with many collinear points: four lines.
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        for side in 0..4 {
            for k in 1..=10 {
                let s = k as f64;
                p.line_to(match side {
                    0 => (s, 0.0),
                    1 => (10.0, s),
                    2 => (10.0 - s, 10.0),
                    _ => (0.0, 10.0 - s),
                });
            }
        }
        p.close_path();
        let f = fit_paths(std::slice::from_ref(&p), 1e-3).remove(0);
        let lines = f
            .elements()
            .iter()
            .filter(|e| matches!(e, PathEl::LineTo(..)))
            .count();
        assert_eq!(lines, 4, "{:?}", f);
        assert_eq!(f.elements().len(), 6);
    }

    #[test]
    fn keyframes_share_one_structure_and_each_holds_the_tolerance() {
        // A circle morphing into a squashed circle with a dent: the spans must suit both.
        let a = circle_polyline(200, 50.0, (0.0, 0.0));
        let b: BezPath = a
            .elements()
            .iter()
            .map(|e| {
                let f = |p: Point| {
                    let dent = (-((p.y - 50.0) / 8.0).powi(2)).exp() * 20.0;
                    Point::new(p.x * 1.5, p.y * 0.6 - dent)
                };
                match *e {
                    PathEl::MoveTo(p) => PathEl::MoveTo(f(p)),
                    PathEl::LineTo(p) => PathEl::LineTo(f(p)),
                    other => other,
                }
            })
            .collect();
        let tol = 0.1;
        let out = fit_paths(&[a.clone(), b.clone()], tol);
        let kinds = |p: &BezPath| {
            p.elements()
                .iter()
                .map(std::mem::discriminant)
                .collect::<Vec<_>>()
        };
        assert_eq!(kinds(&out[0]), kinds(&out[1]));
        assert!(out[0].elements().len() < a.elements().len() / 3);
        assert!(max_deviation(&a, &out[0]) <= tol);
        assert!(max_deviation(&b, &out[1]) <= tol);
        // Each keyframe alone would need no more spans than both together.
        let alone = fit_paths(std::slice::from_ref(&a), tol).remove(0);
        assert!(alone.elements().len() <= out[0].elements().len());
    }

    #[test]
    fn the_fit_does_not_depend_on_the_keyframes_order() {
        // Keyframes dented at different places, so that different spans fail in different
        // keyframes: the keyframe tried first follows the failures, the result must not.
        let a = circle_polyline(240, 50.0, (0.0, 0.0));
        let dented = |at: f64, depth: f64| -> BezPath {
            a.elements()
                .iter()
                .map(|e| {
                    let f = |p: Point| {
                        let d = (-((p.y - at) / 6.0).powi(2)).exp() * depth;
                        Point::new(p.x * (1.0 + depth / 100.0), p.y - d)
                    };
                    match *e {
                        PathEl::MoveTo(p) => PathEl::MoveTo(f(p)),
                        PathEl::LineTo(p) => PathEl::LineTo(f(p)),
                        other => other,
                    }
                })
                .collect()
        };
        let keys: Vec<BezPath> = (0..6)
            .map(|k| dented(-45.0 + 18.0 * k as f64, 4.0 * k as f64))
            .collect();
        let forward = fit_paths(&keys, 0.05);
        let mut reversed = keys.clone();
        reversed.reverse();
        let mut back = fit_paths(&reversed, 0.05);
        back.reverse();
        assert!(forward[0].elements().len() < a.elements().len());
        for (f, b) in forward.iter().zip(&back) {
            assert_eq!(f.elements(), b.elements());
        }
    }

    #[test]
    fn mismatched_or_curved_input_is_left_alone() {
        let a = circle_polyline(10, 1.0, (0.0, 0.0));
        let b = circle_polyline(11, 1.0, (0.0, 0.0));
        let out = fit_paths(&[a.clone(), b.clone()], 0.1);
        assert_eq!(out, vec![a, b]);
        let mut c = BezPath::new();
        c.move_to((0.0, 0.0));
        c.curve_to((1.0, 1.0), (2.0, 1.0), (3.0, 0.0));
        assert_eq!(fit_paths(std::slice::from_ref(&c), 0.1), vec![c.clone()]);
        assert_eq!(fit_paths(std::slice::from_ref(&c), f64::NAN), vec![c]);
    }
}
