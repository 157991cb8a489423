use super::*;
use crate::geometry::bounding_box;
use crate::mapping::samples::{bent_band, circle, pair, turning_bar};
use crate::mesh::Side;
use crate::mesh::{count_inverted, sanity_check};
use crate::triangulation::tests::subdivided;
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
    let side = if from_target {
        Side::Target
    } else {
        Side::Source
    };
    let tri = triangulate(pairs, &tol, side)?;
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
        pair(
            "boundary",
            true,
            subdivided(&[p(0., 0.), p(10., 0.), p(10., 8.), p(0., 8.)], 24),
        ),
        pair("feature-eye", true, circle(p(3., 5.), 1.2, 24)),
        pair(
            "feature-mouth",
            false,
            (0..12)
                .map(|k| p(5., 2.).lerp(p(8., 3.), k as f64 / 11.))
                .collect(),
        ),
    ]
}

/// A strip `len × 2` with a midline feature and a small closed feature, bent into a U of
/// `bend` radians (the strip's midline keeps its length).
fn bent_strip(len: f64, per_unit: usize, bend: f64) -> Vec<CurvePair> {
    bent_band(len, 2.0, per_unit, bend)
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
            assert!(
                expect.distance(*r) < 1e-9 * diag,
                "{deg}°: {} off",
                expect.distance(*r)
            );
        }
    }
}

#[test]
fn a_strip_bent_into_a_u_maps_without_flips() {
    let pairs = bent_strip(20.0, 2, PI);
    let (m, stats) = map(&pairs, false).unwrap();
    assert_healthy(&m, &pairs);
    assert!(stats.steps >= 4 && stats.path != Intermediates::Straight);
    // a wide band curled by three quarters of a turn
    let pairs = bent_band(20.0, 6.0, 2, 1.5 * PI);
    let (m, stats) = map(&pairs, false).unwrap();
    assert_healthy(&m, &pairs);
    assert!(stats.path != Intermediates::Straight);
}

#[test]
fn composing_avoids_the_folds_of_one_direct_map() {
    // Fig.8 vs Fig.10: the direct harmonic map folds triangles around a turning feature,
    // the composite one does not.
    let pairs = turning_bar(45.0);
    let tol = Tolerances::new(diagonal(&pairs), 1.0);
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    let n = tri.points.len();
    let mut fixed = vec![false; n];
    let mut direct = tri.points.clone();
    for (c, pc) in tri.curves.iter().zip(&pairs) {
        for (&v, &q) in c.vertices.iter().zip(&pc.target) {
            fixed[v as usize] = true;
            direct[v as usize] = q;
        }
    }
    Harmonic::new(&tri.triangles, n, &fixed)
        .unwrap()
        .solve(&tri.points, &mut direct)
        .unwrap();
    assert!(count_inverted(&tri.triangles, &direct) > 0);
    let (m, stats) = composite_map(&tri, &pairs, &tol, &MappingOptions::default()).unwrap();
    assert_healthy(&m, &pairs);
    assert!(stats.path != Intermediates::Straight, "{stats:?}");
}

#[test]
fn a_step_that_needed_untangling_grows_after_accepted_ones_and_backs_off_when_growth_fails() {
    let mut s = Step::new(0.25);
    s.rejected();
    s.rejected();
    assert_eq!(s.h, 0.0625);
    s.accepted(false);
    assert_eq!(s.h, 0.0625, "untangled right after a rejection: kept");
    s.accepted(false);
    assert_eq!(s.h, 0.125, "a second accepted map in a row: doubled");
    s.accepted(false);
    assert_eq!(s.h, 0.125, "the count starts again at the new step");
    s.accepted(false);
    assert_eq!(s.h, 0.25);
    // The doubled step is rejected at once: the next growth waits for four accepted maps.
    s.rejected();
    assert_eq!(s.h, 0.125);
    for _ in 0..3 {
        s.accepted(false);
        assert_eq!(s.h, 0.125, "patience after a failed growth");
    }
    s.accepted(false);
    assert_eq!(s.h, 0.25);
    // A rejection that does not follow a growth leaves the patience as it is.
    s.accepted(false);
    s.rejected();
    assert_eq!((s.h, s.patience), (0.125, 4));
    // A clean map doubles at once and forgets the failed growths.
    s.accepted(true);
    assert_eq!((s.h, s.patience), (0.25, 2));
    s.accepted(true);
    assert_eq!(s.h, 0.25, "never beyond the largest step");
    // Failed growths wait longer each time, up to sixteen maps.
    let mut t = Step::new(1.0);
    t.rejected();
    for _ in 0..6 {
        while t.h < 1.0 {
            t.accepted(false);
        }
        t.rejected();
    }
    assert_eq!(t.patience, 16);
}

