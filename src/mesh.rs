//! Compatible triangulations: one connectivity, two vertex sets — and the sanity checker every
//! test and fuzzer uses.
//!
//! This is the data the compatible triangulation stage (§5) produces and the rigid interpolation
//! (§4.1) consumes. Triangles are counter-clockwise (positive [`orient2d`]) in the mesh they were
//! built in (the source, or the target with `--from target`).

use crate::geometry::{orient2d, Point};
use serde::{Deserialize, Serialize};

/// Which of a morph's two drawings (and meshes): the source, shown at t = 0, or the target, at
/// t = 1. The compatible triangulation triangulates one side and maps it onto the other (the
/// paper triangulates the source; Fig. 12 the target).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Side {
    /// The source drawing (default).
    #[default]
    Source,
    /// The target drawing.
    Target,
}

impl Side {
    /// The other side.
    pub fn other(self) -> Side {
        match self {
            Side::Source => Side::Target,
            Side::Target => Side::Source,
        }
    }

    /// This side as the drawing an error of a stage that knows no file names is in
    /// ([`crate::Error::with_files`] names it).
    pub fn drawing(self) -> crate::error::Drawings {
        match self {
            Side::Source => crate::error::Drawings::Source,
            Side::Target => crate::error::Drawings::Target,
        }
    }
}

/// What kind of control curve a mesh curve comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CurveKind {
    /// The outline of the shape (`boundary`, or the viewBox rectangle).
    Boundary,
    /// An interior feature curve (`feature-NAME`).
    Feature,
}

/// A boundary or feature curve as a chain of mesh vertices, in the same order in both meshes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshCurve {
    /// `boundary` or `feature-NAME` (the element id as written in the input).
    pub name: String,
    /// Boundary or feature.
    pub kind: CurveKind,
    /// Whether the last vertex connects back to the first.
    pub closed: bool,
    /// Mesh vertex indices along the curve.
    pub vertices: Vec<u32>,
}

/// Two triangulations with one connectivity: vertex `i` of `source` corresponds to vertex `i` of
/// `target`, and every curve's vertices land on their twins.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CompatibleMeshes {
    /// Shared connectivity, counter-clockwise in the mesh that was triangulated.
    pub triangles: Vec<[u32; 3]>,
    /// Vertex positions in the source drawing's user space.
    pub source: Vec<Point>,
    /// Vertex positions in the target drawing's user space.
    pub target: Vec<Point>,
    /// Boundary first, then features in name order.
    pub curves: Vec<MeshCurve>,
    /// How the meshes split into shapes, when they are several (automatic mode); `None` for
    /// one shape.
    pub parts: Option<Parts>,
}

/// The shapes of compatible meshes made of several (automatic mode: one compatible
/// triangulation per matched shape, issue #7): which triangles belong to which shape, the part
/// that stands still, and the curves that morph without a mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Parts {
    /// The part of every triangle.
    pub of_triangle: Vec<u32>,
    /// Number of parts.
    pub count: u32,
    /// The part that does not move: a frame around the drawing with the same vertices in
    /// both meshes. Artwork outside every shape is bound to it, so it stays where it is.
    pub still: Option<u32>,
    /// Indices into the meshes' curves of curves with no triangles (a stroke's centre line,
    /// an outline morphed without an interior mesh): they move as chains of disc neighbours.
    pub chains: Vec<usize>,
    /// The parts whose frames need the fold repair of the disc interpolation (their meshes
    /// fold a few triangles in between otherwise).
    pub repair: Vec<u32>,
}

/// Counts found by [`sanity_check`]; a healthy pair of meshes has every count zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SanityReport {
    /// Triangles referring to a vertex index out of range or repeating a vertex.
    pub bad_indices: usize,
    /// Vertices with a non-finite coordinate (either mesh).
    pub non_finite: usize,
    /// Source triangles that are not strictly counter-clockwise.
    pub inverted_source: usize,
    /// Target triangles whose orientation is not strictly counter-clockwise.
    pub inverted_target: usize,
    /// Curve vertices whose target position is farther than the tolerance from the expected
    /// twin (only counted when twins are given).
    pub curve_mismatches: usize,
    /// Vertices used by no triangle (curve vertices of [`Parts::chains`] excepted).
    pub unused_vertices: usize,
}

