//! Composite harmonic mapping (§5) of two synthetic scenes of about 700 vertices, with the
//! constrained triangulation they start from: a band bent into a U (a midline feature and a
//! small closed one) and a square whose bar feature turns by 45° (Fig.8 vs Fig.10). These
//! replace an ignored timing test that asserted nothing. Run:
//! `cargo bench --bench mapping`.

use crmorph::Side;
use std::f64::consts::PI;

use criterion::{criterion_group, criterion_main, Criterion};
use crmorph::geometry::bounding_box;
use crmorph::mapping::samples::{bent_band, turning_bar};
use crmorph::mapping::{composite_map, MappingOptions};
use crmorph::tolerance::Tolerances;
use crmorph::triangulation::triangulate;

fn mapping(c: &mut Criterion) {
    let mut g = c.benchmark_group("composite_map");
    g.sample_size(20);
    for (name, pairs, density) in [
        ("u-bent-band", bent_band(20.0, 10.0, 2, PI), 1.1),
        ("turning-bar-45", turning_bar(45.0), 1.0),
    ] {
        let (lo, hi) = bounding_box(pairs[0].source.iter().copied()).unwrap();
        let tol = Tolerances::new(lo.distance(hi), density);
        let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
        let opts = MappingOptions::default();
        let stats = composite_map(&tri, &pairs, &tol, &opts).unwrap().1;
        eprintln!(
            "{name}: {} vertices, {} triangles, {} steps ({} rejected)",
            stats.vertices, stats.triangles, stats.steps, stats.rejected_steps
        );
        g.bench_function(format!("{name}/triangulate"), |b| {
            b.iter(|| triangulate(&pairs, &tol, Side::Source).unwrap())
        });
        g.bench_function(format!("{name}/composite_map"), |b| {
            b.iter(|| composite_map(&tri, &pairs, &tol, &opts).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, mapping);
criterion_main!(benches);
