use super::*;
use crate::geometry::{point_segment_distance, triangle_area};
pub(crate) use crate::mapping::samples::{circle, pair, resampled};
use crate::mesh::Side;
use crate::mesh::{count_inverted, edges};

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

/// A closed polyline through `corners`, each side split into `per_side` edges.
pub(crate) fn subdivided(corners: &[Point], per_side: usize) -> Vec<Point> {
    let n = corners.len();
    (0..n)
        .flat_map(|i| {
            let (a, b) = (corners[i], corners[(i + 1) % n]);
            (0..per_side).map(move |k| a.lerp(b, k as f64 / per_side as f64))
        })
        .collect()
}

fn square_with_features() -> Vec<CurvePair> {
    let sq = subdivided(&[p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)], 30);
    vec![
        pair("boundary", true, sq),
        pair("feature-eye", true, circle(p(7., 7.), 1.5, 32)),
        pair(
            "feature-line",
            false,
            (0..14)
                .map(|k| p(2., 2.).lerp(p(4., 6.), k as f64 / 13.))
                .collect(),
        ),
    ]
}

fn min_angle_deg(a: Point, b: Point, c: Point) -> f64 {
    let ang = |p: Point, q: Point, r: Point| (q - p).angle_to(r - p).abs().to_degrees();
    ang(a, b, c).min(ang(b, c, a)).min(ang(c, a, b))
}

#[test]
fn square_with_open_and_closed_features() {
    let pairs = square_with_features();
    let tol = Tolerances::new(200f64.sqrt(), 1.0);
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    let n_curve: usize = pairs.iter().map(|p| p.source.len()).sum();
    assert!(
        tri.points.len() > n_curve + 20,
        "refinement added Steiner points"
    );
    // curve vertices map one to one
    for (pc, mc) in pairs.iter().zip(&tri.curves) {
        assert_eq!(pc.id, mc.name);
        for (k, &v) in mc.vertices.iter().enumerate() {
            assert_eq!(tri.points[v as usize], pc.source[k]);
        }
    }
    // every curve edge is a mesh edge
    let e = edges(&tri.triangles);
    for mc in &tri.curves {
        let n = mc.vertices.len();
        let m = if mc.closed { n } else { n - 1 };
        for k in 0..m {
            let (a, b) = (mc.vertices[k], mc.vertices[(k + 1) % n]);
            assert!(
                e.binary_search(&(a.min(b), a.max(b))).is_ok(),
                "{} edge {k}",
                mc.name
            );
        }
    }
    // no Steiner point on a curve
    for q in &tri.points[n_curve..] {
        for pc in &pairs {
            let s = &pc.source;
            for k in 0..s.len() - usize::from(!pc.closed) {
                let (d, _) = point_segment_distance(*q, s[k], s[(k + 1) % s.len()]);
                assert!(d > 1e-6, "Steiner point {q} on {}", pc.id);
            }
        }
    }
    assert_eq!(count_inverted(&tri.triangles, &tri.points), 0);
    // the faces cover the square exactly, including the inside of the closed feature
    let area: f64 = tri
        .triangles
        .iter()
        .map(|t| {
            triangle_area(
                tri.points[t[0] as usize],
                tri.points[t[1] as usize],
                tri.points[t[2] as usize],
            )
        })
        .sum();
    assert!((area - 100.0).abs() < 1e-9, "area {area}");
    let eye = &pairs[1].source;
    let eye_area: f64 = tri
        .triangles
        .iter()
        .map(|t| t.map(|i| tri.points[i as usize]))
        .filter(|t| point_in_polygon((t[0] + t[1] + t[2]) / 3.0, eye))
        .map(|t| triangle_area(t[0], t[1], t[2]))
        .sum();
    assert!((eye_area - polygon_area(eye)).abs() < 1e-9);
    // quality away from the curves; max area respected
    for t in &tri.triangles {
        let [a, b, c] = t.map(|i| tri.points[i as usize]);
        let area = triangle_area(a, b, c);
        assert!(area <= tol.max_area * 1.0001, "area {area} at {a}");
        if t.iter().all(|&i| i as usize >= n_curve) {
            assert!(min_angle_deg(a, b, c) > 20.0, "{}", min_angle_deg(a, b, c));
        }
    }
    // deterministic
    assert_eq!(triangulate(&pairs, &tol, Side::Source).unwrap(), tri);
}

