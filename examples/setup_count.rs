//! Sets up the disc method (`Interpolator::new`) on one fixture pair's compatible meshes N
//! times, for counting its instructions under callgrind: on a shared VM whose speed drifts by
//! more than a set-up change saves, the count of instructions does not drift (issue 16). Run:
//!
//! ```text
//! cargo build --release --example setup_count
//! valgrind --tool=callgrind --toggle-collect='crmorph::rigid::Interpolator::new' \
//!     target/release/examples/setup_count fixtures/u-to-s 20
//! ```
//!
//! and divide the "Collected" count by N.

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::rigid::{Interpolator, Method};
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(dir) = args.next().map(PathBuf::from) else {
        eprintln!("usage: setup_count FIXTURE_DIR [N]");
        return ExitCode::FAILURE;
    };
    let n: usize = match args.next().map(|s| s.parse()) {
        None => 20,
        Some(Ok(n)) => n,
        Some(Err(e)) => {
            eprintln!("setup_count: N: {e}");
            return ExitCode::FAILURE;
        }
    };
    let o = ReadOptions::default();
    let open = |name: &str| Drawing::open(&dir.join(name), &o);
    let meshes = match (open("source.svg"), open("target.svg")) {
        (Ok(s), Ok(t)) => match build(&s, &t, &MorphOptions::default()) {
            Ok(c) => c.meshes,
            Err(e) => {
                eprintln!("setup_count: {e}");
                return ExitCode::FAILURE;
            }
        },
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("setup_count: {e}");
            return ExitCode::FAILURE;
        }
    };
    for _ in 0..n {
        let it = Interpolator::new(
            Method::Disc,
            &meshes.source,
            &meshes.target,
            &meshes.triangles,
        );
        if let Err(e) = std::hint::black_box(it) {
            eprintln!("setup_count: {e}");
            return ExitCode::FAILURE;
        }
    }
    println!(
        "{} vertices, {n} set-ups of the disc method",
        meshes.source.len()
    );
    ExitCode::SUCCESS
}
