//! Assembly of local transformations into vertex positions: the normal equations of eq. (1),
//! built and factored once, solved once per frame.
//!
//! Every interpolation method in [`crate::rigid`] minimizes a quadratic energy whose matrix does
//! not depend on `t` — only the right-hand side does. [`SystemBuilder`] collects the matrix terms
//! (weighted edge differences for the disc method, dense per-triangle blocks for the triangle
//! baseline, and optional constant extra rows such as the skeleton's barycentric rows of eq. (2));
//! [`FactoredSystem`] holds the faer sparse Cholesky factor (fill-reducing AMD ordering and
//! symbolic analysis done once) and solves one frame into a caller's buffer without allocating.
//!
//! A frame's cost is dominated by the two triangular solves, which read the factor `L` once
//! each, so the factor is stored for solving (`factor.rs`). Fill-in makes `nnz(L)` grow like
//! `n log n` on planar meshes, which sets how the time per frame grows with the vertex count.
//!
//! ## Translation
//!
//! Energies built only from vertex *differences* are translation invariant, so their matrix is a
//! singular graph Laplacian. The rule that makes the system definite and keeps `t = 0` and `t = 1`
//! exact: in every connected component that no extra row anchors, the vertex with the smallest
//! index is removed from the system (held at the origin); after the solve, the whole component is
//! translated so that its vertex centroid lies at the caller's target, which the methods set to
//! `(1 − t)·c_source + t·c_target` (the component's centroids). When the local transformations are
//! exactly compatible with the source (t = 0) or the target (t = 1), the solve reproduces that
//! shape up to a translation and the centroid rule removes the translation.

use super::factor::{Factor, LaneRow, Row};
use super::simd::vectorized;
use crate::error::Result;
use crate::geometry::Point;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// Collects the constant matrix of a least-squares vertex energy before it is factored.
///
/// Terms are given on the full vertex set; [`SystemBuilder::factor`] picks the translation pins
/// (see the module docs) and drops their rows and columns.
#[derive(Debug, Clone)]
pub(crate) struct SystemBuilder {
    n: usize,
    /// Entries above the diagonal `(row < col, value)` on full vertex indices; duplicates are
    /// summed.
    entries: Vec<(u32, u32, f64)>,
    /// Each vertex's diagonal entry, summed as the terms come (`None` while no term has one):
    /// every term puts weight on the diagonal, so summing it here keeps two thirds of an edge's
    /// entries out of the list and out of the column sort.
    diagonal: Vec<Option<f64>>,
    /// Union-find parents for connected components.
    parent: Vec<u32>,
    /// Vertices touched by an extra (absolute, non-difference) row.
    anchored: Vec<bool>,
}

impl SystemBuilder {
    /// An empty system over `n` vertices.
    pub(crate) fn new(n: usize) -> Self {
        SystemBuilder {
            n,
            entries: Vec::new(),
            diagonal: vec![None; n],
            parent: (0..n as u32).collect(),
            anchored: vec![false; n],
        }
    }

    /// Makes room for `edges` more [`SystemBuilder::add_edge`] terms at once, instead of
    /// growing the entry list step by step.
    pub(crate) fn reserve_edges(&mut self, edges: usize) {
        self.entries.reserve(edges);
    }

