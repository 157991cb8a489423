//! Disc-based rigidity-preserving interpolation (§4.1, eq. 1).
//!
//! Each point `p_i` has a disc `P_i` of neighbours (its one-ring on a triangle mesh). For every
//! `j ∈ P_i` the local linear map `L_(i,j)` rotates `p_j − p_i` by `α_ij` and scales it by `s_ij`
//! onto `q_j − q_i`; its intermediate is `L^t_(i,j)(p_j − p_i) = R(tα_ij)(p_j − p_i)(1 − t + t·s_ij)`.
//! The frame at `t` minimizes eq. (1), `Σ_i Σ_{j∈P_i} ‖L^t_(i,j)(p_j − p_i) − (v_j − v_i)‖²`.
//!
//! ## One term per undirected edge
//!
//! The transformation of `(j, i)` maps `p_i − p_j = −(p_j − p_i)` to `q_i − q_j = −(q_j − q_i)`, so
//! `α_ji = α_ij` and `s_ji = s_ij` exactly, and `L^t_(j,i)(p_i − p_j) = −L^t_(i,j)(p_j − p_i)`: its
//! term in eq. (1) equals the term of `(i, j)`. We therefore store each undirected edge once, with
//! weight = the number of its directions present in the discs (2 on a mesh), which leaves eq. (1)
//! unchanged and halves the per-frame `sin_cos` work.
//!
//! ## Reduced rotation graph
//!
//! §4.1.1 builds a graph with a node per *directed* transformation, linking `(i₁, j₁)` and
//! `(i₂, j₂)` when `p_j₁ ∈ P_j₂` or `p_j₂ ∈ P_j₁` (about 36 links per transformation on a mesh).
//! Since both directions of an edge carry the same angle, we use one node per undirected edge and
//! link two edges when they share a vertex (about 5 links per edge). Why the results agree: two
//! angle assignments that are both consistent on one connected graph (every pair of linked
//! transformations within π) and leave the same root uncorrected are equal — their difference is
//! a multiple of 2π that cannot change across a link, and it is zero at the root. Both graphs pick
//! the same root (smallest `|α|`, lowest index: the node order of the full graph lists each edge
//! first at its smaller end point, as the sorted edge list does). So for deformations whose
//! neighbouring rotations differ by less than π — the case §4.1.1 is designed for — both graphs
//! give the same angles; `reduced_rotation_graph_matches_the_full_graph` checks it on bends and
//! turns past 180°. The edges at a vertex are all linked to each other (a clique), so the
//! spanning forest is found from each clique's own spanning tree
//! ([`super::rotation::consistent_angles_in_cliques`]): the same forest, from a third of the
//! links.
//!
//! On triangle meshes the frames then get the area rule (`area.rs`, a documented deviation):
//! each connected part is scaled uniformly so that its area does not swell where eq. (1)'s
//! per-edge scales stretch it unevenly.

use super::area::AreaRule;
use super::assembly::{
    component_centroids, lerp_into, FactoredSystem, SolveScratch, SystemBuilder,
};
use super::factor::{Row, MAX_LANES};
use super::rotation::{consistent_angles_in_cliques, Cliques};
use super::simd::vectorized;
use super::sincos::sin_cos_many;
use super::Repair;
use crate::error::{Error, Result};
use crate::geometry::{bounding_box, Point};
use std::sync::Arc;

/// Terms whose rotations are computed together in a frame: small enough for the stack and L1.
const CHUNK: usize = 64;

/// Disc edges shorter than this fraction of the point set's bounding-box diagonal have no
/// meaningful direction and are rejected as coincident points.
const MIN_EDGE_FRACTION: f64 = 1e-12;

/// The local transformations of every disc, one per undirected edge (module docs).
#[derive(Debug, Clone)]
pub(crate) struct LocalTransforms {
    /// The discs as pairs: `(i, j)` for every `j` in `p_i`'s disc, once each, sorted.
    pub(crate) directed: Vec<(u32, u32)>,
    /// Undirected edges `(i, j)` with `i < j`, sorted.
    pub(crate) edges: Vec<(u32, u32)>,
    /// How many of the two directions appear in the discs (1 or 2).
    pub(crate) weight: Vec<f64>,
    /// Source edge vectors `p_j − p_i`.
    pub(crate) d: Vec<Point>,
    /// Rotation angles from `p_j − p_i` to `q_j − q_i`, in (−π, π] (before §4.1.1).
    pub(crate) alpha: Vec<f64>,
    /// Scale factors `|q_j − q_i| / |p_j − p_i|`.
    pub(crate) scale: Vec<f64>,
}

/// Checks lengths and finiteness of a compatible point pair.
pub(crate) fn validate_points(source: &[Point], target: &[Point]) -> Result<()> {
    if source.len() != target.len() {
        return Err(Error::input(
            crate::error::Drawings::Target,
            format!(
                "the target has {} points but the source has {}; compatible meshes need one \
                 target point per source point",
                target.len(),
                source.len()
            ),
        ));
    }
    for (name, pts) in [
        (crate::error::Drawings::Source, source),
        (crate::error::Drawings::Target, target),
    ] {
        if let Some(i) = pts.iter().position(|p| !p.is_finite()) {
            return Err(Error::input(
                name,
                format!("point {i} has a non-finite coordinate"),
            ));
        }
    }
    Ok(())
}

