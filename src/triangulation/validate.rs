//! Validation of control curves before triangulation and of intermediate curves during mapping:
//! curves must be simple, must not cross each other, and must not share points.
//!
//! Pairs of curve edges are pruned with a uniform grid over the curves' bounding box, so thousands
//! of edges are checked in about linear time; the remaining pairs are tested with the exact
//! predicates of [`crate::geometry::segments_intersect`].

use crate::geometry::{bounding_box, orient2d, segments_intersect, Point};

/// A curve edge: `(curve index, edge index)`, edge `k` joining vertices `k` and `k + 1` (mod n).
pub(crate) type EdgeRef = (usize, usize);

/// One polyline to check: its vertices and whether it is closed.
pub(crate) type CurveRef<'a> = (&'a [Point], bool);

fn edge_count(points: &[Point], closed: bool) -> usize {
    match (points.len(), closed) {
        (n, true) if n >= 3 => n,
        (n, _) => n.saturating_sub(1),
    }
}

/// Whether edges `k1 < k2` of one curve share a vertex.
fn adjacent(k1: usize, k2: usize, m: usize, closed: bool) -> bool {
    k2 == k1 + 1 || (closed && k1 == 0 && k2 + 1 == m)
}

/// The first (in curve, edge order) pair of curve edges that intersect, touch, or — for two
/// consecutive edges of one curve — fold back onto each other. Consecutive edges meeting at
/// their shared vertex are not a crossing.
pub(crate) fn first_crossing(curves: &[CurveRef<'_>]) -> Option<(EdgeRef, EdgeRef)> {
    crossings(curves, true).into_iter().next()
}

/// Every pair of curves `(c1, c2)` with `c1 <= c2` that cross or touch (as in
/// [`first_crossing`]), sorted.
pub(crate) fn crossing_curves(curves: &[CurveRef<'_>]) -> Vec<(usize, usize)> {
    let mut pairs: Vec<(usize, usize)> = crossings(curves, false)
        .into_iter()
        .map(|((c1, _), (c2, _))| (c1, c2))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Whether any two curve edges cross or touch (as in [`first_crossing`]): the composite
/// mapping's test of every step's intermediate curves. It tests the grid's candidate pairs as
/// they come, stopping at the first hit, without collecting and sorting them (a pair shared by
/// two cells is tested twice, which cannot change the answer).
pub(crate) fn curves_cross(curves: &[CurveRef<'_>]) -> bool {
    let Some(grid) = EdgeGrid::new(curves) else {
        return false;
    };
    grid.any_candidate(|s1, s2| grid.hit(curves, s1, s2))
}

fn crossings(curves: &[CurveRef<'_>], first_only: bool) -> Vec<(EdgeRef, EdgeRef)> {
    let Some(grid) = EdgeGrid::new(curves) else {
        return Vec::new();
    };
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    grid.any_candidate(|s1, s2| {
        pairs.push((s1, s2));
        false
    });
    pairs.sort_unstable();
    pairs.dedup();
    let mut found = Vec::new();
    for (s1, s2) in pairs {
        if grid.hit(curves, s1, s2) {
            found.push((grid.segs[s1 as usize].0, grid.segs[s2 as usize].0));
            if first_only {
                break;
            }
        }
    }
    found
}

/// The curves' edges binned in a uniform grid over their bounding box (about one edge per
/// cell), each cell listing the edges whose box overlaps it, in edge order.
struct EdgeGrid {
    /// Every edge: which it is and its two ends.
    segs: Vec<(EdgeRef, Point, Point)>,
    /// Where each cell's edges start in `items` (one more entry than cells).
    start: Vec<usize>,
    /// The edges of every cell, cell after cell (`mesh::compressed_rows`).
    items: Vec<u32>,
}

impl EdgeGrid {
    /// `None` when the curves have no edge.
    fn new(curves: &[CurveRef<'_>]) -> Option<Self> {
        let edges = curves
            .iter()
            .map(|&(pts, closed)| edge_count(pts, closed))
            .sum();
        let mut segs: Vec<(EdgeRef, Point, Point)> = Vec::with_capacity(edges);
        for (c, &(pts, closed)) in curves.iter().enumerate() {
            let n = pts.len();
            for k in 0..edge_count(pts, closed) {
                segs.push(((c, k), pts[k], pts[(k + 1) % n]));
            }
        }
        let (lo, hi) = bounding_box(segs.iter().flat_map(|s| [s.1, s.2]))?;
        let cells = ((segs.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let ext = (hi - lo).max(Point::splat(f64::MIN_POSITIVE));
        let cell_of = |p: Point| {
            let q = (p - lo) / ext * cells as f64;
            (
                (q.x.max(0.0) as usize).min(cells - 1),
                (q.y.max(0.0) as usize).min(cells - 1),
            )
        };
        // Each edge listed in every cell its box overlaps, edges in order within a cell.
        let mut entries: Vec<(u32, u32)> = Vec::with_capacity(segs.len() * 4);
        for (s, &(_, a, b)) in segs.iter().enumerate() {
            let (c0, c1) = (cell_of(a.min(b)), cell_of(a.max(b)));
            for y in c0.1..=c1.1 {
                for x in c0.0..=c1.0 {
                    entries.push(((y * cells + x) as u32, s as u32));
                }
            }
        }
        let (start, items) = crate::mesh::compressed_rows(cells * cells, entries.iter().copied());
        Some(EdgeGrid { segs, start, items })
    }

    /// Whether `f` holds for any pair of edges `(s1, s2)`, `s1 < s2`, that share a cell (every
    /// pair that can cross, some more than once), stopping at the first. Plain loops over each
    /// cell's pairs: nested iterators cost the crossing test as much as its exact tests did.
    fn any_candidate(&self, mut f: impl FnMut(u32, u32) -> bool) -> bool {
        for w in self.start.windows(2) {
            let cell = &self.items[w[0]..w[1]];
            for (i, &s1) in cell.iter().enumerate() {
                for &s2 in &cell[i + 1..] {
                    if f(s1.min(s2), s1.max(s2)) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Whether edges `s1 < s2` cross or touch; two consecutive edges of one curve only when
    /// one folds back onto the other.
    fn hit(&self, curves: &[CurveRef<'_>], s1: u32, s2: u32) -> bool {
        let ((c1, k1), a, b) = self.segs[s1 as usize];
        let ((c2, k2), c, d) = self.segs[s2 as usize];
        if c1 == c2 && adjacent(k1, k2, edge_count(curves[c1].0, curves[c1].1), curves[c1].1) {
            // Shared vertex: only a fold-back (zero angle between the edges) is a crossing.
            let (v, x, y) = if b == c { (b, a, d) } else { (a, b, c) };
            orient2d(x, v, y) == 0.0 && (x - v).dot(y - v) > 0.0
        } else {
            segments_intersect(a, b, c, d)
        }
    }
}

/// The first pair of vertices (as `(curve, vertex)` pairs) of different curves, or of one curve,
/// closer than `snap`. Runs in `O(n log n)` by sorting on x.
pub(crate) fn first_coincidence(curves: &[CurveRef<'_>], snap: f64) -> Option<(EdgeRef, EdgeRef)> {
    let mut pts: Vec<(Point, EdgeRef)> = curves
        .iter()
        .enumerate()
        .flat_map(|(c, &(p, _))| p.iter().enumerate().map(move |(k, &q)| (q, (c, k))))
        .collect();
    pts.sort_by(|a, b| a.0.x.total_cmp(&b.0.x).then(a.1.cmp(&b.1)));
    let mut best: Option<(EdgeRef, EdgeRef)> = None;
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            if pts[j].0.x - pts[i].0.x > snap {
                break;
            }
            if pts[i].0.distance(pts[j].0) <= snap {
                let pair = (pts[i].1.min(pts[j].1), pts[i].1.max(pts[j].1));
                if best.is_none_or(|b| pair < b) {
                    best = Some(pair);
                }
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn crossings_between_and_within_curves() {
        let sq = [p(0., 0.), p(4., 0.), p(4., 4.), p(0., 4.)];
        let inner = [p(1., 1.), p(3., 3.)];
        assert_eq!(first_crossing(&[(&sq, true), (&inner, false)]), None);
        let out = [p(1., 1.), p(5., 3.)];
        assert_eq!(
            first_crossing(&[(&sq, true), (&out, false)]),
            Some(((0, 1), (1, 0)))
        );
        let bow = [p(0., 0.), p(2., 2.), p(2., 0.), p(0., 2.)];
        assert!(first_crossing(&[(&bow, true)]).is_some());
        let fold = [p(0., 0.), p(2., 0.), p(1., 0.)];
        assert!(first_crossing(&[(&fold, false)]).is_some());
        let coincide = [p(4., 4.), p(2., 1.)];
        assert!(first_coincidence(&[(&sq, true), (&coincide, false)], 1e-9).is_some());
        assert!(first_coincidence(&[(&sq, true), (&inner, false)], 1e-9).is_none());
    }

    #[test]
    fn many_edges_are_pruned_and_still_found() {
        let n = 4000;
        let circle: Vec<Point> = (0..n)
            .map(|k| {
                let a = k as f64 / n as f64 * std::f64::consts::TAU;
                p(a.cos(), a.sin())
            })
            .collect();
        assert_eq!(first_crossing(&[(&circle, true)]), None);
        let chord = [p(0.0, -2.0), p(0.0, 0.0)];
        assert!(first_crossing(&[(&circle, true), (&chord, false)]).is_some());
    }

    /// Crossings by brute force over every pair of edges, with the same predicates.
    fn crossing_by_every_pair(curves: &[CurveRef<'_>]) -> bool {
        let grid = EdgeGrid::new(curves);
        let Some(g) = grid else { return false };
        let n = g.segs.len() as u32;
        (0..n).any(|s1| (s1 + 1..n).any(|s2| g.hit(curves, s1, s2)))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The composite walk's yes-or-no test agrees with the full list of crossings and with
        /// testing every pair of edges: random polylines on a coarse grid (so that touching,
        /// collinear and repeated points are common), open or closed.
        #[test]
        fn curves_cross_is_whether_any_pair_crosses(
            curves in proptest::collection::vec(
                (proptest::collection::vec((-4i32..5, -4i32..5), 0..14), proptest::bool::ANY),
                1..4,
            ),
            fine in proptest::bool::ANY,
        ) {
            let scale = if fine { 0.37 } else { 1.0 };
            let pts: Vec<(Vec<Point>, bool)> = curves
                .iter()
                .map(|(c, closed)| {
                    (c.iter().map(|&(x, y)| p(f64::from(x) * scale, f64::from(y))).collect(), *closed)
                })
                .collect();
            let refs: Vec<CurveRef<'_>> = pts.iter().map(|(c, closed)| (c.as_slice(), *closed)).collect();
            let any = curves_cross(&refs);
            proptest::prop_assert_eq!(any, !crossing_curves(&refs).is_empty());
            proptest::prop_assert_eq!(any, crossing_by_every_pair(&refs));
        }
    }
}