impl SanityReport {
    /// True when nothing is wrong.
    pub fn is_ok(&self) -> bool {
        *self == SanityReport::default()
    }
}

/// Number of triangles of `triangles` that are not strictly positively oriented in `points`
/// (exact predicate). This is the "inverted triangles" quality measure.
pub fn count_inverted(triangles: &[[u32; 3]], points: &[Point]) -> usize {
    triangles
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| points[i as usize]);
            orient2d(a, b, c) <= 0.0
        })
        .count()
}

/// Checks shared connectivity, index validity, finiteness, orientation in both meshes, unused
/// vertices, and — when `twins` is given as `(curve index, target polyline)` pairs — that every
/// curve vertex lies within `tol` of its twin.
pub fn sanity_check(m: &CompatibleMeshes, twins: Option<&[Vec<Point>]>, tol: f64) -> SanityReport {
    let mut r = SanityReport::default();
    let n = m.source.len();
    if m.target.len() != n {
        r.bad_indices += n.abs_diff(m.target.len());
    }
    let mut used = vec![false; n];
    let mut ok_tris = Vec::with_capacity(m.triangles.len());
    for t in &m.triangles {
        let [a, b, c] = *t;
        if (a as usize) >= n || (b as usize) >= n || (c as usize) >= n || a == b || b == c || a == c
        {
            r.bad_indices += 1;
            continue;
        }
        for i in t {
            used[*i as usize] = true;
        }
        ok_tris.push(*t);
    }
    if m.target.len() == n {
        r.inverted_source = count_inverted(&ok_tris, &m.source);
        r.inverted_target = count_inverted(&ok_tris, &m.target);
    }
    r.non_finite = m
        .source
        .iter()
        .chain(m.target.iter())
        .filter(|p| !p.is_finite())
        .count();
    if let Some(parts) = &m.parts {
        for &c in &parts.chains {
            for &v in m.curves.get(c).map_or(&[][..], |c| &c.vertices[..]) {
                if let Some(u) = used.get_mut(v as usize) {
                    *u = true;
                }
            }
        }
    }
    r.unused_vertices = used.iter().filter(|u| !**u).count();
    if let Some(twins) = twins {
        for (curve, twin) in m.curves.iter().zip(twins) {
            if twin.len() != curve.vertices.len() {
                r.curve_mismatches += curve.vertices.len().max(twin.len());
                continue;
            }
            for (&v, &q) in curve.vertices.iter().zip(twin) {
                let ok = m
                    .target
                    .get(v as usize)
                    .is_some_and(|p| p.distance(q) <= tol);
                if !ok {
                    r.curve_mismatches += 1;
                }
            }
        }
    }
    r
}

/// Undirected edges of a triangle list, each once as `(lo, hi)`, sorted.
pub fn edges(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut e: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    sort_pairs(&mut e);
    e.dedup();
    e
}

/// `list` ascending and without repeats, as `sort_unstable` then `dedup` leave it, through one
/// bit per value in `marks` (clear on entry, left clear, grown to a word per 64 values up to the
/// largest, so for indices into a mesh, not arbitrary numbers) instead of a sort: the
/// untangler makes such lists of the same few thousand vertex and triangle indices every sweep
/// (issue 16: their sorts were 3.5 % of the slowest corpus pair's instructions).
pub(crate) fn sort_unique(list: &mut Vec<u32>, marks: &mut Vec<u64>) {
    let Some(&max) = list.iter().max() else {
        return;
    };
    let words = max as usize / 64 + 1;
    if marks.len() < words {
        marks.resize(words, 0);
    }
    let mut first = usize::MAX;
    for &v in list.iter() {
        let w = v as usize / 64;
        marks[w] |= 1u64 << (v % 64);
        first = first.min(w);
    }
    list.clear();
    for (w, bits) in marks[first..words].iter_mut().enumerate() {
        let mut b = std::mem::take(bits);
        while b != 0 {
            list.push(((first + w) * 64) as u32 + b.trailing_zeros());
            b &= b - 1;
        }
    }
}

