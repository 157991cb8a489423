//! Discrete harmonic map with cotangent weights (the harmonic coordinates of \[36\], §5).
//!
//! Given a triangulation, a set of fixed vertices with prescribed new positions, and the current
//! vertex positions (the *metric*), the free vertices are placed where the cotangent Laplacian of
//! the current mesh vanishes: `L_ff x_f = −L_fb x_b`, solved for x and y at once.
//!
//! The cotangent Laplacian is the stiffness matrix of piecewise-linear finite elements, a sum of
//! per-triangle positive semi-definite matrices, so it is positive semi-definite for any
//! positively oriented mesh, even with the negative weights of obtuse triangles; with the
//! boundary rows removed it is positive definite as long as every free vertex is connected to a
//! fixed one. A sparse Cholesky factorization therefore applies. Its symbolic analysis is done
//! once, because the sparsity pattern never changes, and only the numeric factorization is
//! redone per step (the metric changes every step of the composite map, as in libigl's
//! `bijective_composite_harmonic_mapping`). Should the numeric factorization still fail (nearly
//! degenerate triangles), the weights are clamped to a small positive floor, which makes the
//! matrix diagonally dominant and the map a convex-combination (Tutte) map.

use crate::geometry::Point;
use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, simplicial, supernodal, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, Mat, Side};
use std::sync::Arc;

mod up_looking;

use up_looking::UpLooking;

const NONE: u32 = u32::MAX;

/// A reusable harmonic-map solver for one triangulation and one set of fixed vertices: the
/// symbolic factorization is computed once in [`Harmonic::new`], each [`Harmonic::solve`]
/// assembles the cotangent weights of the given metric and refactors numerically.
#[derive(Debug, Clone)]
pub struct Harmonic {
    triangles: Vec<[u32; 3]>,
    /// Undirected edges `(lo, hi)`, sorted.
    edges: Vec<(u32, u32)>,
    /// Per triangle, the edge index opposite each of its corners.
    opposite: Vec<[u32; 3]>,
    /// Vertex → free index, or `NONE` for fixed vertices.
    free_index: Vec<u32>,
    free_vertices: Vec<u32>,
    /// Per edge with both ends free, its slot in `values`, else `NONE`.
    off_slot: Vec<u32>,
    /// Per free vertex, the slot of its diagonal entry in `values`.
    diag_slot: Vec<u32>,
    symbolic: Option<Arc<Symbolic>>,
    /// The entries of `L_ff`, laid out as the factor reads them ([`Symbolic::permuted`]).
    values: Vec<f64>,
    weights: Vec<f64>,
    /// The right-hand side, then the solution, in [`Symbolic::solve`]'s rows.
    rhs: Vec<Point>,
    /// Scratch of the numeric factorization ([`Symbolic::factor`]).
    scratch: Vec<f64>,
    /// The last [`Harmonic::solve`]'s metric, its final weights and factor: a composite-map
    /// step that is rejected is retried, shorter, from the same mesh, so the same matrix.
    last: Option<Box<Factored>>,
}

/// A metric's weights (after any clamping) and its numeric factor, kept for the next solve;
/// when the next metric differs, its vectors hold the next ones.
#[derive(Debug, Clone, Default)]
struct Factored {
    metric: Vec<Point>,
    weights: Vec<f64>,
    /// The values of `L` ([`Symbolic::cholesky`]'s layout).
    llt: Vec<f64>,
}

/// The symbolic factorization of `L_ff` (faer's AMD ordering and choice of simplicial or
/// supernodal, as `SymbolicLlt` makes them) and the matrix laid out in its ordering, so that a
/// numeric factorization reads the assembled values in place: faer's own numeric factorization
/// permutes the whole matrix first, every time (issue 16: a quarter of the composite walk's
/// factorization time). The layout is faer's own permutation of the pattern, computed once, so
/// the factor is the same bit for bit; [`Harmonic`] assembles its values straight into it.
#[derive(Debug)]
struct Symbolic {
    cholesky: SymbolicCholesky<usize>,
    /// The permuted matrix's pattern, on the side the numeric factorization reads.
    permuted: SymbolicSparseColMat<usize>,
    /// Free index → row of [`Symbolic::solve`]'s vector: the factor's ordering for a
    /// simplicial factor (solved here, unpermuted), the free index itself for a supernodal
    /// one (faer permutes).
    position: Vec<usize>,
    /// A simplicial factor's rows' reaches, found once ([`UpLooking`]).
    up_looking: Option<UpLooking>,
}

