//! Area through time of the leaf → butterfly morph, in both directions, for the disc, linear
//! and triangle methods, against the linear blend of the end areas.
//! Run: `cargo run --release --example area`.

use crmorph::Side;
use std::path::Path;

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::quality::area;
use crmorph::rigid::{Interpolator, Method};

fn main() {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/leaf-to-butterfly");
    let o = ReadOptions::default();
    let s = Drawing::open(&d.join("source.svg"), &o).unwrap();
    let t = Drawing::open(&d.join("target.svg"), &o).unwrap();
    for from_target in [false, true] {
        println!("from_target = {from_target}");
        let mut opts = MorphOptions::default();
        opts.triangulated = if from_target {
            Side::Target
        } else {
            Side::Source
        };
        let c = build(&s, &t, &opts).unwrap();
        let m = &c.meshes;
        let (a0, a1) = (area(&m.triangles, &m.source), area(&m.triangles, &m.target));
        for (name, method) in [
            ("disc", Method::Disc),
            ("linear", Method::Linear),
            ("triangle", Method::Triangle),
        ] {
            let ip = match Interpolator::new(method, &m.source, &m.target, &m.triangles) {
                Ok(ip) => ip,
                Err(e) => {
                    println!("{name:8} {e}");
                    continue;
                }
            };
            let worst = (0..=20)
                .map(|k| {
                    let tt = k as f64 / 20.0;
                    let blend = (1.0 - tt) * a0 + tt * a1;
                    area(&m.triangles, &ip.at_vec(tt)) / blend
                })
                .fold(f64::MAX, f64::min);
            let mid = area(&m.triangles, &ip.at_vec(0.5)) / (0.5 * (a0 + a1));
            let most = (0..=20)
                .map(|k| {
                    let tt = k as f64 / 20.0;
                    area(&m.triangles, &ip.at_vec(tt)) / ((1.0 - tt) * a0 + tt * a1)
                })
                .fold(f64::MIN, f64::max);
            println!("{name:8} area / blend of end areas: lowest {worst:.3}, highest {most:.3}, at t=0.5 {mid:.3}");
        }
    }
}