/// Every directed pair `(i, j)` of `directed` (sorted, no repeats) as `(min, max)`, sorted, so
/// that an edge present in both directions appears twice. When the discs are `ascending` and
/// symmetric (`j` in `i`'s disc whenever `i` is in `j`'s, as one-rings are), that is each
/// pair `(i, j)` with `i < j` twice, in the order `directed` has them: no sort. Otherwise
/// the pairs are sorted.
fn undirected_pairs<D: AsRef<[u32]>>(
    directed: &[(u32, u32)],
    discs: &[D],
    ascending: bool,
) -> Vec<(u32, u32)> {
    if ascending && symmetric(directed, discs) {
        return directed
            .iter()
            .filter(|&&(i, j)| i < j)
            .flat_map(|&p| [p, p])
            .collect();
    }
    let mut undirected: Vec<(u32, u32)> = directed
        .iter()
        .map(|&(i, j)| (i.min(j), i.max(j)))
        .collect();
    crate::mesh::sort_pairs(&mut undirected);
    undirected
}

/// Whether ascending discs (each strictly increasing) are symmetric: `i` in `j`'s disc
/// whenever `j` is in `i`'s. `directed` is their pairs as read, disc by disc. Read in that
/// order, the pairs `(i, j)` with `i < j` ask each `j` for its smaller neighbours in ascending
/// order, so one cursor per disc checks them, and every smaller neighbour must have been asked
/// for: linear, where a binary search per pair was about 2 % of a small mesh's set-up.
fn symmetric<D: AsRef<[u32]>>(directed: &[(u32, u32)], discs: &[D]) -> bool {
    let mut met = vec![0usize; discs.len()];
    for &(i, j) in directed {
        if i < j {
            let (disc, m) = (discs[j as usize].as_ref(), &mut met[j as usize]);
            if disc.get(*m) != Some(&i) {
                return false;
            }
            *m += 1;
        }
    }
    discs
        .iter()
        .zip(&met)
        .enumerate()
        .all(|(j, (d, &m))| d.as_ref().get(m).is_none_or(|&k| k as usize > j))
}

fn diagonal(points: &[Point]) -> f64 {
    bounding_box(points.iter().copied()).map_or(0.0, |(lo, hi)| lo.distance(hi))
}

impl LocalTransforms {
    /// Local transformations of the discs `discs[i]` (indices of the points in `p_i`'s disc,
    /// not `i` itself; repeated entries count once).
    pub(crate) fn new<D: AsRef<[u32]>>(
        source: &[Point],
        target: &[Point],
        discs: &[D],
    ) -> Result<Self> {
        validate_points(source, target)?;
        let n = source.len();
        if discs.len() != n {
            return Err(Error::input(
                crate::error::Drawings::Source,
                format!("{} discs given for {} points", discs.len(), n),
            ));
        }
        let mut directed: Vec<(u32, u32)> =
            Vec::with_capacity(discs.iter().map(|d| d.as_ref().len()).sum());
        let mut ascending = true;
        for (i, d) in discs.iter().enumerate() {
            let d = d.as_ref();
            for &j in d {
                if j as usize >= n || j as usize == i {
                    return Err(Error::input(
                        crate::error::Drawings::Source,
                        format!(
                            "the disc of point {i} refers to point {j}, which is not a neighbour"
                        ),
                    ));
                }
                directed.push((i as u32, j));
            }
            ascending &= d.windows(2).all(|w| w[0] < w[1]);
        }
        if !ascending {
            crate::mesh::sort_pairs(&mut directed);
            directed.dedup();
        }
        let undirected = undirected_pairs(&directed, discs, ascending);
        let (min_src, min_tgt) = (
            MIN_EDGE_FRACTION * diagonal(source),
            MIN_EDGE_FRACTION * diagonal(target),
        );
        // One-rings list every edge twice, so half the pairs is the usual count.
        let edges = undirected.len() / 2 + 1;
        let mut t = LocalTransforms {
            directed: Vec::new(),
            edges: Vec::with_capacity(edges),
            weight: Vec::with_capacity(edges),
            d: Vec::with_capacity(edges),
            alpha: Vec::with_capacity(edges),
            scale: Vec::with_capacity(edges),
        };
        for &(i, j) in &undirected {
            if t.edges.last() == Some(&(i, j)) {
                if let Some(w) = t.weight.last_mut() {
                    *w += 1.0;
                }
                continue;
            }
            let d = source[j as usize] - source[i as usize];
            let e = target[j as usize] - target[i as usize];
            let (ld, le) = (d.length(), e.length());
            if ld <= min_src {
                return Err(Error::input(
                    crate::error::Drawings::Source,
                    format!("points {i} and {j} coincide (a disc edge of zero length)"),
                ));
            }
            if le <= min_tgt {
                return Err(Error::input(
                    crate::error::Drawings::Target,
                    format!("points {i} and {j} coincide (a disc edge of zero length)"),
                ));
            }
            let mut a = d.perp_dot(e).atan2(d.dot(e));
            if a <= -std::f64::consts::PI {
                a = std::f64::consts::PI;
            }
            t.edges.push((i, j));
            t.weight.push(1.0);
            t.d.push(d);
            t.alpha.push(a);
            t.scale.push(le / ld);
        }
        t.directed = directed;
        Ok(t)
    }

    /// The mean of `alpha` (one angle per edge) over each point's disc: the rotation of the
    /// point's local transformations. Each disc is summed in ascending neighbour order, as
    /// `Iterator::sum` would sum it; an empty disc has 0.
    pub(crate) fn disc_means(&self, n: usize, alpha: &[f64]) -> Vec<f64> {
        let mut sum = vec![-0.0f64; n];
        let mut count = vec![0u32; n];
        if self.weight.iter().all(|&w| w == 2.0) {
            // Every edge is in the discs of both its ends (one-rings are), so a point's disc
            // pairs are its edges. In edge order those come in ascending neighbour order: the
            // edges `(lo, v)` by `lo`, all before `v`'s own run `(v, hi)` by `hi`.
            for (&(i, j), &a) in self.edges.iter().zip(alpha) {
                sum[i as usize] += a;
                count[i as usize] += 1;
                sum[j as usize] += a;
                count[j as usize] += 1;
            }
            return means(&sum, &count);
        }
        // First edge of each smaller end: an edge `(lo, hi)` is found in `lo`'s short run.
        let mut first = vec![self.edges.len(); n + 1];
        for (k, &(i, _)) in self.edges.iter().enumerate().rev() {
            first[i as usize] = k;
        }
        for v in (0..n).rev() {
            first[v] = first[v].min(first[v + 1]);
        }
        for &(i, j) in &self.directed {
            let key = (i.min(j), i.max(j));
            let run = &self.edges[first[key.0 as usize]..first[key.0 as usize + 1]];
            if let Some(k) = run.iter().position(|&e| e == key) {
                sum[i as usize] += alpha[first[key.0 as usize] + k];
            }
            count[i as usize] += 1;
        }
        means(&sum, &count)
    }

