//! Distortion spikes of the disc method and the triangle baseline on every fixture's compatible
//! meshes (the paper's Fig. 13). Run: `cargo run --release --example fig13`.

use std::path::Path;

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::geometry::triangle_area;
use crmorph::quality::distortion;
use crmorph::rigid::{Interpolator, Method};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    for name in [
        "u-to-s",
        "leaf-to-butterfly",
        "gourd",
        "dancer",
        "star-to-blob",
    ] {
        let d = root.join(name);
        let o = ReadOptions::default();
        let s = Drawing::open(&d.join("source.svg"), &o).unwrap();
        let t = Drawing::open(&d.join("target.svg"), &o).unwrap();
        let c = build(&s, &t, &MorphOptions::default()).unwrap();
        let m = &c.meshes;
        let thin = |pts: &[crmorph::Point], tri: &[u32; 3]| {
            let [a, b, cc] = tri.map(|i| pts[i as usize]);
            let l = a.distance(b).max(b.distance(cc)).max(cc.distance(a));
            2.0 * triangle_area(a, b, cc) / (l * l)
        };
        let skinny = m
            .triangles
            .iter()
            .filter(|tr| thin(&m.source, tr) < 0.02)
            .count();
        let end = distortion(&m.triangles, &m.source, &m.target);
        let mut line = format!(
            "{name:18} {:5} tris, {:4} skinny:",
            m.triangles.len(),
            skinny
        );
        for (label, method) in [("disc", Method::Disc), ("triangle", Method::Triangle)] {
            let ip = match Interpolator::new(method, &m.source, &m.target, &m.triangles) {
                Ok(ip) => ip,
                Err(e) => {
                    line += &format!(" {label}: {e}");
                    continue;
                }
            };
            let (mut worst, mut worst_all, mut over2) = (0.0f64, 0.0f64, 0usize);
            for k in 1..40 {
                let f = ip.at_vec(k as f64 / 40.0);
                let dist = distortion(&m.triangles, &m.source, &f);
                for ((dd, e), tr) in dist.iter().zip(&end).zip(&m.triangles) {
                    let spike = dd / e.max(1.0);
                    worst_all = worst_all.max(spike);
                    if thin(&m.source, tr) >= 0.1 {
                        worst = worst.max(spike);
                        if spike > 2.0 {
                            over2 += 1;
                        }
                    }
                }
            }
            line += &format!(
                " {label}: spike well-shaped {worst:.3} (>2: {over2}), all {worst_all:.3};"
            );
        }
        println!("{line}");
    }
}