    fn find(&mut self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            let gp = self.parent[self.parent[v as usize] as usize];
            self.parent[v as usize] = gp;
            v = gp;
        }
        v
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // Smaller root wins, so components are labelled deterministically.
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi as usize] = lo;
        }
    }

    fn push(&mut self, a: u32, b: u32, v: f64) {
        if a == b {
            // The sum starts from the first term, as a column's repeated entries do.
            let d = &mut self.diagonal[a as usize];
            *d = Some(d.map_or(v, |s| s + v));
        } else {
            self.entries.push((a.min(b), a.max(b), v));
        }
    }

    /// Adds the term `w·‖v_j − v_i − c‖²` (for any per-frame constant `c`): the Laplacian
    /// entries of one weighted edge.
    pub(crate) fn add_edge(&mut self, i: u32, j: u32, w: f64) {
        self.push(i, i, w);
        self.push(j, j, w);
        self.push(i, j, -w);
        self.union(i, j);
    }

    /// Adds a dense symmetric block `M` (row-major `k × k`) on the given vertices: the term
    /// `xᵀ M x` for the vertices' coordinates `x`. Used by the triangle baseline, whose blocks
    /// annihilate constants (rows sum to zero), so it is translation invariant like the edges.
    pub(crate) fn add_block(&mut self, vertices: &[u32], block: &[f64]) {
        let k = vertices.len();
        debug_assert_eq!(block.len(), k * k);
        for a in 0..k {
            for b in a..k {
                let v = block[a * k + b];
                if v != 0.0 || a == b {
                    self.push(vertices[a], vertices[b], v);
                }
            }
            if a > 0 {
                self.union(vertices[0], vertices[a]);
            }
        }
    }

    /// Adds a constant extra row `w·‖Σ c_k v_k − J‖²` with a per-frame target `J` (e.g. the
    /// barycentric rows `C_k V − J'_k` of eq. (2)). An extra row fixes the position of its
    /// component, so that component gets no translation pin and no centroid translation; the
    /// caller adds `w·c_k·J` to the right-hand side of each `v_k` per frame.
    #[allow(dead_code)] // hook for the skeleton control of §4.2 (eq. 2)
    pub(crate) fn add_extra_row(&mut self, coeffs: &[(u32, f64)], w: f64) {
        for (a, &(va, ca)) in coeffs.iter().enumerate() {
            for &(vb, cb) in &coeffs[a..] {
                self.push(va, vb, w * ca * cb);
            }
            self.anchored[va as usize] = true;
            self.union(coeffs[0].0, va);
        }
    }

    /// Chooses the pins, assembles the reduced matrix and factors it (AMD ordering, symbolic
    /// analysis, numeric `LLᵀ`).
    pub(crate) fn factor(mut self) -> Result<FactoredSystem> {
        let n = self.n;
        let mut comp_of_root = vec![u32::MAX; n];
        let mut comp = vec![0u32; n];
        let mut comp_count = 0u32;
        for v in 0..n as u32 {
            let r = self.find(v) as usize;
            if comp_of_root[r] == u32::MAX {
                comp_of_root[r] = comp_count;
                comp_count += 1;
            }
            comp[v as usize] = comp_of_root[r];
        }
        let mut size = vec![0.0f64; comp_count as usize];
        for &c in &comp {
            size[c as usize] += 1.0;
        }
        let mut comp_anchored = vec![false; comp_count as usize];
        for v in 0..n {
            if self.anchored[v] {
                comp_anchored[comp[v] as usize] = true;
            }
        }
        // Pin the smallest vertex of every free component (vertices are scanned in order).
        let mut pinned_comp = comp_anchored.clone();
        let mut reduced = vec![0u32; n];
        let mut n_red = 0u32;
        let mut pins = Vec::new();
        for v in 0..n {
            let c = comp[v] as usize;
            if !pinned_comp[c] {
                pinned_comp[c] = true;
                reduced[v] = u32::MAX;
                pins.push(v as u32);
            } else {
                reduced[v] = n_red;
                n_red += 1;
            }
        }
        let n_red = n_red as usize;
        for r in reduced.iter_mut() {
            if *r == u32::MAX {
                *r = n_red as u32; // the dummy row, ignored by the solve
            }
        }
        let factor = if n_red == 0 {
            None
        } else {
            let mut diagonal = vec![None; n_red];
            for (&r, &d) in reduced.iter().zip(&self.diagonal) {
                if (r as usize) < n_red {
                    diagonal[r as usize] = d;
                }
            }
            let upper = UpperColumns::new(
                n_red,
                self.entries.iter().filter_map(|&(a, b, v)| {
                    let (ra, rb) = (reduced[a as usize], reduced[b as usize]);
                    ((ra as usize) < n_red && (rb as usize) < n_red)
                        .then(|| (ra.min(rb), ra.max(rb), v))
                }),
                &diagonal,
            );
            let symbolic = SymbolicSparseColMatRef::new_checked(
                n_red,
                n_red,
                &upper.col_ptr,
                None,
                &upper.rows,
            );
            let a = SparseColMatRef::new(symbolic, &upper.values);
            let factor = Factor::new(a)?;
            // The rows go straight to their place in the factor's ordering, so a frame never
            // permutes its right-hand side or its solution.
            for r in reduced.iter_mut() {
                if (*r as usize) < n_red {
                    *r = factor.position[*r as usize];
                }
            }
            Some(factor)
        };
        // Each row's vertex, so that placing reads the solution in its own order.
        let mut vertex_of_row = vec![0u32; n_red];
        for (v, &r) in reduced.iter().enumerate() {
            if (r as usize) < n_red {
                vertex_of_row[r as usize] = v as u32;
            }
        }
        Ok(FactoredSystem {
            n,
            n_red,
            reduced,
            vertex_of_row,
            comp,
            size,
            comp_anchored,
            pins,
            factor,
        })
    }
}