    /// The reduced rotation graph (module docs) as cliques: the edges incident to each vertex,
    /// in edge order, every two of which are linked; each edge is in its two end points'
    /// cliques.
    pub(crate) fn rotation_cliques(&self, n: usize) -> Cliques {
        let (start, members) = crate::mesh::compressed_rows(
            n,
            self.edges
                .iter()
                .enumerate()
                .flat_map(|(k, &(i, j))| [(i, k as u32), (j, k as u32)]),
        );
        // Edge `k` is in the cliques of its two end points.
        Cliques {
            start,
            members,
            of_start: (0..=self.edges.len()).map(|k| 2 * k).collect(),
            of_node: self.edges.iter().flat_map(|&(i, j)| [i, j]).collect(),
        }
    }
}

/// Each sum divided by its count, 0 for none.
fn means(sum: &[f64], count: &[u32]) -> Vec<f64> {
    sum.iter()
        .zip(count)
        .map(|(&s, &c)| if c == 0 { 0.0 } else { s / f64::from(c) })
        .collect()
}

/// One precomputed term of the per-frame right-hand side.
#[derive(Debug, Clone, Copy)]
struct EdgeTerm {
    /// Right-hand-side rows of the edge's end points.
    ri: u32,
    rj: u32,
    /// `weight · (p_j − p_i)`.
    wd: Point,
    /// `s − 1`, so the scale at `t` is `1 + t·(s − 1)`.
    s1: f64,
}

/// A constant extra row of the least squares, `weight · ‖Σ_k c_k v_k − J‖²`, whose target `J`
/// changes per frame: the barycentric rows `C_k V − J'_k` of eq. (2) (skeleton control, §4.2).
/// Its weight is relative to eq. (1) as assembled here (each mesh edge counted in both
/// directions). A part of the shape that extra rows reach is positioned by them instead of by
/// the centroid rule.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ExtraRow {
    /// `(point index, coefficient)` pairs, e.g. a triangle's barycentric coordinates.
    pub(crate) coeffs: Vec<(u32, f64)>,
    /// Positive weight of the row.
    pub(crate) weight: f64,
}

/// The disc method, set up: consistent local transformations and the factored eq. (1).
#[derive(Debug)]
pub(crate) struct DiscRigid {
    terms: Vec<EdgeTerm>,
    /// The end points `(i, j)` of each term's edge (for the bone adjustments of §4.2.2).
    ends: Vec<(u32, u32)>,
    /// Consistent rotation angle of each term (§4.1.1).
    alpha: Vec<f64>,
    /// How many discs hold each term's edge: its weight in the matrix, with `ends` and
    /// `extra` all the matrix depends on ([`DiscRigid::with_area_rule`] reuses a system).
    weights: Vec<f64>,
    extra: Vec<ExtraRow>,
    /// The factored matrix of eq. (1), shared with the set-ups that reused it.
    system: Arc<FactoredSystem>,
    centroid_source: Vec<Point>,
    centroid_target: Vec<Point>,
    rotation: Vec<f64>,
    /// The area rule (`area.rs`), for frames of a triangle mesh without extra rows.
    area: Option<AreaRule>,
    /// Parts that move together ([`DiscRigid::group_parts`]).
    group: Option<Box<PartGroup>>,
    /// The post-solve fold repair (`repair.rs`), for meshes that need it.
    pub(crate) repair: Option<Box<super::repair::FoldRepair>>,
}

/// Connected parts that move as one figure (automatic mode's shapes of one icon): their
/// centroids follow the disc-based rigid interpolation of the *barycenter mesh* — one point
/// per part, every part linked to every other, as the paper's shape model links its curves
/// (§5, Fig. 9) — instead of straight lines, so parts that swing round together keep their
/// layout; and each part's rotations are taken on the branch (a multiple of 2π) nearest the
/// barycenter mesh's own turn, so that parts turning together turn the same way.
#[derive(Debug)]
struct PartGroup {
    /// The member components, in increasing order.
    members: Vec<u32>,
    /// The barycenter mesh's interpolation (`None` with fewer than two distinct centroids:
    /// the centroids then keep their straight lines).
    barycenters: Option<Box<DiscRigid>>,
}

/// The extra-row targets and adjustments of a batch's frames, laid end to end (either empty
/// for none), as [`DiscRigid::frames_into`] takes them: `rows` targets and `points`
/// adjustments per frame.
struct Lanes<'a> {
    targets: &'a [Point],
    adjust: &'a [Point],
    rows: usize,
    points: usize,
}

impl<'a> Lanes<'a> {
    /// Frame `k`'s extra-row targets (empty for none).
    fn targets(&self, k: usize) -> &'a [Point] {
        &self.targets[k * self.rows..(k + 1) * self.rows]
    }

    /// Frame `k`'s adjustments, if the frames have them.
    fn adjust(&self, k: usize) -> Option<&'a [Point]> {
        (self.points > 0).then(|| &self.adjust[k * self.points..(k + 1) * self.points])
    }
}

