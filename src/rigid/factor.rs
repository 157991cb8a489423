//! The Cholesky factor of a rigid system, laid out for the two triangular solves of every frame.
//!
//! faer orders (AMD), analyses and factors the reduced matrix once (`P A Pᵀ = L Lᵀ`). A frame
//! then only solves, and the solve reads all of `L` twice, so its layout sets the frame's cost:
//!
//! - **Both coordinates at once.** The right-hand side is one `(x, y)` pair per row, so each
//!   entry of `L` is read once for both.
//! - **No permutation.** Callers write the right-hand side straight into the factor's ordering
//!   ([`Factor::position`]) and read the solution from it.
//! - **32-bit indices, compressed columns, the diagonal apart**: a third less memory traffic
//!   than `usize` indices. A layout that grouped nested columns into dense nodes (fundamental
//!   supernodes) read fewer indices but measured slower on the fixtures: most columns of an AMD
//!   ordered mesh stand alone, and the nodes' short dense loops cost more than they saved.
//! - **Inverted diagonal**, so a frame multiplies instead of dividing.

use crate::error::{Error, Result};
use crate::geometry::Point;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SparseColMatRef;
use faer::{Par, Side};

/// The factor `L` of `P A Pᵀ = L Lᵀ`, laid out for solving (module docs).
#[derive(Debug)]
pub(super) struct Factor {
    /// `position[r]`: the row of the matrix's row `r` in the factor's ordering (`P`).
    pub(super) position: Vec<u32>,
    /// `1 / L[j, j]`.
    inv_diag: Vec<f64>,
    /// Start of column `j`'s entries below the diagonal in `rows` and `values`.
    col_ptr: Vec<u32>,
    rows: Vec<u32>,
    values: Vec<f64>,
}

impl Factor {
    /// Orders (AMD), analyses and factors the symmetric positive definite `a` (upper triangle
    /// given) with faer's simplicial `LLᵀ`, then lays the factor out for solving.
    pub(super) fn new(a: SparseColMatRef<'_, u32, f64>) -> Result<Self> {
        let n = a.nrows();
        // Simplicial, not faer's flop-based choice: the factor is computed once and solved
        // with every frame, and simplicial solves measured faster (100k-vertex grid:
        // 14.2 ms against 25.4 ms per frame with faer's supernodal factor).
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(a.symbolic(), Side::Upper, SymmetricOrdering::Amd, params)
                .map_err(|e| {
                    Error::internal(format!("symbolic Cholesky of the rigid system: {e:?}"))
                })?;
        let mut values = vec![0.0f64; symbolic.len_val()];
        let mut mem = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        )
        .map_err(|e| Error::internal(format!("allocating the Cholesky scratch: {e:?}")))?;
        symbolic
            .factorize_numeric_llt(
                &mut values,
                a,
                Side::Upper,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| {
                Error::internal(format!("the rigid system is not positive definite: {e:?}"))
            })?;
        let SymbolicCholeskyRaw::Simplicial(l) = symbolic.raw() else {
            return Err(Error::internal(
                "the rigid system's factor is not simplicial",
            ));
        };
        let position = match symbolic.perm() {
            Some(p) => p.arrays().1.to_vec(),
            None => (0..n as u32).collect(),
        };
        let (ptr, idx) = (l.col_ptr(), l.row_idx());
        let mut inv_diag = Vec::with_capacity(n);
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut rows = Vec::with_capacity(idx.len().saturating_sub(n));
        let mut below = Vec::with_capacity(idx.len().saturating_sub(n));
        col_ptr.push(0u32);
        for j in 0..n {
            let (start, end) = (ptr[j] as usize, ptr[j + 1] as usize);
            // faer stores each column's diagonal entry first.
            match (idx.get(start), values.get(start)) {
                (Some(&i), Some(&d)) if start < end && i as usize == j && d > 0.0 => {
                    inv_diag.push(1.0 / d)
                }
                _ => return Err(Error::internal("the rigid system's factor has no diagonal")),
            }
            rows.extend_from_slice(&idx[start + 1..end]);
            below.extend_from_slice(&values[start + 1..end]);
            col_ptr.push(rows.len() as u32);
        }
        Ok(Factor {
            position,
            inv_diag,
            col_ptr,
            rows,
            values: below,
        })
    }

    /// Bytes one pass of a lone solve reads: every entry below the diagonal (an `f64` value
    /// and a `u32` row), the column starts and the inverted diagonal. Each frame reads them
    /// twice, so at large meshes this sets the frame's floor ([`crate::rigid::Interpolator::factor_bytes`]).
    pub(super) fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.values.len() * size_of::<f64>()
            + self.rows.len() * size_of::<u32>()
            + self.col_ptr.len() * size_of::<u32>()
            + self.inv_diag.len() * size_of::<f64>()
    }

    /// Overwrites `b` (the first `n` rows, in the factor's ordering) with `(L Lᵀ)⁻¹ b`: a
    /// scatter down the columns of `L`, then a gather up them.
    pub(super) fn solve_in_place(&self, b: &mut [Point]) {
        self.solve_rows::<1, Point>(b);
    }

    /// [`Factor::solve_in_place`] for the first `K` lanes of every row at once (a batch of
    /// right-hand sides, `b[r].lane(k)` row `r` of right-hand side `k`; further lanes are left
    /// alone). One pass over `L` serves every lane, so the frames share its memory traffic;
    /// each lane takes exactly the operations of a lone solve, so its result has the same bits.
    pub(super) fn solve_rows<const K: usize, R: Row>(&self, b: &mut [R]) {
        super::simd::vectorized(
            #[inline(always)]
            || self.substitute::<K, R>(b),
        )
    }

    /// [`Factor::solve_rows`]'s two substitutions, inlined into each instruction set's copy
    /// (`simd.rs`).
    #[inline(always)]
    fn substitute<const K: usize, R: Row>(&self, b: &mut [R]) {
        let n = self.inv_diag.len();
        let b = &mut b[..n];
        // L y = b, column by column.
        for j in 0..n {
            let d = self.inv_diag[j];
            let yj: [Point; K] = std::array::from_fn(|k| b[j].lane(k) * d);
            for (k, &y) in yj.iter().enumerate() {
                *b[j].lane_mut(k) = y;
            }
            let (s, e) = (self.col_ptr[j] as usize, self.col_ptr[j + 1] as usize);
            for (&i, &l) in self.rows[s..e].iter().zip(&self.values[s..e]) {
                let bi = &mut b[i as usize];
                for (k, &y) in yj.iter().enumerate() {
                    *bi.lane_mut(k) -= y * l;
                }
            }
        }
        // Lᵀ x = y, from the last column back.
        for j in (0..n).rev() {
            let (s, e) = (self.col_ptr[j] as usize, self.col_ptr[j + 1] as usize);
            let sum = dot_lanes::<K, R>(&self.rows[s..e], &self.values[s..e], b);
            let d = self.inv_diag[j];
            for (k, &sum) in sum.iter().enumerate() {
                let x = b[j].lane_mut(k);
                *x = (*x - sum) * d;
            }
        }
    }
}

