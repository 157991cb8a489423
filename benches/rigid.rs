//! Set-up and per-frame cost of the rigid interpolation methods (§4.1) on synthetic grids with a
//! smooth non-rigid target (the strip bent along an arc and rotated).
//!
//! Run: `cargo bench --bench rigid -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use crmorph::rigid::{Interpolator, Method};
use crmorph::Point;
use crmorph::Side;
use std::hint::black_box;

/// `nx × ny` grid, unit spacing, counter-clockwise triangles.
fn grid(nx: usize, ny: usize) -> (Vec<Point>, Vec<[u32; 3]>) {
    let pts = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| Point::new(i as f64, j as f64)))
        .collect();
    let mut tris = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let v = |i: usize, j: usize| (j * nx + i) as u32;
            tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    (pts, tris)
}

/// Bend along an arc turning by 1.5 rad over the grid's width, then rotate by 2 rad: local
/// rotations from 2.0 to 3.5 rad, across the ±π wrap.
fn target(src: &[Point], width: f64) -> Vec<Point> {
    let r = 2.0 * width / 1.5;
    let rot = Point::from_angle(2.0);
    src.iter()
        .map(|p| {
            let phi = p.x / r;
            rot.rotate(Point::new((r - p.y) * phi.sin(), r - (r - p.y) * phi.cos()))
        })
        .collect()
}

/// Times of [`eight_frames`]: spread over the morph, none at its ends.
const EIGHT: [f64; 8] = [0.06, 0.18, 0.31, 0.43, 0.56, 0.68, 0.81, 0.93];

/// Eight frames with one [`Interpolator::at_many`] call: they share each pass over the disc
/// method's factor. Criterion's time is for all eight; a frame costs an eighth of it.
fn eight_frames(it: &Interpolator) -> impl FnMut() + '_ {
    let mut ws = it.workspace();
    let mut out = vec![Point::ZERO; EIGHT.len() * it.vertex_count()];
    move || it.at_many(black_box(&EIGHT), &mut out, &mut ws)
}

/// Sixteen frames through [`Interpolator::frames`], as the exporters ask for them: two batches
/// of eight, on both of rayon's threads when the work is large enough (about 1,000 vertices
/// and up). Criterion's time is the wall time of all sixteen, output vectors included.
fn sixteen_frames(it: &Interpolator) -> impl FnMut() -> Vec<Vec<Point>> + '_ {
    let ts: Vec<f64> = (1..=16).map(|k| k as f64 / 17.0).collect();
    move || it.frames(black_box(&ts))
}

/// The memory floor of a lone frame: a buffer of the factor's size (`factor_bytes`) read as
/// a frame's two triangular solves read the factor, forward and then back from its end, with no
/// arithmetic between the reads that waits on them. Where the factor outgrows the caches (the
/// 100k-vertex grid's is about 50 MB), no lone frame on one core can beat this (issue 16).
fn factor_reads(bytes: usize) -> impl FnMut() -> u64 {
    let words: Vec<u64> = (0..bytes.div_ceil(8) as u64).collect();
    move || {
        // Eight running sums, so the reads, not the additions, set the pace.
        let mut sum = [0u64; 8];
        for chunk in words.chunks_exact(8) {
            for (s, &w) in sum.iter_mut().zip(chunk) {
                *s = s.wrapping_add(w);
            }
        }
        for chunk in words.rchunks_exact(8) {
            for (s, &w) in sum.iter_mut().zip(chunk) {
                *s ^= w;
            }
        }
        black_box(sum.iter().fold(0, |a, &s| a ^ s))
    }
}

