//! The whole `morph` of the gourd fixture to a 60-frame animated SVG (reading, compatible
//! triangulation, interpolator, binding the artwork, keyframes, writing), the animated SVG
//! alone once the morph is built, and rendering PNG frames at 512×512. The animated SVG's size
//! is printed once.
//!
//! Run: `cargo bench --bench export -- --warm-up-time 1 --measurement-time 5`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use crmorph::artwork::Rgba;
use crmorph::export::{Morph, Timeline};
use crmorph::render::encode_png;
use crmorph::Morpher;
use std::hint::black_box;

const SOURCE: &str = include_str!("../fixtures/gourd/source.svg");
const TARGET: &str = include_str!("../fixtures/gourd/target.svg");

/// Everything `crmorph morph` does before writing, from the two files' text: the front door
/// with the view fitted to the morph, as the CLI makes it.
fn morph(size: Option<(u32, u32)>) -> Morph {
    let white = Rgba {
        r: 255,
        g: 255,
        b: 255,
        a: 255,
    };
    Morpher::from_svg(("source.svg", SOURCE), ("target.svg", TARGET))
        .unwrap()
        .size(size)
        .background(Some(white))
        .build()
        .unwrap()
}

fn bench(c: &mut Criterion) {
    let timeline = Timeline::default(); // 60 frames
    let svg = morph(None).animated_svg(&timeline).unwrap();
    println!(
        "gourd, 60-frame animated SVG: {} bytes ({:.1} KiB)",
        svg.len(),
        svg.len() as f64 / 1024.0
    );
    let mut g = c.benchmark_group("export");
    g.sample_size(20);
    g.bench_function("gourd/morph-to-animated-svg-60", |b| {
        b.iter(|| morph(None).animated_svg(black_box(&timeline)).unwrap())
    });
    let built = morph(None);
    g.bench_function("gourd/animated-svg-60-only", |b| {
        b.iter(|| built.animated_svg(black_box(&timeline)).unwrap())
    });
    let big = morph(Some((512, 512)));
    g.throughput(Throughput::Elements(1));
    g.bench_function("gourd/png-frame-512", |b| {
        b.iter(|| encode_png(&big.pixmap_at(black_box(0.37)).unwrap()).unwrap())
    });
    let ten = Timeline {
        frames: 10,
        ..Timeline::default()
    };
    g.throughput(Throughput::Elements(10));
    g.bench_function("gourd/png-frames-512-x10-parallel", |b| {
        b.iter(|| big.pixmap_frames(black_box(&ten)).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