/// A row of right-hand sides, one point per lane: a lone [`Point`] (one frame), or a batch's
/// row of [`MAX_LANES`] frames of which the first few are in use. The solve and the disc
/// method's assembly are written once over rows, for one frame or a batch.
pub(crate) trait Row: Copy {
    /// Lane `k`'s point.
    fn lane(&self, k: usize) -> Point;
    /// Lane `k`'s point, to write.
    fn lane_mut(&mut self, k: usize) -> &mut Point;
}

impl Row for Point {
    #[inline(always)]
    fn lane(&self, _: usize) -> Point {
        *self
    }
    #[inline(always)]
    fn lane_mut(&mut self, _: usize) -> &mut Point {
        self
    }
}

impl<const W: usize> Row for [Point; W] {
    #[inline(always)]
    fn lane(&self, k: usize) -> Point {
        self[k]
    }
    #[inline(always)]
    fn lane_mut(&mut self, k: usize) -> &mut Point {
        &mut self[k]
    }
}

/// Most right-hand sides solved at once ([`Factor::solve_rows`]). Eight frames of a
/// 100k-vertex grid share a pass over its 50 MB factor; more lanes gained little more.
pub(crate) const MAX_LANES: usize = 8;

/// Lanes whose points fill one 64-byte cache line of a [`LaneRow`].
const LINE_LANES: usize = 4;

/// A batch's row of right-hand sides, one point per frame ([`MAX_LANES`] of them, 128 bytes),
/// aligned to a cache line so that each four lanes are one line: the solve reads a row a line
/// at a time ([`dot_lanes`]), and an unaligned row would straddle three lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct LaneRow(pub(crate) [Point; MAX_LANES]);

// Each four lanes fill exactly one cache line.
const _: () = assert!(std::mem::size_of::<[Point; LINE_LANES]>() == 64);

impl LaneRow {
    /// A row of zeros.
    pub(crate) const ZERO: LaneRow = LaneRow([Point::ZERO; MAX_LANES]);
}

