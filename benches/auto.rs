//! Automatic-mode set-up on the random icon corpus sample (issue 16): for each of the 40 pairs
//! of `fixtures/corpus/pairs.json` (drawn at random with seed 2026, not picked by hand), the
//! time from the two files' text to the compatible meshes — both drawings read, their artwork
//! scenes, then `auto::build_auto` (contours, shape matching, one triangulation per shape, the
//! fold checks) — in-process, one thread's work as the CLI does it.
//!
//! Run: `cargo bench --bench auto -- --warm-up-time 0.5 --measurement-time 1`, then
//! `python3 tools/bench/auto-setup.py` for the median, 90th and 99th percentile and maximum over
//! the pairs (criterion's median per pair).

use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};
use crmorph::artwork::Scene;
use crmorph::auto::build_auto;
use crmorph::compatible::MorphOptions;
use crmorph::drawing::{Drawing, ReadOptions};
use std::hint::black_box;

/// The corpus sample's pairs: id, source file, target file.
fn corpus_pairs() -> Vec<(String, PathBuf, PathBuf)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/corpus");
    let text = std::fs::read_to_string(dir.join("pairs.json")).expect("fixtures/corpus/pairs.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("pairs.json is JSON");
    v["pairs"]
        .as_array()
        .expect("a pairs array")
        .iter()
        .map(|p| {
            let field = |k: &str| p[k].as_str().expect("string fields").to_string();
            (
                field("id"),
                dir.join(field("source")),
                dir.join(field("target")),
            )
        })
        .collect()
}

/// Reads one drawing and its artwork scene from `text`, as the CLI does.
fn read(path: &Path, text: &str) -> (Drawing, Scene) {
    let name = path.display().to_string();
    let d = Drawing::from_str(&name, text, &ReadOptions::default()).expect("corpus icons read");
    let s = Scene::from_svg_in(&name, text, "controls", path.parent()).expect("scene");
    (d, s)
}

fn auto_setup(c: &mut Criterion) {
    let mut g = c.benchmark_group("auto-setup");
    g.sample_size(10);
    for (id, s, t) in corpus_pairs() {
        let (st, tt) = (
            std::fs::read_to_string(&s).expect("source icon"),
            std::fs::read_to_string(&t).expect("target icon"),
        );
        g.bench_function(&id, |b| {
            b.iter(|| {
                let (sd, ss) = read(&s, black_box(&st));
                let (td, ts) = read(&t, black_box(&tt));
                build_auto(&sd, &td, &ss, &ts, &MorphOptions::default()).expect("auto mode")
            })
        });
    }
    g.finish();
}

criterion_group!(benches, auto_setup);
criterion_main!(benches);
