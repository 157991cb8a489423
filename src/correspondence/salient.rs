//! Salient point detection (§3, after \[15\]): curvature extrema of a curve at a scale.
//!
//! The turning of the curve at a vertex is measured over a window of arc length `±h` around it
//! (`h` a fraction of the curve's length): the signed angle from the chord arriving at the vertex
//! from `s − h` to the chord leaving it towards `s + h`. Vertices where `|turning|` reaches a
//! threshold are candidates, as are sharp corners of the flattened polyline (the angle between a
//! vertex's two edges reaches the corner threshold, even when the window smooths it out). The
//! strongest candidates win by non-maximum suppression: a candidate is dropped when a stronger
//! one lies within `h` of it. End points of open curves are not reported here: they are always
//! associated with each other.

use super::measure::Polyline;
use super::CorrespondenceOptions;

/// A salient point: a vertex of the curve with its arc-length position and signed turning angle
/// (radians, positive counter-clockwise in user coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Salient {
    /// Vertex index.
    pub(crate) index: usize,
    /// Arc length at the vertex.
    pub(crate) s: f64,
    /// Signed turning angle at the detection scale.
    pub(crate) turning: f64,
}

/// The signed angle from `a` to `b` in radians, in `(−π, π]`; zero if either is zero.
fn signed_angle(a: crate::geometry::Point, b: crate::geometry::Point) -> f64 {
    if a == crate::geometry::Point::ZERO || b == crate::geometry::Point::ZERO {
        return 0.0;
    }
    a.perp_dot(b).atan2(a.dot(b))
}

/// The half-width `h` of the detection window on `curve`: also the radius of non-maximum
/// suppression, and how close a salient point may come to an associated end point or anchor.
pub(crate) fn window(curve: &Polyline, opts: &CorrespondenceOptions) -> f64 {
    let f = opts.window_fraction;
    let f = if f.is_finite() {
        f.clamp(1e-6, 0.25)
    } else {
        0.03
    };
    f * curve.length()
}

/// The salient points of `curve`, sorted by arc length: at most `opts.max_salient`, the strongest
/// ones.
pub(crate) fn detect(curve: &Polyline, opts: &CorrespondenceOptions) -> Vec<Salient> {
    let n = curve.len();
    let length = curve.length();
    let closed = curve.closed();
    if n < 3 || length <= 0.0 {
        return Vec::new();
    }
    let h = window(curve, opts);
    let threshold = opts.salient_angle_deg.to_radians();
    let corner = opts.corner_angle_deg.to_radians();
    let pts = curve.points();
    let interior = if closed { 0..n } else { 1..n - 1 };
    let mut candidates: Vec<Salient> = Vec::new();
    for i in interior {
        let s = curve.s(i);
        let p = pts[i];
        let before = curve.point_at(s - h);
        let after = curve.point_at(s + h);
        let window = signed_angle(p - before, after - p);
        let prev = pts[(i + n - 1) % n];
        let next = pts[(i + 1) % n];
        let local = signed_angle(p - prev, next - p);
        let turning = if window.abs() >= threshold {
            window
        } else if local.abs() >= corner {
            local
        } else {
            continue;
        };
        candidates.push(Salient {
            index: i,
            s,
            turning,
        });
    }
    // Non-maximum suppression: strongest first, ties by index for determinism.
    candidates.sort_by(|a, b| {
        b.turning
            .abs()
            .total_cmp(&a.turning.abs())
            .then(a.index.cmp(&b.index))
    });
    let mut kept: Vec<Salient> = Vec::new();
    for c in candidates {
        if kept.len() >= opts.max_salient {
            break;
        }
        let near = kept.iter().any(|k| {
            let d = (k.s - c.s).abs();
            let d = if closed { d.min(length - d) } else { d };
            d < h
        });
        if !near {
            kept.push(c);
        }
    }
    kept.sort_by_key(|k| k.index);
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    /// A square with every side split into `k` edges.
    fn dense_square(k: usize) -> Polyline {
        let corners = [p(0., 0.), p(1., 0.), p(1., 1.), p(0., 1.)];
        let mut pts = Vec::new();
        for c in 0..4 {
            let (a, b) = (corners[c], corners[(c + 1) % 4]);
            for j in 0..k {
                pts.push(a + (b - a) * (j as f64 / k as f64));
            }
        }
        Polyline::new(pts, true)
    }

    #[test]
    fn the_corners_of_a_square_are_salient() {
        let sq = dense_square(10);
        let found = detect(&sq, &CorrespondenceOptions::default());
        let idx: Vec<usize> = found.iter().map(|s| s.index).collect();
        assert_eq!(idx, vec![0, 10, 20, 30]);
        assert!(found
            .iter()
            .all(|s| (s.turning - std::f64::consts::FRAC_PI_2).abs() < 1e-9));
    }

    #[test]
    fn a_circle_has_no_salient_points_and_a_reflex_corner_turns_negative() {
        let circle: Vec<Point> = (0..100)
            .map(|k| {
                let a = k as f64 / 100.0 * std::f64::consts::TAU;
                p(a.cos(), a.sin())
            })
            .collect();
        assert!(detect(
            &Polyline::new(circle, true),
            &CorrespondenceOptions::default()
        )
        .is_empty());
        // An L-shaped hexagon: five convex corners and one reflex corner.
        let l = vec![
            p(0., 0.),
            p(2., 0.),
            p(2., 1.),
            p(1., 1.),
            p(1., 2.),
            p(0., 2.),
        ];
        let found = detect(&Polyline::new(l, true), &CorrespondenceOptions::default());
        assert_eq!(found.len(), 6);
        assert!(found[3].turning < 0.0 && found[3].index == 3);
        assert_eq!(found.iter().filter(|s| s.turning > 0.0).count(), 5);
    }

    #[test]
    fn open_curve_end_points_are_left_to_the_caller() {
        let v = Polyline::new(vec![p(0., 0.), p(1., 1.), p(2., 0.)], false);
        let found = detect(&v, &CorrespondenceOptions::default());
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].index, 1);
        assert!(found[0].turning < 0.0);
    }
}