/// The upper triangle of a reduced matrix in compressed columns, as faer's
/// `try_new_from_triplets` would build it (rows ascending in each column, repeated entries
/// summed in the order they were given), without its general bookkeeping: assembling the
/// matrix was a twentieth of a small mesh's set-up.
struct UpperColumns {
    col_ptr: Vec<u32>,
    rows: Vec<u32>,
    values: Vec<f64>,
}

impl UpperColumns {
    /// The `n × n` matrix of `entries` `(row < col, value)`, all below `n` (iterated twice),
    /// and the diagonal `diagonal` (`None`: no entry), which ends each column.
    fn new(
        n: usize,
        entries: impl Iterator<Item = (u32, u32, f64)> + Clone,
        diagonal: &[Option<f64>],
    ) -> Self {
        // Entries bucketed by column, in the order given (a counting sort).
        let mut start = vec![0usize; n + 1];
        for (_, c, _) in entries.clone() {
            start[c as usize + 1] += 1;
        }
        for c in 0..n {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut bucket = vec![(0u32, 0.0f64); start[n]];
        for (r, c, v) in entries {
            bucket[fill[c as usize]] = (r, v);
            fill[c as usize] += 1;
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut rows = Vec::with_capacity(bucket.len() + n);
        let mut values: Vec<f64> = Vec::with_capacity(bucket.len() + n);
        col_ptr.push(0u32);
        for c in 0..n {
            let column = &mut bucket[start[c]..start[c + 1]];
            // Stable, so repeated entries keep their order and sum as given.
            column.sort_by_key(|&(r, _)| r);
            let first = rows.len();
            for &(r, v) in column.iter() {
                match values.last_mut() {
                    Some(sum) if rows.len() > first && rows.last() == Some(&r) => *sum += v,
                    _ => {
                        rows.push(r);
                        values.push(v);
                    }
                }
            }
            if let Some(d) = diagonal[c] {
                rows.push(c as u32);
                values.push(d);
            }
            col_ptr.push(rows.len() as u32);
        }
        UpperColumns {
            col_ptr,
            rows,
            values,
        }
    }
}

/// A factored least-squares system over the vertices: per frame, fill the right-hand side with
/// [`FactoredSystem::rhs_index`] rows, then [`FactoredSystem::solve`].
#[derive(Debug)]
pub(crate) struct FactoredSystem {
    n: usize,
    n_red: usize,
    /// Row of each vertex in the reduced system; pinned vertices map to the dummy row `n_red`.
    reduced: Vec<u32>,
    /// The vertex of each row of the reduced system (`reduced`'s inverse).
    vertex_of_row: Vec<u32>,
    /// Connected component of each vertex.
    comp: Vec<u32>,
    /// Number of vertices of each component.
    size: Vec<f64>,
    /// Whether a component is fixed by extra rows (no centroid translation).
    comp_anchored: Vec<bool>,
    /// The pinned vertex of every free component.
    pins: Vec<u32>,
    factor: Option<Factor>,
}

/// Per-thread scratch of a [`FactoredSystem`] solve.
#[derive(Debug)]
pub(crate) struct SolveScratch {
    /// Right-hand side, one `(x, y)` row per reduced vertex in the factor's ordering (rows
    /// from [`FactoredSystem::rhs_index`]), and a last dummy row that pinned vertices write to.
    pub(crate) rhs: Vec<Point>,
    sums: Vec<Point>,
    /// Right-hand sides of frames solved together ([`FactoredSystem::solve_lanes`]), row by
    /// row; empty until the first batch.
    lanes: Vec<LaneRow>,
}

impl FactoredSystem {
    /// Row of vertex `v` in the right-hand side buffer (pinned vertices write to a dummy row).
    #[inline]
    pub(crate) fn rhs_index(&self, v: u32) -> usize {
        self.reduced[v as usize] as usize
    }

    /// Number of vertices.
    pub(crate) fn vertex_count(&self) -> usize {
        self.n
    }

    /// Number of connected components.
    pub(crate) fn component_count(&self) -> usize {
        self.comp_anchored.len()
    }

    /// Component of each vertex.
    pub(crate) fn components(&self) -> &[u32] {
        &self.comp
    }

    /// The translation pins, one per component not anchored by extra rows.
    #[allow(dead_code)]
    pub(crate) fn pins(&self) -> &[u32] {
        &self.pins
    }

    /// Scratch buffers sized for this system.
    pub(crate) fn scratch(&self) -> SolveScratch {
        SolveScratch {
            rhs: vec![Point::ZERO; self.n_red + 1],
            sums: vec![Point::ZERO; self.component_count()],
            lanes: Vec::new(),
        }
    }

    /// Bytes of the Cholesky factor one pass of a frame's solve reads (0 when every vertex is
    /// pinned); a frame makes two passes.
    pub(crate) fn factor_bytes(&self) -> usize {
        self.factor.as_ref().map_or(0, Factor::bytes)
    }

    /// Clears the right-hand side (for callers that fill it row by row, e.g. with extra rows).
    #[cfg_attr(not(test), allow(dead_code))]
    #[inline]
    pub(crate) fn clear_rhs(&self, s: &mut SolveScratch) {
        s.rhs.fill(Point::ZERO);
    }

    /// Adds `b` to the right-hand side row of vertex `v` (e.g. `w·c_k·J` of an extra row).
    #[cfg_attr(not(test), allow(dead_code))]
    #[inline]
    pub(crate) fn add_rhs(&self, s: &mut SolveScratch, v: u32, b: Point) {
        s.rhs[self.rhs_index(v)] += b;
    }

    /// Solves for the right-hand side in `s.rhs` and writes every vertex into `out`, translating
    /// each free component so its vertex centroid is `centroids[component]` (module docs).
    pub(crate) fn solve(&self, s: &mut SolveScratch, centroids: &[Point], out: &mut [Point]) {
        if let Some(f) = &self.factor {
            f.solve_in_place(&mut s.rhs);
        }
        self.place(&s.rhs, 0, &mut s.sums, centroids, out);
    }

    /// The rows of a batch of `K ≤` [`MAX_LANES`](super::factor::MAX_LANES) right-hand sides,
    /// one per frame, with lanes `0..K` zeroed for [`FactoredSystem::solve_lanes`]: row `r` of
    /// frame `k` is `rows[r].0[k]`
    /// (rows as in [`FactoredSystem::rhs_index`]).
    pub(crate) fn lanes<'s, const K: usize>(&self, s: &'s mut SolveScratch) -> &'s mut [LaneRow] {
        s.lanes.resize(s.rhs.len(), LaneRow::ZERO);
        for row in &mut s.lanes {
            row.0[..K].fill(Point::ZERO);
        }
        &mut s.lanes
    }

