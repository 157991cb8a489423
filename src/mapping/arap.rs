//! As-rigid-as-possible relaxation of the free vertices toward the triangulated mesh's own shape
//! (local/global iterations of Liu et al. 2008), used after each harmonic step of the composite
//! map.
//!
//! Why: a harmonic map follows its Dirichlet values smoothly but has no memory of the original
//! triangle shapes, so over many composite steps triangles near strongly moving curves thin out
//! until even a tiny step folds them. Relaxing toward the rest shape after every step keeps the
//! triangles close to their original (Delaunay-refined) shapes, which is what lets later steps
//! stay flip-free. This goes beyond the paper's §5, which composes plain harmonic maps.
//!
//! The energy is `Σ_t Σ_{(i,j) ∈ t} w_ij ‖(v_i − v_j) − R_t (p_i − p_j)‖²` with the cotangent
//! weights `w` of the rest mesh `p`; its global step is a Poisson solve whose matrix is the rest
//! mesh's cotangent Laplacian restricted to the free vertices — constant, so it is factored once.
//! Per triangle the energy equals `area · ‖J_t − R_t‖²`, so the matrix is positive semi-definite
//! even with the negative weights of obtuse triangles, and positive definite once the curve
//! vertices are fixed. Cotangent weights annihilate linear functions, so a configuration that is
//! an exact similarity of the rest mesh is a fixed point: similarities stay exact.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};

use crate::geometry::Point;
use crate::{Error, Result};

const NONE: u32 = u32::MAX;

/// A factored ARAP relaxation for one rest mesh and one set of fixed vertices.
#[derive(Debug)]
pub struct ArapRelax {
    triangles: Vec<[u32; 3]>,
    /// Per triangle and corner k: the cotangent weight (½ cot of the angle at k) of the edge
    /// opposite corner k, from `t[k+1]` to `t[k+2]`.
    weights: Vec<[f64; 3]>,
    /// Per triangle and corner k: the rest edge vector `p[t[k+1]] − p[t[k+2]]`.
    rest_edges: Vec<[Point; 3]>,
    free_index: Vec<u32>,
    free_vertices: Vec<u32>,
    llt: Option<Llt<usize, f64>>,
    rotations: Vec<(f64, f64)>,
    rhs: Mat<f64>,
}

impl ArapRelax {
    /// Factors the relaxation for the rest mesh `rest` (positively oriented) with the vertices
    /// marked in `fixed` held in place.
    pub fn new(rest: &[Point], triangles: &[[u32; 3]], fixed: &[bool]) -> Result<Self> {
        let n = rest.len();
        if fixed.len() != n || triangles.iter().flatten().any(|&v| v as usize >= n) {
            return Err(Error::internal("ARAP relaxation: index out of range"));
        }
        let mut free_index = vec![NONE; n];
        let mut free_vertices = Vec::new();
        for v in 0..n {
            if !fixed[v] {
                free_index[v] = free_vertices.len() as u32;
                free_vertices.push(v as u32);
            }
        }
        let mut weights = Vec::with_capacity(triangles.len());
        let mut rest_edges = Vec::with_capacity(triangles.len());
        let mut triplets = Vec::new();
        for t in triangles {
            let p = t.map(|v| rest[v as usize]);
            let twice_area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
            if !(twice_area > 0.0) {
                return Err(Error::internal("ARAP relaxation: degenerate rest triangle"));
            }
            let mut w = [0.0; 3];
            let mut e = [Point::ZERO; 3];
            for k in 0..3 {
                let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                w[k] = 0.5 * a.dot(b) / twice_area;
                e[k] = p[(k + 1) % 3] - p[(k + 2) % 3];
                let (i, j) = (t[(k + 1) % 3] as usize, t[(k + 2) % 3] as usize);
                let (fi, fj) = (free_index[i], free_index[j]);
                if fi != NONE {
                    triplets.push(Triplet::new(fi as usize, fi as usize, w[k]));
                }
                if fj != NONE {
                    triplets.push(Triplet::new(fj as usize, fj as usize, w[k]));
                }
                if fi != NONE && fj != NONE {
                    let (lo, hi) = (fi.min(fj) as usize, fi.max(fj) as usize);
                    triplets.push(Triplet::new(lo, hi, -w[k]));
                }
            }
            weights.push(w);
            rest_edges.push(e);
        }
        let nf = free_vertices.len();
        let llt = if nf > 0 {
            let m = SparseColMat::<usize, f64>::try_new_from_triplets(nf, nf, &triplets)
                .map_err(|e| Error::internal(format!("ARAP relaxation: assembly: {e:?}")))?;
            Some(
                Llt::try_new_with_symbolic(
                    faer::sparse::linalg::solvers::SymbolicLlt::try_new(m.symbolic(), Side::Upper)
                        .map_err(|e| Error::internal(format!("ARAP relaxation: {e:?}")))?,
                    m.as_ref(),
                    Side::Upper,
                )
                .map_err(|e| Error::internal(format!("ARAP relaxation: factorization: {e:?}")))?,
            )
        } else {
            None
        };
        Ok(ArapRelax {
            triangles: triangles.to_vec(),
            rotations: vec![(1.0, 0.0); triangles.len()],
            weights,
            rest_edges,
            free_index,
            free_vertices,
            llt,
            rhs: Mat::zeros(nf, 2),
        })
    }

