//! Relaxing the mapped mesh towards the shapes of the triangulated one (a step after §5 that
//! the paper does not have; issue #9 item 4).
//!
//! The composite harmonic map is flip-free but not shape-aware: where the target bends a lot
//! it leaves slivers (triangles of 3–5° whose source twins have 25° and more). The disc
//! interpolation of eq. (1) then has to turn a fat triangle into a needle, and in between it
//! folds some of them, more often when rounding or a density other than the default moves the
//! vertices a little. Moving a free vertex of the mapped mesh anywhere in its star's kernel
//! keeps the two meshes compatible and every feature aligned (curve vertices never move), so
//! this pass moves each free vertex towards where its star's triangles would put it if each
//! were similar to its twin: the mean, over the star, of the apex that the similarity carrying
//! the twin's opposite side onto this side gives. A move is taken only if the star stays
//! positive and its worst distortion (the singular-value ratio of the affine map from the
//! twin, `quality::distortion`) does not grow.

use crate::geometry::Point;
use crate::mesh::is_positive as positive;

/// Passes over the free vertices.
const PASSES: usize = 8;

/// Stars whose worst distortion is at most this are left as the harmonic map placed them.
const CALM: f64 = 2.0;

/// Relaxes `mapped` (the mesh that the harmonic map produced) towards the triangle shapes of
/// `rest` (the triangulated mesh), with the vertices flagged in `held` kept where they are;
/// returns how many moves were taken. Deterministic: vertices are visited in index order.
pub(crate) fn relax_towards(
    rest: &[Point],
    mapped: &mut [Point],
    triangles: &[[u32; 3]],
    held: &[bool],
) -> usize {
    let n = mapped.len();
    if rest.len() != n {
        return 0;
    }
    let star = crate::mesh::stars(triangles, n);
    let distortion = |mapped: &[Point], g: u32| {
        crate::quality::triangle_distortion(triangles[g as usize], rest, mapped)
    };
    let worst = |mapped: &[Point], v: usize| -> f64 {
        star[v]
            .iter()
            .map(|&g| distortion(mapped, g))
            .fold(1.0, f64::max)
    };
    // Every triangle's distortion, kept up to date as vertices move: a star none of whose
    // vertices moved has the same worst distortion as before, read without recomputing it.
    let mut known: Vec<f64> = (0..triangles.len() as u32)
        .map(|g| distortion(mapped, g))
        .collect();
    let mut moves = 0;
    for _ in 0..PASSES {
        let mut moved = false;
        for v in 0..n {
            if held.get(v).copied().unwrap_or(true) || star[v].is_empty() {
                continue;
            }
            let before = star[v]
                .iter()
                .map(|&g| known[g as usize])
                .fold(1.0, f64::max);
            if before <= CALM {
                continue;
            }
            let mut sum = Point::ZERO;
            let mut weight = 0.0;
            for &g in &star[v] {
                let t = triangles[g as usize];
                let Some(k) = t.iter().position(|&x| x as usize == v) else {
                    continue;
                };
                let (a, b) = (t[(k + 1) % 3] as usize, t[(k + 2) % 3] as usize);
                let (ra, rb, ma, mb) = (rest[a], rest[b], mapped[a], mapped[b]);
                let d = rb - ra;
                let len = d.length_squared();
                if len == 0.0 {
                    continue;
                }
                // The similarity z ↦ ma + (z − ra)·q with q = (mb − ma)/(rb − ra) (complex).
                let m = mb - ma;
                let q = Point::new(m.x * d.x + m.y * d.y, m.y * d.x - m.x * d.y) / len;
                let z = rest[v] - ra;
                let apex = ma + Point::new(z.x * q.x - z.y * q.y, z.x * q.y + z.y * q.x);
                sum += apex * len;
                weight += len;
            }
            if weight <= 0.0 {
                continue;
            }
            let aim = sum / weight;
            let old = mapped[v];
            for step in [1.0, 0.5, 0.25] {
                mapped[v] = old + (aim - old) * step;
                let ok = star[v]
                    .iter()
                    .all(|&g| positive(mapped, triangles[g as usize]));
                if ok && worst(mapped, v) <= before {
                    break;
                }
                mapped[v] = old;
            }
            if mapped[v] != old {
                moved = true;
                moves += 1;
                for &g in &star[v] {
                    known[g as usize] = distortion(mapped, g);
                }
            }
        }
        if !moved {
            break;
        }
    }
    moves
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan whose centre the map pushed next to one side: relaxing brings it back to where
    /// the triangles are similar to their twins (the centre of the regular hexagon), and held
    /// vertices stay.
    #[test]
    fn a_pushed_centre_returns_to_similar_triangles() {
        let (rest, tris) = crate::mesh::hexagon_fan();
        // The mapped mesh: the same hexagon turned and scaled, its centre pushed aside.
        let turn = |p: Point| Point::new(2.0 * p.y, -2.0 * p.x) + Point::new(5.0, 1.0);
        let mut mapped: Vec<Point> = rest.iter().map(|&p| turn(p)).collect();
        mapped[6] = turn(Point::new(0.8, 0.1));
        let mut held = vec![true; 7];
        held[6] = false;
        let before = crate::quality::max_distortion(&tris, &rest, &mapped);
        assert!(relax_towards(&rest, &mut mapped, &tris, &held) > 0);
        let after = crate::quality::max_distortion(&tris, &rest, &mapped);
        assert!(after < 1.0 + 1e-9 && after < before, "{before} → {after}");
        assert!(mapped[6].distance(turn(Point::ZERO)) < 1e-9);
        for k in 0..6 {
            assert_eq!(mapped[k], turn(rest[k]));
        }
    }
}