impl Row for LaneRow {
    #[inline(always)]
    fn lane(&self, k: usize) -> Point {
        self.0[k]
    }
    #[inline(always)]
    fn lane_mut(&mut self, k: usize) -> &mut Point {
        &mut self.0[k]
    }
}

/// [`dot`] for the first `K` lanes, four lanes (a cache line of a [`LaneRow`]) at a time. Eight
/// lanes' four partial sums at once (64 values) would not fit the sixteen vector registers of
/// AVX2 and spill to the stack on every entry; four lanes' fit. Each lane's sums are the same
/// operations either way, so the bits are the same. Measured on the 100k-vertex grid, eight
/// frames at once: 5.1–5.9 against 5.5–6.2 ms per frame (best of 30 batches, six alternating
/// runs).
#[inline(always)]
fn dot_lanes<const K: usize, R: Row>(index: &[u32], values: &[f64], b: &[R]) -> [Point; K] {
    let mut sums = [Point::ZERO; K];
    for first in (0..K).step_by(LINE_LANES) {
        let part = &mut sums[first..(first + LINE_LANES).min(K)];
        match part.len() {
            1 => part.copy_from_slice(&dot::<1, R>(index, values, b, first)),
            2 => part.copy_from_slice(&dot::<2, R>(index, values, b, first)),
            3 => part.copy_from_slice(&dot::<3, R>(index, values, b, first)),
            _ => part.copy_from_slice(&dot::<LINE_LANES, R>(index, values, b, first)),
        }
    }
    sums
}

