//! Counts the triangles that invert in the frames of the disc interpolation, as the CLI builds
//! it, over every marked-up fixture pair: both directions, densities 0.5–2, and the inputs'
//! numbers rounded to 1, 2 and 3 decimals (as SVG optimisers write them) or kept. Also reports
//! the distortion of the frames (the mean and worst deviation of each triangle's singular values
//! from the rigid interpolation of its end shapes, see `quality`), to show what repair costs.
//! Run: `cargo run --release --example folds [FRAMES]` (default 201 frames per morph).

use crmorph::Side;
use std::path::Path;

use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::geometry::orient2d;
use crmorph::rigid::Method;

#[path = "../tests/integration/rounding.rs"]
mod rounding;
use rounding::rounded;

fn main() {
    let frames: usize = std::env::args()
        .nth(1)
        .and_then(|f| f.parse().ok())
        .unwrap_or(201);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut total = (0usize, 0usize, 0usize);
    // Distortion of every triangle of every frame against the source mesh: sum, count, worst.
    let mut dist = (0.0f64, 0usize, 1.0f64);
    // A histogram of log10(distortion) in 1/100 steps, for the median and the 99th percentile.
    let mut hist = vec![0u64; 1001];
    let only = std::env::var("ONLY").ok();
    for name in [
        "gourd",
        "leaf-to-butterfly",
        "dancer",
        "u-to-s",
        "star-to-blob",
    ] {
        if only.as_deref().is_some_and(|o| !o.starts_with(name)) {
            continue;
        }
        let text = |f: &str| std::fs::read_to_string(root.join(name).join(f)).unwrap();
        let (src, tgt) = (text("source.svg"), text("target.svg"));
        for decimals in [None, Some(3), Some(2), Some(1)] {
            for density in [0.5, 0.75, 1.0, 1.25, 1.5, 2.0] {
                let mut o = ReadOptions::default();
                o.density = density;
                let (Ok(s), Ok(t)) = (
                    Drawing::from_str("s", &rounded(&src, decimals), &o),
                    Drawing::from_str("t", &rounded(&tgt, decimals), &o),
                ) else {
                    println!(
                        "{name} {decimals:?} {density}: unreadable: {:?}",
                        Drawing::from_str("s", &rounded(&src, decimals), &o)
                            .err()
                            .or(Drawing::from_str("t", &rounded(&tgt, decimals), &o).err())
                            .map(|e| e.to_string())
                    );
                    continue;
                };
                for from_target in [false, true] {
                    let mut opts = MorphOptions::default();
                    opts.triangulated = if from_target {
                        Side::Target
                    } else {
                        Side::Source
                    };
                    opts.density = density;
                    total.0 += 1;
                    let c = match build(&s, &t, &opts) {
                        Ok(c) => c,
                        Err(e) => {
                            println!("{name} dec={decimals:?} density={density} from_target={from_target}: no mesh: {e}");
                            continue;
                        }
                    };
                    let ip = c.interpolator(Method::Disc).unwrap();
                    let m = &c.meshes;
                    let mut bad_frames = 0;
                    let mut worst = 0;
                    let mut on_curve = vec![false; m.source.len()];
                    for &v in m.curves.iter().flat_map(|c| &c.vertices) {
                        on_curve[v as usize] = true;
                    }
                    let mut pinned = std::collections::BTreeSet::new();
                    let mut loose = std::collections::BTreeSet::new();
                    for k in 0..frames {
                        let v = ip.at_vec(k as f64 / (frames - 1) as f64);
                        for d in crmorph::quality::distortion(&m.triangles, &m.source, &v) {
                            if d.is_finite() {
                                hist[((d.log10() * 100.0) as usize).min(1000)] += 1;
                                dist.0 += d.min(100.0);
                                dist.1 += 1;
                                dist.2 = dist.2.max(d);
                            }
                        }
                        let mut n = 0;
                        for (f, t) in m.triangles.iter().enumerate() {
                            let [a, b, cc] = t.map(|x| v[x as usize]);
                            if orient2d(a, b, cc) <= 0.0 {
                                n += 1;
                                if t.iter().all(|&x| on_curve[x as usize]) {
                                    pinned.insert(f);
                                } else {
                                    loose.insert(f);
                                }
                            }
                        }
                        if n > 0 {
                            bad_frames += 1;
                            worst = worst.max(n);
                        }
                    }
                    if bad_frames > 0 {
                        total.1 += 1;
                        total.2 += bad_frames;
                        println!("{name} dec={decimals:?} density={density} from_target={from_target}: {bad_frames} of {frames} frames fold (at most {worst} triangles; {} vertices; {} folding triangles with every corner on a curve, {} with a free corner)", m.source.len(), pinned.len(), loose.len());
                    }
                }
            }
        }
    }
    let quantile = |q: f64| {
        let want = (q * dist.1 as f64) as u64;
        let mut seen = 0;
        for (k, &c) in hist.iter().enumerate() {
            seen += c;
            if seen > want {
                return 10f64.powf((k as f64 + 0.5) / 100.0);
            }
        }
        f64::INFINITY
    };
    println!(
        "{} morphs, {} with folded frames, {} folded frames in all; distortion (σ₁/σ₂ of each frame's triangles against the source) median {:.3}, p99 {:.2}, mean (capped at 100) {:.3}",
        total.0, total.1, total.2, quantile(0.5), quantile(0.99), dist.0 / dist.1.max(1) as f64
    );
}
