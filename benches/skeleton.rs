//! Skeleton control (§4.2) on the dancer fixture with its bundled control pose: the one-time
//! set-up (harmonic weights, binding, phase-1 track, both factorizations) and the time per
//! frame, against the plain disc interpolation's set-up and frame; and sixteen frames through
//! `frames` (batched and on both threads), each way.
//!
//! Run: `cargo bench --bench skeleton -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, Criterion};
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::rigid::{Interpolator, Method};
use crmorph::skeleton::{Pose, Skeleton, SkeletonControl};
use crmorph::Point;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/dancer/");
    let opts = ReadOptions::default();
    let open = |f: &str| Drawing::open(std::path::Path::new(&format!("{dir}{f}")), &opts).unwrap();
    let (s, t) = (open("source.svg"), open("target.svg"));
    let pose_file = open("pose-0.5.svg");
    let comp = build(&s, &t, &MorphOptions::default()).unwrap();
    let m = &comp.meshes;
    let skeleton =
        Skeleton::from_chains(&s.file, &s.controls.skeleton, comp.tolerances.snap).unwrap();
    let joints = skeleton
        .pose_from_chains(&pose_file.file, &pose_file.controls.skeleton)
        .unwrap();
    let poses = [Pose { t: 0.5, joints }];
    let n = m.source.len();
    let mut g = c.benchmark_group(format!("skeleton/dancer-{n}v"));
    g.bench_function("setup/plain", |b| {
        b.iter(|| Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap())
    });
    g.bench_function("setup/skeleton", |b| {
        b.iter(|| SkeletonControl::new(m, skeleton.clone(), black_box(&poses)).unwrap())
    });
    let plain = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
    let mut ws = plain.workspace();
    let mut out = vec![Point::ZERO; n];
    g.bench_function("frame/plain", |b| {
        b.iter(|| plain.at(black_box(0.37), &mut out, &mut ws))
    });
    let control = SkeletonControl::new(m, skeleton.clone(), &poses).unwrap();
    let mut cws = control.workspace();
    g.bench_function("frame/skeleton", |b| {
        b.iter(|| control.at(black_box(0.37), &mut out, &mut cws))
    });
    // Sixteen frames through `frames`, as the exporters take them: batches of up to eight
    // frames per pass over the factor, on both threads.
    let ts: Vec<f64> = (0..16).map(|k| k as f64 / 15.0).collect();
    g.bench_function("frames16/plain", |b| {
        b.iter(|| plain.frames(black_box(&ts)))
    });
    g.bench_function("frames16/skeleton", |b| {
        b.iter(|| control.frames(black_box(&ts)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