/// Compressed rows over `n` rows: `(start, values)`, where row `r`'s values, in the order
/// `entries` gives them as `(r, value)`, are `values[start[r]..start[r + 1]]`. Every `r` must
/// be below `n`.
pub(crate) fn compressed_rows<I>(n: usize, entries: I) -> (Vec<usize>, Vec<u32>)
where
    I: Iterator<Item = (u32, u32)> + Clone,
{
    // `for_each`, not a `for` loop: entries are often a `flat_map`, which runs its inner
    // arrays far faster when it drives the loop itself.
    let mut start = vec![0usize; n + 1];
    entries
        .clone()
        .for_each(|(r, _)| start[r as usize + 1] += 1);
    for r in 0..n {
        start[r + 1] += start[r];
    }
    let mut fill = start.clone();
    let mut values = vec![0u32; start[n]];
    entries.for_each(|(r, v)| {
        values[fill[r as usize]] = v;
        fill[r as usize] += 1;
    });
    (start, values)
}

/// [`compressed_rows`] with every row sorted: read in row order, the pairs in the order
/// `sort_unstable` gives them.
pub(crate) fn sorted_rows<I>(n: usize, entries: I) -> (Vec<usize>, Vec<u32>)
where
    I: Iterator<Item = (u32, u32)> + Clone,
{
    let (start, mut values) = compressed_rows(n, entries);
    for r in 0..n {
        values[start[r]..start[r + 1]].sort_unstable();
    }
    (start, values)
}

/// Sorts `pairs` into the order `sort_unstable` gives (lexicographic), by rows: a counting pass
/// over the first indices, then a sort of each row's few second indices. On a mesh's edges
/// that is linear where a comparison sort pays a log factor, and every set-up of a mesh sorts
/// its edges several times (issue 16). Pairs whose first indices are sparse (more rows than
/// pairs would be made) are sorted by comparison.
pub(crate) fn sort_pairs(pairs: &mut Vec<(u32, u32)>) {
    let Some(n) = pairs.iter().map(|p| p.0 as usize + 1).max() else {
        return;
    };
    if n > 4 * pairs.len() + 64 {
        pairs.sort_unstable();
        return;
    }
    let (start, seconds) = sorted_rows(n, pairs.iter().copied());
    pairs.clear();
    for r in 0..n {
        pairs.extend(
            seconds[start[r]..start[r + 1]]
                .iter()
                .map(|&s| (r as u32, s)),
        );
    }
}

/// Whether triangle `t` is strictly counter-clockwise in `points` (exact predicate).
pub(crate) fn is_positive(points: &[Point], t: [u32; 3]) -> bool {
    orient2d(
        points[t[0] as usize],
        points[t[1] as usize],
        points[t[2] as usize],
    ) > 0.0
}

