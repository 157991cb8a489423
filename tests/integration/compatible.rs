//! Invariants 1 and 3 of DESIGN.md §5 on every fixture, in both directions.

use crate::common::{compatible, directions, open, pairs};
use crmorph::mesh::sanity_check;

#[test]
fn every_fixture_gives_flip_free_compatible_meshes_in_both_directions() {
    for (name, s, t, from_target) in directions() {
        let (s, t) = (open(&s), open(&t));
        let c = compatible(&s, &t, from_target);
        let m = &c.meshes;
        let twins: Vec<_> = c.pairs.iter().map(|p| p.target.clone()).collect();
        let r = sanity_check(m, Some(&twins), 1e-9 * c.tolerances.diagonal);
        assert!(r.is_ok(), "{name} (from target: {from_target}): {r:?}");
        // the source side lands on the source curves too
        for (curve, pair) in m.curves.iter().zip(&c.pairs) {
            assert_eq!(
                curve.vertices.len(),
                pair.source.len(),
                "{name}: {}",
                curve.name
            );
            for (&v, &p) in curve.vertices.iter().zip(&pair.source) {
                assert!(m.source[v as usize].distance(p) <= 1e-9 * c.tolerances.diagonal);
            }
        }
        assert!(
            m.triangles.len() > 100,
            "{name}: only {} triangles",
            m.triangles.len()
        );
        assert_eq!(m.curves[0].name, "boundary");
    }
}

#[test]
fn features_are_matched_by_name_and_all_present() {
    for (name, s, t) in pairs() {
        let (s, t) = (open(&s), open(&t));
        let c = compatible(&s, &t, false);
        let names: Vec<_> = c.meshes.curves.iter().map(|c| c.name.clone()).collect();
        assert_eq!(names.len(), 1 + s.controls.features.len(), "{name}");
        for f in &s.controls.features {
            assert!(names.contains(&f.id), "{name}: {} missing", f.id);
        }
    }
}

#[test]
fn the_same_input_gives_identical_meshes() {
    let (name, s, t) = pairs().remove(0);
    let (s, t) = (open(&s), open(&t));
    let a = compatible(&s, &t, false);
    let b = compatible(&s, &t, false);
    assert_eq!(
        crmorph::json::meshes_json(&a.meshes),
        crmorph::json::meshes_json(&b.meshes),
        "{name}"
    );
}
