//! Property tests of automatic mode over generated outlines: random star-shaped and non-convex
//! polygons, with and without holes. Whatever the pair, it morphs as one shape: compatible meshes
//! with no inverted triangle at either end or in any frame, exact ends, every hole either aligned,
//! carried or closing, and a morphing path drawing it.

use super::*;
use crate::mesh::{count_inverted, sanity_check};
use proptest::prelude::*;

/// A closed star-shaped polygon about (50, 50): `radii` evenly spaced by angle (so non-convex
/// wherever they vary), turned by `phase`, as SVG path data.
fn star(radii: &[f64], phase: f64, scale: f64) -> String {
    let n = radii.len();
    let mut d = String::new();
    for (k, r) in radii.iter().enumerate() {
        let a = std::f64::consts::TAU * k as f64 / n as f64 + phase;
        let (x, y) = (50.0 + scale * r * a.cos(), 50.0 + scale * r * a.sin());
        d.push_str(&format!("{}{x:.4} {y:.4} ", if k == 0 { "M" } else { "L" }));
    }
    d.push('Z');
    d
}

/// A small square hole about (50, 50) of half-side `h`, wound against the outline.
fn hole(h: f64) -> String {
    format!(
        "M{} {} L{} {} L{} {} L{} {} Z",
        50.0 - h,
        50.0 - h,
        50.0 - h,
        50.0 + h,
        50.0 + h,
        50.0 + h,
        50.0 + h,
        50.0 - h
    )
}

fn drawing(name: &str, d: &str) -> (Drawing, Scene) {
    let svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 100 100"><path fill-rule="evenodd" fill="#123" d="{d}"/></svg>"##
    );
    let o = crate::drawing::ReadOptions::default();
    (
        Drawing::from_str(name, &svg, &o).unwrap(),
        Scene::from_svg(name, &svg, "controls").unwrap(),
    )
}

fn check(a: &str, b: &str) -> std::result::Result<(), TestCaseError> {
    let (ds, ss) = drawing("a.svg", a);
    let (dt, ts) = drawing("b.svg", b);
    let (c, report, _, _) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default())
        .map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(report.shapes.len(), 1, "{}", report);
    prop_assert_eq!(report.morphing.len(), 1, "{}", report);
    let m = &c.meshes;
    let r = sanity_check(m, None, 0.0);
    prop_assert!(r.is_ok(), "{:?}", r);
    let interp = c.interpolator(crate::rigid::Method::Disc).unwrap();
    let diag = c.tolerances.diagonal;
    for k in 0..=16 {
        let t = k as f64 / 16.0;
        let v = interp.at_vec(t);
        prop_assert_eq!(count_inverted(&m.triangles, &v), 0, "t = {}: {}", t, report);
        let end = match k {
            0 => Some(&m.source),
            16 => Some(&m.target),
            _ => None,
        };
        if let Some(end) = end {
            let off = v
                .iter()
                .zip(end)
                .map(|(p, q)| p.distance(*q))
                .fold(0.0, f64::max);
            prop_assert!(off < 1e-9 * diag, "t = {}: {} off the end", t, off);
        }
        // The morphing path has the outline and, where there are holes, their rings.
        let path = report.morphing[0].at(m, &v, t);
        prop_assert!(crate::artwork::subpath_count(&path.path) >= 1);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn random_star_shapes_morph_as_one_shape(
        a in proptest::collection::vec(0.45f64..1.0, 5..14),
        b in proptest::collection::vec(0.45f64..1.0, 5..14),
        phase in -3.2f64..3.2,
        scale in 20.0f64..45.0,
        holes in 0usize..4,
    ) {
        // holes: 0 none, 1 source only (closes), 2 target only (opens), 3 both (paired).
        let (mut da, mut db) = (star(&a, 0.0, 40.0), star(&b, phase, scale));
        if holes & 1 == 1 {
            da = format!("{da} {}", hole(6.0));
        }
        if holes & 2 == 2 {
            db = format!("{db} {}", hole(0.15 * scale));
        }
        check(&da, &db)?;
    }
}