/// The triangles around each of `vertex_count` vertices (indices into `triangles`).
pub(crate) fn stars(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<Vec<u32>> {
    let mut star = vec![Vec::new(); vertex_count];
    for (f, t) in triangles.iter().enumerate() {
        for &v in t {
            star[v as usize].push(f as u32);
        }
    }
    star
}

/// One-ring neighbour lists (the "discs" of §4.1 for a triangulation), each sorted ascending.
pub fn one_rings(triangles: &[[u32; 3]], vertex_count: usize) -> Vec<Vec<u32>> {
    let (start, rings) = ring_rows(triangles, vertex_count, std::iter::empty());
    (0..vertex_count)
        .map(|v| rings[start[v]..start[v + 1]].to_vec())
        .collect()
}

/// [`one_rings`] in compressed rows, vertex `v`'s ring `rings[start[v]..start[v + 1]]`, with
/// the pairs `links` (distinct, below `vertex_count`) joined both ways too, each neighbour
/// once. One allocation instead of one per vertex, for a set-up that reads every ring once
/// (issue 16).
pub(crate) fn ring_rows(
    triangles: &[[u32; 3]],
    vertex_count: usize,
    links: impl Iterator<Item = (u32, u32)>,
) -> (Vec<usize>, Vec<u32>) {
    let mut edges = edges(triangles);
    let mesh_edges = edges.len();
    edges.extend(links.map(|(a, b)| (a.min(b), a.max(b))));
    if edges.len() > mesh_edges {
        sort_pairs(&mut edges);
        edges.dedup();
    }
    // The edges come sorted, so each ring receives its smaller neighbours (as the second
    // index of `(lo, v)`) in ascending order before its larger ones (as `(v, hi)`): every ring
    // is sorted as it is filled.
    compressed_rows(
        vertex_count,
        edges.iter().flat_map(|&(a, b)| [(a, b), (b, a)]),
    )
}

/// A regular hexagon of unit radius about its centre (vertex 6), as six counter-clockwise
/// triangles: the smallest star, for the tests of what moves a vertex in its star.
#[cfg(test)]
pub(crate) fn hexagon_fan() -> (Vec<Point>, Vec<[u32; 3]>) {
    let mut pts: Vec<Point> = (0..6)
        .map(|k| Point::from_angle(std::f64::consts::TAU * k as f64 / 6.0))
        .collect();
    pts.push(Point::ZERO);
    (pts, (0..6u32).map(|k| [k, (k + 1) % 6, 6]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        /// The counting sort of pairs gives `sort_unstable`'s order, dense and sparse first
        /// indices (the comparison fallback) alike, duplicates kept.
        #[test]
        fn pairs_are_sorted_as_sort_unstable_sorts_them(
            pairs in proptest::collection::vec((0u32..50, 0u32..50), 0..400),
            spread in 1u32..100_000,
        ) {
            let mut pairs: Vec<(u32, u32)> = pairs.iter().map(|&(a, b)| (a * spread, b)).collect();
            let mut expected = pairs.clone();
            expected.sort_unstable();
            sort_pairs(&mut pairs);
            proptest::prop_assert_eq!(pairs, expected);
        }

        /// The bit marks give the list `sort_unstable` and `dedup` give, and leave every mark
        /// clear for the next list, whatever the marks' length before (one list after another
        /// through the same marks, as the untangler's sweeps use them).
        #[test]
        fn unique_lists_are_sort_and_dedup(
            lists in proptest::collection::vec(
                proptest::collection::vec(0u32..3000, 0..300), 1..4),
            spread in 1u32..1000,
        ) {
            let mut marks = Vec::new();
            for list in lists {
                let mut list: Vec<u32> = list.iter().map(|&v| v * spread).collect();
                let mut expected = list.clone();
                expected.sort_unstable();
                expected.dedup();
                sort_unique(&mut list, &mut marks);
                proptest::prop_assert_eq!(list, expected);
                proptest::prop_assert!(marks.iter().all(|&w| w == 0));
            }
        }
    }

    fn square() -> CompatibleMeshes {
        let s = vec![
            Point::new(0., 0.),
            Point::new(1., 0.),
            Point::new(1., 1.),
            Point::new(0., 1.),
        ];
        CompatibleMeshes {
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            target: s.iter().map(|p| *p * 2.0).collect(),
            source: s,
            curves: vec![MeshCurve {
                name: "boundary".into(),
                kind: CurveKind::Boundary,
                closed: true,
                vertices: vec![0, 1, 2, 3],
            }],
            parts: None,
        }
    }

    #[test]
    fn healthy_meshes_pass_and_counts_are_specific() {
        let mut m = square();
        let twins = vec![m.target.clone()];
        assert!(sanity_check(&m, Some(&twins), 1e-12).is_ok());
        m.target.swap(0, 2); // folds both triangles
        let r = sanity_check(&m, Some(&twins), 1e-12);
        assert_eq!(r.inverted_target, 2);
        assert_eq!(r.curve_mismatches, 2);
        assert_eq!(r.inverted_source, 0);
        m.triangles.push([0, 0, 1]);
        assert_eq!(sanity_check(&m, None, 0.0).bad_indices, 1);
    }

    #[test]
    fn edges_and_rings() {
        let m = square();
        assert_eq!(
            edges(&m.triangles),
            vec![(0, 1), (0, 2), (0, 3), (1, 2), (2, 3)]
        );
        let r = one_rings(&m.triangles, 4);
        assert_eq!(r[0], vec![1, 2, 3]);
        assert_eq!(r[1], vec![0, 2]);
        // A link joins its two ends both ways, once even where the mesh has it already.
        let (start, rings) = ring_rows(&m.triangles, 5, [(4, 1), (2, 0), (1, 4)].into_iter());
        let row = |v: usize| &rings[start[v]..start[v + 1]];
        assert_eq!(row(0), [1, 2, 3]);
        assert_eq!(row(1), [0, 2, 4]);
        assert_eq!(row(4), [1]);
    }
}