impl Symbolic {
    /// Analyses the upper-triangle `pattern` and lays it out in the factor's ordering; also
    /// returns, per slot of `pattern`, its place among the laid-out matrix's values.
    fn new(pattern: &SymbolicSparseColMat<usize>) -> Result<(Self, Vec<usize>)> {
        let fail = |e: &dyn std::fmt::Debug| {
            Error::internal(format!("harmonic map: symbolic factorization: {e:?}"))
        };
        let cholesky = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            Default::default(),
            Default::default(),
        )
        .map_err(|e| fail(&e))?;
        let n = pattern.nrows();
        let nnz = pattern.row_idx().len();
        // Each slot's number as its value, permuted as faer permutes the values: where each
        // slot lands.
        let ids: Vec<f64> = (0..nnz).map(|k| k as f64).collect();
        let out_side = match cholesky.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => Side::Upper,
            SymbolicCholeskyRaw::Supernodal(_) => Side::Lower,
        };
        let (mut val, mut col_ptr, mut row_idx) =
            (vec![0.0; nnz], vec![0usize; n + 1], vec![0usize; nnz]);
        let identity: Vec<usize> = (0..n).collect();
        let perm = match cholesky.perm() {
            Some(p) => p,
            None => faer::perm::PermRef::new_checked(&identity, &identity, n),
        };
        let mut mem = MemBuffer::try_new(StackReq::new::<usize>(n)).map_err(|e| fail(&e))?;
        faer::sparse::utils::permute_self_adjoint_to_unsorted(
            &mut val,
            &mut col_ptr,
            &mut row_idx,
            SparseColMatRef::new(pattern.as_ref(), &ids),
            perm,
            Side::Upper,
            out_side,
            MemStack::new(&mut mem),
        );
        let mut place = vec![0usize; nnz];
        for (at, &id) in val.iter().enumerate() {
            place[id as usize] = at;
        }
        let permuted = SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx);
        let position = match cholesky.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => perm.arrays().1.to_vec(),
            SymbolicCholeskyRaw::Supernodal(_) => identity,
        };
        let up_looking = match cholesky.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => UpLooking::new(
                (permuted.col_ptr(), permuted.row_idx()),
                (s.col_ptr(), s.row_idx()),
            ),
            SymbolicCholeskyRaw::Supernodal(_) => None,
        };
        Ok((
            Symbolic {
                cholesky,
                permuted,
                position,
                up_looking,
            },
            place,
        ))
    }

    /// The numeric factor of the matrix with `values` laid out as [`Symbolic::permuted`] into
    /// `l` (its old contents and room reused), or `false` if the matrix is not numerically
    /// positive definite.
    fn factor(&self, values: &[f64], l: &mut Vec<f64>, scratch: &mut Vec<f64>) -> bool {
        let cholesky = &self.cholesky;
        if let (SymbolicCholeskyRaw::Simplicial(s), Some(up)) = (cholesky.raw(), &self.up_looking) {
            l.resize(cholesky.len_val(), 0.0);
            let a = (self.permuted.col_ptr(), self.permuted.row_idx());
            return up.factor(a, values, (s.col_ptr(), s.row_idx()), l, scratch);
        }
        let a = SparseColMatRef::new(self.permuted.as_ref(), values);
        l.clear();
        l.resize(cholesky.len_val(), 0.0);
        let par = faer::get_global_parallelism();
        let scratch = cholesky.factorize_numeric_llt_scratch::<f64>(par, Default::default());
        let Ok(mut mem) = MemBuffer::try_new(scratch) else {
            return false;
        };
        let stack = MemStack::new(&mut mem);
        let factored = match cholesky.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                simplicial::factorize_simplicial_numeric_llt(l, a, Default::default(), s, stack)
                    .map(|_| ())
            }
            SymbolicCholeskyRaw::Supernodal(s) => supernodal::factorize_supernodal_numeric_llt(
                l,
                a,
                Default::default(),
                s,
                par,
                stack,
                Default::default(),
            )
            .map(|_| ()),
        };
        factored.is_ok()
    }

    /// Solves with the factor `l` (from [`Symbolic::factor`]) in place of `x`, both
    /// coordinates at once, row `position[f]` for free index `f`.
    ///
    /// A simplicial factor is solved here with faer's arithmetic (`LltRef`'s solve: each
    /// column's pivot times the diagonal's reciprocal, the scatter down the columns, then each
    /// column's terms summed from its last entry up), so the bits are faer's; but the rows
    /// stay in the factor's ordering, where faer permutes the right-hand side in and out of a
    /// scratch matrix it allocates, and one pass over `L` serves both coordinates.
    fn solve(&self, l: &[f64], x: &mut [Point]) -> Result<()> {
        let SymbolicCholeskyRaw::Simplicial(s) = self.cholesky.raw() else {
            return self.solve_supernodal(l, x);
        };
        let (ptr, idx) = (s.col_ptr(), s.row_idx());
        let n = x.len();
        if ptr.len() != n + 1 || l.len() < ptr[n] {
            return Err(Error::internal(
                "harmonic map: factor does not fit the system",
            ));
        }
        // L y = b.
        for j in 0..n {
            let (a, b) = (ptr[j], ptr[j + 1]);
            let xj = x[j] * l[a].recip();
            x[j] = xj;
            for (&i, &lij) in idx[a + 1..b].iter().zip(&l[a + 1..b]) {
                x[i] -= xj * lij;
            }
        }
        // Lᵀ x = y.
        for j in (0..n).rev() {
            let (a, b) = (ptr[j], ptr[j + 1]);
            let mut acc = Point::ZERO;
            for (&i, &lij) in idx[a + 1..b].iter().zip(&l[a + 1..b]).rev() {
                acc += x[i] * lij;
            }
            x[j] = (x[j] - acc) * l[a].recip();
        }
        Ok(())
    }

    /// [`Symbolic::solve`] for a supernodal factor, through faer (rows are free indices).
    fn solve_supernodal(&self, l: &[f64], x: &mut [Point]) -> Result<()> {
        let mut rhs = Mat::from_fn(x.len(), 2, |i, k| if k == 0 { x[i].x } else { x[i].y });
        let par = faer::get_global_parallelism();
        let scratch = self.cholesky.solve_in_place_scratch::<f64>(2, par);
        let mut mem = MemBuffer::try_new(scratch)
            .map_err(|e| Error::internal(format!("harmonic map: solver scratch: {e:?}")))?;
        LltRef::<'_, usize, f64>::new(&self.cholesky, l).solve_in_place_with_conj(
            Conj::No,
            rhs.as_mut(),
            par,
            MemStack::new(&mut mem),
        );
        for (i, p) in x.iter_mut().enumerate() {
            *p = Point::new(rhs[(i, 0)], rhs[(i, 1)]);
        }
        Ok(())
    }
}

