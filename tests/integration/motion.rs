//! Invariants 1 and 2 of DESIGN.md §5 for the disc-based interpolation on every fixture.

use crate::common::{compatible, mappable_pairs, open};
use crmorph::mesh::count_inverted;
use crmorph::rigid::{Interpolator, Method};

#[test]
fn frames_are_exact_at_the_ends_and_never_inverted() {
    for (name, s, t, from_target) in mappable_pairs() {
        let (s, t) = (open(&s), open(&t));
        let c = compatible(&s, &t, from_target);
        let m = &c.meshes;
        let tol = 1e-9 * c.tolerances.diagonal;
        let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
        let ts: Vec<f64> = (0..=40).map(|i| i as f64 / 40.0).collect();
        let frames = interp.frames(&ts);
        for (p, q) in frames[0].iter().zip(&m.source) {
            assert!(
                p.distance(*q) <= tol,
                "{name}: t=0 off by {}",
                p.distance(*q)
            );
        }
        for (p, q) in frames[40].iter().zip(&m.target) {
            assert!(
                p.distance(*q) <= tol,
                "{name}: t=1 off by {}",
                p.distance(*q)
            );
        }
        // Known defect: the composite map leaves slivers on the leaf when mapping from the
        // butterfly, and one of them turns inside out between t ≈ 0.11 and 0.5.
        let allowed = if name == "leaf-to-butterfly" && from_target {
            1
        } else {
            0
        };
        let mut worst = 0;
        for (t, f) in ts.iter().zip(&frames) {
            let n = count_inverted(&m.triangles, f);
            assert!(n <= allowed, "{name}: {n} inverted triangles at t={t}");
            worst = worst.max(n);
        }
        assert_eq!(
            worst, allowed,
            "{name}: the known inversion is gone; update this test"
        );
    }
}

#[test]
fn a_half_turn_keeps_its_area_where_linear_interpolation_collapses() {
    // leaf → butterfly turns by about 180°; it maps when triangulated from the butterfly.
    use crmorph::quality::area;
    let d = crate::common::fixtures().join("leaf-to-butterfly");
    let (s, t) = (open(&d.join("source.svg")), open(&d.join("target.svg")));
    let c = compatible(&s, &t, true);
    let m = &c.meshes;
    let (a0, a1) = (area(&m.triangles, &m.source), area(&m.triangles, &m.target));
    let disc = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
    let linear = Interpolator::new(Method::Linear, &m.source, &m.target, &m.triangles).unwrap();
    for k in 0..=20 {
        let t = k as f64 / 20.0;
        let blend = (1.0 - t) * a0 + t * a1;
        let r = area(&m.triangles, &disc.at_vec(t)) / blend;
        assert!(
            (r - 1.0).abs() <= 0.10,
            "disc area at t={t} is {r:.3} of the blend"
        );
    }
    let r = area(&m.triangles, &linear.at_vec(0.5)) / (0.5 * (a0 + a1));
    assert!(
        r < 0.1,
        "linear interpolation should collapse the half turn, area ratio {r:.3}"
    );
}
