//! Prints the worst triangles of each fixture's source triangulation (smallest angle, shortest
//! edge), for checking the triangulation stage. Run: `cargo run --release --example triquality`.

use crmorph::Side;
use std::path::Path;

use crmorph::compatible::{curve_pairs, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::triangulation::triangulate;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    for name in ["u-to-s", "leaf-to-butterfly", "gourd", "dancer"] {
        let d = root.join(name);
        let o = ReadOptions::default();
        let s = Drawing::open(&d.join("source.svg"), &o).unwrap();
        let t = Drawing::open(&d.join("target.svg"), &o).unwrap();
        let (tol, pairs) = curve_pairs(&s, &t, &MorphOptions::default()).unwrap();
        let curve_vertices: usize = pairs.iter().map(|p| p.source.len()).sum();
        let tri = triangulate(&pairs, &tol, Side::Source).unwrap();
        let mut worst: Vec<(f64, f64, [u32; 3])> = tri
            .triangles
            .iter()
            .map(|t| {
                let p = t.map(|v| tri.points[v as usize]);
                let mut min_angle = f64::MAX;
                for k in 0..3 {
                    let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                    min_angle = min_angle.min(a.perp_dot(b).abs().atan2(a.dot(b)).to_degrees());
                }
                let min_edge = (0..3)
                    .map(|k| p[k].distance(p[(k + 1) % 3]))
                    .fold(f64::MAX, f64::min);
                (min_angle, min_edge, *t)
            })
            .collect();
        worst.sort_by(|a, b| a.0.total_cmp(&b.0));
        let fixed = |v: u32| (v as usize) < curve_vertices;
        println!(
            "{name}: {} vertices ({curve_vertices} on curves), {} triangles; max_edge {:.2}",
            tri.points.len(),
            tri.triangles.len(),
            tol.max_edge
        );
        for (a, e, t) in worst.iter().take(5) {
            println!(
                "   angle {a:7.3}°  shortest edge {e:.4}  fixed corners {}",
                t.iter().filter(|v| fixed(**v)).count()
            );
            if *a < 0.01 {
                println!("      {:?}", t.map(|v| (v, tri.points[v as usize])));
            }
        }
        let all_fixed = tri
            .triangles
            .iter()
            .filter(|t| t.iter().all(|v| fixed(*v)))
            .count();
        println!("   triangles with all corners on curves: {all_fixed}");
    }
}
