//! Bad input gives one located line, never a panic (DESIGN.md §3, §5 invariant 5).

use crate::common::fixtures;
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};

fn read_err(name: &str) -> String {
    let p = fixtures().join("errors").join(name);
    match Drawing::open(&p, &ReadOptions::default()) {
        Ok(_) => panic!("{name} was accepted"),
        Err(e) => {
            let s = e.to_string();
            assert!(e.is_input(), "{name}: {s}");
            assert!(!s.contains('\n'), "{name}: {s}");
            assert!(
                s.contains(name),
                "{name}: the message does not name the file: {s}"
            );
            s
        }
    }
}

#[test]
fn each_bad_file_is_named_with_its_problem() {
    let cases = [
        ("open-boundary.svg", "not closed"),
        ("self-crossing-boundary.svg", "crosses itself"),
        ("degenerate-boundary.svg", "no area"),
        ("feature-outside.svg", "feature-"),
        ("features-cross.svg", "crosses"),
        ("nan-coords.svg", "boundary"),
        ("truncated.svg", "truncated"),
        ("not-svg.svg", "not an SVG"),
        ("empty.svg", "empty"),
    ];
    for (file, expected) in cases {
        let e = read_err(file);
        assert!(
            e.contains(expected),
            "{file}: expected '{expected}' in: {e}"
        );
    }
}

#[test]
fn crossing_features_are_both_in_the_error_as_data() {
    // What code decides on (automatic mode gives up a feature the failure concerns): the two
    // ids as data, the element first, not only in the message.
    let p = fixtures().join("errors/features-cross.svg");
    let e = Drawing::open(&p, &ReadOptions::default()).unwrap_err();
    let mut curves = e.curves().to_vec();
    curves.sort();
    assert_eq!(curves, ["feature-a", "feature-b"], "{e}");
    assert_eq!(e.kind(), Some(crmorph::ProblemKind::Crossing), "{e}");
    // Other problems are of other kinds: a missing file is neither a curve nor a crossing.
    let missing = Drawing::open(
        &fixtures().join("errors/no-such-file.svg"),
        &ReadOptions::default(),
    );
    assert_eq!(
        missing.unwrap_err().kind(),
        Some(crmorph::ProblemKind::Other)
    );
    // A curve unusable in itself.
    let own = Drawing::open(
        &fixtures().join("errors/self-crossing-boundary.svg"),
        &ReadOptions::default(),
    );
    assert_eq!(own.unwrap_err().kind(), Some(crmorph::ProblemKind::Element));
}

#[test]
fn a_feature_in_one_file_only_is_named() {
    let o = ReadOptions::default();
    let a = Drawing::open(&fixtures().join("errors/square.svg"), &o).unwrap();
    let b = Drawing::open(&fixtures().join("errors/square-no-line.svg"), &o).unwrap();
    for (s, t) in [(&a, &b), (&b, &a)] {
        let e = build(s, t, &MorphOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("feature-line"), "{e}");
        assert!(!e.contains('\n'));
    }
}
