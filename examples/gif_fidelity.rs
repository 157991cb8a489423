//! Prints, for fixture pairs, how faithfully the morph's GIF shows its frames (mean ΔEOK per
//! covered pixel, plain and averaged over 5 × 5 pixels: `crmorph::export::gif_fidelity`) and
//! the GIF's size, for the morph `crmorph morph SRC TGT -o x.gif` writes (60 frames, 2 s, the
//! drawing's own size, over white). Run:
//! `cargo run --release --example gif_fidelity [NAME…]`, where each NAME is a folder under
//! fixtures/ (default: the gradient pairs in fixtures/gradients/ and every top-level pair).

use std::path::{Path, PathBuf};

use crmorph::artwork::Scene;
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::export::{encode_gif, gif_fidelity, Morph, Timeline};
use crmorph::render::FrameOptions;
use crmorph::rigid::Method;

/// Folders under `root` holding a source.svg and a target.svg, sorted.
fn pairs_in(root: &Path) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|d| d.join("source.svg").exists() && d.join("target.svg").exists())
        .collect();
    dirs.sort();
    dirs
}

/// The morph the CLI builds for a marked-up pair (disc method, paths that are their own
/// boundary or feature curve morphing as one shape).
fn morph_of(dir: &Path) -> Morph {
    let o = ReadOptions::default();
    let read = |f: &str| {
        let d = Drawing::open(&dir.join(f), &o).unwrap_or_else(|e| panic!("{e}"));
        let s = Scene::from_svg_in(&d.file, &d.svg, "controls", Some(dir)).unwrap();
        (d, s)
    };
    let ((s, ss), (t, ts)) = (read("source.svg"), read("target.svg"));
    let c = build(&s, &t, &MorphOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let interp = c.interpolator(Method::Disc).unwrap();
    let paths = crmorph::morphing::named_morphing_paths(&ss, &ts, &c);
    let frame = FrameOptions::for_scene(&ss);
    Morph::with_morphing_paths(c.meshes, interp, &ss, &ts, frame, paths).unwrap()
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let names: Vec<String> = std::env::args().skip(1).collect();
    let dirs = if names.is_empty() {
        let mut v = pairs_in(&root.join("gradients"));
        v.extend(pairs_in(&root));
        v
    } else {
        names.iter().map(|n| root.join(n)).collect()
    };
    println!(
        "{:28} {:>9} {:>9} {:>10}",
        "pair", "ΔE mean", "ΔE 5×5", "GIF bytes"
    );
    for dir in dirs {
        let m = morph_of(&dir);
        let tl = Timeline::default();
        let frames = m.pixmap_frames(&tl).unwrap();
        let gif = encode_gif(&frames, &tl, None).unwrap();
        let f = gif_fidelity(&gif, &frames, &tl, None).unwrap();
        let name = dir
            .strip_prefix(&root)
            .unwrap_or(&dir)
            .display()
            .to_string();
        println!(
            "{name:28} {:9.4} {:9.4} {:10}",
            f.mean_delta_e,
            f.mean_smoothed_delta_e,
            gif.len()
        );
    }
}