/// Whether two metrics are the same, bit for bit (so their weights and factor are too).
fn same_metric(a: &[Point], b: &[Point]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| p.x.to_bits() == q.x.to_bits() && p.y.to_bits() == q.y.to_bits())
}

/// Per triangle, the index in `edges` (sorted, each `(lo, hi)` once, as
/// [`crate::mesh::edges`] gives them) of the edge opposite each corner, `NONE` if absent. Each
/// lower end's edges are one short run of the sorted list, found from the run's start instead
/// of by a binary search over all edges (issue 16: the searches were a quarter of the harmonic
/// map's set-up, which every composite map attempt pays).
fn opposite_edges(
    triangles: &[[u32; 3]],
    edges: &[(u32, u32)],
    vertex_count: usize,
) -> Vec<[u32; 3]> {
    // Row `lo` holds the upper ends of `lo`'s edges, in the order (and so at the indices) of
    // `edges`.
    let (run, upper) = crate::mesh::compressed_rows(vertex_count, edges.iter().copied());
    let find = |a: u32, b: u32| {
        let (lo, hi) = (a.min(b) as usize, a.max(b));
        let (s, e) = (run[lo], run[lo + 1]);
        upper[s..e]
            .iter()
            .position(|&x| x == hi)
            .map_or(NONE, |k| (s + k) as u32)
    };
    triangles
        .iter()
        .map(|t| [find(t[1], t[2]), find(t[2], t[0]), find(t[0], t[1])])
        .collect()
}

