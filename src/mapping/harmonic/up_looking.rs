//! The numeric simplicial Cholesky factorization of the harmonic map's matrix, row by row
//! ("up-looking"), with each row's elimination-tree reach found once.
//!
//! faer's simplicial factorization finds, for every row `k`, the columns `j < k` that row
//! updates (its reach in the elimination tree) by walking the tree, on every factorization;
//! the composite map factors a matrix of the same pattern at every accepted step (issue 16:
//! the walks were a quarter of faer's factorization time on the slowest corpus pairs). The
//! reach depends on the pattern alone, so it is walked once here, in faer's order, with the
//! slot of `L` each update fills; the arithmetic is faer's, operation for operation, so the
//! factor has faer's bits.

/// Per row of the factor, the columns it updates in the order faer's `ereach` lists them, and
/// the slot of `L` each one's entry goes into.
#[derive(Debug)]
pub(super) struct UpLooking {
    /// Where each row's updates start in `column` and `slot` (one more entry than rows).
    start: Vec<usize>,
    column: Vec<u32>,
    slot: Vec<u32>,
}

impl UpLooking {
    /// The reaches of the upper-triangle pattern `(a_col_ptr, a_row_idx)` (in the order its
    /// rows are stored: the reach's order follows it) for the factor pattern
    /// `(l_col_ptr, l_row_idx)` (each column's rows ascending, the diagonal first). `None`
    /// when the two do not fit each other or the sizes pass `u32`.
    pub(super) fn new(
        (a_col_ptr, a_row_idx): (&[usize], &[usize]),
        (l_col_ptr, l_row_idx): (&[usize], &[usize]),
    ) -> Option<Self> {
        let n = a_col_ptr.len().checked_sub(1)?;
        if l_col_ptr.len() != n + 1 || l_row_idx.len() != *l_col_ptr.last()? {
            return None;
        }
        u32::try_from(l_row_idx.len()).ok()?;
        // The elimination tree: a column's parent is its first row below the diagonal.
        let parent: Vec<usize> = (0..n)
            .map(|j| {
                let (a, b) = (l_col_ptr[j], l_col_ptr[j + 1]);
                if b > a + 1 {
                    l_row_idx[a + 1]
                } else {
                    usize::MAX
                }
            })
            .collect();
        let mut visited = vec![usize::MAX; n];
        let mut stack = vec![0usize; n];
        // Per column, the next slot of `L` to fill (after the diagonal).
        let mut next: Vec<usize> = l_col_ptr[..n].iter().map(|&p| p + 1).collect();
        let mut start = Vec::with_capacity(n + 1);
        let (mut column, mut slot) = (Vec::new(), Vec::new());
        start.push(0);
        for k in 0..n {
            // faer's `ereach`: from every row above the diagonal up the tree to a visited
            // node, each path moved to the top of the stack in turn.
            let mut top = n;
            visited[k] = k;
            for &row in &a_row_idx[a_col_ptr[k]..a_col_ptr[k + 1]] {
                if row >= k {
                    continue;
                }
                let (mut i, mut len) = (row, 0);
                while visited.get(i)? != &k {
                    *stack.get_mut(len)? = i;
                    len += 1;
                    visited[i] = k;
                    i = parent[i];
                }
                stack.copy_within(..len, top.checked_sub(len)?);
                top -= len;
            }
            for &j in &stack[top..] {
                let s = next[j];
                if s >= l_col_ptr[j + 1] || l_row_idx[s] != k {
                    return None;
                }
                next[j] += 1;
                column.push(j as u32);
                slot.push(s as u32);
            }
            start.push(column.len());
        }
        // Every slot of `L` filled.
        if next.iter().zip(&l_col_ptr[1..]).any(|(&s, &end)| s != end) {
            return None;
        }
        Some(UpLooking {
            start,
            column,
            slot,
        })
    }

    /// Factors the matrix with `values` (on the pattern given to [`UpLooking::new`]) into `l`
    /// (the factor pattern's values; every slot is written), with `x` as scratch; `false` when
    /// a pivot is not positive (the matrix is not numerically positive definite). faer's
    /// `factorize_simplicial_numeric_llt` without regularization, operation for operation.
    pub(super) fn factor(
        &self,
        (a_col_ptr, a_row_idx): (&[usize], &[usize]),
        values: &[f64],
        (l_col_ptr, l_row_idx): (&[usize], &[usize]),
        l: &mut [f64],
        x: &mut Vec<f64>,
    ) -> bool {
        let n = self.start.len() - 1;
        x.clear();
        x.resize(n, 0.0);
        for k in 0..n {
            let (a, b) = (a_col_ptr[k], a_col_ptr[k + 1]);
            for (&i, &v) in a_row_idx[a..b].iter().zip(&values[a..b]) {
                x[i] += v;
            }
            let mut d = x[k];
            x[k] = 0.0;
            let (s, e) = (self.start[k], self.start[k + 1]);
            for (&j, &to) in self.column[s..e].iter().zip(&self.slot[s..e]) {
                let (j, to) = (j as usize, to as usize);
                let j_start = l_col_ptr[j];
                let xj = x[j];
                x[j] = 0.0;
                let lkj = xj * l[j_start].recip();
                for (&i, &lij) in l_row_idx[j_start + 1..to].iter().zip(&l[j_start + 1..to]) {
                    x[i] -= lij * lkj;
                }
                d -= lkj * lkj;
                l[to] = lkj;
            }
            if d <= 0.0 || d.is_nan() {
                return false;
            }
            l[l_col_ptr[k]] = d.sqrt();
        }
        true
    }
}
