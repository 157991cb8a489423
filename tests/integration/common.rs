//! Fixture discovery and shared helpers.

use crmorph::Side;
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
    o.triangulated = if from_target {
        Side::Target
    } else {
        Side::Source
    };
    build(s, t, &o).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders the SVG file `file` with resvg at the size of `got` and counts the pixels of `got`
/// that differ from it by more than 8 in any channel: `(differing, total)`. How a frame at
/// t = 0 or t = 1 compares with the input drawing itself.
pub(crate) fn pixels_off_input(file: &Path, got: &tiny_skia::Pixmap) -> (usize, usize) {
    let text = std::fs::read_to_string(file).unwrap();
    let o = usvg::Options {
        resources_dir: file.parent().map(Path::to_path_buf),
        ..Default::default()
    };
    let tree = usvg::Tree::from_str(&text, &o).unwrap();
    let mut want = tiny_skia::Pixmap::new(got.width(), got.height()).unwrap();
    let sx = got.width() as f32 / tree.size().width();
    let sy = got.height() as f32 / tree.size().height();
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(sx, sy),
        &mut want.as_mut(),
    );
    let bad = want
        .pixels()
        .iter()
        .zip(got.pixels())
        .filter(|(a, b)| {
            a.red().abs_diff(b.red()) > 8
                || a.green().abs_diff(b.green()) > 8
                || a.blue().abs_diff(b.blue()) > 8
                || a.alpha().abs_diff(b.alpha()) > 8
        })
        .count();
    (bad, want.pixels().len())
}

/// A drawing's artwork, guides in its `controls` group left out, resources beside the file.
pub(crate) fn scene_of(p: &Path) -> crmorph::artwork::Scene {
    crmorph::artwork::Scene::from_svg_in(
        &p.display().to_string(),
        &std::fs::read_to_string(p).unwrap(),
        "controls",
        p.parent(),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}
