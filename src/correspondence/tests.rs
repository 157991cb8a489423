//! Tests of the curve-pair correspondence as a whole (the parts have their own beside them).

use super::*;
use crate::drawing::Anchor;
use crate::geometry::{polygon_area, polyline_length};
use proptest::prelude::*;
use std::f64::consts::TAU;

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

fn curve(id: &str, closed: bool, points: Vec<Point>) -> ControlCurve {
    let kind = if id == "boundary" {
        CurveKind::Boundary
    } else {
        CurveKind::Feature
    };
    let name = id.strip_prefix("feature-").unwrap_or(id).to_string();
    ControlCurve {
        id: id.into(),
        name,
        kind,
        closed,
        points,
    }
}

fn ellipse(n: usize, a: f64, b: f64, phase: f64, centre: Point) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let t = phase + TAU * k as f64 / n as f64;
            centre + p(a * t.cos(), b * t.sin())
        })
        .collect()
}

fn tol() -> Tolerances {
    Tolerances::new(10.0, 1.0)
}

/// Checks the invariants every pair must hold and that every original vertex of both curves is
/// in the result.
fn check_pair(pair: &CurvePair, src: &[Point], tgt: &[Point], tol: &Tolerances) {
    assert_eq!(pair.source.len(), pair.target.len());
    let n = pair.source.len();
    let edges = if pair.closed { n } else { n - 1 };
    for i in 0..edges {
        let j = (i + 1) % n;
        for side in [&pair.source, &pair.target] {
            let d = side[i].distance(side[j]);
            assert!(d > tol.snap, "coincident consecutive points at {i}");
            assert!(
                d <= tol.max_edge * (1.0 + 1e-9),
                "edge {i} of length {d} is too long"
            );
        }
    }
    if pair.closed {
        assert!(polygon_area(&pair.source) > 0.0);
        assert!(polygon_area(&pair.target) > 0.0);
    }
    for q in src {
        assert!(pair.source.contains(q), "source vertex {q} lost");
    }
    for q in tgt {
        assert!(pair.target.contains(q), "target vertex {q} lost");
    }
    // Shape preserved: every result point lies on the original polyline, and (with every original
    // vertex present) the result's length equals the original's.
    for (res, orig) in [(&pair.source, src), (&pair.target, tgt)] {
        let line = Polyline::new(orig.to_vec(), pair.closed);
        for q in res.iter() {
            assert!(line.project(*q).0 <= tol.snap, "{q} is off the curve");
        }
    }
    let closed = pair.closed;
    assert!((polyline_length(&pair.source, closed) - polyline_length(src, closed)).abs() < 1e-9);
    assert!((polyline_length(&pair.target, closed) - polyline_length(tgt, closed)).abs() < 1e-9);
}

#[test]
fn circle_to_ellipse() {
    let tol = tol();
    let c = ellipse(90, 2.0, 2.0, 0.0, p(5., 5.));
    let e: Vec<Point> = ellipse(120, 3.0, 1.0, 0.7, p(5., 5.))
        .into_iter()
        .rev()
        .collect();
    let pair = correspond(
        &curve("boundary", true, c.clone()),
        &curve("boundary", true, e.clone()),
        &[],
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &c, &e, &tol);
    assert_eq!(pair.salient, vec![0]);
    assert!(c.contains(&pair.source[0]) && e.contains(&pair.target[0]));
    // The circle's rightmost point goes to the ellipse's rightmost end (no needless turning).
    assert!(pair.target[0].x > 7.5, "start {:?}", pair.target[0]);
}

fn dense_polygon(corners: &[Point], k: usize) -> Vec<Point> {
    let mut pts = Vec::new();
    for c in 0..corners.len() {
        let (a, b) = (corners[c], corners[(c + 1) % corners.len()]);
        for j in 0..k {
            pts.push(a + (b - a) * (j as f64 / k as f64));
        }
    }
    pts
}

