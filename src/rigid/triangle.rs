//! Triangle-based as-rigid-as-possible interpolation, the baseline of §4.1 (Alexa et al. 2000,
//! in the normal-equation form of Baxter et al. 2008).
//!
//! Every triangle `f` has the affine map `A_f = Q_f P_f⁻¹` from its source edge matrix
//! `P_f = [p₁ − p₀, p₂ − p₀]` to its target one. Its polar decomposition `A_f = R(θ_f)·S_f`
//! (`S_f` symmetric) gives the intermediate `A_f(t) = R(t·θ_f)·((1 − t)I + t·S_f)`. The angles
//! `θ_f` are made consistent across triangles sharing an edge with the same minimum-spanning-tree
//! propagation as the disc method (§4.1.1). The frame minimizes
//! `Σ_f ‖B_f(V) − A_f(t)‖²_F`, where `B_f(V) = [v₁ − v₀, v₂ − v₀] P_f⁻¹` is the affine map the frame
//! gives the triangle — Alexa et al.'s unweighted sum, so every triangle pulls equally however
//! thin it is. `B_f` is linear in `V` through the triangle's constant gradient matrix, so the
//! normal equations' matrix is constant and factored once; translation is pinned as for the disc
//! method (see [`super::assembly`]).

use super::assembly::{component_centroids, lerp_into, FactoredSystem, SystemBuilder};
use super::disc::{validate_points, FrameScratch};
use super::rotation::consistent_angles;
use crate::error::{Error, Result};
use crate::geometry::Point;

/// Per-triangle data of the baseline.
#[derive(Debug, Clone, Copy)]
struct TriangleTerm {
    /// Right-hand-side rows of the three corners.
    rows: [u32; 3],
    /// Rows of the gradient matrix `G = [[-1,-1],[1,0],[0,1]]·P⁻¹`: `g_k` for corner `k`.
    g: [Point; 3],
    /// Symmetric stretch `S = [[s00, s01], [s01, s11]]`.
    s: [f64; 3],
}

/// The triangle baseline, set up.
#[derive(Debug)]
pub(crate) struct TriangleRigid {
    terms: Vec<TriangleTerm>,
    /// Consistent polar rotation angle of each triangle.
    theta: Vec<f64>,
    system: FactoredSystem,
    centroid_source: Vec<Point>,
    centroid_target: Vec<Point>,
}

/// `M⁻¹` of the 2×2 matrix with columns `a`, `b`, as its rows (so `M⁻¹ x = (r0·x, r1·x)`).
fn inverse_columns(a: Point, b: Point) -> Option<[Point; 2]> {
    let det = a.perp_dot(b);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some([Point::new(b.y, -b.x) / det, Point::new(-a.y, a.x) / det])
}

/// Polar decomposition of the 2×2 matrix `[[a, b], [c, d]]` = `R(θ)·S`, `S` symmetric.
pub(crate) fn polar(a: f64, b: f64, c: f64, d: f64) -> (f64, [f64; 3]) {
    let theta = (c - b).atan2(a + d);
    let (sn, cs) = theta.sin_cos();
    // S = R(−θ)·A; its off-diagonal entries agree by the choice of θ.
    let s00 = cs * a + sn * c;
    let s01 = cs * b + sn * d;
    let s11 = -sn * b + cs * d;
    (theta, [s00, s01, s11])
}

