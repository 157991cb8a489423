//! Spin of automatic mode's middle frames (issue #7, item 7): for every pair of shapes that
//! morph with an outline, how far the outline's turn at t = ½ is from half the shapes' own
//! turn (`crmorph::quality::spin`); and which rung of the ladder the pairs of shapes took.
//! Over the icon fixtures and, when given, a corpus (`pairs.json` as `tools/corpus` draws it).
//! Run:
//! `cargo run --release --example spin [-- tools/corpus/.cache/corpus]`.

use std::path::{Path, PathBuf};

use crmorph::artwork::Scene;
use crmorph::auto::build_auto;
use crmorph::compatible::MorphOptions;
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::mesh::CurveKind;
use crmorph::rigid::Method;

fn pairs(corpus: Option<&Path>) -> Vec<(String, PathBuf, PathBuf)> {
    let mut out = Vec::new();
    let icons = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/icons");
    for e in std::fs::read_dir(&icons).unwrap() {
        let p = e.unwrap().path();
        if p.join("source.svg").exists() {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            out.push((name, p.join("source.svg"), p.join("target.svg")));
        }
    }
    out.sort();
    if let Some(dir) = corpus {
        let text = std::fs::read_to_string(dir.join("pairs.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        for p in v["pairs"].as_array().unwrap() {
            out.push((
                p["id"].as_str().unwrap().to_string(),
                dir.join(p["source"].as_str().unwrap()),
                dir.join(p["target"].as_str().unwrap()),
            ));
        }
    }
    out
}

fn main() {
    let corpus = std::env::args().nth(1).map(PathBuf::from);
    let mut spins: Vec<(f64, String)> = Vec::new();
    let mut rungs: std::collections::BTreeMap<String, usize> = Default::default();
    let (mut lone, mut blended) = (0usize, 0usize);
    for (name, s, t) in pairs(corpus.as_deref()) {
        let o = ReadOptions::default();
        let (Ok(ds), Ok(dt)) = (Drawing::open(&s, &o), Drawing::open(&t, &o)) else {
            continue;
        };
        let scene = |d: &Drawing| Scene::from_svg(&d.file, &d.svg, "controls").unwrap();
        let (ss, ts) = (scene(&ds), scene(&dt));
        let Ok((c, report, _, _)) = build_auto(&ds, &dt, &ss, &ts, &MorphOptions::default()) else {
            continue;
        };
        for s in &report.shapes {
            let rung = match s.rung {
                crmorph::auto::part::Rung::Mapped {
                    triangulated,
                    features,
                } => format!(
                    "composite harmonic mapping{}{}",
                    if triangulated == crmorph::Side::Target {
                        " from the target"
                    } else {
                        ""
                    },
                    if features > 0 { ", holes aligned" } else { "" }
                ),
                other => other.to_string(),
            };
            *rungs.entry(rung).or_default() += 1;
        }
        lone += report.lone.len();
        blended += report.blended;
        let interp = c.interpolator(Method::Disc).unwrap();
        let mid = interp.at_vec(0.5);
        let m = &c.meshes;
        for curve in &m.curves {
            if curve.kind != CurveKind::Boundary || !curve.closed || curve.name == "still-frame" {
                continue;
            }
            let pick = |v: &[crmorph::Point]| -> Vec<crmorph::Point> {
                curve.vertices.iter().map(|&i| v[i as usize]).collect()
            };
            let spin = crmorph::quality::spin(&pick(&m.source), &pick(&m.target), &pick(&mid));
            spins.push((spin.to_degrees(), format!("{name} {}", curve.name)));
        }
    }
    println!("pairs of shapes by rung:");
    for (rung, n) in &rungs {
        println!("  {n:5}  {rung}");
    }
    println!("shapes without a partner: {lone}; paths cross-fading: {blended}");
    spins.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = spins.len();
    let q = |f: f64| spins[((n as f64 - 1.0) * f).round() as usize].0;
    println!(
        "{n} outlines: spin median {:.1}°, p90 {:.1}°, max {:.1}°; over 15°: {}",
        q(0.5),
        q(0.9),
        q(1.0),
        spins.iter().filter(|s| s.0 > 15.0).count()
    );
    let show: usize = std::env::var("SPIN_SHOW")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(12);
    for (d, what) in spins.iter().rev().take(show) {
        println!("  {d:6.1}°  {what}");
    }
}