fn bench(c: &mut Criterion) {
    for (nx, ny) in [(27, 26), (32, 32), (100, 100), (317, 316)] {
        let (src, tris) = grid(nx, ny);
        let tgt = target(&src, nx as f64);
        let n = src.len();
        let mut g = c.benchmark_group("rigid");
        if n > 50_000 {
            g.sample_size(10);
        }
        for (name, m) in [("disc", Method::Disc), ("triangle", Method::Triangle)] {
            g.bench_with_input(BenchmarkId::new(format!("setup/{name}"), n), &n, |b, _| {
                b.iter(|| Interpolator::new(m, black_box(&src), black_box(&tgt), &tris).unwrap())
            });
            let it = Interpolator::new(m, &src, &tgt, &tris).unwrap();
            let mut ws = it.workspace();
            let mut out = vec![Point::ZERO; n];
            g.bench_with_input(BenchmarkId::new(format!("frame/{name}"), n), &n, |b, _| {
                b.iter(|| it.at(black_box(0.37), &mut out, &mut ws))
            });
            if m == Method::Disc {
                let mut eight = eight_frames(&it);
                g.bench_with_input(BenchmarkId::new("frames8/disc", n), &n, |b, _| {
                    b.iter(&mut eight)
                });
                let mut sixteen = sixteen_frames(&it);
                g.bench_with_input(BenchmarkId::new("frames16-parallel/disc", n), &n, |b, _| {
                    b.iter(&mut sixteen)
                });
                let mut floor = factor_reads(it.factor_bytes());
                g.bench_with_input(BenchmarkId::new("floor/disc", n), &n, |b, _| {
                    b.iter(&mut floor)
                });
            }
        }
        g.finish();
    }
}

/// The compatible meshes of every fixture pair that maps (source direction first, else from the
/// target), built once.
fn fixture_meshes() -> Vec<(String, crmorph::CompatibleMeshes)> {
    use crmorph::compatible::{build, MorphOptions};
    use crmorph::drawing::{Drawing, ReadOptions};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mut dirs: Vec<_> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    let mut out = Vec::new();
    for d in dirs {
        let (s, t) = (d.join("source.svg"), d.join("target.svg"));
        if !(s.exists() && t.exists()) {
            continue;
        }
        let o = ReadOptions::default();
        let (s, t) = (
            Drawing::open(&s, &o).unwrap(),
            Drawing::open(&t, &o).unwrap(),
        );
        let name = d.file_name().unwrap().to_string_lossy().into_owned();
        for from_target in [false, true] {
            let mut opts = MorphOptions::default();
            opts.triangulated = if from_target {
                Side::Target
            } else {
                Side::Source
            };
            if let Ok(c) = build(&s, &t, &opts) {
                let label = if from_target {
                    format!("{name}(from-target)")
                } else {
                    name.clone()
                };
                out.push((label, c.meshes));
                break;
            }
        }
    }
    out
}

fn fixtures(c: &mut Criterion) {
    let mut g = c.benchmark_group("rigid-fixtures");
    for (name, m) in fixture_meshes() {
        eprintln!("fixture {name}: {} vertices", m.source.len());
        g.bench_function(format!("setup/disc/{name}"), |b| {
            b.iter(|| {
                Interpolator::new(Method::Disc, black_box(&m.source), &m.target, &m.triangles)
                    .unwrap()
            })
        });
        let it = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
        let mut ws = it.workspace();
        let mut out = vec![Point::ZERO; m.source.len()];
        g.bench_function(format!("frame/disc/{name}"), |b| {
            b.iter(|| it.at(black_box(0.37), &mut out, &mut ws))
        });
        let mut eight = eight_frames(&it);
        g.bench_function(format!("frames8/disc/{name}"), |b| b.iter(&mut eight));
    }
    g.finish();
}

/// Frame and set-up time of the disc method against mesh size, 1k to 1M vertices: the data of
/// `docs/rigid-scaling.svg` (`python3 tools/bench/scaling.py` draws it from criterion's output).
/// Run on its own: `cargo bench --bench rigid -- rigid-scaling --warm-up-time 1
/// --measurement-time 3`.
fn scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("rigid-scaling");
    g.sample_size(10);
    for side in [32, 55, 100, 173, 317, 548, 1000] {
        let (src, tris) = grid(side, side);
        let tgt = target(&src, side as f64);
        let n = src.len();
        g.bench_with_input(BenchmarkId::new("setup", n), &n, |b, _| {
            b.iter(|| Interpolator::new(Method::Disc, black_box(&src), &tgt, &tris).unwrap())
        });
        let it = Interpolator::new(Method::Disc, &src, &tgt, &tris).unwrap();
        let mut ws = it.workspace();
        let mut out = vec![Point::ZERO; n];
        g.bench_with_input(BenchmarkId::new("frame", n), &n, |b, _| {
            b.iter(|| it.at(black_box(0.37), &mut out, &mut ws))
        });
        let mut eight = eight_frames(&it);
        g.bench_with_input(BenchmarkId::new("frames8", n), &n, |b, _| {
            b.iter(&mut eight)
        });
    }
    g.finish();
}

criterion_group!(benches, bench, fixtures, scaling);
criterion_main!(benches);
