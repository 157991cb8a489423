//! Making an animation from Rust: two marked-up SVG drawings in, an animated SVG and a GIF out,
//! through the same stages the CLI runs (read → compatible triangulation → disc interpolation
//! → artwork bound to the meshes → exporters).
//!
//! Run: `cargo run --release --example animate [SOURCE.svg TARGET.svg] [OUT_DIR]` (default:
//! the bundled gourd, into `./crmorph-animate/`).

use std::path::{Path, PathBuf};

use crmorph::artwork::Scene;
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::export::{Easing, Morph, Playback, Timeline};
use crmorph::render::FrameOptions;
use crmorph::rigid::Method;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/gourd");
    let (src, tgt) = match args.as_slice() {
        [s, t, ..] => (PathBuf::from(s), PathBuf::from(t)),
        _ => (fixtures.join("source.svg"), fixtures.join("target.svg")),
    };
    let out = PathBuf::from(args.get(2).map_or("crmorph-animate", String::as_str));

    // 1. The control geometry of both drawings (boundary, feature curves, anchors).
    let s = Drawing::open(&src, &ReadOptions::default())?;
    let t = Drawing::open(&tgt, &ReadOptions::default())?;
    // 2. Compatible triangulations: the source's mesh carried onto the target (§3, §5).
    let c = build(&s, &t, &MorphOptions::default())?;
    // 3. The disc-based rigid interpolation, factored once (§4.1).
    let interp = c.interpolator(Method::Disc)?;
    // 4. The artwork of both files, bound to the meshes; the paths that are their own boundary
    //    or feature curve morph as one shape instead of cross-fading.
    let (ss, ts) = (
        Scene::from_svg(&s.file, &s.svg, "controls")?,
        Scene::from_svg(&t.file, &t.svg, "controls")?,
    );
    let paths = crmorph::morphing::named_morphing_paths(&ss, &ts, &c);
    let frame = FrameOptions::for_scene(&ss);
    let morph = Morph::with_morphing_paths(c.meshes, interp, &ss, &ts, frame, paths)?;
    // 5. One timeline for every exporter: 48 frames over 1.5 s, eased, back and forth.
    let timeline = Timeline {
        frames: 48,
        duration: 1.5,
        easing: Easing::EaseInOut,
        playback: Playback::Yoyo,
    };
    std::fs::create_dir_all(&out)?;
    std::fs::write(out.join("morph.svg"), morph.animated_svg(&timeline)?)?;
    std::fs::write(out.join("morph.gif"), morph.gif(&timeline)?)?;
    println!(
        "{} → {}: {} vertices, {} triangles; wrote {}/morph.svg and morph.gif",
        src.display(),
        tgt.display(),
        morph.meshes().source.len(),
        morph.meshes().triangles.len(),
        out.display()
    );
    Ok(())
}