/// The upper-triangle pattern of the free vertices' matrix in compressed columns (`col_ptr`,
/// rows): column `j` holds the rows `i ≤ j` of its free neighbours and itself, ascending. Free
/// indices follow vertex order and `edges` are sorted with their lower end first, so a column's
/// off-diagonal rows arrive ascending and all below its diagonal, which is put last: no sort,
/// and no list per column.
fn upper_pattern(edges: &[(u32, u32)], free_index: &[u32], nf: usize) -> (Vec<usize>, Vec<usize>) {
    let off_diagonal = edges.iter().filter_map(|&(a, b)| {
        let (fa, fb) = (free_index[a as usize], free_index[b as usize]);
        (fa != NONE && fb != NONE).then_some((fa.max(fb), fa.min(fb)))
    });
    let diagonal = (0..nf as u32).map(|j| (j, j));
    let (col_ptr, rows) = crate::mesh::compressed_rows(nf, off_diagonal.chain(diagonal));
    (col_ptr, rows.into_iter().map(|i| i as usize).collect())
}

impl Harmonic {
    /// Prepares the solver: `fixed[v]` marks the vertices whose positions are prescribed.
    /// Errors if an index is out of range.
    pub fn new(triangles: &[[u32; 3]], vertex_count: usize, fixed: &[bool]) -> Result<Self> {
        if fixed.len() != vertex_count
            || triangles
                .iter()
                .flatten()
                .any(|&v| v as usize >= vertex_count)
        {
            return Err(Error::internal("harmonic map: index out of range"));
        }
        let edges = crate::mesh::edges(triangles);
        let opposite = opposite_edges(triangles, &edges, vertex_count);
        let mut free_index = vec![NONE; vertex_count];
        let mut free_vertices = Vec::new();
        for v in 0..vertex_count {
            if !fixed[v] {
                free_index[v] = free_vertices.len() as u32;
                free_vertices.push(v as u32);
            }
        }
        let nf = free_vertices.len();
        let (col_ptr, row_idx) = upper_pattern(&edges, &free_index, nf);
        let slot = |i: usize, j: usize| -> u32 {
            let col = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            (col_ptr[j] + col.binary_search(&i).unwrap_or(0)) as u32
        };
        let mut diag_slot: Vec<u32> = (0..nf).map(|j| slot(j, j)).collect();
        let mut off_slot: Vec<u32> = edges
            .iter()
            .map(|&(a, b)| {
                let (fa, fb) = (free_index[a as usize], free_index[b as usize]);
                if fa != NONE && fb != NONE {
                    slot(fa.min(fb) as usize, fa.max(fb) as usize)
                } else {
                    NONE
                }
            })
            .collect();
        let nnz = row_idx.len();
        let pattern = SymbolicSparseColMat::new_checked(nf, nf, col_ptr, None, row_idx);
        let symbolic = if nf > 0 {
            // The slots, moved to where the factor's layout keeps them.
            let (symbolic, place) = Symbolic::new(&pattern)?;
            for s in diag_slot.iter_mut().chain(off_slot.iter_mut()) {
                if *s != NONE {
                    *s = place[*s as usize] as u32;
                }
            }
            Some(Arc::new(symbolic))
        } else {
            None
        };
        Ok(Harmonic {
            triangles: triangles.to_vec(),
            weights: vec![0.0; edges.len()],
            edges,
            opposite,
            free_index,
            free_vertices,
            off_slot,
            diag_slot,
            symbolic,
            values: vec![0.0; nnz],
            rhs: vec![Point::ZERO; nf],
            scratch: Vec::new(),
            last: None,
        })
    }

    /// Checks the vertex counts and computes the cotangent weights of `metric`; the symbolic
    /// factorization to solve with, or `None` when no vertex is free (nothing to solve).
    fn weigh(&mut self, metric: &[Point], out: &[Point]) -> Result<Option<Arc<Symbolic>>> {
        let n = self.free_index.len();
        if metric.len() != n || out.len() != n {
            return Err(Error::internal("harmonic map: wrong vertex count"));
        }
        let Some(symbolic) = self.symbolic.clone() else {
            return Ok(None);
        };
        self.cotangent_weights(metric);
        Ok(Some(symbolic))
    }