#[test]
fn a_folding_step_is_untangled_instead_of_abandoned() {
    // One whole step with no halving allowed: the harmonic map alone folds (above), the local
    // untangling of its folded triangles makes it valid.
    let pairs = turning_bar(45.0);
    let tol = Tolerances::new(diagonal(&pairs), 1.0);
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    let one = MappingOptions::default()
        .with_initial_steps(1)
        .with_min_step(0.75)
        .with_last_resort(Intermediates::Carried);
    let (m, stats) = composite_map(&tri, &pairs, &tol, &one).unwrap();
    assert_healthy(&m, &pairs);
    assert_eq!((stats.steps, stats.rejected_steps), (1, 0));
}

#[test]
fn a_curled_strip_carries_its_features_with_the_boundary() {
    // Curled by 270°, the BSM moves the small feature across the narrow strip into the midline
    // (a limitation of placing curves by their barycenters); carried by the boundary around it,
    // the feature stays in its place in the strip.
    let pairs = bent_strip(20.0, 2, 1.5 * PI);
    let tol = Tolerances::new(diagonal(&pairs), 1.0);
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    let strict = MappingOptions::default().with_last_resort(Intermediates::Carried);
    let (m, stats) = composite_map(&tri, &pairs, &tol, &strict).unwrap();
    assert_healthy(&m, &pairs);
    assert_eq!(stats.path, Intermediates::Carried, "{stats:?}");
    // The paper's curves alone cannot: the strategy stops there.
    let paper = MappingOptions::default().with_last_resort(Intermediates::Bsm);
    let e = composite_map(&tri, &pairs, &tol, &paper).unwrap_err();
    assert!(e.is_input(), "{e}");
    assert_eq!(e.kind(), Some(crate::ProblemKind::NoFlipFreeMapping), "{e}");
}

#[test]
fn carried_features_end_exactly_on_their_twins_and_stay_inside() {
    let pairs = bent_strip(20.0, 2, 1.5 * PI);
    let model = ShapeModel::carried(&pairs, Side::Source).unwrap();
    let mut curves = Vec::new();
    for (t, side) in [(0.0, Side::Source), (1.0, Side::Target)] {
        model.curves_at(t, &mut curves);
        for (c, p) in curves.iter().zip(&pairs) {
            assert_eq!(c.as_slice(), crate::triangulation::side_of(p, side));
        }
    }
    for k in 1..20 {
        model.curves_at(k as f64 / 20.0, &mut curves);
        for c in &curves[1..] {
            for q in c {
                assert!(
                    crate::geometry::point_in_polygon(*q, &curves[0]),
                    "t={k}/20: {q}"
                );
            }
        }
    }
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
    let pairs = trading_places(1.0, [3.0, 7.0], 0.3, 10);
    let e = map(&pairs, false).unwrap_err();
    assert!(e.is_input());
    let msg = e.to_string();
    assert!(
        msg.contains("feature-left") && msg.contains("feature-right"),
        "{msg}"
    );
    assert!(msg.contains("Fig.16"), "{msg}");
    println!("{msg}");
}

/// A strip 10 long and `height` high whose two round features (centres at `xs` on its
/// midline, `radius`, `points` vertices each) trade places.
fn trading_places(height: f64, xs: [f64; 2], radius: f64, points: usize) -> Vec<CurvePair> {
    let b = subdivided(&[p(0., 0.), p(10., 0.), p(10., height), p(0., height)], 20);
    let round = |x: f64| circle(p(x, height / 2.0), radius, points);
    let mut pairs = vec![
        pair("boundary", true, b),
        pair("feature-left", true, round(xs[0])),
        pair("feature-right", true, round(xs[1])),
    ];
    pairs[1].target = round(xs[1]);
    pairs[2].target = round(xs[0]);
    pairs
}

/// Two round features filling most of a strip's height trade places: a quarter of the way,
/// the BSM's and the carried features' curves cross the boundary, and halfway the straight
/// lines' cross each other.
fn features_trading_places() -> Vec<CurvePair> {
    trading_places(2.0, [4.0, 6.0], 0.8, 16)
}