/// Per-thread scratch for [`DiscRigid::at`] and the triangle baseline.
#[derive(Debug)]
pub(crate) struct FrameScratch {
    pub(crate) solve: SolveScratch,
    pub(crate) centroids: Vec<Point>,
    /// Per-term angles at `t`, then their sines and cosines.
    pub(crate) angle: Vec<f64>,
    pub(crate) sin: Vec<f64>,
    pub(crate) cos: Vec<f64>,
    /// Per-component areas for the area rule.
    areas: Vec<f64>,
    /// The barycenter mesh's scratch and frame, for grouped parts.
    group: Option<Box<(FrameScratch, Vec<Point>)>>,
}

impl FrameScratch {
    /// Scratch for `system` with `terms` rotations per frame.
    pub(crate) fn new(system: &FactoredSystem, components: usize, terms: usize) -> Self {
        FrameScratch {
            solve: system.scratch(),
            centroids: vec![Point::ZERO; components],
            angle: vec![0.0; terms],
            sin: vec![0.0; terms],
            cos: vec![0.0; terms],
            areas: vec![0.0; components],
            group: None,
        }
    }

    /// Fills `sin`, `cos` with the rotations `R(t·alpha[k])`.
    pub(crate) fn rotations(&mut self, t: f64, alpha: &[f64]) {
        for (a, &al) in self.angle.iter_mut().zip(alpha) {
            *a = t * al;
        }
        sin_cos_many(&self.angle, &mut self.sin, &mut self.cos);
    }
}

impl DiscRigid {
    /// Sets up the disc method for compatible point sets and their discs (§4.1): local
    /// transformations, consistent rotation (§4.1.1), normal equations factored once.
    pub(crate) fn new<D: AsRef<[u32]>>(
        source: &[Point],
        target: &[Point],
        discs: &[D],
    ) -> Result<Self> {
        Self::set_up(source, target, discs, Vec::new(), None)
    }

    /// [`DiscRigid::new`] on a triangle mesh (`discs` its one-rings) with the area rule
    /// (`area.rs`): every connected part's area — that of `triangles`, all of the mesh's or a
    /// region of them, and of the closed outlines without a mesh whose directed edges are
    /// `cycles` — follows the similarity curve between its end areas instead of swelling or
    /// shrinking where it stretches unevenly.
    ///
    /// The matrix of eq. (1) depends on the discs alone, not on the points. So when `like` was
    /// set up on the same discs (the same edges, each in as many discs), its factored system
    /// serves this set-up too, the same bits without a second ordering and factorization:
    /// automatic mode sets up a part's mapped mesh and its relaxed twin, which differ only in
    /// their points (issue 16). A `like` on other discs is not used.
    pub(crate) fn with_area_rule<D: AsRef<[u32]>>(
        source: &[Point],
        target: &[Point],
        discs: &[D],
        triangles: &[[u32; 3]],
        cycles: &[(u32, u32)],
        like: Option<&DiscRigid>,
    ) -> Result<Self> {
        let mut d = Self::set_up(source, target, discs, Vec::new(), like)?;
        let count = d.system.component_count();
        d.area = Some(AreaRule::new(
            triangles,
            cycles,
            d.system.components(),
            count,
            source,
            target,
        ));
        Ok(d)
    }

    /// [`DiscRigid::new`] with constant extra rows added to the matrix before it is factored
    /// (the hook for eq. (2)); evaluate with [`DiscRigid::at_with_targets`].
    pub(crate) fn with_extra_rows<D: AsRef<[u32]>>(
        source: &[Point],
        target: &[Point],
        discs: &[D],
        extra: Vec<ExtraRow>,
    ) -> Result<Self> {
        Self::set_up(source, target, discs, extra, None)
    }

    /// [`DiscRigid::with_extra_rows`], reusing the factored system of `like` when it was set
    /// up on the same discs and extra rows ([`DiscRigid::with_area_rule`]).
    fn set_up<D: AsRef<[u32]>>(
        source: &[Point],
        target: &[Point],
        discs: &[D],
        extra: Vec<ExtraRow>,
        like: Option<&DiscRigid>,
    ) -> Result<Self> {
        let local = LocalTransforms::new(source, target, discs)?;
        let n = source.len();
        let alpha = consistent_angles_in_cliques(&local.alpha, || local.rotation_cliques(n));
        let same_matrix = |d: &&DiscRigid| {
            d.vertex_count() == n
                && d.ends == local.edges
                && d.weights == local.weight
                && d.extra == extra
        };
        let system = match like.filter(same_matrix) {
            Some(d) => d.system.clone(),
            None => {
                let mut builder = SystemBuilder::new(n);
                builder.reserve_edges(local.edges.len());
                for (&(i, j), &w) in local.edges.iter().zip(&local.weight) {
                    builder.add_edge(i, j, w);
                }
                for (r, row) in extra.iter().enumerate() {
                    let bad = row.coeffs.is_empty()
                        || !(row.weight > 0.0 && row.weight.is_finite())
                        || row
                            .coeffs
                            .iter()
                            .any(|&(v, c)| v as usize >= n || !c.is_finite());
                    if bad {
                        return Err(Error::internal(format!(
                            "extra row {r} has no coefficients, a bad weight or a bad point index"
                        )));
                    }
                    builder.add_extra_row(&row.coeffs, row.weight);
                }
                Arc::new(builder.factor()?)
            }
        };
        let terms = local
            .edges
            .iter()
            .enumerate()
            .map(|(k, &(i, j))| EdgeTerm {
                ri: system.rhs_index(i) as u32,
                rj: system.rhs_index(j) as u32,
                wd: local.d[k] * local.weight[k],
                s1: local.scale[k] - 1.0,
            })
            .collect();
        // rotation_at: mean consistent angle of the transformations L_(i,j), j ∈ P_i.
        let rotation = local.disc_means(n, &alpha);
        let count = system.component_count();
        Ok(DiscRigid {
            centroid_source: component_centroids(system.components(), count, source),
            centroid_target: component_centroids(system.components(), count, target),
            terms,
            ends: local.edges,
            alpha,
            weights: local.weight,
            extra,
            system,
            rotation,
            area: None,
            group: None,
            repair: None,
        })
    }