#[test]
fn square_corners_go_to_diamond_corners() {
    let tol = tol();
    let sq_corners = [p(1., 1.), p(4., 1.), p(4., 4.), p(1., 4.)];
    let dia_corners = [p(5., 2.), p(7., 4.), p(5., 6.), p(3., 4.)];
    let sq = dense_polygon(&sq_corners, 7);
    let dia = dense_polygon(&dia_corners, 3);
    let pair = correspond(
        &curve("boundary", true, sq.clone()),
        &curve("boundary", true, dia.clone()),
        &[],
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &sq, &dia, &tol);
    assert_eq!(pair.salient.len(), 4);
    for c in sq_corners {
        let i = pair.source.iter().position(|&q| q == c).unwrap();
        assert!(pair.salient.contains(&i));
        assert!(
            dia_corners.contains(&pair.target[i]),
            "corner {c} went to {}",
            pair.target[i]
        );
    }
}

#[test]
fn an_open_curve_drawn_backwards_is_reversed() {
    let tol = tol();
    let hook = vec![p(1., 1.), p(1., 5.), p(2., 6.), p(3., 5.)];
    let back: Vec<Point> = hook.iter().rev().map(|&q| q * 1.2 + p(0.5, 0.)).collect();
    let pair = correspond(
        &curve("feature-hook", false, hook.clone()),
        &curve("feature-hook", false, back.clone()),
        &[],
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &hook, &back, &tol);
    assert_eq!(pair.target[0], back[3]);
    assert_eq!(*pair.target.last().unwrap(), back[0]);
    assert_eq!(pair.source[0], hook[0]);
    assert_eq!(*pair.salient.last().unwrap(), pair.source.len() - 1);
}

#[test]
fn an_anchor_forces_a_correspondence() {
    let tol = tol();
    let c = ellipse(64, 2.0, 2.0, 0.0, p(5., 5.));
    let d = ellipse(64, 2.0, 2.0, 0.0, p(5., 5.));
    // Pin the circle's top to the other circle's left: a quarter turn.
    let (a, b) = (p(5., 7.), p(3., 5.));
    let pair = correspond(
        &curve("boundary", true, c.clone()),
        &curve("boundary", true, d.clone()),
        &[(a, b)],
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &c, &d, &tol);
    assert_eq!(pair.salient, vec![0]);
    assert!(pair.source[0].distance(a) < 1e-9 && pair.target[0].distance(b) < 1e-9);
    // The whole circle turns by a quarter.
    for (s, t) in pair.source.iter().zip(&pair.target) {
        let r = p(5., 5.) + (*s - p(5., 5.)).perp();
        assert!(r.distance(*t) < 1e-6);
    }
}

#[test]
fn anchors_in_crossing_order_are_refused() {
    let tol = tol();
    let c = curve("boundary", true, ellipse(64, 2.0, 2.0, 0.0, p(5., 5.)));
    let pins = [
        (p(7., 5.), p(7., 5.)),
        (p(5., 7.), p(3., 5.)),
        (p(3., 5.), p(5., 7.)),
    ];
    let err = correspond(&c, &c, &pins, &tol, &CorrespondenceOptions::default()).unwrap_err();
    assert!(err.to_string().contains("order"), "{err}");
}

fn controls(boundary: ControlCurve, features: Vec<ControlCurve>, anchors: Vec<Anchor>) -> Controls {
    Controls {
        boundary,
        boundary_from_view_box: false,
        features,
        anchors,
        skeleton: Vec::new(),
        near_misses: Vec::new(),
    }
}

fn anchor(name: &str, point: Point) -> Anchor {
    Anchor {
        id: format!("anchor-{name}"),
        name: name.into(),
        point,
    }
}

