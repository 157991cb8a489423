//! Lists the triangles that invert in any frame of the disc interpolation of each fixture, with
//! their smallest angle in the source and target meshes. Run:
//! `cargo run --release --example inverted [DENSITY]`.

use crmorph::Side;
use std::path::Path;

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::geometry::orient2d;
use crmorph::rigid::{Interpolator, Method};
use crmorph::Point;

fn min_angle(p: [Point; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            a.perp_dot(b).abs().atan2(a.dot(b)).to_degrees()
        })
        .fold(f64::MAX, f64::min)
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    for name in ["gourd", "leaf-to-butterfly", "dancer", "u-to-s"] {
        let o = ReadOptions::default();
        let s = Drawing::open(&root.join(name).join("source.svg"), &o).unwrap();
        let t = Drawing::open(&root.join(name).join("target.svg"), &o).unwrap();
        for from_target in [false, true] {
            let mut opts = MorphOptions::default();
            opts.triangulated = if from_target {
                Side::Target
            } else {
                Side::Source
            };
            opts.density = std::env::args()
                .nth(1)
                .and_then(|d| d.parse().ok())
                .unwrap_or(1.0);
            let Ok(c) = build(&s, &t, &opts) else {
                continue;
            };
            let m = &c.meshes;
            let ip = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
            let mut bad = std::collections::BTreeMap::new();
            for k in 0..=200 {
                let tt = k as f64 / 200.0;
                let v = ip.at_vec(tt);
                for (i, tr) in m.triangles.iter().enumerate() {
                    let [a, b, cc] = tr.map(|x| v[x as usize]);
                    if orient2d(a, b, cc) <= 0.0 {
                        bad.entry(i).or_insert_with(Vec::new).push(tt);
                    }
                }
            }
            println!(
                "{name} from_target={from_target}: {} triangles invert",
                bad.len()
            );
            for (i, ts) in bad.iter().take(5) {
                let tr = m.triangles[*i];
                let on_curve: Vec<bool> = tr
                    .iter()
                    .map(|v| m.curves.iter().any(|c| c.vertices.contains(v)))
                    .collect();
                println!("   corners on curves: {on_curve:?}");
                println!(
                    "   triangle {i}: t in {:.3}..{:.3}, min angle source {:.2}° target {:.2}°",
                    ts[0],
                    ts[ts.len() - 1],
                    min_angle(tr.map(|x| m.source[x as usize])),
                    min_angle(tr.map(|x| m.target[x as usize]))
                );
            }
        }
    }
}
