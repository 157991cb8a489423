//! Raster images riding the mesh (issue 14): one 512×512 frame of a picture pair warped
//! through a mesh of about a thousand triangles and blended (the interpolator's solve, the
//! warp of both texture grids, the two textures rasterized, the blend), and the 60-frame GIF
//! of the same pair. The mesh's triangle count and the grid sizes are printed once.
//!
//! Run: `cargo bench --bench texture -- --warm-up-time 1 --measurement-time 5`

use criterion::{criterion_group, criterion_main, Criterion};
use crmorph::drawing::ReadOptions;
use crmorph::export::{Morph, Timeline};
use crmorph::morpher::View;
use crmorph::Morpher;
use std::hint::black_box;

/// The picture of `fixtures/textures/turn` (144 × 112 px).
const PICTURE: &[u8] = include_bytes!("../fixtures/textures/turn/picture.png");

/// A 512 × 512 drawing of the picture filling most of it under `transform`, its rectangle the
/// boundary, its corner an anchor.
fn drawing(transform: &str) -> String {
    format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
             width="512" height="512" viewBox="0 0 512 512">
          <g transform="{transform}">
            <image id="picture" width="144" height="112" xlink:href="data:image/png;base64,{}"/>
            <g id="controls" style="display:none">
              <rect id="boundary" width="144" height="112"/>
              <circle id="anchor-corner" cx="0" cy="0" r="1"/>
            </g>
          </g>
        </svg>"##,
        crmorph::base64::encode(PICTURE)
    )
}

/// The picture scaled to 460 × 358 in the middle → turned by 40°, stretched and squashed,
/// through the front door showing the source's 512 × 512 view. The drawings are read at
/// density 0.7 and triangulated at density 1: the 1,246-triangle mesh of the figures in
/// docs/benchmarks-texture.md.
fn morph() -> Morph {
    let (source, target) = (
        drawing("translate(26 77) scale(3.2)"),
        drawing("translate(256 256) rotate(40) scale(3.3 2.4) translate(-72 -56)"),
    );
    let mut opts = ReadOptions::default();
    opts.density = 0.7;
    Morpher::read_svg(("source.svg", &source), ("target.svg", &target), &opts)
        .unwrap()
        .density(1.0)
        .view(View::Source)
        .raster(true)
        .build()
        .unwrap()
}

fn bench(c: &mut Criterion) {
    let m = morph();
    let (s, _) = m.scenes_at(0.37).unwrap();
    let grid = match &s.root.children[..] {
        [crmorph::artwork::Item::Group(g), ..] => g.children.iter().find_map(|i| match i {
            crmorph::artwork::Item::Image(img) => img.grid.clone(),
            _ => None,
        }),
        _ => None,
    };
    println!(
        "picture pair at 512×512: {} triangles, texture grid {:?}",
        m.meshes().triangles.len(),
        grid.map(|g| (g.columns, g.rows))
    );
    let mut g = c.benchmark_group("texture");
    g.sample_size(20);
    g.bench_function("picture/frame-512", |b| {
        b.iter(|| m.pixmap_at(black_box(0.37)).unwrap())
    });
    let timeline = Timeline::default();
    g.sample_size(10);
    g.bench_function("picture/gif-60-512", |b| {
        b.iter(|| m.gif(black_box(&timeline)).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