#[test]
fn crossing_and_outside_features_are_named() {
    let tol = Tolerances::new(200f64.sqrt(), 1.0);
    let mut pairs = square_with_features();
    pairs[2].source = vec![p(5., 5.), p(12., 5.)];
    pairs[2].target = pairs[2].source.clone();
    let e = triangulate(&pairs, &tol, Side::Source)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("feature-line") && e.contains("crosses the boundary"),
        "{e}"
    );

    let mut pairs = square_with_features();
    pairs[2].source = vec![p(7., 3.), p(7., 9.)];
    pairs[2].target = pairs[2].source.clone();
    let e = triangulate(&pairs, &tol, Side::Source)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("feature-line") && e.contains("crosses feature-eye"),
        "{e}"
    );

    let mut pairs = square_with_features();
    pairs[1].target = circle(p(20., 20.), 1.0, 32);
    let e = triangulate(&pairs, &tol, Side::Target)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("<target>") && e.contains("feature-eye") && e.contains("outside"),
        "{e}"
    );
    assert!(triangulate(&pairs, &tol, Side::Source).is_ok());

    let mut pairs = square_with_features();
    pairs[2].source[1] = pairs[1].source[3];
    let e = triangulate(&pairs, &tol, Side::Source)
        .unwrap_err()
        .to_string();
    assert!(e.contains("coincides"), "{e}");

    let mut pairs = square_with_features();
    pairs[0].source.reverse();
    assert!(triangulate(&pairs, &tol, Side::Source).is_err());
}

/// A star-shaped polygon around the origin with radii `radii` (counter-clockwise), edges split
/// to at most `max_edge`.
pub(crate) fn star(radii: &[f64], max_edge: f64) -> Vec<Point> {
    let n = radii.len();
    let corners: Vec<Point> = radii
        .iter()
        .enumerate()
        .map(|(k, r)| *r * Point::from_angle(k as f64 / n as f64 * std::f64::consts::TAU))
        .collect();
    resampled(&corners, max_edge)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]

    #[test]
    fn random_star_shapes_triangulate_exactly(
        radii in proptest::collection::vec(0.6f64..1.0, 5..12),
        with_feature in proptest::bool::ANY,
    ) {
        let mut pairs = vec![pair("boundary", true, star(&radii, 0.08))];
        if with_feature {
            pairs.push(pair("feature-c", true, circle(p(0.05, -0.02), 0.2, 12)));
        }
        let tol = Tolerances::new(2.0, 1.0);
        let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
        proptest::prop_assert_eq!(count_inverted(&tri.triangles, &tri.points), 0);
        let area: f64 = tri
            .triangles
            .iter()
            .map(|t| triangle_area(tri.points[t[0] as usize], tri.points[t[1] as usize], tri.points[t[2] as usize]))
            .sum();
        proptest::prop_assert!((area - polygon_area(&pairs[0].source)).abs() < 1e-12);
        let e = edges(&tri.triangles);
        for mc in &tri.curves {
            let n = mc.vertices.len();
            for k in 0..n {
                let (a, b) = (mc.vertices[k], mc.vertices[(k + 1) % n]);
                proptest::prop_assert!(e.binary_search(&(a.min(b), a.max(b))).is_ok());
            }
        }
        let r = crate::mesh::sanity_check(
            &crate::mesh::CompatibleMeshes {
                triangles: tri.triangles.clone(),
                source: tri.points.clone(),
                target: tri.points.clone(),
                curves: tri.curves.clone(),
                parts: None,
            },
            None,
            0.0,
        );
        proptest::prop_assert!(r.is_ok(), "{:?}", r);
    }
}

/// Shrunk proptest case: nearly collinear boundary vertices on the convex hull make outer
/// slivers whose circumcenters are not finite; refining them made spade loop and panic.
#[test]
fn regression_collinear_hull_vertices() {
    let radii = [0.6, 0.721148464254704, 0.7455831531867653, 0.6, 0.6];
    let pairs = vec![pair("boundary", true, star(&radii, 0.08))];
    let tol = Tolerances::new(2.0, 1.0);
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    assert_eq!(count_inverted(&tri.triangles, &tri.points), 0);
}

#[test]
fn no_triangle_has_every_corner_on_a_curve() {
    // A star's narrow tips: a plain CDT fills them with triangles of boundary vertices only,
    // whose shape the curves alone decide (they fold when the star becomes an ellipse). Chords
    // are split, so every triangle has a free corner.
    let p = Point::new;
    let star: Vec<Point> = (0..10)
        .map(|k| {
            let a = std::f64::consts::PI * k as f64 / 5.0;
            let r = if k % 2 == 0 { 90.0 } else { 35.0 };
            p(100.0 + r * a.sin(), 100.0 - r * a.cos())
        })
        .collect();
    let pairs = vec![pair("boundary", true, subdivided(&star, 6))];
    let tol = Tolerances::new(180.0, 1.0);
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    let on_curve = pairs[0].source.len() as u32;
    let all_fixed = tri
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&v| v < on_curve))
        .count();
    assert_eq!(all_fixed, 0);
    assert_eq!(crate::mesh::count_inverted(&tri.triangles, &tri.points), 0);
}