    /// Computes the harmonic map with the cotangent weights of `metric` (the current vertex
    /// positions): fixed entries of `out` are read as the prescribed positions, free entries are
    /// overwritten with the solution.
    /// The metric's weights and factor are kept: solving again with the same metric (bit for
    /// bit) and other fixed positions only solves.
    pub fn solve(&mut self, metric: &[Point], out: &mut [Point]) -> Result<()> {
        let mut spare = None;
        if let Some(mut last) = self.last.take() {
            if same_metric(&last.metric, metric) && out.len() == metric.len() {
                // `weights` is the solve's scratch: the kept weights are lent to it, not copied.
                std::mem::swap(&mut self.weights, &mut last.weights);
                let done = self.finish(&last.llt, out);
                std::mem::swap(&mut self.weights, &mut last.weights);
                self.last = Some(last);
                return done;
            }
            spare = Some(last);
        }
        let Some(symbolic) = self.weigh(metric, out)? else {
            return Ok(());
        };
        if self.weights.iter().any(|w| !w.is_finite()) {
            return Err(Error::internal(
                "harmonic map: degenerate triangle in the metric",
            ));
        }
        let mut kept = spare.unwrap_or_default();
        if !self.factor(&symbolic, None, &mut kept.llt) {
            // Numerically indefinite: clamp to a positive floor (a convex-combination map).
            let mean = self.weights.iter().map(|w| w.abs()).sum::<f64>()
                / self.weights.len().max(1) as f64;
            let floor = 1e-3 * mean.max(f64::MIN_POSITIVE);
            log::debug!("harmonic map: cotangent matrix not positive definite, clamping weights");
            if !self.factor(&symbolic, Some(floor), &mut kept.llt) {
                return Err(Error::internal("harmonic map: factorization failed"));
            }
        }
        let done = self.finish(&kept.llt, out);
        kept.metric.clear();
        kept.metric.extend_from_slice(metric);
        // Kept by exchange: the next metric's weights are computed afresh into the scratch.
        std::mem::swap(&mut kept.weights, &mut self.weights);
        self.last = Some(kept);
        done
    }

    /// [`Harmonic::solve`] with every weight clamped to a small positive floor first: a
    /// convex-combination map, which is one-to-one onto a convex boundary by Tutte's theorem
    /// (Floater's form for positive weights), and as close to harmonic as the floor allows.
    pub fn solve_convex(&mut self, metric: &[Point], out: &mut [Point]) -> Result<()> {
        let Some(symbolic) = self.weigh(metric, out)? else {
            return Ok(());
        };
        let mean = self
            .weights
            .iter()
            .filter(|w| w.is_finite())
            .map(|w| w.abs())
            .sum::<f64>()
            / self.weights.len().max(1) as f64;
        let floor = 1e-2 * mean.max(f64::MIN_POSITIVE);
        for w in &mut self.weights {
            if !w.is_finite() {
                *w = floor;
            }
        }
        let mut llt = Vec::new();
        if !self.factor(&symbolic, Some(floor), &mut llt) {
            return Err(Error::internal("harmonic map: factorization failed"));
        }
        self.finish(&llt, out)
    }

    /// The cotangent weight of every edge in the metric `metric`, into `self.weights`.
    fn cotangent_weights(&mut self, metric: &[Point]) {
        // Zeroed at the edges' count: a solve may have exchanged the vector with a kept one.
        self.weights.clear();
        self.weights.resize(self.edges.len(), 0.0);
        for (t, opp) in self.triangles.iter().zip(&self.opposite) {
            let p = t.map(|v| metric[v as usize]);
            let twice_area = (p[1] - p[0]).perp_dot(p[2] - p[0]).abs();
            for k in 0..3 {
                let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                if opp[k] != NONE {
                    self.weights[opp[k] as usize] += 0.5 * a.dot(b) / twice_area;
                }
            }
        }
    }

    /// Assembles `L_ff` from the edge weights (clamped below at `floor` if given, and then stored
    /// back so that the right-hand side uses the same weights) and factors it numerically.
    /// The factor goes into `l` (`false` if the matrix is not numerically positive definite).
    fn factor(&mut self, symbolic: &Symbolic, floor: Option<f64>, l: &mut Vec<f64>) -> bool {
        self.values.fill(0.0);
        for (e, &(a, b)) in self.edges.iter().enumerate() {
            let w = match floor {
                Some(f) => self.weights[e].max(f),
                None => self.weights[e],
            };
            let (fa, fb) = (self.free_index[a as usize], self.free_index[b as usize]);
            if fa != NONE {
                self.values[self.diag_slot[fa as usize] as usize] += w;
            }
            if fb != NONE {
                self.values[self.diag_slot[fb as usize] as usize] += w;
            }
            if self.off_slot[e] != NONE {
                self.values[self.off_slot[e] as usize] -= w;
            }
            if floor.is_some() {
                self.weights[e] = w;
            }
        }
        symbolic.factor(&self.values, l, &mut self.scratch)
    }