#[test]
fn all_pairs_boundary_first_then_features_with_anchors() {
    let tol = tol();
    let opts = CorrespondenceOptions::default();
    let b = curve(
        "boundary",
        true,
        dense_polygon(&[p(0., 0.), p(10., 0.), p(10., 8.), p(0., 8.)], 2),
    );
    let eye = curve("feature-eye", true, ellipse(40, 1.0, 0.5, 0.0, p(3., 3.)));
    let mouth = curve(
        "feature-mouth",
        false,
        vec![p(2., 6.), p(5., 7.), p(8., 6.)],
    );
    let src = controls(
        b.clone(),
        vec![eye.clone(), mouth.clone()],
        vec![anchor("chin", p(5., 7.))],
    );
    let tgt = controls(b, vec![eye, mouth], vec![anchor("chin", p(6., 6.5))]);
    let pairs = correspond_all("a.svg", &src, "b.svg", &tgt, &tol, &opts).unwrap();
    let ids: Vec<&str> = pairs.iter().map(|p| p.id.as_str()).collect();
    assert_eq!(ids, ["boundary", "feature-eye", "feature-mouth"]);
    let mouth = &pairs[2];
    let k = mouth.source.iter().position(|&q| q == p(5., 7.)).unwrap();
    assert!(mouth.salient.contains(&k));
    assert!(mouth.target[k].distance(p(6., 6.5)) < 0.5 && mouth.target[k].y > 6.0);
    // Deterministic: the same input gives the same output.
    assert_eq!(
        pairs,
        correspond_all("a.svg", &src, "b.svg", &tgt, &tol, &opts).unwrap()
    );
}

#[test]
fn a_half_turn_symmetric_boundary_turns_the_way_its_features_say() {
    // A 4×1 bar whose corners match its twin equally well turned by 0° or 180°. The feature
    // near the left end moves to the right end, so only the half turn keeps it with its
    // surroundings; the least-turning tie-break alone would pick 0° and drag the feature
    // across the bar.
    let tol = tol();
    let opts = CorrespondenceOptions::default();
    let bar = dense_polygon(&[p(0., 0.), p(4., 0.), p(4., 1.), p(0., 1.)], 4);
    let half = |q: Point| p(4.0 - q.x, 1.0 - q.y);
    let line = vec![p(0.5, 0.2), p(0.6, 0.5), p(0.5, 0.8)];
    let src = controls(
        curve("boundary", true, bar.clone()),
        vec![curve("feature-line", false, line.clone())],
        vec![],
    );
    let tgt = controls(
        curve("boundary", true, bar.iter().map(|&q| half(q)).collect()),
        vec![curve(
            "feature-line",
            false,
            line.iter().map(|&q| half(q)).collect(),
        )],
        vec![],
    );
    let pairs = correspond_all("a.svg", &src, "b.svg", &tgt, &tol, &opts).unwrap();
    for pair in &pairs {
        for (&a, &b) in pair.source.iter().zip(&pair.target) {
            assert!(half(a).distance(b) < 1e-9, "{}: {a} ↦ {b}", pair.id);
        }
    }
    assert!(feature_misfit(&pairs, &mut Correspondences::default()) < 1e-9);
}

#[test]
fn an_open_feature_runs_the_way_its_surroundings_move() {
    // A stroke along a bar (a trapezoid, so it has no symmetry), nearly straight with a small
    // hook at its start; in the target it is drawn from the same end, gently bent, with the
    // hook at its far end. By shape alone the reversed target fits marginally better; the bar
    // around it does not move, so the stroke must not turn round.
    let tol = tol();
    let opts = CorrespondenceOptions::default();
    let bar = dense_polygon(&[p(0., 0.), p(10., 0.), p(10., 3.), p(0., 2.)], 8);
    let src_line: Vec<Point> = std::iter::once(p(1.0, 1.4))
        .chain((0..=16).map(|k| p(1.2 + 7.8 * k as f64 / 16.0, 1.0)))
        .collect();
    let tgt_line: Vec<Point> = (0..=16)
        .map(|k| {
            let u = k as f64 / 16.0;
            p(1.0 + 7.8 * u, 1.0 + 0.3 * (u * std::f64::consts::PI).sin())
        })
        .chain(std::iter::once(p(9.0, 0.6)))
        .collect();
    let (a, b) = (
        Polyline::new(src_line.clone(), false),
        Polyline::new(tgt_line.clone(), false),
    );
    assert!(
        orientation::open_target_reversed(&a, &b),
        "premise: shape alone reverses"
    );
    let src = controls(
        curve("boundary", true, bar.clone()),
        vec![curve("feature-stroke", false, src_line)],
        vec![],
    );
    let tgt = controls(
        curve("boundary", true, bar),
        vec![curve("feature-stroke", false, tgt_line)],
        vec![],
    );
    let pairs = correspond_all("a.svg", &src, "b.svg", &tgt, &tol, &opts).unwrap();
    let stroke = &pairs[1];
    assert_eq!(stroke.target[0], p(1.0, 1.0));
    assert_eq!(*stroke.target.last().unwrap(), p(9.0, 0.6));
}