    /// Solves lanes `0..K` of the batch in one pass over the factor: each lane's solution has
    /// the bits of a lone solve (`factor.rs`).
    pub(crate) fn solve_lanes<const K: usize>(&self, s: &mut SolveScratch) {
        if let Some(f) = &self.factor {
            f.solve_rows::<K, _>(&mut s.lanes);
        }
    }

    /// Places the solution of lane `lane` of the batch like [`FactoredSystem::solve`] does.
    pub(crate) fn place_lane(
        &self,
        s: &mut SolveScratch,
        lane: usize,
        centroids: &[Point],
        out: &mut [Point],
    ) {
        self.place(&s.lanes, lane, &mut s.sums, centroids, out);
    }

    /// Writes lane `lane` of the solved `rows` into `out`, every vertex, translating each free
    /// component so its vertex centroid is `centroids[component]` (module docs); `sums` is
    /// scratch, one per component. Runs in the widest instructions at hand (`simd.rs`).
    fn place<R: Row>(
        &self,
        rows: &[R],
        lane: usize,
        sums: &mut [Point],
        centroids: &[Point],
        out: &mut [Point],
    ) {
        vectorized(
            #[inline(always)]
            || self.place_kernel(rows, lane, sums, centroids, out),
        )
    }

    /// [`FactoredSystem::place`]'s loops, inlined into each instruction set's copy.
    #[inline(always)]
    fn place_kernel<R: Row>(
        &self,
        rows: &[R],
        lane: usize,
        sums: &mut [Point],
        centroids: &[Point],
        out: &mut [Point],
    ) {
        debug_assert_eq!(out.len(), self.n);
        // The solution is read in its rows' order and written to the vertices: a read from
        // a scattered row waits for it, where a scattered write does not. Pinned vertices are
        // at the origin before translation.
        for &p in &self.pins {
            out[p as usize] = Point::ZERO;
        }
        for (row, &v) in rows.iter().zip(&self.vertex_of_row) {
            out[v as usize] = row.lane(lane);
        }
        sums.fill(Point::ZERO);
        // Components are mostly runs of consecutive vertices: sum a run in a register, not
        // through memory one vertex after the other.
        let (mut run, mut sum) = (u32::MAX, Point::ZERO);
        for (o, &c) in out.iter().zip(&self.comp) {
            if c != run {
                if run != u32::MAX {
                    sums[run as usize] += sum;
                }
                (run, sum) = (c, Point::ZERO);
            }
            sum += *o;
        }
        if run != u32::MAX {
            sums[run as usize] += sum;
        }
        for (c, acc) in sums.iter_mut().enumerate() {
            *acc = if self.comp_anchored[c] {
                Point::ZERO
            } else {
                centroids[c] - *acc / self.size[c]
            };
        }
        for (o, &c) in out.iter_mut().zip(&self.comp) {
            *o += sums[c as usize];
        }
    }
}