/// `Σ_k values[k] · b[index[k]]` for each of the `K` lanes from `first` on, in four partial
/// sums per lane: one running sum would wait on every addition.
#[inline(always)]
fn dot<const K: usize, R: Row>(index: &[u32], values: &[f64], b: &[R], first: usize) -> [Point; K] {
    let mut acc = [[Point::ZERO; K]; 4];
    for (r, v) in index.chunks_exact(4).zip(values.chunks_exact(4)) {
        for q in 0..4 {
            let br = &b[r[q] as usize];
            for (k, a) in acc[q].iter_mut().enumerate() {
                *a += br.lane(first + k) * v[q];
            }
        }
    }
    let tail = index.len() - index.len() % 4;
    for (&i, &l) in index[tail..].iter().zip(&values[tail..]) {
        let br = &b[i as usize];
        for (k, a) in acc[0].iter_mut().enumerate() {
            *a += br.lane(first + k) * l;
        }
    }
    std::array::from_fn(|k| (acc[0][k] + acc[1][k]) + (acc[2][k] + acc[3][k]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{SparseColMat, Triplet};

    type Dense = Vec<Vec<f64>>;

    /// Laplacians of a path, grids and a fan, plus a small diagonal so they are definite:
    /// each as a dense matrix and as its upper triangle for faer.
    fn test_systems() -> Vec<(Dense, SparseColMat<u32, f64>)> {
        let grid = |nx: u32, ny: u32| {
            let mut e = Vec::new();
            for y in 0..ny {
                for x in 0..nx {
                    let v = y * nx + x;
                    if x + 1 < nx {
                        e.push((v, v + 1));
                    }
                    if y + 1 < ny {
                        e.push((v, v + nx));
                        if x + 1 < nx {
                            e.push((v, v + nx + 1));
                        }
                    }
                }
            }
            (nx * ny, e)
        };
        let path = (30u32, (0..29u32).map(|i| (i, i + 1)).collect::<Vec<_>>());
        let fan = (25u32, (1..25u32).map(|i| (0, i)).collect::<Vec<_>>());
        [grid(9, 7), grid(20, 3), path, fan]
            .into_iter()
            .map(|(n, edges)| {
                let n = n as usize;
                let mut dense = vec![vec![0.0f64; n]; n];
                for (i, d) in dense.iter_mut().enumerate() {
                    d[i] = 0.01 * (1 + i % 3) as f64;
                }
                for &(a, b) in &edges {
                    let (a, b) = (a as usize, b as usize);
                    let w = 1.0 + ((a * 7 + b) % 5) as f64 * 0.3;
                    dense[a][a] += w;
                    dense[b][b] += w;
                    dense[a][b] -= w;
                    dense[b][a] -= w;
                }
                let triplets: Vec<Triplet<u32, u32, f64>> = (0..n)
                    .flat_map(|c| (0..=c).map(move |r| (r, c)))
                    .filter(|&(r, c)| dense[r][c] != 0.0)
                    .map(|(r, c)| Triplet::new(r as u32, c as u32, dense[r][c]))
                    .collect();
                let a = SparseColMat::<u32, f64>::try_new_from_triplets(n, n, &triplets).unwrap();
                (dense, a)
            })
            .collect()
    }

    /// Each system solved through the factor's layout and ordering gives back the vector it
    /// was made from.
    #[test]
    fn factor_layout_solves_like_the_matrix() {
        for (dense, a) in test_systems() {
            let n = dense.len();
            let f = Factor::new(a.as_ref()).unwrap();
            let want: Vec<Point> = (0..n)
                .map(|i| Point::new(i as f64 * 0.5 - 3.0, (i * i % 11) as f64))
                .collect();
            // b = A·want, written in the factor's ordering.
            let mut b = vec![Point::ZERO; n];
            for r in 0..n {
                let s: Point = (0..n).map(|c| want[c] * dense[r][c]).sum();
                b[f.position[r] as usize] = s;
            }
            f.solve_in_place(&mut b);
            for r in 0..n {
                let got = b[f.position[r] as usize];
                assert!(
                    got.distance(want[r]) < 1e-9,
                    "row {r}: {got} vs {}",
                    want[r]
                );
            }
        }
    }

    /// Every lane of a solve of `K` right-hand sides at once has the bits of that right-hand
    /// side solved alone, and the lanes past `K` are left alone.
    fn check_lanes<const K: usize>() {
        for (dense, a) in test_systems() {
            let n = dense.len();
            let f = Factor::new(a.as_ref()).unwrap();
            let rhs = |k: usize| -> Vec<Point> {
                (0..n)
                    .map(|i| Point::new((i * (k + 3) % 17) as f64 - 8.0, ((i + k) as f64).sin()))
                    .collect()
            };
            let marker = Point::new(-7.5, 2.25);
            let mut b = vec![LaneRow([marker; MAX_LANES]); n];
            for k in 0..K {
                for (row, p) in b.iter_mut().zip(rhs(k)) {
                    row.0[k] = p;
                }
            }
            f.solve_rows::<K, _>(&mut b);
            for k in 0..K {
                let mut alone = rhs(k);
                f.solve_in_place(&mut alone);
                for (r, (row, p)) in b.iter().zip(&alone).enumerate() {
                    let got = row.0[k];
                    assert!(
                        got.x.to_bits() == p.x.to_bits() && got.y.to_bits() == p.y.to_bits(),
                        "{n} rows, {K} lanes, lane {k}, row {r}: {got} vs {p}"
                    );
                }
            }
            assert!(b.iter().all(|row| row.0[K..].iter().all(|&p| p == marker)));
        }
    }

    /// The solve compiled for wide instructions has the bits of plain code (`simd.rs`), one
    /// lane or eight.
    #[test]
    fn wide_instructions_keep_the_bits_of_plain_code() {
        let bits = |v: &[Point]| -> Vec<(u64, u64)> {
            v.iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect()
        };
        for (dense, a) in test_systems() {
            let n = dense.len();
            let f = Factor::new(a.as_ref()).unwrap();
            let rhs = |k: usize| -> Vec<Point> {
                (0..n)
                    .map(|i| {
                        Point::new(
                            ((i * 7 + k) % 13) as f64 / 3.0 - 2.0,
                            ((i + k) as f64).cos(),
                        )
                    })
                    .collect()
            };
            for k in [0, 5] {
                let mut wide = rhs(k);
                f.solve_in_place(&mut wide);
                let mut plain = rhs(k);
                crate::rigid::simd::scalar(|| f.solve_in_place(&mut plain));
                assert!(bits(&wide) == bits(&plain), "{n} rows, rhs {k}");
            }
            let batch = || -> Vec<[Point; MAX_LANES]> {
                (0..n).map(|i| std::array::from_fn(|k| rhs(k)[i])).collect()
            };
            let (mut wide, mut plain) = (batch(), batch());
            f.solve_rows::<MAX_LANES, _>(&mut wide);
            crate::rigid::simd::scalar(|| f.solve_rows::<MAX_LANES, _>(&mut plain));
            assert!(
                bits(&wide.concat()) == bits(&plain.concat()),
                "{n} rows, eight lanes"
            );
        }
    }

    #[test]
    fn lanes_give_the_bits_of_lone_solves() {
        check_lanes::<1>();
        check_lanes::<2>();
        check_lanes::<3>();
        check_lanes::<4>();
        check_lanes::<5>();
        check_lanes::<6>();
        check_lanes::<7>();
        check_lanes::<MAX_LANES>();
    }
}
