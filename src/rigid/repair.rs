//! Fold repair: a post-solve pass that straightens the few triangles a frame of eq. (1) inverts
//! (a deviation from the paper, which has no such pass; issue #7 item 2 and issue #9 item 4).
//!
//! The disc interpolation of two valid compatible meshes can still fold a triangle in between,
//! where neighbouring local transformations disagree a lot (slivers of an overlaid
//! triangulation, a mesh pushed through a narrow neck). Those folds are local: a handful of
//! triangles out of thousands. So after the solve, each free vertex (not on a curve, whose
//! position the frame must keep) of an inverted triangle is moved within its star — to the
//! mean of its neighbours, or part of the way there — when that leaves fewer inverted
//! triangles around it, then tries the same again, a few passes at most.
//!
//! Why this keeps the ends exact: the meshes at t = 0 and t = 1 fold nothing, so the pass does
//! nothing there. Why it is deterministic: vertices are visited in a fixed order. What it
//! cannot do: straighten a triangle whose three vertices are all on curves (the outline
//! itself folding); such frames stay as they are, and callers count them.

use crate::geometry::{orient2d, Point};

/// Passes over the inverted triangles per frame.
const PASSES: usize = 10;

/// What the repair needs of a mesh, precomputed once.
#[derive(Debug, Clone)]
pub(crate) struct FoldRepair {
    /// The triangles checked (a subset of the mesh's, e.g. the parts that can fold).
    triangles: Vec<[u32; 3]>,
    /// Per vertex: whether it may move (not on a curve).
    free: Vec<bool>,
    /// Per vertex: the checked triangles around it (indices into `triangles`).
    star: Vec<Vec<u32>>,
    /// Per vertex: its neighbours in the checked triangles.
    ring: Vec<Vec<u32>>,
}

use crate::mesh::is_positive as positive;

impl FoldRepair {
    /// The repair of `triangles` over `n` points, of which those flagged in `fixed` never move.
    pub(crate) fn new(triangles: &[[u32; 3]], n: usize, fixed: &[bool]) -> Self {
        let star = crate::mesh::stars(triangles, n);
        let ring = crate::mesh::one_rings(triangles, n);
        FoldRepair {
            triangles: triangles.to_vec(),
            free: (0..n)
                .map(|v| !fixed.get(v).copied().unwrap_or(false))
                .collect(),
            star,
            ring,
        }
    }

    /// Straightens the inverted triangles of frame `out` where a free vertex can (module docs);
    /// returns how many stay inverted.
    pub(crate) fn apply(&self, out: &mut [Point]) -> usize {
        let mut bad: Vec<u32> = (0..self.triangles.len() as u32)
            .filter(|&f| !positive(out, self.triangles[f as usize]))
            .collect();
        for _ in 0..PASSES {
            if bad.is_empty() {
                break;
            }
            let mut moved = false;
            for &f in &bad {
                for &v in &self.triangles[f as usize] {
                    moved |= self.relax(v as usize, out);
                }
            }
            if !moved {
                break;
            }
            bad.retain(|&f| !positive(out, self.triangles[f as usize]));
        }
        bad.len()
    }

    /// Moves free vertex `v` to the candidate that best straightens its star — fewest inverted
    /// triangles, then the largest smallest signed area — among the mean of its neighbours,
    /// points part of the way there, and for each triangle of its star a point just inside the
    /// side opposite `v`; whether it moved.
    fn relax(&self, v: usize, out: &mut [Point]) -> bool {
        if !self.free[v] || self.ring[v].is_empty() {
            return false;
        }
        // (inverted triangles, smallest doubled signed area) of the star with v at p.
        let score = |out: &mut [Point], p: Point| -> (usize, f64) {
            out[v] = p;
            let mut bad = 0;
            let mut least = f64::INFINITY;
            for &g in &self.star[v] {
                let [a, b, c] = self.triangles[g as usize].map(|k| out[k as usize]);
                let o = orient2d(a, b, c);
                if o <= 0.0 {
                    bad += 1;
                }
                least = least.min((b - a).perp_dot(c - a));
            }
            (bad, least)
        };
        let old = out[v];
        let before = score(out, old);
        if before.0 == 0 {
            return false;
        }
        let mean = self.ring[v].iter().map(|&w| out[w as usize]).sum::<Point>()
            / self.ring[v].len() as f64;
        let mut candidates: Vec<Point> = [1.0, 0.5, 0.25, 0.75, 0.1]
            .iter()
            .map(|&s| old + (mean - old) * s)
            .collect();
        for &g in &self.star[v] {
            let t = self.triangles[g as usize];
            let k = t.iter().position(|&x| x as usize == v).unwrap_or(0);
            let (a, b) = (out[t[(k + 1) % 3] as usize], out[t[(k + 2) % 3] as usize]);
            // The side a → b is crossed counter-clockwise: inside is to its left.
            let inward = Point::new(-(b - a).y, (b - a).x);
            candidates.push((a + b) * 0.5 + inward * 0.3);
        }
        let better = |x: (usize, f64), y: (usize, f64)| x.0 < y.0 || (x.0 == y.0 && x.1 > y.1);
        let mut best = (before, old);
        for p in candidates {
            let s = score(out, p);
            if better(s, best.0) {
                best = (s, p);
            }
        }
        out[v] = best.1;
        best.1 != old
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan around a centre vertex pushed out of its star: the repair brings it back.
    #[test]
    fn a_pushed_out_vertex_returns_into_its_star() {
        let mut pts: Vec<Point> = (0..6)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 6.0;
                Point::new(a.cos(), a.sin())
            })
            .collect();
        pts.push(Point::ZERO);
        let tris: Vec<[u32; 3]> = (0..6u32).map(|k| [k, (k + 1) % 6, 6]).collect();
        let mut fixed = vec![true; 7];
        fixed[6] = false;
        let r = FoldRepair::new(&tris, 7, &fixed);
        let mut frame = pts.clone();
        frame[6] = Point::new(1.5, 0.2);
        assert!(crate::mesh::count_inverted(&tris, &frame) > 0);
        assert_eq!(r.apply(&mut frame), 0);
        assert_eq!(crate::mesh::count_inverted(&tris, &frame), 0);
        // A valid frame is left exactly as it is.
        let mut same = pts.clone();
        assert_eq!(r.apply(&mut same), 0);
        assert_eq!(same, pts);
    }
}