/// Vertex centroid of every component.
pub(crate) fn component_centroids(comp: &[u32], count: usize, points: &[Point]) -> Vec<Point> {
    let mut sums = vec![(Point::ZERO, 0.0f64); count];
    for (&c, &p) in comp.iter().zip(points) {
        sums[c as usize].0 += p;
        sums[c as usize].1 += 1.0;
    }
    sums.into_iter()
        .map(|(s, k)| if k > 0.0 { s / k } else { Point::ZERO })
        .collect()
}

/// `out[i] = (1 − t)·a[i] + t·b[i]`: the translation rule's straight-line centroids at `t`.
pub(crate) fn lerp_into(out: &mut [Point], a: &[Point], b: &[Point], t: f64) {
    for ((o, &p), &q) in out.iter_mut().zip(a).zip(b) {
        *o = p * (1.0 - t) + q * t;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// The compressed columns of the builder's entries are faer's from the same triplets:
        /// the same rows, and the same sums of repeated entries (the diagonal's summed apart),
        /// bit for bit where faer sorts a column stably (up to twenty entries, where its sort
        /// is an insertion sort), to rounding elsewhere.
        #[test]
        fn upper_columns_are_the_matrix_of_the_triplets(
            n in 1usize..30,
            raw in proptest::collection::vec((0u32..30, 0u32..30, -4.0f64..4.0), 0..300),
        ) {
            let entries: Vec<(u32, u32, f64)> = raw
                .iter()
                .map(|&(a, b, v)| {
                    let (a, b) = (a % n as u32, b % n as u32);
                    (a.min(b), a.max(b), v)
                })
                .collect();
            // Through the builder, which sums the diagonal apart as the entries come.
            let mut builder = SystemBuilder::new(n);
            for &(r, c, v) in &entries {
                builder.push(r, c, v);
            }
            let ours = UpperColumns::new(n, builder.entries.iter().copied(), &builder.diagonal);
            let triplets: Vec<faer::sparse::Triplet<u32, u32, f64>> = entries
                .iter()
                .map(|&(r, c, v)| faer::sparse::Triplet::new(r, c, v))
                .collect();
            let theirs =
                faer::sparse::SparseColMat::<u32, f64>::try_new_from_triplets(n, n, &triplets)
                    .unwrap();
            let (sym, val) = theirs.parts();
            let ptr: Vec<u32> = sym.col_ptr().to_vec();
            proptest::prop_assert_eq!(&ours.col_ptr, &ptr);
            proptest::prop_assert_eq!(&ours.rows[..], sym.row_idx());
            for c in 0..n {
                let given = entries.iter().filter(|e| e.1 == c as u32).count();
                let column = ptr[c] as usize..ptr[c + 1] as usize;
                for (&a, &b) in ours.values[column.clone()].iter().zip(&val[column]) {
                    if given <= 20 {
                        proptest::prop_assert_eq!(a.to_bits(), b.to_bits());
                    } else {
                        proptest::prop_assert!((a - b).abs() < 1e-9);
                    }
                }
            }
        }
    }

    /// A path 0–1–2 and a separate edge 3–4: two components, two pins, exact edge targets.
    #[test]
    fn laplacian_solve_reproduces_consistent_differences_per_component() {
        let mut b = SystemBuilder::new(5);
        for (i, j) in [(0, 1), (1, 2), (3, 4)] {
            b.add_edge(i, j, 2.0);
        }
        let sys = b.factor().unwrap();
        assert_eq!(sys.component_count(), 2);
        assert_eq!(sys.pins(), &[0, 3]);
        let want = [
            Point::new(1.0, 2.0),
            Point::new(3.0, -1.0),
            Point::new(4.0, 0.5),
            Point::new(-7.0, 1.0),
            Point::new(-6.0, 3.0),
        ];
        let mut s = sys.scratch();
        sys.clear_rhs(&mut s);
        for (i, j) in [(0u32, 1u32), (1, 2), (3, 4)] {
            let d = (want[j as usize] - want[i as usize]) * 2.0;
            sys.add_rhs(&mut s, j, d);
            sys.add_rhs(&mut s, i, -d);
        }
        let cents = component_centroids(sys.components(), 2, &want);
        let mut out = vec![Point::ZERO; 5];
        sys.solve(&mut s, &cents, &mut out);
        for (a, b) in out.iter().zip(&want) {
            assert!(a.distance(*b) < 1e-12, "{a} vs {b}");
        }
    }

    /// An extra row anchors its component: no pin, and the position comes from the row.
    #[test]
    fn extra_rows_anchor_a_component() {
        let mut b = SystemBuilder::new(3);
        b.add_edge(0, 1, 1.0);
        b.add_edge(1, 2, 1.0);
        b.add_extra_row(&[(2, 1.0)], 1.0);
        let sys = b.factor().unwrap();
        assert!(sys.pins().is_empty());
        let mut s = sys.scratch();
        sys.clear_rhs(&mut s);
        // Edges want unit x steps, the extra row wants v2 = (10, 5).
        for (i, j) in [(0u32, 1u32), (1, 2)] {
            sys.add_rhs(&mut s, j, Point::X);
            sys.add_rhs(&mut s, i, -Point::X);
        }
        sys.add_rhs(&mut s, 2, Point::new(10.0, 5.0));
        let mut out = vec![Point::ZERO; 3];
        sys.solve(&mut s, &[Point::new(99.0, 99.0)], &mut out);
        assert!(out[2].distance(Point::new(10.0, 5.0)) < 1e-12);
        assert!(out[0].distance(Point::new(8.0, 5.0)) < 1e-12);
    }
}