    /// Makes the connected parts whose vertices are flagged in `together` (a flag per point;
    /// a part belongs when its first point is flagged and it is not the same at both ends)
    /// move as one figure ([`PartGroup`]):
    /// their centroids follow the barycenter mesh's rigid interpolation and their rotations
    /// the barycenter mesh's branch. Frames t = 0 and 1 stay exact: the barycenter mesh
    /// reproduces its ends, and a 2π shift does not change an end.
    pub(crate) fn group_parts(&mut self, together: &[bool]) {
        let comp = self.system.components();
        let count = self.centroid_source.len();
        let mut first = vec![None; count];
        for (v, &c) in comp.iter().enumerate() {
            first[c as usize].get_or_insert(v);
        }
        // A part that is the same at both ends (a badge's background under a changing glyph)
        // stands still rather than riding the figure's motion.
        let mut moves = vec![false; count];
        for ((e, &al), &(vi, _)) in self.terms.iter().zip(&self.alpha).zip(&self.ends) {
            if al != 0.0 || e.s1 != 0.0 {
                moves[comp[vi as usize] as usize] = true;
            }
        }
        for (c, m) in moves.iter_mut().enumerate() {
            *m |= self.centroid_source[c] != self.centroid_target[c];
        }
        let members: Vec<u32> = (0..count as u32)
            .filter(|&c| {
                moves[c as usize]
                    && first[c as usize].is_some_and(|v| together.get(v) == Some(&true))
            })
            .collect();
        if members.len() < 2 {
            return;
        }
        let pick =
            |cs: &[Point]| -> Vec<Point> { members.iter().map(|&c| cs[c as usize]).collect() };
        let (a, b) = (pick(&self.centroid_source), pick(&self.centroid_target));
        let k = members.len() as u32;
        let discs: Vec<Vec<u32>> = (0..k)
            .map(|i| (0..k).filter(|&j| j != i).collect())
            .collect();
        // Coincident centroids (concentric rings) give no layout to keep.
        let barycenters = DiscRigid::new(&a, &b, &discs).ok().map(Box::new);
        if let Some(bm) = &barycenters {
            let turn = bm.alpha.iter().sum::<f64>() / bm.alpha.len().max(1) as f64;
            let mut sum = vec![(0.0f64, 0usize); count];
            for (&(vi, _), &al) in self.ends.iter().zip(&self.alpha) {
                let c = comp[vi as usize] as usize;
                sum[c].0 += al;
                sum[c].1 += 1;
            }
            let shift: Vec<f64> = sum
                .iter()
                .enumerate()
                .map(|(c, &(s, n))| {
                    if n == 0 || !members.contains(&(c as u32)) {
                        return 0.0;
                    }
                    // Only a part whose own turn is near a half turn either way takes the
                    // figure's branch; a part turning a quarter turn keeps the short way.
                    let tau = std::f64::consts::TAU;
                    let mean = s / n as f64;
                    let k = ((turn - mean) / tau).round();
                    if (mean + k * tau).abs() <= 1.25 * std::f64::consts::PI {
                        k * tau
                    } else {
                        0.0
                    }
                })
                .collect();
            for (&(vi, _), al) in self.ends.iter().zip(self.alpha.iter_mut()) {
                *al += shift[comp[vi as usize] as usize];
            }
            for (v, r) in self.rotation.iter_mut().enumerate() {
                *r += shift[comp[v] as usize];
            }
        }
        self.group = Some(Box::new(PartGroup {
            members,
            barycenters,
        }));
    }

    /// Number of points.
    /// Whether this set-up and `other` share one factored system (a reused one).
    #[cfg(test)]
    pub(crate) fn shares_system(&self, other: &DiscRigid) -> bool {
        Arc::ptr_eq(&self.system, &other.system)
    }

    pub(crate) fn vertex_count(&self) -> usize {
        self.system.vertex_count()
    }

    /// Bytes of the factor one pass of a frame's solve reads.
    pub(crate) fn factor_bytes(&self) -> usize {
        self.system.factor_bytes()
    }

    /// Mean consistent rotation angle of point `i`'s disc (radians).
    pub(crate) fn rotation_at(&self, i: usize) -> f64 {
        self.rotation[i]
    }

    pub(crate) fn scratch(&self) -> FrameScratch {
        // No rotation buffers: the disc method's frames take their rotations a chunk at a time
        // on the stack (`assemble`).
        let mut s = FrameScratch::new(&self.system, self.centroid_source.len(), 0);
        if let Some(bm) = self.group.as_ref().and_then(|g| g.barycenters.as_ref()) {
            s.group = Some(Box::new((
                bm.scratch(),
                vec![Point::ZERO; bm.vertex_count()],
            )));
        }
        s
    }

    /// Points at `t` into `out` (eq. 1), without allocating.
    pub(crate) fn at(&self, t: f64, out: &mut [Point], ws: &mut FrameScratch) {
        self.at_with_targets(t, &[], out, ws);
    }

    /// Points at `t` with the extra rows' targets `targets[r]` (`J` of row `r`; missing targets
    /// count as the origin), without allocating.
    pub(crate) fn at_with_targets(
        &self,
        t: f64,
        targets: &[Point],
        out: &mut [Point],
        ws: &mut FrameScratch,
    ) {
        self.at_adjusted(t, targets, None, out, ws, Repair::AsSetUp);
    }

