//! Vertex correspondence (§3) of large closed curves: a 4000-vertex wavy star against a
//! 3000-vertex one (many salient points to associate), and a 5000-vertex circle against a
//! 6000-vertex ellipse (the circle has no salient point). These replace an ignored timing
//! test that asserted nothing. Run: `cargo bench --bench correspondence`.

use std::f64::consts::TAU;

use criterion::{criterion_group, criterion_main, Criterion};
use crmorph::correspondence::{correspond, CorrespondenceOptions};
use crmorph::drawing::ControlCurve;
use crmorph::geometry::Point;
use crmorph::tolerance::Tolerances;
use crmorph::CurveKind;

/// A closed boundary curve through `points`.
fn boundary(points: Vec<Point>) -> ControlCurve {
    ControlCurve {
        id: "boundary".into(),
        name: "boundary".into(),
        kind: CurveKind::Boundary,
        closed: true,
        points,
    }
}

/// Points at angles `phase + TAU·k/n` and radii `radii[k]` around `centre`, counter-clockwise.
fn star(centre: Point, radii: &[f64], phase: f64) -> Vec<Point> {
    let n = radii.len();
    radii
        .iter()
        .enumerate()
        .map(|(k, &r)| centre + r * Point::from_angle(phase + TAU * k as f64 / n as f64))
        .collect()
}

/// `n` points on an ellipse with half-axes `a`, `b` around `centre`, counter-clockwise.
fn ellipse(n: usize, a: f64, b: f64, phase: f64, centre: Point) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let t = phase + TAU * k as f64 / n as f64;
            centre + Point::new(a * t.cos(), b * t.sin())
        })
        .collect()
}

fn correspondence(c: &mut Criterion) {
    let tol = Tolerances::new(10.0, 1.0);
    let opts = CorrespondenceOptions::default();
    let centre = Point::new(5.0, 5.0);
    let radii: Vec<f64> = (0..4000)
        .map(|k| 2.0 + 0.5 * (k as f64 * 0.0157 * 12.0).sin())
        .collect();
    let radii2: Vec<f64> = (0..3000)
        .map(|k| 2.5 + 0.6 * (k as f64 * 0.0209 * 12.0 + 0.3).sin())
        .collect();
    let cases = [
        (
            "stars-4000-3000",
            boundary(star(centre, &radii, 0.0)),
            boundary(star(centre, &radii2, 0.4)),
        ),
        (
            "circle-5000-ellipse-6000",
            boundary(ellipse(5000, 3.0, 3.0, 0.0, centre)),
            boundary(ellipse(6000, 4.0, 2.0, 0.5, centre)),
        ),
    ];
    let mut g = c.benchmark_group("correspondence");
    g.sample_size(10);
    for (name, a, b) in &cases {
        let pair = correspond(a, b, &[], &tol, &opts).unwrap();
        eprintln!(
            "{name}: {} pairs, {} salient",
            pair.source.len(),
            pair.salient.len()
        );
        g.bench_function(*name, |bench| {
            bench.iter(|| correspond(a, b, &[], &tol, &opts).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, correspondence);
criterion_main!(benches);
