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
//! and divide the "Collected" count by N. With a third argument `frames`, it sets up once and
//! evaluates N lone frames at t = 0.37 instead, for counting a frame's instructions with
//! `--toggle-collect='crmorph::rigid::Interpolator::at'`.

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::geometry::Point;
use crmorph::rigid::{Interpolator, Method};
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(dir) = args.next().map(PathBuf::from) else {
        eprintln!("usage: setup_count FIXTURE_DIR [N] [frames]");
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
    let frames = args.next().as_deref() == Some("frames");
    let set_up = || {
        Interpolator::new(
            Method::Disc,
            &meshes.source,
            &meshes.target,
            &meshes.triangles,
        )
    };
    if frames {
        let it = match set_up() {
            Ok(it) => it,
            Err(e) => {
                eprintln!("setup_count: {e}");
                return ExitCode::FAILURE;
            }
        };
        let (mut out, mut ws) = (vec![Point::ZERO; it.vertex_count()], it.workspace());
        for _ in 0..n {
            it.at(std::hint::black_box(0.37), &mut out, &mut ws);
            std::hint::black_box(&out);
        }
    } else {
        for _ in 0..n {
            if let Err(e) = std::hint::black_box(set_up()) {
                eprintln!("setup_count: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    let what = if frames { "frames" } else { "set-ups" };
    println!(
        "{} vertices, {n} {what} of the disc method",
        meshes.source.len()
    );
    ExitCode::SUCCESS
}
