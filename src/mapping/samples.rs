//! Synthetic curve pairs for the mapping's tests and benchmarks: the kinds of input that §5's
//! composite mapping exists for (Fig. 8 vs Fig. 10) — a band bent into a U, a bar turning in a
//! square — built from a few numbers, so that tests and `benches/mapping.rs` measure the same
//! scenes.

use std::f64::consts::PI;

use crate::correspondence::CurvePair;
use crate::geometry::Point;
use crate::mesh::CurveKind;

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

/// A curve pair whose target is its source (to be moved by the caller); `boundary` is the
/// boundary, any other id a feature curve.
pub fn pair(id: &str, closed: bool, pts: Vec<Point>) -> CurvePair {
    CurvePair {
        id: id.into(),
        kind: if id == "boundary" {
            CurveKind::Boundary
        } else {
            CurveKind::Feature
        },
        closed,
        target: pts.clone(),
        source: pts,
        salient: vec![],
    }
}

/// The closed polygon through `corners`, each side split into edges of at most `max_edge`.
pub fn resampled(corners: &[Point], max_edge: f64) -> Vec<Point> {
    let n = corners.len();
    (0..n)
        .flat_map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            let k = (a.distance(b) / max_edge).ceil().max(1.0) as usize;
            (0..k).map(move |j| a.lerp(b, j as f64 / k as f64))
        })
        .collect()
}

/// `n` points on the circle of centre `c` and radius `r`, counter-clockwise from angle 0.
pub fn circle(c: Point, r: f64, n: usize) -> Vec<Point> {
    (0..n)
        .map(|k| c + r * Point::from_angle(k as f64 / n as f64 * std::f64::consts::TAU))
        .collect()
}

/// A band `len × height` (`per_unit` boundary vertices per unit length) with a midline feature
/// and a small closed feature, bent by `bend` radians around a centre so that its midline
/// keeps its length.
pub fn bent_band(len: f64, height: f64, per_unit: usize, bend: f64) -> Vec<CurvePair> {
    let n = (len * per_unit as f64) as usize;
    let h = height / 2.0;
    let b = resampled(
        &[p(0., 0.), p(len, 0.), p(len, height), p(0., height)],
        1.0 / per_unit as f64,
    );
    let mid: Vec<Point> = (0..=n)
        .map(|k| p(0.5 + (len - 1.0) * k as f64 / n as f64, h))
        .collect();
    let mut pairs = vec![
        pair("boundary", true, b),
        pair(
            "feature-dot",
            true,
            circle(p(len * 0.3, h / 2.0), 0.25 * h, 10),
        ),
        pair("feature-mid", false, mid),
    ];
    let radius = len / bend;
    let f = |q: Point| {
        let (r, a) = (radius + h - q.y, q.x / radius - PI / 2.0);
        p(r * a.cos(), r * a.sin())
    };
    for pc in &mut pairs {
        pc.target = pc.source.iter().map(|q| f(*q)).collect();
    }
    pairs
}

/// A 10 × 10 square with a 4 × 1 bar in the middle that turns by `deg` degrees in the target.
pub fn turning_bar(deg: f64) -> Vec<CurvePair> {
    let mut pairs = vec![
        pair(
            "boundary",
            true,
            resampled(&[p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)], 0.4),
        ),
        pair(
            "feature-bar",
            true,
            resampled(&[p(3., 4.5), p(7., 4.5), p(7., 5.5), p(3., 5.5)], 0.25),
        ),
    ];
    let r = Point::from_angle(deg.to_radians());
    pairs[1].target = pairs[1]
        .source
        .iter()
        .map(|q| p(5., 5.) + r.rotate(*q - p(5., 5.)))
        .collect();
    pairs
}
