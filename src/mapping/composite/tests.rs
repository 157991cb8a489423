use super::*;
use crate::geometry::bounding_box;
use crate::mesh::sanity_check;
use crate::triangulation::tests::{circle, pair, resampled, subdivided};
use crate::triangulation::triangulate;
use std::f64::consts::PI;

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

fn diagonal(pairs: &[CurvePair]) -> f64 {
    let (lo, hi) = bounding_box(pairs[0].source.iter().copied()).unwrap();
    lo.distance(hi)
}

fn map(pairs: &[CurvePair], from_target: bool) -> Result<(CompatibleMeshes, MappingStats)> {
    let tol = Tolerances::new(diagonal(pairs), 1.0);
    let tri = triangulate(pairs, &tol, from_target)?;
    composite_map(&tri, pairs, &tol, &MappingOptions::default())
}

fn assert_healthy(m: &CompatibleMeshes, pairs: &[CurvePair]) {
    let twins: Vec<Vec<Point>> = pairs.iter().map(|p| p.target.clone()).collect();
    let r = sanity_check(m, Some(&twins), 0.0);
    assert!(r.is_ok(), "{r:?}");
    for (c, pc) in m.curves.iter().zip(pairs) {
        for (&v, q) in c.vertices.iter().zip(&pc.source) {
            assert_eq!(m.source[v as usize], *q);
        }
    }
}

fn square_scene() -> Vec<CurvePair> {
    vec![
        pair("boundary", true, subdivided(&[p(0., 0.), p(10., 0.), p(10., 8.), p(0., 8.)], 24)),
        pair("feature-eye", true, circle(p(3., 5.), 1.2, 24)),
        pair("feature-mouth", false, (0..12).map(|k| p(5., 2.).lerp(p(8., 3.), k as f64 / 11.)).collect()),
    ]
}

/// A strip `len × 2` with a midline feature and a small closed feature, bent into a U of
/// `bend` radians (the strip's midline keeps its length).
fn bent_strip(len: f64, per_unit: usize, bend: f64) -> Vec<CurvePair> {
    let n = (len * per_unit as f64) as usize;
    let b = resampled(&[p(0., 0.), p(len, 0.), p(len, 2.), p(0., 2.)], 1.0 / per_unit as f64);
    let mid: Vec<Point> = (0..=n).map(|k| p(0.5 + (len - 1.0) * k as f64 / n as f64, 1.0)).collect();
    let mut pairs = vec![
        pair("boundary", true, b),
        pair("feature-dot", true, circle(p(len * 0.3, 0.5), 0.25, 10)),
        pair("feature-mid", false, mid),
    ];
    let radius = len / bend;
    let f = |q: Point| {
        let (r, a) = (radius + 1.0 - q.y, q.x / radius - PI / 2.0);
        p(r * a.cos(), r * a.sin())
    };
    for pc in &mut pairs {
        pc.target = pc.source.iter().map(|q| f(*q)).collect();
    }
    pairs
}

#[test]
fn a_similar_target_gives_the_similar_mesh() {
    for deg in [30.0f64, 179.0, 181.0, 270.0] {
        let mut pairs = square_scene();
        let (rot, s, d) = (Point::from_angle(deg.to_radians()), 0.6, p(40., -7.));
        for pc in &mut pairs {
            pc.target = pc.source.iter().map(|q| d + s * rot.rotate(*q)).collect();
        }
        let (m, stats) = map(&pairs, false).unwrap();
        assert_healthy(&m, &pairs);
        assert_eq!(stats.rejected_steps, 0);
        let diag = diagonal(&pairs);
        for (q, r) in m.source.iter().zip(&m.target) {
            let expect = d + s * rot.rotate(*q);
            assert!(expect.distance(*r) < 1e-9 * diag, "{deg}°: {} off", expect.distance(*r));
        }
    }
}

#[test]
fn a_strip_bent_into_a_u_maps_without_flips() {
    let pairs = bent_strip(20.0, 2, PI);
    let (m, stats) = map(&pairs, false).unwrap();
    assert_healthy(&m, &pairs);
    assert!(stats.steps >= 4);
    // a tighter curl, three quarters of a turn
    let pairs = bent_strip(20.0, 2, 1.5 * PI);
    let (m, _) = map(&pairs, false).unwrap();
    assert_healthy(&m, &pairs);
}