#[test]
fn curves_that_cross_at_once_fail_without_a_triangulation_as_they_fail_with_one() {
    let pairs = features_trading_places();
    let tol = Tolerances::new(diagonal(&pairs), 1.0);
    let opts = MappingOptions::default();
    for side in [Side::Source, Side::Target] {
        let checked = check_curves(&pairs, &tol, &opts, side, &mut Attachments::default());
        let CurveCheck::Fails(e) = checked else {
            panic!("{side:?}: the crossing was not found on the curves alone");
        };
        let tri = triangulate(&pairs, &tol, side).unwrap();
        let mapped = composite_map(&tri, &pairs, &tol, &opts).unwrap_err();
        assert_eq!(e.to_string(), mapped.to_string());
        assert_eq!(e.curves(), mapped.curves());
        assert!(e.curves().contains(&"feature-left".to_string()), "{e}");
    }
}

#[test]
fn a_map_given_what_the_check_found_is_the_map_without_it() {
    // Bent by half a turn the BSM's first map is clear; curled by 1.8 turns its first map
    // crosses and the carried features' is handed on.
    for (bend, path) in [(PI, Intermediates::Bsm), (1.8 * PI, Intermediates::Carried)] {
        let pairs = bent_strip(20.0, 2, bend);
        let tol = Tolerances::new(diagonal(&pairs), 1.0);
        let opts = MappingOptions::default();
        let made = &mut Attachments::default();
        let CurveCheck::Try(Some(checked)) = check_curves(&pairs, &tol, &opts, Side::Source, made)
        else {
            panic!("{bend}: a strip whose paths do not all cross at once was not left to the map");
        };
        assert_eq!(checked.path, path);
        let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
        let with = composite_map_reusing(&tri, &pairs, &tol, &opts, made, Some(checked));
        let without = composite_map(&tri, &pairs, &tol, &opts);
        match (with, without) {
            (Ok((a, sa)), Ok((b, sb))) => {
                let bits = |v: &[Point]| {
                    v.iter()
                        .map(|q| (q.x.to_bits(), q.y.to_bits()))
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&a.target), bits(&b.target), "{bend}");
                assert_eq!(sa, sb, "{bend}");
            }
            (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string(), "{bend}"),
            (a, b) => panic!("{bend}: {:?} against {:?}", a.map(|x| x.1), b.map(|x| x.1)),
        }
    }
}

#[test]
fn straight_lines_are_left_out_only_with_features_that_cross_halfway() {
    let pairs = features_trading_places();
    let linear = |pairs: &[CurvePair]| ShapeModel::linear(pairs, Side::Source).unwrap();
    assert!(straight_lines_cross(&linear(&pairs), &pairs));
    // A boundary alone is tried even where its straight lines cross halfway (a half turn
    // takes every point through the centre), and so are features that keep their places.
    let mut turned = pairs[..1].to_vec();
    turned[0].target = turned[0].source.iter().map(|&q| p(10., 2.) - q).collect();
    assert!(cross_at(&linear(&turned), &turned, 0.5, &mut Vec::new()));
    assert!(!straight_lines_cross(&linear(&turned), &turned));
    let mut kept = pairs.clone();
    kept[1].target = kept[1].source.clone();
    kept[2].target = kept[2].source.clone();
    assert!(!straight_lines_cross(&linear(&kept), &kept));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(16))]

    #[test]
    fn random_similarities_map_exactly(
        radii in proptest::collection::vec(0.6f64..1.0, 5..10),
        angle in -7.0f64..7.0,
        scale in 0.2f64..5.0,
        dx in -10.0f64..10.0,
    ) {
        let mut pairs = vec![
            pair("boundary", true, crate::triangulation::tests::star(&radii, 0.1)),
            pair("feature-c", true, circle(p(0.1, 0.0), 0.2, 10)),
            pair("feature-l", false, vec![p(-0.3, -0.3), p(-0.2, -0.1), p(-0.25, 0.1)]),
        ];
        let rot = Point::from_angle(angle);
        for pc in &mut pairs {
            pc.target = pc.source.iter().map(|q| p(dx, 1.0) + scale * rot.rotate(*q)).collect();
        }
        let (m, _) = map(&pairs, false).unwrap();
        assert_healthy(&m, &pairs);
        for (q, r) in m.source.iter().zip(&m.target) {
            let expect = p(dx, 1.0) + scale * rot.rotate(*q);
            proptest::prop_assert!(expect.distance(*r) < 1e-9 * 2.0 * scale.max(1.0));
        }
    }
}