#[test]
fn input_errors_name_the_file_and_the_element() {
    let tol = tol();
    let opts = CorrespondenceOptions::default();
    let b = curve(
        "boundary",
        true,
        vec![p(0., 0.), p(10., 0.), p(10., 8.), p(0., 8.)],
    );
    let eye = curve("feature-eye", false, vec![p(2., 2.), p(3., 3.)]);
    let src = controls(b.clone(), vec![eye.clone()], vec![]);
    let tgt = controls(b.clone(), vec![], vec![]);
    let e = correspond_all("source.svg", &src, "target.svg", &tgt, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("feature-eye is in source.svg but not in target.svg"),
        "{e}"
    );
    let e = correspond_all("source.svg", &tgt, "target.svg", &src, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("target.svg") && e.contains("not in source.svg"),
        "{e}"
    );

    let flat = curve("feature-eye", false, vec![p(2., 2.), p(2., 2.)]);
    let bad = controls(b.clone(), vec![flat], vec![]);
    let e = correspond_all("source.svg", &src, "target.svg", &bad, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("target.svg: element 'feature-eye'") && e.contains("distinct"),
        "{e}"
    );
    let tri = curve("boundary", true, vec![p(0., 0.), p(1., 1.), p(2., 2.)]);
    let bad = controls(tri, vec![], vec![]);
    let e = correspond_all("source.svg", &bad, "target.svg", &tgt, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("source.svg: element 'boundary'") && e.contains("no area"),
        "{e}"
    );

    let lone = controls(b.clone(), vec![eye.clone()], vec![anchor("x", p(2.5, 2.5))]);
    let e = correspond_all("source.svg", &lone, "target.svg", &src, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("anchor-x") && e.contains("no twin in target.svg"),
        "{e}"
    );
    let far = controls(b.clone(), vec![eye.clone()], vec![anchor("x", p(5., 5.))]);
    let e = correspond_all("source.svg", &far, "target.svg", &far, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("source.svg: element 'anchor-x'") && e.contains("farther"),
        "{e}"
    );
    let open = curve("boundary", false, vec![p(0., 0.), p(10., 0.), p(10., 8.)]);
    let e = correspond(&open, &b, &[], &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("closed in one file and open in the other"),
        "{e}"
    );
}

#[test]
fn density_bounds_the_edge_length() {
    let c = ellipse(12, 4.0, 3.0, 0.0, p(5., 5.));
    let e = ellipse(12, 3.0, 4.0, 0.0, p(5., 5.));
    let (a, b) = (
        curve("boundary", true, c.clone()),
        curve("boundary", true, e.clone()),
    );
    let opts = CorrespondenceOptions::default().with_density(3.0);
    let tol = tol();
    let pair = correspond(&a, &b, &[], &tol, &opts).unwrap();
    let fine = Tolerances {
        max_edge: tol.max_edge / 3.0,
        ..tol
    };
    check_pair(&pair, &c, &e, &fine);
    let coarse = correspond(&a, &b, &[], &tol, &CorrespondenceOptions::default()).unwrap();
    assert!(pair.source.len() > 2 * coarse.source.len());
}

/// A star-shaped polygon around `centre`: radii at increasing angles.
fn star(centre: Point, radii: &[f64], phase: f64, clockwise: bool) -> Vec<Point> {
    let n = radii.len();
    let mut pts: Vec<Point> = radii
        .iter()
        .enumerate()
        .map(|(k, &r)| {
            let t = phase + TAU * k as f64 / n as f64;
            centre + p(r * t.cos(), r * t.sin())
        })
        .collect();
    if clockwise {
        pts.reverse();
    }
    pts
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
    #[test]
    fn random_star_polygons_correspond(
        ra in prop::collection::vec(0.5f64..3.0, 3..40),
        rb in prop::collection::vec(0.5f64..3.0, 3..40),
        phase in 0.0f64..TAU,
        cw_a in any::<bool>(),
        cw_b in any::<bool>(),
    ) {
        let tol = tol();
        let a = star(p(5., 5.), &ra, 0.0, cw_a);
        let b = star(p(4., 6.), &rb, phase, cw_b);
        let opts = CorrespondenceOptions::default();
        let pair = correspond(&curve("boundary", true, a.clone()), &curve("boundary", true, b.clone()), &[], &tol, &opts).unwrap();
        check_pair(&pair, &a, &b, &tol);
        let again = correspond(&curve("boundary", true, a), &curve("boundary", true, b), &[], &tol, &opts).unwrap();
        prop_assert_eq!(pair, again);
    }
}

