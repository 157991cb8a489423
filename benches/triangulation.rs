//! Criterion benchmark of the compatible triangulation (correspondence, CDT, composite harmonic
//! mapping) of every fixture, like the paper's Table 1. Run: `cargo bench --bench triangulation`.
//!
//! Besides criterion's timings it prints, once per fixture, the curve count, the mesh's vertex
//! count and the number of mapping steps.

use crmorph::Side;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};

fn fixtures() -> Vec<(String, Drawing, Drawing)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut v = Vec::new();
    let mut dirs: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    for d in dirs {
        let (s, t) = (d.join("source.svg"), d.join("target.svg"));
        if s.exists() && t.exists() {
            let o = ReadOptions::default();
            let name = d.file_name().unwrap().to_string_lossy().into_owned();
            v.push((
                name,
                Drawing::open(&s, &o).unwrap(),
                Drawing::open(&t, &o).unwrap(),
            ));
        }
    }
    v
}

fn compatible_triangulation(c: &mut Criterion) {
    let mut g = c.benchmark_group("compatible_triangulation");
    g.sample_size(20);
    for (name, s, t) in fixtures() {
        for from_target in [false, true] {
            let mut opts = MorphOptions::default();
            opts.triangulated = if from_target {
                Side::Target
            } else {
                Side::Source
            };
            let label = if from_target {
                format!("{name}(from-target)")
            } else {
                name.clone()
            };
            match build(&s, &t, &opts) {
                Ok(r) => {
                    eprintln!(
                        "fixture {label}: {} feature curves, {} mesh vertices, {} triangles, {} mapping steps",
                        r.meshes.curves.len() - 1,
                        r.meshes.source.len(),
                        r.meshes.triangles.len(),
                        r.stats.steps
                    );
                    g.bench_function(&label, |b| b.iter(|| build(&s, &t, &opts).unwrap()));
                }
                Err(e) => eprintln!("fixture {label}: does not map ({e})"),
            }
        }
    }
    g.finish();
}

criterion_group!(benches, compatible_triangulation);
criterion_main!(benches);
