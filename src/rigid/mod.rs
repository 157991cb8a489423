//! Disc-based rigidity-preserving interpolation with globally consistent rotation (§4.1).
//!
//! PLACEHOLDER (mapping branch): a small dense implementation of the agreed API, good enough for
//! the few points of the barycenter mesh (§5). It is replaced by the real sparse implementation at
//! merge time.

use crate::geometry::Point;
use crate::{Error, Result};
use std::f64::consts::PI;

/// Local transformation of one disc edge `(i, j)`: rotation angle and scale from `p_j − p_i` to
/// `q_j − q_i` (§4.1).
#[derive(Debug, Clone, Copy)]
struct LocalTransform {
    i: usize,
    j: usize,
    alpha: f64,
    scale: f64,
}

/// Precomputed interpolation between two compatible point sets, with disc neighbourhoods.
#[derive(Debug, Clone)]
pub struct Interpolator {
    source: Vec<Point>,
    transforms: Vec<LocalTransform>,
    disc_rotation: Vec<f64>,
    centroid: (Point, Point),
    /// Row-major inverse of the regularized normal matrix `L + 1 1ᵀ` (n × n).
    inverse: Vec<f64>,
}

/// Scratch buffers for [`Interpolator::at`].
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    rhs: Vec<Point>,
}

/// `a + 2kπ` closest to `reference`.
fn branch_near(a: f64, reference: f64) -> f64 {
    a + 2.0 * PI * ((reference - a) / (2.0 * PI)).round()
}

impl Interpolator {
    /// Builds the interpolator: local transformations per disc edge, rotations made consistent
    /// by propagation over a spanning tree of the disc graph, and the factored normal equations of
    /// eq. (1).
    pub fn from_discs(source: &[Point], target: &[Point], discs: &[Vec<u32>]) -> Result<Self> {
        let n = source.len();
        if target.len() != n || discs.len() != n || n == 0 {
            return Err(Error::internal("interpolator: mismatched point sets"));
        }
        let mut transforms = Vec::new();
        let mut per_disc: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (i, disc) in discs.iter().enumerate() {
            for &j in disc {
                let j = j as usize;
                if j >= n || j == i {
                    return Err(Error::internal("interpolator: bad disc index"));
                }
                let (a, b) = (source[j] - source[i], target[j] - target[i]);
                if a.length() == 0.0 || b.length() == 0.0 {
                    continue;
                }
                let alpha = a.perp_dot(b).atan2(a.dot(b));
                per_disc[i].push(transforms.len());
                transforms.push(LocalTransform {
                    i,
                    j,
                    alpha,
                    scale: b.length() / a.length(),
                });
            }
        }
        // Disc rotation: circular mean of its edges' angles; then made consistent by breadth-first
        // propagation from the disc with the smallest rotation magnitude.
        let mut disc_rotation: Vec<f64> = per_disc
            .iter()
            .map(|ks| {
                let (s, c) = ks.iter().fold((0.0, 0.0), |(s, c), &k| {
                    (s + transforms[k].alpha.sin(), c + transforms[k].alpha.cos())
                });
                if ks.is_empty() {
                    0.0
                } else {
                    s.atan2(c)
                }
            })
            .collect();
        let mut done = vec![false; n];
        while let Some(root) = (0..n)
            .filter(|&i| !done[i])
            .min_by(|&a, &b| disc_rotation[a].abs().total_cmp(&disc_rotation[b].abs()))
        {
            done[root] = true;
            let mut queue = std::collections::VecDeque::from([root]);
            while let Some(i) = queue.pop_front() {
                for &j in &discs[i] {
                    let j = j as usize;
                    if !done[j] {
                        done[j] = true;
                        disc_rotation[j] = branch_near(disc_rotation[j], disc_rotation[i]);
                        queue.push_back(j);
                    }
                }
            }
        }
        for t in &mut transforms {
            t.alpha = branch_near(t.alpha, disc_rotation[t.i]);
        }
        // Normal matrix of Σ |(v_j − v_i) − L_ij|², regularized with 1 1ᵀ to fix the centroid.
        let mut a = vec![1.0; n * n];
        for t in &transforms {
            let (i, j) = (t.i, t.j);
            a[i * n + i] += 1.0;
            a[j * n + j] += 1.0;
            a[i * n + j] -= 1.0;
            a[j * n + i] -= 1.0;
        }
        let inverse = invert(&a, n)
            .ok_or_else(|| Error::internal("interpolator: disc graph is not connected"))?;
        let c0 = crate::geometry::centroid(source);
        let c1 = crate::geometry::centroid(target);
        Ok(Interpolator {
            source: source.to_vec(),
            transforms,
            disc_rotation,
            centroid: (c0, c1),
            inverse,
        })
    }

    /// A scratch workspace for [`Interpolator::at`].
    pub fn workspace(&self) -> Workspace {
        Workspace {
            rhs: vec![Point::ZERO; self.source.len()],
        }
    }

    /// Positions at time `t` (0 = source, 1 = target) into `out`.
    pub fn at(&self, t: f64, out: &mut [Point], ws: &mut Workspace) {
        let n = self.source.len();
        ws.rhs.clear();
        ws.rhs.resize(n, Point::ZERO);
        for lt in &self.transforms {
            let d = self.source[lt.j] - self.source[lt.i];
            let (s, c) = (t * lt.alpha).sin_cos();
            let l = Point::new(c * d.x - s * d.y, s * d.x + c * d.y) * (1.0 - t + t * lt.scale);
            ws.rhs[lt.j] += l;
            ws.rhs[lt.i] -= l;
        }
        let c = self.centroid.0 * (1.0 - t) + self.centroid.1 * t;
        for r in &mut ws.rhs {
            *r += c * n as f64;
        }
        for (i, o) in out.iter_mut().enumerate().take(n) {
            *o = (0..n).map(|k| ws.rhs[k] * self.inverse[i * n + k]).sum();
        }
    }

    /// Consistent rotation (radians) of point `i`'s disc.
    pub fn rotation_at(&self, i: usize) -> f64 {
        self.disc_rotation[i]
    }
}

/// Gauss–Jordan inverse with partial pivoting of a small dense matrix.
fn invert(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut m = a.to_vec();
    let mut inv = vec![0.0; n * n];
    for i in 0..n {
        inv[i * n + i] = 1.0;
    }
    for col in 0..n {
        let piv =
            (col..n).max_by(|&x, &y| m[x * n + col].abs().total_cmp(&m[y * n + col].abs()))?;
        if m[piv * n + col].abs() < 1e-12 {
            return None;
        }
        for k in 0..n {
            m.swap(col * n + k, piv * n + k);
            inv.swap(col * n + k, piv * n + k);
        }
        let d = m[col * n + col];
        for k in 0..n {
            m[col * n + k] /= d;
            inv[col * n + k] /= d;
        }
        for r in 0..n {
            if r != col {
                let f = m[r * n + col];
                if f != 0.0 {
                    for k in 0..n {
                        m[r * n + k] -= f * m[col * n + k];
                        inv[r * n + k] -= f * inv[col * n + k];
                    }
                }
            }
        }
    }
    Some(inv)
}