#[test]
fn one_direct_harmonic_map_would_fold_the_bent_strip() {
    // the reason for composing: with a single step the same target folds triangles
    let pairs = bent_strip(20.0, 2, 1.5 * PI);
    let tol = Tolerances::new(diagonal(&pairs), 1.0);
    let tri = triangulate(&pairs, &tol, false).unwrap();
    let opts = MappingOptions::default().with_initial_steps(1).with_min_step(0.75);
    let e = composite_map(&tri, &pairs, &tol, &opts);
    assert!(e.is_err());
}

#[test]
fn mapping_from_the_target_side() {
    let pairs = bent_strip(12.0, 2, PI);
    let (m, _) = map(&pairs, true).unwrap();
    assert_healthy(&m, &pairs);
    // the triangulated side keeps its counter-clockwise triangles
    assert_eq!(count_inverted(&m.triangles, &m.target), 0);
}

#[test]
fn features_that_swap_sides_are_reported_by_name() {
    let b = subdivided(&[p(0., 0.), p(10., 0.), p(10., 1.), p(0., 1.)], 20);
    let mut pairs = vec![
        pair("boundary", true, b),
        pair("feature-left", true, circle(p(3., 0.5), 0.3, 10)),
        pair("feature-right", true, circle(p(7., 0.5), 0.3, 10)),
    ];
    pairs[1].target = circle(p(7., 0.5), 0.3, 10);
    pairs[2].target = circle(p(3., 0.5), 0.3, 10);
    let e = map(&pairs, false).unwrap_err();
    assert!(e.is_input());
    let msg = e.to_string();
    assert!(msg.contains("feature-left") && msg.contains("feature-right"), "{msg}");
    assert!(msg.contains("Fig.16"), "{msg}");
}

#[test]
#[ignore = "timing, run with --ignored --nocapture"]
fn timing_of_a_700_vertex_mesh() {
    let pairs = bent_strip(40.0, 2, 1.5 * PI);
    let diag = diagonal(&pairs);
    let tol = Tolerances::new(diag, 1.3);
    let tri = triangulate(&pairs, &tol, false).unwrap();
    let opts = MappingOptions::default();
    let start = std::time::Instant::now();
    let runs = 20;
    let mut stats = MappingStats::default();
    for _ in 0..runs {
        stats = composite_map(&tri, &pairs, &tol, &opts).unwrap().1;
    }
    println!(
        "composite map: {} vertices, {} triangles, {} steps ({} rejected): {:.2} ms per map",
        stats.vertices,
        stats.triangles,
        stats.steps,
        stats.rejected_steps,
        start.elapsed().as_secs_f64() * 1e3 / runs as f64
    );
}

#[test]
fn dbg_bsm_gap() {
    let pairs = bent_strip(20.0, 2, 1.5 * PI);
    let m = ShapeModel::new(&pairs, false).unwrap();
    let mut out = Vec::new();
    for t in [0.0, 0.1, 0.2, 0.25, 0.3, 0.31, 0.32, 0.4, 0.6, 0.8, 1.0] {
        m.curves_at(t, &mut out);
        let gap = |a: &[Point], b: &[Point]| {
            a.iter()
                .map(|q| b.windows(2).map(|w| crate::geometry::point_segment_distance(*q, w[0], w[1]).0).fold(f64::INFINITY, f64::min))
                .fold(f64::INFINITY, f64::min)
        };
        let c: Vec<Point> = out.iter().map(|c| crate::geometry::centroid(c)).collect();
        eprintln!("t {t}: mid-boundary gap {:.3} dot-boundary {:.3} dot-mid {:.3} centres {:?}", gap(&out[2], &out[0]), gap(&out[1], &out[0]), gap(&out[1], &out[2]), c);
    }
}

#[test]
fn dbg_fold() {
    let pairs = bent_strip(20.0, 2, 1.5 * PI);
    let tol = Tolerances::new(diagonal(&pairs), 1.0);
    let tri = triangulate(&pairs, &tol, false).unwrap();
    for ms in [1.0 / 4096.0, 1.0 / 65536.0, 1.0 / 1048576.0] {
        let opts = MappingOptions::default().with_min_step(ms).with_max_steps(100000);
        match composite_map(&tri, &pairs, &tol, &opts) {
            Ok((_, s)) => eprintln!("min_step {ms}: ok {s:?}"),
            Err(e) => eprintln!("min_step {ms}: {e}"),
        }
    }
    eprintln!("vertices {}", tri.points.len());
}