#[test]
fn an_anchor_picks_which_corner_goes_where() {
    let tol = tol();
    let sq_corners = [p(1., 1.), p(4., 1.), p(4., 4.), p(1., 4.)];
    let dia_corners = [p(5., 2.), p(7., 4.), p(5., 6.), p(3., 4.)];
    let sq = dense_polygon(&sq_corners, 5);
    let dia = dense_polygon(&dia_corners, 4);
    let opts = CorrespondenceOptions::default();
    for shift in 0..4 {
        let pin = [(sq_corners[0], dia_corners[shift])];
        let pair = correspond(
            &curve("boundary", true, sq.clone()),
            &curve("boundary", true, dia.clone()),
            &pin,
            &tol,
            &opts,
        )
        .unwrap();
        check_pair(&pair, &sq, &dia, &tol);
        assert_eq!((pair.source[0], pair.target[0]), pin[0]);
        // The other corners follow in order, each associated with a corner.
        for (k, c) in sq_corners.iter().enumerate() {
            let i = pair.source.iter().position(|q| q == c).unwrap();
            assert!(pair.salient.contains(&i));
            assert_eq!(pair.target[i], dia_corners[(k + shift) % 4]);
        }
    }
}

#[test]
fn open_zigzags_match_corner_to_corner() {
    let tol = tol();
    let zig: Vec<Point> = (0..6)
        .map(|k| p(1.0 + k as f64, if k % 2 == 0 { 2.0 } else { 3.0 }))
        .collect();
    // The target: stretched unevenly and drawn densely, so its corners sit elsewhere in arc length.
    let corners: Vec<Point> = [0.0, 0.7, 2.2, 2.9, 4.6, 5.2]
        .iter()
        .enumerate()
        .map(|(k, &x)| p(2.0 + x, if k % 2 == 0 { 5.0 } else { 6.5 }))
        .collect();
    let mut tgt = Vec::new();
    for w in corners.windows(2) {
        for j in 0..3 {
            tgt.push(w[0] + (w[1] - w[0]) * (j as f64 / 3.0));
        }
    }
    tgt.push(corners[5]);
    let pair = correspond(
        &curve("feature-zig", false, zig.clone()),
        &curve("feature-zig", false, tgt.clone()),
        &[],
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &zig, &tgt, &tol);
    assert_eq!(pair.salient.len(), 6);
    for (k, c) in zig.iter().enumerate() {
        let i = pair.source.iter().position(|q| q == c).unwrap();
        assert_eq!(pair.target[i], corners[k], "corner {k}");
    }
}

