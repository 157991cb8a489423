//! The pipeline the fuzz target drives and the regression corpus replays: reading → mesh → one
//! frame, in-process, through the front door the CLI uses ([`crmorph::Morpher`]: automatic
//! mode for unmarked pairs, marked-up mode otherwise, the view fitted; the frame at t = ½ as
//! SVG and as a small PNG).
//!
//! Shared by `tests/integration/hostile.rs` and `fuzz/fuzz_targets/pipeline.rs` (included by
//! path), so that what the fuzzer found is replayed exactly by the tests.

use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::Morpher;

/// The target used when a fuzz input holds one drawing only.
pub(crate) const CIRCLE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><circle cx="50" cy="50" r="30" fill="blue"/></svg>"#;

/// Splits a fuzz input into the source and target drawings: at the first NUL byte, else the
/// whole input morphs into [`CIRCLE`].
pub(crate) fn split(data: &[u8]) -> (&[u8], &[u8]) {
    match data.iter().position(|&b| b == 0) {
        Some(k) => (&data[..k], &data[k + 1..]),
        None => (data, CIRCLE.as_bytes()),
    }
}

/// Limits small enough that a fuzz case stays quick, as a batch server would set them.
pub(crate) fn options() -> ReadOptions {
    let mut opts = ReadOptions::default();
    opts.policy.limits.input_bytes = 1 << 20;
    opts.policy.limits.elements = 2_000;
    opts.policy.limits.segments = 20_000;
    opts.policy.limits.vertices = 20_000;
    opts.policy.limits.pixels = 1 << 16;
    opts.policy.limits.shapes = 50;
    opts
}

/// Runs the pipeline on one pair. `Ok` when it morphed, `Err` with the one-line input error
/// otherwise. An internal error or a panic is a finding (the caller decides).
pub(crate) fn morph_once(source: &[u8], target: &[u8]) -> crmorph::Result<()> {
    let opts = options();
    let read = |name: &str, bytes: &[u8]| -> crmorph::Result<Drawing> {
        let text = crmorph::input::decode(name, bytes, &opts.policy.limits)?;
        Drawing::from_str(name, &text, &opts)
    };
    let (s, t) = (read("source.svg", source)?, read("target.svg", target)?);
    // The CLI's own path, through the front door; frames small, as a server would make them.
    let morph = Morpher::new(s, t)
        .size(Some((64, 64)))
        .raster(true)
        .build()?;
    morph.svg_at(0.5)?;
    morph.pixmap_at(0.5)?;
    Ok(())
}