    /// Assembles `−L_fb x_b` from the fixed entries of `out`, solves, and writes the free entries.
    fn finish(&mut self, llt: &[f64], out: &mut [Point]) -> Result<()> {
        let Some(symbolic) = self.symbolic.as_deref() else {
            return Ok(());
        };
        let position = &symbolic.position;
        self.rhs.fill(Point::ZERO);
        for (e, &(a, b)) in self.edges.iter().enumerate() {
            let w = self.weights[e];
            let (fa, fb) = (self.free_index[a as usize], self.free_index[b as usize]);
            if fa != NONE && fb == NONE {
                self.rhs[position[fa as usize]] += out[b as usize] * w;
            } else if fb != NONE && fa == NONE {
                self.rhs[position[fb as usize]] += out[a as usize] * w;
            }
        }
        symbolic.solve(llt, &mut self.rhs)?;
        for (&v, &at) in self.free_vertices.iter().zip(position) {
            let p = self.rhs[at];
            if !p.is_finite() {
                return Err(Error::internal("harmonic map: non-finite solution"));
            }
            out[v as usize] = p;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangulation::tests::{circle, pair, subdivided};
    use crate::triangulation::triangulate;

    proptest::proptest! {
        /// The opposite edges and the pattern are those of a binary search over all edges and
        /// of a sorted list per column (the construction they replace), on triangle soups with
        /// repeated, isolated and fixed vertices.
        #[test]
        fn opposite_edges_and_pattern_are_the_searched_and_sorted_ones(
            soup in proptest::collection::vec((0u32..30, 0u32..30, 0u32..30), 1..60),
            fixed in proptest::collection::vec(proptest::bool::weighted(0.3), 30),
        ) {
            let triangles: Vec<[u32; 3]> = soup.iter().map(|&(a, b, c)| [a, b, c]).collect();
            let edges = crate::mesh::edges(&triangles);
            let search = |a: u32, b: u32| {
                edges.binary_search(&(a.min(b), a.max(b))).map_or(NONE, |e| e as u32)
            };
            let searched: Vec<[u32; 3]> = triangles
                .iter()
                .map(|t| [search(t[1], t[2]), search(t[2], t[0]), search(t[0], t[1])])
                .collect();
            proptest::prop_assert_eq!(opposite_edges(&triangles, &edges, 30), searched);

            let mut free_index = vec![NONE; 30];
            let mut nf = 0;
            for (v, f) in free_index.iter_mut().zip(&fixed) {
                if !f {
                    *v = nf as u32;
                    nf += 1;
                }
            }
            let mut cols: Vec<Vec<usize>> = (0..nf).map(|j| vec![j]).collect();
            for &(a, b) in &edges {
                let (fa, fb) = (free_index[a as usize], free_index[b as usize]);
                if fa != NONE && fb != NONE {
                    cols[fa.max(fb) as usize].push(fa.min(fb) as usize);
                }
            }
            let mut col_ptr = vec![0usize];
            let mut rows = Vec::new();
            for c in &mut cols {
                c.sort_unstable();
                rows.extend_from_slice(c);
                col_ptr.push(rows.len());
            }
            proptest::prop_assert_eq!(upper_pattern(&edges, &free_index, nf), (col_ptr, rows));
        }
    }

    /// The factor laid out in advance solves bit for bit as faer's own `Llt` does, on grid
    /// Laplacians (shifted, so positive definite) small enough for faer's simplicial factor
    /// and large enough for its supernodal one.
    #[test]
    fn the_laid_out_factor_solves_as_faers_own() {
        use faer::linalg::solvers::Solve;
        use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
        let mut kinds = (false, false);
        // Grids, and a dense block (supernodal at any size worth the name).
        for (side, dense) in [(5usize, false), (30, false), (120, false), (13, true)] {
            let n = side * side;
            let id = |i: usize, j: usize| j * side + i;
            // Column c holds rows r ≤ c: the diagonal and the grid neighbours before it (all
            // rows before it, when dense).
            let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
            for j in 0..side {
                for i in 0..side {
                    let c = id(i, j);
                    if dense {
                        cols[c]
                            .extend((0..c).map(|r| (r, -1.0 / n as f64 - 1e-3 * (r % 3) as f64)));
                    } else {
                        if j > 0 {
                            cols[c].push((id(i, j - 1), -1.0 - 0.01 * (c % 7) as f64));
                        }
                        if i > 0 {
                            cols[c].push((id(i - 1, j), -1.0));
                        }
                    }
                    cols[c].push((c, 4.5 + 0.03 * (c % 5) as f64));
                }
            }
            let mut col_ptr = vec![0usize];
            let (mut rows, mut values) = (Vec::new(), Vec::new());
            for c in &cols {
                for &(r, v) in c {
                    rows.push(r);
                    values.push(v);
                }
                col_ptr.push(rows.len());
            }
            let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
            let rhs = Mat::from_fn(n, 2, |i, k| ((i * 31 + k * 17) % 13) as f64 - 6.0);
            let (ours, place) = Symbolic::new(&pattern).unwrap();
            match ours.cholesky.raw() {
                SymbolicCholeskyRaw::Simplicial(_) => {
                    kinds.0 = true;
                    assert!(ours.up_looking.is_some(), "{side}²: factored row by row");
                }
                SymbolicCholeskyRaw::Supernodal(_) => kinds.1 = true,
            }
            let mut laid_out = vec![0.0; values.len()];
            for (&v, &at) in values.iter().zip(&place) {
                laid_out[at] = v;
            }
            let mut l = vec![f64::NAN; 3];
            assert!(ours.factor(&laid_out, &mut l, &mut Vec::new()));
            let mut got = vec![Point::ZERO; n];
            for i in 0..n {
                got[ours.position[i]] = Point::new(rhs[(i, 0)], rhs[(i, 1)]);
            }
            ours.solve(&l, &mut got).unwrap();
            let symbolic = SymbolicLlt::try_new(pattern.as_ref(), Side::Upper).unwrap();
            let mat = SparseColMatRef::new(pattern.as_ref(), &values);
            let llt = Llt::try_new_with_symbolic(symbolic, mat, Side::Upper).unwrap();
            let mut want = rhs.clone();
            llt.solve_in_place(want.as_mut());
            for i in 0..n {
                let p = got[ours.position[i]];
                for (k, v) in [p.x, p.y].into_iter().enumerate() {
                    assert_eq!(v.to_bits(), want[(i, k)].to_bits(), "{side}²: row {i}");
                }
            }
        }
        assert_eq!(
            kinds,
            (true, true),
            "both of faer's factor kinds are tested"
        );
    }

    /// The factor found row by row with the reaches walked once has the bits of faer's
    /// simplicial factorization, on a real mesh's Laplacian (rows stored unsorted, as laid
    /// out in the factor's ordering) at two metrics.
    #[test]
    fn the_up_looking_factor_has_faers_bits() {
        let (tri, fixed) = square_with_a_ring(24);
        let n = tri.points.len();
        let mut h = Harmonic::new(&tri.triangles, n, &fixed).unwrap();
        let symbolic = h.symbolic.clone().unwrap();
        let SymbolicCholeskyRaw::Simplicial(s) = symbolic.cholesky.raw() else {
            panic!("a mesh this small gets a simplicial factor");
        };
        assert!(symbolic.up_looking.is_some());
        let bent: Vec<Point> = tri
            .points
            .iter()
            .map(|&q| Point::new(q.x + 0.3 * (q.y * 0.4).sin(), q.y + 0.02 * q.x * q.x))
            .collect();
        for metric in [&tri.points, &bent] {
            h.cotangent_weights(metric);
            let mut ours = vec![f64::NAN; 5];
            assert!(h.factor(&symbolic, None, &mut ours));
            let mut faers = vec![0.0; symbolic.cholesky.len_val()];
            let a = SparseColMatRef::new(symbolic.permuted.as_ref(), &h.values);
            let scratch = symbolic
                .cholesky
                .factorize_numeric_llt_scratch::<f64>(faer::Par::Seq, Default::default());
            let mut mem = MemBuffer::new(scratch);
            simplicial::factorize_simplicial_numeric_llt(
                &mut faers,
                a,
                Default::default(),
                s,
                MemStack::new(&mut mem),
            )
            .unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&ours), bits(&faers));
        }
    }