/// Random open polylines in the drawing's box; `tiny` repeats some points a hair away.
fn open_polyline(raw: &[(f64, f64, bool)]) -> Vec<Point> {
    let mut pts: Vec<Point> = Vec::new();
    for &(x, y, tiny) in raw {
        let q = p(x, y);
        if pts.last().is_some_and(|l| l.distance(q) < 1e-3) {
            continue;
        }
        pts.push(q);
        if tiny {
            pts.push(q + p(1e-7, -1e-7));
        }
    }
    pts
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
    #[test]
    fn random_open_curves_correspond(
        ra in prop::collection::vec((0.0f64..10.0, 0.0f64..8.0, prop::bool::weighted(0.2)), 2..30),
        rb in prop::collection::vec((0.0f64..10.0, 0.0f64..8.0, prop::bool::weighted(0.2)), 2..30),
    ) {
        let (a, b) = (open_polyline(&ra), open_polyline(&rb));
        prop_assume!(a.len() >= 2 && b.len() >= 2);
        let tol = tol();
        let pair = correspond(&curve("feature-f", false, a.clone()), &curve("feature-f", false, b.clone()), &[], &tol, &CorrespondenceOptions::default()).unwrap();
        check_pair(&pair, &a, &b, &tol);
        let (first, last) = (pair.target[0], *pair.target.last().unwrap());
        prop_assert!((first == b[0] && last == *b.last().unwrap()) || (last == b[0] && first == *b.last().unwrap()));
        prop_assert_eq!(pair.source[0], a[0]);
    }

    #[test]
    fn one_anchor_on_random_stars_is_honoured(
        ra in prop::collection::vec(0.5f64..3.0, 3..30),
        rb in prop::collection::vec(0.5f64..3.0, 3..30),
        ia in 0usize..1000,
        ib in 0usize..1000,
        ta in 0.0f64..1.0,
    ) {
        let tol = tol();
        let a = star(p(5., 5.), &ra, 0.0, false);
        let b = star(p(5., 5.), &rb, 0.3, true);
        let (i, j) = (ia % a.len(), ib % b.len());
        let pa = a[i] + (a[(i + 1) % a.len()] - a[i]) * ta;
        let pin = [(pa, b[j])];
        let pair = correspond(&curve("boundary", true, a.clone()), &curve("boundary", true, b.clone()), &pin, &tol, &CorrespondenceOptions::default()).unwrap();
        check_pair(&pair, &a, &b, &tol);
        prop_assert!(pair.source[0].distance(pa) < 1e-9);
        prop_assert_eq!(pair.target[0], b[j]);
    }
}

#[test]
fn a_tiny_part_pinned_to_a_long_one_keeps_its_points_apart() {
    let tol = tol();
    let src = vec![p(0., 0.), p(10., 0.)];
    let tgt = vec![p(-5., 5.), p(5., 5.), p(5. + 1e-7, 5.), p(15., 5.)];
    // Anchors pin a source piece of length 1e-5 to the target's whole middle (length 10).
    let pins = [(p(5., 0.), p(0., 5.)), (p(5. + 1e-5, 0.), p(10., 5.))];
    let pair = correspond(
        &curve("feature-f", false, src.clone()),
        &curve("feature-f", false, tgt.clone()),
        &pins,
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &src, &tgt, &tol);
    assert_eq!(pair.salient.len(), 4);
}

#[test]
fn a_similar_copy_corresponds_vertex_to_vertex_even_half_turned() {
    let tol = tol();
    let radii = [2.0, 1.1, 2.6, 0.9, 1.8, 1.7, 0.6, 2.9, 1.2, 1.5, 2.2, 0.8];
    let src = star(p(5., 5.), &radii, 0.2, false);
    // Turned by 170°, scaled by 0.7, moved, and started at another vertex.
    let (c, s) = (
        170f64.to_radians().cos() * 0.7,
        170f64.to_radians().sin() * 0.7,
    );
    let map = |q: Point| p(c * q.x - s * q.y + 1.0, s * q.x + c * q.y + 9.0);
    let mut tgt: Vec<Point> = src.iter().map(|&q| map(q)).collect();
    tgt.rotate_left(7);
    let pair = correspond(
        &curve("boundary", true, src.clone()),
        &curve("boundary", true, tgt.clone()),
        &[],
        &tol,
        &CorrespondenceOptions::default(),
    )
    .unwrap();
    check_pair(&pair, &src, &tgt, &tol);
    for (a, b) in pair.source.iter().zip(&pair.target) {
        assert!(
            map(*a).distance(*b) < 1e-9,
            "{a} went to {b}, not {}",
            map(*a)
        );
    }
}