impl TriangleRigid {
    pub(crate) fn new(source: &[Point], target: &[Point], triangles: &[[u32; 3]]) -> Result<Self> {
        validate_points(source, target)?;
        let n = source.len();
        let mut raw = Vec::with_capacity(triangles.len());
        let mut builder = SystemBuilder::new(n);
        for (f, tri) in triangles.iter().enumerate() {
            let [i0, i1, i2] = tri.map(|v| v as usize);
            if i0 >= n || i1 >= n || i2 >= n || i0 == i1 || i1 == i2 || i0 == i2 {
                return Err(Error::input(
                    crate::error::Drawings::Source,
                    format!("triangle {f} has invalid vertex indices {tri:?}"),
                ));
            }
            let Some(pinv) = inverse_columns(source[i1] - source[i0], source[i2] - source[i0])
            else {
                return Err(Error::input(
                    crate::error::Drawings::Source,
                    format!("triangle {f} is degenerate (zero area)"),
                ));
            };
            // A = Q P⁻¹: column k of A is Q times column k of P⁻¹.
            let (qa, qb) = (target[i1] - target[i0], target[i2] - target[i0]);
            let col = |k: usize| qa * pinv[0][k] + qb * pinv[1][k];
            let (c0, c1) = (col(0), col(1));
            let (theta, s) = polar(c0.x, c1.x, c0.y, c1.y);
            // Rows of G: corner 0 is −(r0 + r1) transposed, corners 1, 2 are P⁻¹'s rows.
            let g = [-(pinv[0] + pinv[1]), pinv[0], pinv[1]];
            let mut block = [0.0; 9];
            for a in 0..3 {
                for b in 0..3 {
                    block[a * 3 + b] = g[a].dot(g[b]);
                }
            }
            builder.add_block(tri, &block);
            raw.push((g, theta, s));
        }
        let links = adjacent_triangles(triangles);
        let thetas: Vec<f64> = raw.iter().map(|r| r.1).collect();
        let thetas = consistent_angles(&thetas, &links);
        // Alexa's energy weighs each triangle by the inverse of its shape, so near-degenerate
        // triangles make the system numerically singular: the sensitivity the paper's Fig.13
        // shows. Say so instead of reporting an internal failure.
        let system = builder.factor().map_err(|e| match e {
            Error::Internal(m) if m.contains("not positive definite") => Error::input(
                "<meshes>",
                "the triangle-based interpolation cannot handle this mesh: near-degenerate \
                 triangles make its system numerically singular",
            )
            .with_hint("use --method disc, which does not depend on triangle shapes"),
            other => other,
        })?;
        let terms = triangles
            .iter()
            .zip(raw)
            .map(|(tri, (g, _, s))| TriangleTerm {
                rows: tri.map(|v| system.rhs_index(v) as u32),
                g,
                s,
            })
            .collect();
        let count = system.component_count();
        Ok(TriangleRigid {
            centroid_source: component_centroids(system.components(), count, source),
            centroid_target: component_centroids(system.components(), count, target),
            terms,
            theta: thetas,
            system,
        })
    }

    /// Bytes of the factor one pass of a frame's solve reads.
    pub(crate) fn factor_bytes(&self) -> usize {
        self.system.factor_bytes()
    }

    pub(crate) fn scratch(&self) -> FrameScratch {
        FrameScratch::new(&self.system, self.centroid_source.len(), self.terms.len())
    }

    pub(crate) fn at(&self, t: f64, out: &mut [Point], ws: &mut FrameScratch) {
        ws.rotations(t, &self.theta);
        let rhs = &mut ws.solve.rhs;
        rhs.fill(Point::ZERO);
        for ((f, &sn), &cs) in self.terms.iter().zip(&ws.sin).zip(&ws.cos) {
            // M = (1 − t)I + tS, then A(t) = R(tθ) M.
            let (m00, m01, m11) = (1.0 - t + t * f.s[0], t * f.s[1], 1.0 - t + t * f.s[2]);
            let a00 = cs * m00 - sn * m01;
            let a01 = cs * m01 - sn * m11;
            let a10 = sn * m00 + cs * m01;
            let a11 = sn * m01 + cs * m11;
            for (k, g) in f.g.iter().enumerate() {
                let r = f.rows[k] as usize;
                rhs[r] += Point::new(a00 * g.x + a01 * g.y, a10 * g.x + a11 * g.y);
            }
        }
        lerp_into(
            &mut ws.centroids,
            &self.centroid_source,
            &self.centroid_target,
            t,
        );
        self.system.solve(&mut ws.solve, &ws.centroids, out);
    }
}

/// Pairs of triangles sharing an edge.
fn adjacent_triangles(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut half: Vec<(u32, u32, u32)> = triangles
        .iter()
        .enumerate()
        .flat_map(|(f, t)| {
            [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])].map(|(a, b)| (a.min(b), a.max(b), f as u32))
        })
        .collect();
    half.sort_unstable();
    half.windows(2)
        .filter(|w| w[0].0 == w[1].0 && w[0].1 == w[1].1)
        .map(|w| (w[0].2, w[1].2))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polar_decomposition_recovers_rotation_and_stretch() {
        let theta = 2.5f64;
        let (sn, cs) = theta.sin_cos();
        // S = [[2, 0.3], [0.3, 0.7]], A = R S.
        let s = [2.0, 0.3, 0.7];
        let a = cs * s[0] - sn * s[1];
        let b = cs * s[1] - sn * s[2];
        let c = sn * s[0] + cs * s[1];
        let d = sn * s[1] + cs * s[2];
        let (th, got) = polar(a, b, c, d);
        assert!((th - theta).abs() < 1e-12);
        for k in 0..3 {
            assert!((got[k] - s[k]).abs() < 1e-12);
        }
    }
}