    /// A 10 × 10 square (each side in `steps` edges) with a circular feature curve: the
    /// triangulation and its fixed vertices.
    fn square_with_a_ring(steps: usize) -> (crate::triangulation::Triangulation, Vec<bool>) {
        let p = Point::new;
        let sq = subdivided(&[p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)], steps);
        meshed(&[
            pair("boundary", true, sq),
            pair("feature-o", true, circle(p(6., 5.), 2., 24)),
        ])
    }

    /// The source triangulation of `pairs` and its curve vertices (the fixed ones).
    fn meshed(
        pairs: &[crate::correspondence::CurvePair],
    ) -> (crate::triangulation::Triangulation, Vec<bool>) {
        let tri = triangulate(
            pairs,
            &crate::tolerance::Tolerances::new(14.0, 1.0),
            crate::mesh::Side::Source,
        )
        .unwrap();
        let mut fixed = vec![false; tri.points.len()];
        for &v in tri.curves.iter().flat_map(|c| &c.vertices) {
            fixed[v as usize] = true;
        }
        (tri, fixed)
    }

    #[test]
    fn reproduces_an_affine_map_exactly() {
        let p = Point::new;
        let (tri, fixed) = square_with_a_ring(20);
        let n = tri.points.len();
        assert!(fixed.iter().filter(|f| !**f).count() > 50);
        let affine =
            |q: Point| Point::new(1.3 * q.x - 0.4 * q.y + 3.0, 0.2 * q.x + 0.7 * q.y - 1.0);
        let mut h = Harmonic::new(&tri.triangles, n, &fixed).unwrap();
        for _ in 0..2 {
            // free entries start with garbage: they must be overwritten
            let mut out: Vec<Point> = tri
                .points
                .iter()
                .zip(&fixed)
                .map(|(q, &f)| if f { affine(*q) } else { p(1e3, -7.) })
                .collect();
            h.solve(&tri.points, &mut out).unwrap();
            for (q, o) in tri.points.iter().zip(&out) {
                assert!(affine(*q).distance(*o) < 1e-11, "{} vs {}", affine(*q), o);
            }
        }
    }

    #[test]
    fn a_kept_factor_solves_as_a_fresh_one() {
        // One solver reused (the second and fourth solves take the kept factor, the third a
        // new metric) against a fresh solver per solve: the same bits.
        let p = Point::new;
        let sq = subdivided(&[p(0., 0.), p(10., 0.), p(10., 10.), p(0., 10.)], 16);
        let pairs = vec![pair("boundary", true, sq)];
        let (tri, fixed) = meshed(&pairs);
        let n = tri.points.len();
        let bent = |q: Point, k: f64| Point::new(q.x + k * (q.y * 0.3).sin(), q.y + k * q.x * 0.05);
        let warped: Vec<Point> = tri.points.iter().map(|&q| bent(q, 0.4)).collect();
        let mut kept = Harmonic::new(&tri.triangles, n, &fixed).unwrap();
        for (metric, k) in [
            (&tri.points, 1.0),
            (&tri.points, 2.0),
            (&warped, 1.5),
            (&warped, 0.5),
        ] {
            let prescribed: Vec<Point> = tri.points.iter().map(|&q| bent(q, k)).collect();
            let mut a = prescribed.clone();
            kept.solve(metric, &mut a).unwrap();
            let mut b = prescribed;
            Harmonic::new(&tri.triangles, n, &fixed)
                .unwrap()
                .solve(metric, &mut b)
                .unwrap();
            let bits = |v: &[Point]| {
                v.iter()
                    .map(|q| (q.x.to_bits(), q.y.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&a), bits(&b), "metric of step k = {k}");
        }
    }

    #[test]
    fn a_vertex_in_the_middle_goes_to_the_weighted_average() {
        // square fan around a centre: symmetric weights put the centre at the mean
        let p = Point::new;
        let pts = vec![p(0., 0.), p(2., 0.), p(2., 2.), p(0., 2.), p(1., 1.)];
        let tris = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        let fixed = [true, true, true, true, false];
        let mut h = Harmonic::new(&tris, 5, &fixed).unwrap();
        let mut out = vec![p(0., 0.), p(4., 0.), p(4., 4.), p(0., 6.), p(0., 0.)];
        h.solve(&pts, &mut out).unwrap();
        assert!(out[4].distance(p(2.0, 2.5)) < 1e-12, "{}", out[4]);
    }
}
