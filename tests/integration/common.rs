//! Fixture discovery and shared helpers.

use std::path::{Path, PathBuf};

use crmorph::compatible::{build, Compatible, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};

/// The repository's fixtures folder.
pub(crate) fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures")
}

/// Every fixture pair: folders of fixtures/ holding source.svg and target.svg.
pub(crate) fn pairs() -> Vec<(String, PathBuf, PathBuf)> {
    let mut v = Vec::new();
    for e in std::fs::read_dir(fixtures()).unwrap() {
        let p = e.unwrap().path();
        let (s, t) = (p.join("source.svg"), p.join("target.svg"));
        if s.exists() && t.exists() {
            v.push((p.file_name().unwrap().to_string_lossy().into_owned(), s, t));
        }
    }
    v.sort();
    assert!(
        v.len() >= 4,
        "expected at least four fixture pairs, found {}",
        v.len()
    );
    v
}

/// Every fixture pair in both directions: `(name, source, target, from_target)`.
pub(crate) fn directions() -> Vec<(String, PathBuf, PathBuf, bool)> {
    pairs()
        .into_iter()
        .flat_map(|(n, s, t)| [false, true].map(|d| (n.clone(), s.clone(), t.clone(), d)))
        .collect()
}

/// Reads a drawing with default options, panicking with the error message on failure.
pub(crate) fn open(p: &Path) -> Drawing {
    Drawing::open(p, &ReadOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Builds the compatible triangulation of a pair.
pub(crate) fn compatible(s: &Drawing, t: &Drawing, from_target: bool) -> Compatible {
    let mut o = MorphOptions::default();
    o.from_target = from_target;
    build(s, t, &o).unwrap_or_else(|e| panic!("{e}"))
}
