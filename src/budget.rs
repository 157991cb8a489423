//! The vertex budget: how many vertices a compatible triangulation of given curves gets at given
//! tolerances, worked out before it is built, and the one-line error when that passes
//! [`Limits::vertices`] (issue #12).
//!
//! `--density` multiplies the vertices per unit length, so the count of a mesh grows with its
//! square: a density of 50 asks for millions of vertices and minutes of work. The estimate is
//! what the stages do: correspondence splits every curve edge longer than
//! [`Tolerances::max_edge`] (the two curves of a pair get equal counts), and refinement fills
//! the inside with triangles no larger than [`Tolerances::max_area`] (of at least a third of
//! it, with its angle bound, so about one vertex per `max_area`).

use crate::error::{Error, Result};
use crate::geometry::{polygon_area, Point};
use crate::input::{Limit, Limits};
use crate::tolerance::Tolerances;

/// The vertices of a curve after correspondence at `max_edge`: its points, plus the points that
/// split its edges longer than `max_edge`.
pub fn curve_vertices(points: &[Point], closed: bool, max_edge: f64) -> f64 {
    let n = points.len();
    let edges = if closed { n } else { n.saturating_sub(1) };
    let split: f64 = (0..edges)
        .map(|i| {
            let k = points[i].distance(points[(i + 1) % n]) / max_edge;
            if k.is_finite() {
                k.ceil().max(1.0)
            } else {
                f64::INFINITY
            }
        })
        .sum();
    split + if closed { 0.0 } else { 1.0 }
}

/// The vertices refinement adds inside a closed outline `points` at `max_area`.
pub fn interior_vertices(points: &[Point], max_area: f64) -> f64 {
    let v = polygon_area(points).abs() / max_area;
    if v.is_nan() {
        f64::INFINITY
    } else {
        v
    }
}

/// The vertices of a compatible triangulation of one pair of shapes: the larger side's curves
/// (each pair of curves corresponds to equal counts, at least the larger of the two) and the
/// larger side's inside, with `tol`. Each side is its outline first, then its other curves.
pub fn mesh_vertices(
    source: &[(&[Point], bool)],
    target: &[(&[Point], bool)],
    tol: &Tolerances,
) -> f64 {
    let curves: f64 = source
        .iter()
        .zip(target)
        .map(|(a, b)| {
            curve_vertices(a.0, a.1, tol.max_edge).max(curve_vertices(b.0, b.1, tol.max_edge))
        })
        .sum();
    let inside = |side: &[(&[Point], bool)]| {
        side.first()
            .filter(|c| c.1)
            .map_or(0.0, |c| interior_vertices(c.0, tol.max_area))
    };
    curves + inside(source).max(inside(target))
}

/// The one-line error for a mesh of about `vertices` vertices when that passes the budget of
/// `limits`; `file` names the input(s).
pub fn check(vertices: f64, density: f64, file: &str, limits: &Limits) -> Result<()> {
    if vertices <= limits.vertices as f64 {
        return Ok(());
    }
    let density = if density > 0.0 { density } else { 1.0 };
    let what = format!(
        "a mesh of about {} vertices at density {density}",
        count_text(vertices)
    );
    let e: Error = Limit::Vertices.exceeded(file, &what, limits);
    Err(e)
}

/// A vertex count for a message: whole below a million, else in scientific notation.
pub fn count_text(n: f64) -> String {
    if n < 1e6 {
        format!("{n:.0}")
    } else {
        format!("{n:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_grow_with_the_square_of_the_density() {
        let sq = [
            Point::new(0.0, 0.0),
            Point::new(100.0, 0.0),
            Point::new(100.0, 100.0),
            Point::new(0.0, 100.0),
        ];
        let side = [(&sq[..], true)];
        let d = 100.0 * 2f64.sqrt();
        let one = mesh_vertices(&side, &side, &Tolerances::new(d, 1.0));
        let ten = mesh_vertices(&side, &side, &Tolerances::new(d, 10.0));
        assert!(one > 500.0 && one < 2000.0, "{one}");
        assert!(ten / one > 80.0 && ten / one < 101.0, "{}", ten / one);
        let l = Limits::default();
        assert!(check(one, 1.0, "a.svg", &l).is_ok());
        let e = check(1e7, 50.0, "a.svg", &l).unwrap_err().to_string();
        assert!(
            e.contains("--max-vertices") && e.contains("1.0e7") && !e.contains('\n'),
            "{e}"
        );
    }
}