    /// Runs `iterations` local/global iterations on `v`: fixed entries stay, free entries move
    /// toward the as-rigid-as-possible placement.
    pub fn relax(&mut self, v: &mut [Point], iterations: usize) -> Result<()> {
        let Some(llt) = &self.llt else {
            return Ok(());
        };
        if v.len() != self.free_index.len() {
            return Err(Error::internal("ARAP relaxation: wrong vertex count"));
        }
        for _ in 0..iterations {
            // Local step: the best rotation of each triangle's rest edges onto its current edges.
            for (((t, w), e), r) in self
                .triangles
                .iter()
                .zip(&self.weights)
                .zip(&self.rest_edges)
                .zip(&mut self.rotations)
            {
                let (mut dot, mut cross) = (0.0, 0.0);
                for k in 0..3 {
                    let d = v[t[(k + 1) % 3] as usize] - v[t[(k + 2) % 3] as usize];
                    dot += w[k] * e[k].dot(d);
                    cross += w[k] * e[k].perp_dot(d);
                }
                let len = dot.hypot(cross);
                *r = if len > 0.0 {
                    (dot / len, cross / len)
                } else {
                    (1.0, 0.0)
                };
            }
            // Global step: L_ff v_f = b_f + Σ_fixed w v_fixed.
            self.rhs.fill(0.0);
            for (((t, w), e), &(c, s)) in self
                .triangles
                .iter()
                .zip(&self.weights)
                .zip(&self.rest_edges)
                .zip(&self.rotations)
            {
                for k in 0..3 {
                    let (i, j) = (t[(k + 1) % 3] as usize, t[(k + 2) % 3] as usize);
                    let re = Point::new(c * e[k].x - s * e[k].y, s * e[k].x + c * e[k].y) * w[k];
                    let (fi, fj) = (self.free_index[i], self.free_index[j]);
                    if fi != NONE {
                        let mut b = re;
                        if fj == NONE {
                            b += v[j] * w[k];
                        }
                        self.rhs[(fi as usize, 0)] += b.x;
                        self.rhs[(fi as usize, 1)] += b.y;
                    }
                    if fj != NONE {
                        let mut b = -re;
                        if fi == NONE {
                            b += v[i] * w[k];
                        }
                        self.rhs[(fj as usize, 0)] += b.x;
                        self.rhs[(fj as usize, 1)] += b.y;
                    }
                }
            }
            llt.solve_in_place(self.rhs.as_mut());
            for (f, &vtx) in self.free_vertices.iter().enumerate() {
                let p = Point::new(self.rhs[(f, 0)], self.rhs[(f, 1)]);
                if !p.is_finite() {
                    return Err(Error::internal("ARAP relaxation: non-finite solution"));
                }
                v[vtx as usize] = p;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangulated grid of `n × n` cells; the border vertices are fixed.
    fn grid(n: usize) -> (Vec<Point>, Vec<[u32; 3]>, Vec<bool>) {
        let mut pts = Vec::new();
        let mut fixed = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                pts.push(Point::new(
                    x as f64,
                    y as f64 + 0.3 * (x as f64 * 0.7).sin(),
                ));
                fixed.push(x == 0 || y == 0 || x == n || y == n);
            }
        }
        let id = |x: usize, y: usize| (y * (n + 1) + x) as u32;
        let mut tris = Vec::new();
        for y in 0..n {
            for x in 0..n {
                tris.push([id(x, y), id(x + 1, y), id(x + 1, y + 1)]);
                tris.push([id(x, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
        (pts, tris, fixed)
    }

    #[test]
    fn similarities_are_fixed_points() {
        let (p, t, fixed) = grid(8);
        let mut a = ArapRelax::new(&p, &t, &fixed).unwrap();
        let (s, c) = 2.5f64.sin_cos();
        let sim =
            |q: Point| Point::new(c * q.x - s * q.y, s * q.x + c * q.y) * 1.7 + Point::new(3., -1.);
        let mut v: Vec<Point> = p.iter().map(|q| sim(*q)).collect();
        a.relax(&mut v, 5).unwrap();
        for (q, r) in p.iter().zip(&v) {
            assert!(sim(*q).distance(*r) < 1e-10, "{} vs {}", sim(*q), r);
        }
    }

    #[test]
    fn relaxation_restores_a_scrambled_interior_of_a_rigid_motion() {
        let (p, t, fixed) = grid(8);
        let mut a = ArapRelax::new(&p, &t, &fixed).unwrap();
        let (s, c) = 0.8f64.sin_cos();
        let rot = |q: Point| Point::new(c * q.x - s * q.y, s * q.x + c * q.y);
        // border rotated exactly, interior left where it was (badly folded)
        let mut v: Vec<Point> = p
            .iter()
            .zip(&fixed)
            .map(|(q, f)| if *f { rot(*q) } else { *q })
            .collect();
        assert!(crate::mesh::count_inverted(&t, &v) > 0);
        a.relax(&mut v, 30).unwrap();
        assert_eq!(crate::mesh::count_inverted(&t, &v), 0);
        let worst = p
            .iter()
            .zip(&v)
            .map(|(q, r)| rot(*q).distance(*r))
            .fold(0.0, f64::max);
        assert!(worst < 1e-6, "{worst}");
    }
}
