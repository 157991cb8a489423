//! `crmorph` with no arguments: morph the bundled gourd fixture into `./crmorph-demo/`.

use std::path::Path;

use anyhow::{Context, Result};
use crmorph::artwork::Rgba;
use crmorph::export::{Easing, Playback, Timeline};
use crmorph::render::encode_png;
use crmorph::Morpher;

use crate::output::write_atomic;
use crate::progress::Progress;

const SOURCE: &str = include_str!("../../fixtures/gourd/source.svg");
const TARGET: &str = include_str!("../../fixtures/gourd/target.svg");

/// The demo's animation: two seconds each way, eased, back and forth forever.
const TIMELINE: Timeline = Timeline {
    frames: 60,
    duration: 2.0,
    easing: Easing::EaseInOut,
    playback: Playback::Yoyo,
};

/// Runs the demo into `dir`, and returns a summary for stdout.
pub(crate) fn run(dir: &Path, progress: &Progress) -> Result<String> {
    let started = std::time::Instant::now();
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    progress.stage("reading the bundled gourd");
    let white = Rgba {
        r: 255,
        g: 255,
        b: 255,
        a: 255,
    };
    // The same front door as `crmorph morph`: the gourd's skin and leaf are their own
    // boundary and features, so they morph as one shape.
    let m = Morpher::from_svg(("gourd/source.svg", SOURCE), ("gourd/target.svg", TARGET))?
        .background(Some(white))
        .raster(true);
    let mut report = crate::commands::report(progress);
    let prepared = m.prepare(&mut report)?;
    let c = &prepared.compatible;
    let inspect = crmorph::inspect::inspect_svg(c);
    let (vertices, triangles, curves, steps) = (
        c.meshes.source.len(),
        c.meshes.triangles.len(),
        c.meshes.curves.len(),
        c.stats.steps,
    );
    let (morph, _) = m.finish(prepared, &mut report)?;
    let inverted: usize = morph
        .vertex_frames(&TIMELINE)
        .iter()
        .map(|f| crmorph::mesh::count_inverted(&morph.meshes().triangles, f))
        .sum();
    progress.stage("rendering");
    let svg = morph.animated_svg(&TIMELINE)?;
    let html = morph.html(&TIMELINE, "crmorph demo: gourd in the air → on the ground")?;
    let gif = morph.gif(&TIMELINE)?;
    let middle = encode_png(&morph.pixmap_at(0.5)?)?;
    let meshes = crmorph::json::meshes_json(morph.meshes());
    progress.stage("writing");
    let files: [(&str, &[u8]); 8] = [
        ("source.svg", SOURCE.as_bytes()),
        ("target.svg", TARGET.as_bytes()),
        ("morph.svg", svg.as_bytes()),
        ("morph.gif", &gif),
        ("morph.html", html.as_bytes()),
        ("middle.png", &middle),
        ("inspect.svg", inspect.as_bytes()),
        ("meshes.json", meshes.as_bytes()),
    ];
    for (name, bytes) in files {
        write_atomic(&dir.join(name), bytes)?;
    }
    Ok(format!(
        "crmorph demo: gourd in the air -> on the ground\n\
         compatible triangulation: {vertices} vertices, {triangles} triangles, {curves} curves, \
         {steps} mapping steps\n\
         {} frames, {inverted} inverted triangles, made in {:.2} s\n\
         wrote {}/: morph.svg (animated SVG, {} KiB), morph.gif ({} KiB), morph.html (preview), \
         middle.png, inspect.svg, meshes.json, source.svg, target.svg\n\
         open {}/morph.html in a browser to play, scrub and see the triangulation",
        TIMELINE.frames,
        started.elapsed().as_secs_f64(),
        dir.display(),
        svg.len() / 1024,
        gif.len() / 1024,
        dir.display(),
    ))
}
