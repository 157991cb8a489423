//! Prints, for every fixture pair and both directions, the compatible triangulation's size, the
//! number of mapping steps and the time it took, or the error. Run:
//! `cargo run --release --example report`.

use crmorph::Side;
use std::path::Path;
use std::time::Instant;

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut dirs: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    for d in dirs {
        let (s, t) = (d.join("source.svg"), d.join("target.svg"));
        if !(s.exists() && t.exists()) {
            continue;
        }
        let only = std::env::args().nth(1);
        if only.as_deref().is_some_and(|o| !d.ends_with(o)) {
            continue;
        }
        let o = ReadOptions::default();
        let (s, t) = (
            Drawing::open(&s, &o).unwrap(),
            Drawing::open(&t, &o).unwrap(),
        );
        for from_target in [false, true] {
            let mut opts = MorphOptions::default();
            opts.triangulated = if from_target {
                Side::Target
            } else {
                Side::Source
            };
            let start = Instant::now();
            let r = build(&s, &t, &opts);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let name = d.file_name().unwrap().to_string_lossy();
            match r {
                Ok(c) => println!(
                    "{name:20} from_target={from_target:5} curves={:2} vertices={:4} triangles={:4} steps={:3} rejected={:3} {:6.1} ms",
                    c.meshes.curves.len(),
                    c.meshes.source.len(),
                    c.meshes.triangles.len(),
                    c.stats.steps,
                    c.stats.rejected_steps,
                    ms
                ),
                Err(e) => println!("{name:20} from_target={from_target:5} ERROR {e}"),
            }
        }
    }
}
