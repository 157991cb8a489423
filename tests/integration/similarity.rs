//! Invariant 4 of DESIGN.md §5: a target that is a similarity of the source gives a target mesh
//! that is exactly that similarity of the source mesh, and frames that are exact similarities
//! with the angle linear in t, the short way round.

use crate::common::{fixtures, open};
use crmorph::compatible::{build, MorphOptions};
use crmorph::drawing::{Drawing, ReadOptions};
use crmorph::rigid::{Interpolator, Method};
use crmorph::Point;

/// Wraps a drawing's content in a group with `transform`, keeping the root element.
fn transformed(svg: &str, transform: &str) -> String {
    let open_end = svg
        .find("<svg")
        .and_then(|i| svg[i..].find('>').map(|j| i + j + 1))
        .unwrap();
    let close = svg.rfind("</svg>").unwrap();
    format!(
        "{}<g transform=\"{transform}\">{}</g></svg>",
        &svg[..open_end],
        &svg[open_end..close]
    )
}

fn similarity(angle_deg: f64, scale: f64, shift: Point) -> impl Fn(Point) -> Point {
    let (s, c) = angle_deg.to_radians().sin_cos();
    move |p: Point| Point::new(c * p.x - s * p.y, s * p.x + c * p.y) * scale + shift
}

/// Best-fit similarity angle from `a` to `b` (centred), and the largest residual.
fn fit(a: &[Point], b: &[Point]) -> (f64, f64, f64) {
    let f = crmorph::geometry::SimilarityFit::new(a, b);
    let angle = f.rotation();
    let scale = f.dot.hypot(f.cross) / f.from_spread;
    let (s, c) = angle.sin_cos();
    let mut worst: f64 = 0.0;
    for (p, q) in a.iter().zip(b) {
        let u = *p - f.from_centroid;
        let r = Point::new(c * u.x - s * u.y, s * u.x + c * u.y) * scale + f.to_centroid;
        worst = worst.max(r.distance(*q));
    }
    (angle, scale, worst)
}

#[test]
fn similar_targets_give_similar_meshes_and_rigid_frames() {
    let src_path = fixtures().join("u-to-s/source.svg");
    let text = std::fs::read_to_string(&src_path).unwrap();
    let src = open(&src_path);
    for angle in [30.0, 90.0, 179.0, 181.0, 270.0, 350.0] {
        let (scale, shift) = (1.7, Point::new(40.0, -25.0));
        let tr = format!(
            "translate({} {}) scale({scale}) rotate({angle})",
            shift.x, shift.y
        );
        let tgt = Drawing::from_str(
            "rotated.svg",
            &transformed(&text, &tr),
            &ReadOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let c =
            build(&src, &tgt, &MorphOptions::default()).unwrap_or_else(|e| panic!("{angle}°: {e}"));
        let m = &c.meshes;
        let f = similarity(angle, scale, shift);
        let tol = 1e-9 * c.tolerances.diagonal;
        let worst = m
            .source
            .iter()
            .zip(&m.target)
            .map(|(p, q)| f(*p).distance(*q))
            .fold(0.0, f64::max);
        assert!(
            worst <= tol,
            "{angle}°: target mesh is off the similarity by {worst}"
        );

        let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
        // the short way round: 181° turns by -179°
        let expected = if angle > 180.0 { angle - 360.0 } else { angle };
        for k in 1..10 {
            let t = k as f64 / 10.0;
            let v = interp.at_vec(t);
            let (a, s, res) = fit(&m.source, &v);
            assert!(
                res <= 1e-8 * c.tolerances.diagonal,
                "{angle}° t={t}: not a similarity ({res})"
            );
            assert!(
                (a.to_degrees() - t * expected).abs() < 1e-6,
                "{angle}° t={t}: angle {}",
                a.to_degrees()
            );
            assert!(
                (s - (1.0 - t + t * scale)).abs() < 1e-9,
                "{angle}° t={t}: scale {s}"
            );
        }
    }
}
