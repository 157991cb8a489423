//! Lists the triangles of the source triangulation whose three corners all lie on curves (their
//! target shape is fixed by the curves alone), with their signed area at both ends.
//! Run: `cargo run --release --example ears -- SRC.svg TGT.svg`.

use crmorph::compatible::{curve_pairs, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::geometry::triangle_area;
use crmorph::triangulation::triangulate;
use crmorph::Side;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let o = ReadOptions::default();
    let s = Drawing::open(a[1].as_ref(), &o).unwrap();
    let t = Drawing::open(a[2].as_ref(), &o).unwrap();
    let (tol, pairs) = curve_pairs(&s, &t, &MorphOptions::default()).unwrap();
    let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
    let curve_count: usize = pairs.iter().map(|p| p.source.len()).sum();
    let target: Vec<_> = pairs
        .iter()
        .flat_map(|p| p.target.iter().copied())
        .collect();
    let mut n = 0;
    for tr in &tri.triangles {
        if tr.iter().all(|&v| (v as usize) < curve_count) {
            n += 1;
            let [p, q, r] = tr.map(|v| tri.points[v as usize]);
            let [p1, q1, r1] = tr.map(|v| target[v as usize]);
            println!(
                "{tr:?}: area source {:.4}, target {:.6}",
                triangle_area(p, q, r),
                triangle_area(p1, q1, r1)
            );
        }
    }
    println!(
        "{n} triangles with every corner on a curve, of {}",
        tri.triangles.len()
    );
}
