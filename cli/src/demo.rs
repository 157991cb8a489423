//! `crmorph` with no arguments: morph the bundled gourd fixture into `./crmorph-demo/`.

use std::path::Path;

use anyhow::{Context, Result};
use crmorph::artwork::{ArtworkPair, Rgba, Scene};
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::render::{frame_png, frame_svg, FrameOptions};
use crmorph::rigid::{Interpolator, Method};

use crate::output::write_atomic;
use crate::progress::Progress;

const SOURCE: &str = include_str!("../../fixtures/gourd/source.svg");
const TARGET: &str = include_str!("../../fixtures/gourd/target.svg");
const FRAMES: usize = 60;
/// Rendered frames written as PNG (t = i / (RENDERED − 1)).
const RENDERED: usize = 9;

/// Runs the demo into `dir`, and returns a summary for stdout.
pub(crate) fn run(dir: &Path, progress: &Progress) -> Result<String> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the folder", dir.display()))?;
    let opts = ReadOptions::default();
    progress.stage("reading the bundled gourd");
    let s = Drawing::from_str("gourd/source.svg", SOURCE, &opts)?;
    let t = Drawing::from_str("gourd/target.svg", TARGET, &opts)?;
    progress.stage("compatible triangulation");
    let c = build(&s, &t, &MorphOptions::default())?;
    progress.stage("interpolation");
    let m = &c.meshes;
    let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles)?;
    let ts: Vec<f64> = (0..FRAMES)
        .map(|i| i as f64 / (FRAMES - 1) as f64)
        .collect();
    let frames = interp.frames(&ts);
    progress.stage("writing");
    write_atomic(&dir.join("source.svg"), SOURCE.as_bytes())?;
    write_atomic(&dir.join("target.svg"), TARGET.as_bytes())?;
    write_atomic(
        &dir.join("inspect.svg"),
        crmorph::inspect::inspect_svg(&c).as_bytes(),
    )?;
    write_atomic(
        &dir.join("meshes.json"),
        crmorph::json::meshes_json(m).as_bytes(),
    )?;
    write_atomic(
        &dir.join("frames.json"),
        crmorph::json::frames_json(m, &ts, &frames).as_bytes(),
    )?;
    progress.stage("rendering frames");
    let ss = Scene::from_svg("gourd/source.svg", SOURCE, "controls")?;
    let ts = Scene::from_svg("gourd/target.svg", TARGET, "controls")?;
    let mut opts = FrameOptions::for_scene(&ss);
    opts.background = Some(Rgba {
        r: 255,
        g: 255,
        b: 255,
        a: 255,
    });
    let pair = ArtworkPair::new(&ss, &ts, m, opts.flatten_tolerance())?;
    let frames_dir = dir.join("frames");
    std::fs::create_dir_all(&frames_dir)
        .with_context(|| format!("{}: cannot create the folder", frames_dir.display()))?;
    for i in 0..RENDERED {
        let t = i as f64 / (RENDERED - 1) as f64;
        let (sw, tw) = pair.at(&interp.at_vec(t))?;
        write_atomic(
            &frames_dir.join(format!("frame_{i:03}.png")),
            &frame_png(&sw, &tw, t, &opts)?,
        )?;
        if i == RENDERED / 2 {
            write_atomic(
                &dir.join("middle.svg"),
                frame_svg(&sw, &tw, t, &opts)?.as_bytes(),
            )?;
        }
    }
    let inverted: usize = frames
        .iter()
        .map(|f| crmorph::mesh::count_inverted(&m.triangles, f))
        .sum();
    Ok(format!(
        "crmorph demo: gourd in the air -> on the ground\n\
         compatible triangulation: {} vertices, {} triangles, {} curves, {} mapping steps\n\
         {} frames interpolated, {} inverted triangles\n\
         wrote {}/{{source.svg, target.svg, inspect.svg, meshes.json, frames.json, middle.svg, frames/frame_000..008.png}}",
        m.source.len(),
        m.triangles.len(),
        m.curves.len(),
        c.stats.steps,
        FRAMES,
        inverted,
        dir.display()
    ))
}