#[test]
fn a_feature_whose_twin_is_misspelt_names_it() {
    let tol = tol();
    let opts = CorrespondenceOptions::default();
    let b = curve(
        "boundary",
        true,
        vec![p(0., 0.), p(10., 0.), p(10., 8.), p(0., 8.)],
    );
    let line = vec![p(2., 2.), p(3., 3.)];
    let stripe = |n: &str| curve(&format!("feature-stripe-{n}"), false, line.clone());
    // stripe-3 and stripe-4 (one letter apart) are each other's near names only when
    // neither has a twin: the matched stripe-1 is never offered.
    let src = controls(b.clone(), vec![stripe("1"), stripe("3")], vec![]);
    let tgt = controls(b.clone(), vec![stripe("1"), stripe("4")], vec![]);
    let e = correspond_all("a.svg", &src, "b.svg", &tgt, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("feature-stripe-3 is in a.svg but not in b.svg")
            && e.contains("b.svg has 'feature-stripe-4' instead"),
        "{e}"
    );
    let tgt = controls(b.clone(), vec![stripe("1")], vec![]);
    let e = correspond_all("a.svg", &src, "b.svg", &tgt, &tol, &opts)
        .unwrap_err()
        .to_string();
    assert!(e.contains("hint: add feature-stripe-3 to b.svg"), "{e}");
    // One file with a boundary, the other with none.
    let mut plain = controls(b.clone(), vec![], vec![]);
    plain.boundary_from_view_box = true;
    let e = correspond_all(
        "a.svg",
        &controls(b, vec![], vec![]),
        "b.svg",
        &plain,
        &tol,
        &opts,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("b.svg: has no 'boundary' element, but a.svg has one"),
        "{e}"
    );
}

#[test]
fn correspondences_kept_from_an_earlier_rung_give_what_making_them_anew_gives() {
    // Automatic mode's ladder: the outline with three holes, then the same with the middle
    // hole given up and the others renamed.
    let tol = tol();
    let opts = CorrespondenceOptions::default();
    let b_src = curve("boundary", true, ellipse(64, 4.0, 3.0, 0.0, p(5., 5.)));
    let b_tgt = curve("boundary", true, ellipse(64, 3.6, 3.2, 0.3, p(5.5, 5.)));
    let hole = |k: usize, c: Point, r: f64| {
        curve(
            &format!("feature-hole-{k}"),
            true,
            ellipse(20, r, 0.6 * r, 0.0, c),
        )
    };
    let src_holes = [(p(3., 5.), 0.7), (p(5., 6.), 0.5), (p(7., 5.), 0.6)];
    let tgt_holes = [(p(3.5, 5.), 0.6), (p(5.5, 6.2), 0.5), (p(7.2, 4.8), 0.7)];
    let rung = |keep: &[usize]| {
        let side = |b: &ControlCurve, hs: &[(Point, f64)]| {
            let features = keep
                .iter()
                .enumerate()
                .map(|(k, &h)| hole(k, hs[h].0, hs[h].1))
                .collect();
            controls(b.clone(), features, Vec::new())
        };
        (side(&b_src, &src_holes), side(&b_tgt, &tgt_holes))
    };
    let made = &mut Correspondences::default();
    let (s1, t1) = rung(&[0, 1, 2]);
    let first = correspond_all_reusing("a.svg", &s1, "b.svg", &t1, &tol, &opts, made).unwrap();
    assert_eq!(
        first,
        correspond_all("a.svg", &s1, "b.svg", &t1, &tol, &opts).unwrap()
    );
    let counts = made.counts();
    assert!(counts.0 >= 4 && counts.1 >= 3, "{counts:?}");
    let (s2, t2) = rung(&[0, 2]);
    let second = correspond_all_reusing("a.svg", &s2, "b.svg", &t2, &tol, &opts, made).unwrap();
    // Nothing made anew, and the same pairs as made from scratch, under the new names.
    assert_eq!(made.counts(), counts);
    assert_eq!(
        second,
        correspond_all("a.svg", &s2, "b.svg", &t2, &tol, &opts).unwrap()
    );
    let ids: Vec<&str> = second.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["boundary", "feature-hole-0", "feature-hole-1"]);
    // A hole moved by the smallest step is another curve: made anew.
    let (mut s3, t3) = rung(&[0, 2]);
    let q = &mut s3.features[1].points[3];
    q.x = f64::from_bits(q.x.to_bits() + 1);
    correspond_all_reusing("a.svg", &s3, "b.svg", &t3, &tol, &opts, made).unwrap();
    assert!(made.counts().0 > counts.0);
}