    /// [`DiscRigid::at_with_targets`] with every local transformation of point `i`'s disc
    /// further rotated and scaled by the complex factor `adjust[i]` (`scale · (cos θ, sin θ)`):
    /// the bone transformations added to the disc transformations in §4.2.2. An edge's term
    /// stands for the transformations of both end points' discs (`L_(i,j)` and `L_(j,i)`, equal
    /// before adjustment), so it takes the mean of the two factors. The fold repair is applied
    /// as `repair` says ([`Repair::AsSetUp`] but for automatic mode's checks, which read one
    /// interpolator three ways).
    pub(crate) fn at_adjusted(
        &self,
        t: f64,
        targets: &[Point],
        adjust: Option<&[Point]>,
        out: &mut [Point],
        ws: &mut FrameScratch,
        repair: Repair,
    ) {
        ws.solve.rhs.fill(Point::ZERO);
        self.assemble([t], [targets], adjust.map(|a| [a]), &mut ws.solve.rhs);
        self.centroids_at(t, ws);
        self.system.solve(&mut ws.solve, &ws.centroids, out);
        self.finish(t, out, ws, repair);
    }

    /// Frames at every `t` of `ts` (fold repair as `repair` says), the same bits as one
    /// [`DiscRigid::at_adjusted`] call each: up to [`MAX_LANES`] frames share each pass over
    /// the factor, which at large meshes is most of a frame's cost, and each pass over the
    /// terms. Each frame's extra-row targets and adjustments are as `at_adjusted` takes them
    /// for one frame: frame `k`'s are `targets[k·r..(k + 1)·r]` for `r` extra rows and
    /// `adjust[k·n..(k + 1)·n]` for `n` points (either empty for none). Frame `k` goes to the
    /// `k`-th slice of `outs`, `n` points each: a flat buffer's chunks, or the caller's own
    /// vectors, so nothing is copied.
    pub(crate) fn frames_into<'o>(
        &self,
        ts: &[f64],
        targets: &[Point],
        adjust: &[Point],
        mut outs: impl Iterator<Item = &'o mut [Point]>,
        ws: &mut FrameScratch,
        repair: Repair,
    ) {
        let n = self.vertex_count();
        debug_assert!(targets.len() % ts.len().max(1) == 0);
        debug_assert!(adjust.is_empty() || adjust.len() == ts.len() * n);
        if n == 0 {
            return;
        }
        let frames = ts.len().max(1);
        let (rows, points) = (targets.len() / frames, adjust.len() / frames);
        for (b, ts) in ts.chunks(MAX_LANES).enumerate() {
            let (first, end) = (b * MAX_LANES, b * MAX_LANES + ts.len());
            let lanes = Lanes {
                targets: &targets[first * rows..end * rows],
                adjust: &adjust[first * points..end * points],
                rows,
                points,
            };
            let outs = &mut outs;
            match ts.len() {
                1 => {
                    if let Some(out) = outs.next() {
                        self.at_adjusted(ts[0], lanes.targets(0), lanes.adjust(0), out, ws, repair)
                    }
                }
                2 => self.batch::<2>(ts, &lanes, outs, ws, repair),
                3 => self.batch::<3>(ts, &lanes, outs, ws, repair),
                4 => self.batch::<4>(ts, &lanes, outs, ws, repair),
                5 => self.batch::<5>(ts, &lanes, outs, ws, repair),
                6 => self.batch::<6>(ts, &lanes, outs, ws, repair),
                7 => self.batch::<7>(ts, &lanes, outs, ws, repair),
                _ => self.batch::<MAX_LANES>(ts, &lanes, outs, ws, repair),
            }
        }
    }

    /// The `K` frames at `ts` (`ts.len() == K`) as one batch: their right-hand sides in the
    /// lanes of one buffer, one solve, then each frame placed, repaired and area-corrected.
    fn batch<'o, const K: usize>(
        &self,
        ts: &[f64],
        lanes: &Lanes<'_>,
        outs: &mut impl Iterator<Item = &'o mut [Point]>,
        ws: &mut FrameScratch,
        repair: Repair,
    ) {
        let ts: [f64; K] = std::array::from_fn(|k| ts[k]);
        let targets: [&[Point]; K] = std::array::from_fn(|k| lanes.targets(k));
        let adjust: Option<[&[Point]; K]> = (lanes.points > 0)
            .then(|| std::array::from_fn(|k| lanes.adjust(k).unwrap_or_default()));
        let rows = self.system.lanes::<K>(&mut ws.solve);
        self.assemble(ts, targets, adjust, rows);
        self.system.solve_lanes::<K>(&mut ws.solve);
        for (lane, (&t, out)) in ts.iter().zip(outs).enumerate() {
            self.centroids_at(t, ws);
            self.system
                .place_lane(&mut ws.solve, lane, &ws.centroids, out);
            self.finish(t, out, ws, repair);
        }
    }

    /// The right-hand sides of eq. (1) at the times `ts` into lanes `0..K` of `rhs` (the
    /// factor's rows, zero on entry): every edge's rotated, scaled difference, adjusted as
    /// [`DiscRigid::at_adjusted`] says (lane `k` by `adjust[k]`), and the extra rows' targets
    /// (lane `k`'s `targets[k]`). Each lane takes the operations of a lone frame in the same
    /// order, so it has its bits. Runs in the widest instructions at hand (`simd.rs`).
    fn assemble<const K: usize, R: Row>(
        &self,
        ts: [f64; K],
        targets: [&[Point]; K],
        adjust: Option<[&[Point]; K]>,
        rhs: &mut [R],
    ) {
        vectorized(
            #[inline(always)]
            || self.assemble_kernel(ts, targets, adjust, rhs),
        )
    }

    /// [`DiscRigid::assemble`]'s loops, inlined into each instruction set's copy.
    #[inline(always)]
    fn assemble_kernel<const K: usize, R: Row>(
        &self,
        ts: [f64; K],
        targets: [&[Point]; K],
        adjust: Option<[&[Point]; K]>,
        rhs: &mut [R],
    ) {
        // Rotations a chunk at a time, each used while it is still in registers and L1.
        let mut angle = [0.0; CHUNK];
        let (mut sin, mut cos) = ([[0.0; CHUNK]; K], [[0.0; CHUNK]; K]);
        for (c, (terms, alpha)) in self
            .terms
            .chunks(CHUNK)
            .zip(self.alpha.chunks(CHUNK))
            .enumerate()
        {
            let m = terms.len();
            for (k, &t) in ts.iter().enumerate() {
                for (a, &al) in angle.iter_mut().zip(alpha) {
                    *a = t * al;
                }
                sin_cos_many(&angle[..m], &mut sin[k][..m], &mut cos[k][..m]);
            }
            // Term `i`'s difference rotated and scaled for lane `k`.
            let rotated = |i: usize, k: usize| {
                let (e, sn, cs) = (&terms[i], sin[k][i], cos[k][i]);
                Point::new(cs * e.wd.x - sn * e.wd.y, sn * e.wd.x + cs * e.wd.y)
                    * (1.0 + ts[k] * e.s1)
            };
            match adjust {
                None => {
                    // Terms are sorted by their first end point: its row's sums stay in
                    // registers while the run lasts.
                    let (mut row, mut sum) = (u32::MAX, [Point::ZERO; K]);
                    for (i, e) in terms.iter().enumerate() {
                        let mut l = [Point::ZERO; K];
                        for (k, l) in l.iter_mut().enumerate() {
                            *l = rotated(i, k);
                        }
                        let rj = &mut rhs[e.rj as usize];
                        for (k, &l) in l.iter().enumerate() {
                            *rj.lane_mut(k) += l;
                        }
                        if e.ri != row {
                            if row != u32::MAX {
                                let ri = &mut rhs[row as usize];
                                for (k, &s) in sum.iter().enumerate() {
                                    *ri.lane_mut(k) -= s;
                                }
                            }
                            (row, sum) = (e.ri, [Point::ZERO; K]);
                        }
                        for (s, &l) in sum.iter_mut().zip(&l) {
                            *s += l;
                        }
                    }
                    if row != u32::MAX {
                        let ri = &mut rhs[row as usize];
                        for (k, &s) in sum.iter().enumerate() {
                            *ri.lane_mut(k) -= s;
                        }
                    }
                }
                Some(a) => {
                    let ends = &self.ends[c * CHUNK..c * CHUNK + m];
                    for (i, (e, &(vi, vj))) in terms.iter().zip(ends).enumerate() {
                        for (k, a) in a.iter().enumerate() {
                            let f = (a[vi as usize] + a[vj as usize]) * 0.5;
                            let l = rotated(i, k);
                            let l = Point::new(f.x * l.x - f.y * l.y, f.y * l.x + f.x * l.y);
                            *rhs[e.rj as usize].lane_mut(k) += l;
                            *rhs[e.ri as usize].lane_mut(k) -= l;
                        }
                    }
                }
            }
        }
        for (q, row) in self.extra.iter().enumerate() {
            for &(v, c) in &row.coeffs {
                let r = &mut rhs[self.system.rhs_index(v)];
                for (k, targets) in targets.iter().enumerate() {
                    if let Some(&j) = targets.get(q) {
                        *r.lane_mut(k) += j * (row.weight * c);
                    }
                }
            }
        }
    }

    /// Every component's centroid at `t` into `ws.centroids`: the straight line between its
    /// ends, or the barycenter mesh's motion for grouped parts.
    fn centroids_at(&self, t: f64, ws: &mut FrameScratch) {
        lerp_into(
            &mut ws.centroids,
            &self.centroid_source,
            &self.centroid_target,
            t,
        );
        if let (Some(g), Some(gs)) = (&self.group, ws.group.as_mut()) {
            if let Some(bm) = &g.barycenters {
                let (scratch, at) = &mut **gs;
                bm.at(t, at, scratch);
                for (&c, &p) in g.members.iter().zip(at.iter()) {
                    ws.centroids[c as usize] = p;
                }
            }
        }
    }

    /// The solved frame's fold repair (as `repair` says) and area rule.
    fn finish(&self, t: f64, out: &mut [Point], ws: &mut FrameScratch, repair: Repair) {
        // Repair first, then the area rule: its uniform scales keep every orientation, and the
        // area comes out exact whatever the repair moved.
        if let Some(fold) = &self.repair {
            match repair {
                Repair::AsSetUp => {
                    fold.apply(out);
                }
                Repair::FreeOnly => {
                    fold.apply_with(out, false);
                }
                Repair::Off => {}
            }
        }
        if let Some(rule) = &self.area {
            rule.apply(
                t,
                self.system.components(),
                &ws.centroids,
                out,
                &mut ws.areas,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Discs over `n` points from drawn pairs `(a, b)` (taken modulo `n`, a point paired with
    /// itself dropped): `b` in `a`'s disc, and `a` in `b`'s too when `mirror`.
    fn discs_of_pairs(raw: &[(u32, u32)], n: usize, mirror: bool) -> Vec<Vec<u32>> {
        let mut discs = vec![Vec::new(); n];
        for &(a, b) in raw {
            let (a, b) = (a % n as u32, b % n as u32);
            if a != b {
                discs[a as usize].push(b);
                if mirror {
                    discs[b as usize].push(a);
                }
            }
        }
        discs
    }

    /// The pairs `(i, j)` of the discs as read, disc by disc.
    fn pairs_of_discs(discs: &[Vec<u32>]) -> Vec<(u32, u32)> {
        discs
            .iter()
            .enumerate()
            .flat_map(|(i, d)| d.iter().map(move |&j| (i as u32, j)))
            .collect()
    }

    proptest::proptest! {
        /// The cursor check finds discs symmetric exactly when a binary search for every
        /// pair's reverse does: symmetric discs, the same with one neighbour taken out, and
        /// one-sided ones, all ascending.
        #[test]
        fn symmetric_discs_are_found_as_a_search_finds_them(
            raw in proptest::collection::vec((0u32..30, 0u32..30), 0..120),
            n in 2usize..30,
            mirror in proptest::bool::ANY,
            drop in proptest::option::of(0usize..200),
        ) {
            let mut discs = discs_of_pairs(&raw, n, mirror);
            for d in &mut discs {
                d.sort_unstable();
                d.dedup();
            }
            if let Some(k) = drop {
                if let Some(d) = discs.iter_mut().filter(|d| !d.is_empty()).nth(k % n) {
                    d.remove(k % d.len());
                }
            }
            let directed = pairs_of_discs(&discs);
            let want = directed
                .iter()
                .all(|&(i, j)| discs[j as usize].binary_search(&i).is_ok());
            proptest::prop_assert_eq!(symmetric(&directed, &discs), want);
        }

        /// The pairs of both directions come out as a sort would give them, whether the discs
        /// are one-rings (ascending and symmetric: no sort) or not (unsorted, repeated or
        /// one-sided neighbours).
        #[test]
        fn undirected_pairs_are_the_sorted_pairs(
            raw in proptest::collection::vec((0u32..40, 0u32..40), 0..200),
            n in 2usize..40,
            symmetric in proptest::bool::ANY,
        ) {
            let mut discs = discs_of_pairs(&raw, n, symmetric);
            if symmetric {
                for d in &mut discs {
                    d.sort_unstable();
                    d.dedup();
                }
            }
            let ascending = discs.iter().all(|d| d.windows(2).all(|w| w[0] < w[1]));
            let mut directed = pairs_of_discs(&discs);
            directed.sort_unstable();
            directed.dedup();
            let mut want: Vec<(u32, u32)> =
                directed.iter().map(|&(i, j)| (i.min(j), i.max(j))).collect();
            want.sort_unstable();
            proptest::prop_assert_eq!(undirected_pairs(&directed, &discs, ascending), want);
        }

        /// Each disc's mean angle, summed by disc pairs, is bit for bit the mean over the
        /// disc sorted and deduplicated with each edge's angle found by binary search (how it
        /// was computed before), repeated and unsorted discs included, and discs made
        /// symmetric (each point in the discs of its disc's points, as one-rings are: the sums
        /// by edges).
        #[test]
        fn disc_means_match_the_mean_over_each_sorted_disc(
            coords in proptest::collection::vec((-10.0f64..10.0, -10.0f64..10.0), 3..30),
            raw_discs in proptest::collection::vec(proptest::collection::vec(0u32..30, 0..8), 30),
            seed in -3.0f64..3.0,
            symmetric in proptest::bool::ANY,
        ) {
            let n = coords.len();
            let pts: Vec<Point> = coords.iter().map(|&(x, y)| Point::new(x, y)).collect();
            let mut discs: Vec<Vec<u32>> = raw_discs[..n]
                .iter()
                .enumerate()
                .map(|(i, d)| d.iter().map(|&j| j % n as u32).filter(|&j| j as usize != i).collect())
                .collect();
            if symmetric {
                for i in 0..n {
                    for j in discs[i].clone() {
                        discs[j as usize].push(i as u32);
                    }
                }
            }
            let Ok(local) = LocalTransforms::new(&pts, &pts, &discs) else {
                return Ok(());
            };
            let alpha: Vec<f64> = (0..local.edges.len()).map(|k| seed * (k as f64 + 0.37).sin()).collect();
            let expected: Vec<f64> = discs
                .iter()
                .enumerate()
                .map(|(i, disc)| {
                    let mut disc = disc.clone();
                    disc.sort_unstable();
                    disc.dedup();
                    let sum: f64 = disc
                        .iter()
                        .map(|&j| {
                            let key = ((i as u32).min(j), (i as u32).max(j));
                            local.edges.binary_search(&key).map_or(0.0, |k| alpha[k])
                        })
                        .sum();
                    if disc.is_empty() { 0.0 } else { sum / disc.len() as f64 }
                })
                .collect();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            proptest::prop_assert_eq!(bits(&local.disc_means(n, &alpha)), bits(&expected));
        }
    }

    /// Eq. (2)'s hook: one extra row holding the midpoint of an edge at a moving target. The
    /// shape is the unit square, target = source, so eq. (1) wants a rigid square; with the
    /// row's target moved by `m`, the whole square follows it by `m`.
    #[test]
    fn extra_rows_steer_the_frame() {
        let src = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let discs: Vec<Vec<u32>> = (0..4u32)
            .map(|i| (0..4).filter(|&j| j != i).collect())
            .collect();
        let row = ExtraRow {
            coeffs: vec![(0, 0.5), (1, 0.5)],
            weight: 3.0,
        };
        let d = DiscRigid::with_extra_rows(&src, &src, &discs, vec![row]).unwrap();
        let mut ws = d.scratch();
        let mut out = vec![Point::ZERO; 4];
        let m = Point::new(5.0, -2.0);
        d.at_with_targets(0.5, &[Point::new(0.5, 0.0) + m], &mut out, &mut ws);
        for (a, b) in out.iter().zip(&src) {
            assert!(a.distance(*b + m) < 1e-12, "{a} vs {}", *b + m);
        }
        let bad = ExtraRow {
            coeffs: vec![(9, 1.0)],
            weight: 1.0,
        };
        assert!(DiscRigid::with_extra_rows(&src, &src, &discs, vec![bad]).is_err());
    }
}
