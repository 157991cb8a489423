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
//! turns past 180°.
//!
//! ## Disc size follows the similarity curve (a deviation from the paper)
//!
//! Interpolating each edge's scale on its own, `1 − t + t·s_ij`, swells a disc that stretches
//! unevenly: stretched ×2 one way and ×½ the other, it has area `1.5 × 0.75 = 1.125` at t = ½
//! where both end areas are 1 (the leaf → butterfly fixture swells 12.8 % this way). So every
//! disc's intermediate vectors `l_ij(t)` are scaled by one factor `c_i(t)` that gives the disc the
//! size a similarity would: with the disc's size `σ_i(t) = det(Σ_j l_ij l_ijᵀ)^¼` (for vectors
//! mapped by a linear map `A`, `σ` grows by `|det A|^½`, a length), `c_i(t) = ((1 − t)·σ_i(0) +
//! t·σ_i(1)) / σ_i(t)`. For a similarity every `c_i` is 1 — frames stay exact similarities with
//! the scale linear in t — and at t = 0 and t = 1 it is 1, so the ends stay exact. It needs no
//! triangles (barycenter discs work too), costs one more pass over the edges per frame, and, as
//! a per-disc uniform scale, cannot fold anything. An edge stands for both of its discs, so its
//! vector takes the mean of their factors. Discs whose neighbours are collinear have no size
//! and keep factor 1.

use super::assembly::{
    component_centroids, lerp_into, FactoredSystem, SolveScratch, SystemBuilder,
};
use super::rotation::consistent_angles;
use super::sincos::sin_cos_many;
use crate::error::{Error, Result};
use crate::geometry::{bounding_box, Point};

/// Disc edges shorter than this fraction of the point set's bounding-box diagonal have no
/// meaningful direction and are rejected as coincident points.
const MIN_EDGE_FRACTION: f64 = 1e-12;

/// The local transformations of every disc, one per undirected edge (module docs).
#[derive(Debug, Clone)]
pub(crate) struct LocalTransforms {
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
            "<target>",
            format!(
                "the target has {} points but the source has {}; compatible meshes need one \
                 target point per source point",
                target.len(),
                source.len()
            ),
        ));
    }
    for (name, pts) in [("<source>", source), ("<target>", target)] {
        if let Some(i) = pts.iter().position(|p| !p.is_finite()) {
            return Err(Error::input(
                name,
                format!("point {i} has a non-finite coordinate"),
            ));
        }
    }
    Ok(())
}

fn diagonal(points: &[Point]) -> f64 {
    bounding_box(points.iter().copied()).map_or(0.0, |(lo, hi)| lo.distance(hi))
}

impl LocalTransforms {
    /// Local transformations of the discs `discs[i]` (indices of the points in `p_i`'s disc,
    /// not `i` itself; repeated entries count once).
    pub(crate) fn new(source: &[Point], target: &[Point], discs: &[Vec<u32>]) -> Result<Self> {
        validate_points(source, target)?;
        let n = source.len();
        if discs.len() != n {
            return Err(Error::input(
                "<source>",
                format!("{} discs given for {} points", discs.len(), n),
            ));
        }
        let mut directed: Vec<(u32, u32)> = Vec::new();
        for (i, d) in discs.iter().enumerate() {
            for &j in d {
                if j as usize >= n || j as usize == i {
                    return Err(Error::input(
                        "<source>",
                        format!(
                            "the disc of point {i} refers to point {j}, which is not a neighbour"
                        ),
                    ));
                }
                directed.push((i as u32, j));
            }
        }
        directed.sort_unstable();
        directed.dedup();
        let mut undirected: Vec<(u32, u32)> = directed
            .iter()
            .map(|&(i, j)| (i.min(j), i.max(j)))
            .collect();
        undirected.sort_unstable();
        let (min_src, min_tgt) = (
            MIN_EDGE_FRACTION * diagonal(source),
            MIN_EDGE_FRACTION * diagonal(target),
        );
        let mut t = LocalTransforms {
            edges: Vec::new(),
            weight: Vec::new(),
            d: Vec::new(),
            alpha: Vec::new(),
            scale: Vec::new(),
        };
        for &(i, j) in &undirected {
            if t.edges.last() == Some(&(i, j)) {
                *t.weight.last_mut().expect("weight per edge") += 1.0;
                continue;
            }
            let d = source[j as usize] - source[i as usize];
            let e = target[j as usize] - target[i as usize];
            let (ld, le) = (d.length(), e.length());
            if ld <= min_src {
                return Err(Error::input(
                    "<source>",
                    format!("points {i} and {j} coincide (a disc edge of zero length)"),
                ));
            }
            if le <= min_tgt {
                return Err(Error::input(
                    "<target>",
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
        Ok(t)
    }

    /// The reduced rotation graph: links between edges that share a vertex (module docs).
    pub(crate) fn rotation_links(&self, n: usize) -> Vec<(u32, u32)> {
        let mut incident: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (k, &(i, j)) in self.edges.iter().enumerate() {
            incident[i as usize].push(k as u32);
            incident[j as usize].push(k as u32);
        }
        let mut links = Vec::new();
        for inc in &incident {
            for (a, &ka) in inc.iter().enumerate() {
                for &kb in &inc[a + 1..] {
                    links.push((ka, kb));
                }
            }
        }
        links
    }
}

/// One precomputed term of the per-frame right-hand side.
#[derive(Debug, Clone, Copy)]
struct EdgeTerm {
    /// The edge's end points.
    vi: u32,
    vj: u32,
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
    /// Consistent rotation angle of each term (§4.1.1).
    alpha: Vec<f64>,
    extra: Vec<ExtraRow>,
    system: FactoredSystem,
    centroid_source: Vec<Point>,
    centroid_target: Vec<Point>,
    rotation: Vec<f64>,
    /// Each disc's size `σ_i` at t = 0 and t = 1 (module docs); 0 for a disc without size.
    size_source: Vec<f64>,
    size_target: Vec<f64>,
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
    /// Per-term intermediate vectors `l_ij(t)` (disc method only).
    local: Vec<Point>,
    /// Per-point second moments `Σ_j l lᵀ` as `[xx, xy, yy]`.
    moment: Vec<[f64; 3]>,
    /// Per-point disc size factors `c_i(t)`.
    factor: Vec<f64>,
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
            local: Vec::new(),
            moment: Vec::new(),
            factor: Vec::new(),
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
    pub(crate) fn new(source: &[Point], target: &[Point], discs: &[Vec<u32>]) -> Result<Self> {
        Self::with_extra_rows(source, target, discs, Vec::new())
    }

    /// [`DiscRigid::new`] with constant extra rows added to the matrix before it is factored
    /// (the hook for eq. (2)); evaluate with [`DiscRigid::at_with_targets`].
    pub(crate) fn with_extra_rows(
        source: &[Point],
        target: &[Point],
        discs: &[Vec<u32>],
        extra: Vec<ExtraRow>,
    ) -> Result<Self> {
        let local = LocalTransforms::new(source, target, discs)?;
        let n = source.len();
        let alpha = consistent_angles(&local.alpha, &local.rotation_links(n));
        let mut builder = SystemBuilder::new(n);
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
        let system = builder.factor()?;
        let terms: Vec<EdgeTerm> = local
            .edges
            .iter()
            .enumerate()
            .map(|(k, &(i, j))| EdgeTerm {
                vi: i,
                vj: j,
                ri: system.rhs_index(i) as u32,
                rj: system.rhs_index(j) as u32,
                wd: local.d[k] * local.weight[k],
                s1: local.scale[k] - 1.0,
            })
            .collect();
        // rotation_at: mean consistent angle of the transformations L_(i,j), j ∈ P_i.
        let rotation = discs
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
                if disc.is_empty() {
                    0.0
                } else {
                    sum / disc.len() as f64
                }
            })
            .collect();
        let mut moment = Vec::new();
        let source_vectors: Vec<Point> = terms.iter().map(|e| e.wd).collect();
        let size_source = disc_sizes(&terms, &source_vectors, n, &mut moment);
        let target_vectors: Vec<Point> = terms
            .iter()
            .zip(&alpha)
            .map(|(e, &a)| {
                let (sn, cs) = a.sin_cos();
                Point::new(cs * e.wd.x - sn * e.wd.y, sn * e.wd.x + cs * e.wd.y) * (1.0 + e.s1)
            })
            .collect();
        let size_target = disc_sizes(&terms, &target_vectors, n, &mut moment);
        let count = system.component_count();
        Ok(DiscRigid {
            centroid_source: component_centroids(system.components(), count, source),
            centroid_target: component_centroids(system.components(), count, target),
            terms,
            alpha,
            extra,
            system,
            rotation,
            size_source,
            size_target,
        })
    }

    /// Number of points.
    pub(crate) fn vertex_count(&self) -> usize {
        self.system.vertex_count()
    }

    /// Mean consistent rotation angle of point `i`'s disc (radians).
    pub(crate) fn rotation_at(&self, i: usize) -> f64 {
        self.rotation[i]
    }

    pub(crate) fn scratch(&self) -> FrameScratch {
        let mut ws = FrameScratch::new(&self.system, self.centroid_source.len(), self.terms.len());
        ws.local = vec![Point::ZERO; self.terms.len()];
        ws.moment = vec![[0.0; 3]; self.size_source.len()];
        ws.factor = vec![1.0; self.size_source.len()];
        ws
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
        self.at_adjusted(t, targets, None, out, ws);
    }

    /// [`DiscRigid::at_with_targets`] with every local transformation of point `i`'s disc
    /// further rotated and scaled by the complex factor `adjust[i]` (`scale · (cos θ, sin θ)`):
    /// the bone transformations added to the disc transformations in §4.2.2. An edge's term
    /// stands for the transformations of both end points' discs (`L_(i,j)` and `L_(j,i)`, equal
    /// before adjustment), so it takes the mean of the two factors.
    pub(crate) fn at_adjusted(
        &self,
        t: f64,
        targets: &[Point],
        adjust: Option<&[Point]>,
        out: &mut [Point],
        ws: &mut FrameScratch,
    ) {
        ws.rotations(t, &self.alpha);
        // The intermediate vectors and each disc's second moment in one pass, then the disc
        // size factors c_i(t) (module docs).
        ws.moment.fill([0.0; 3]);
        for (((l, e), &sn), &cs) in ws
            .local
            .iter_mut()
            .zip(&self.terms)
            .zip(&ws.sin)
            .zip(&ws.cos)
        {
            let f = 1.0 + t * e.s1;
            *l = Point::new(cs * e.wd.x - sn * e.wd.y, sn * e.wd.x + cs * e.wd.y) * f;
            add_moment(&mut ws.moment, e, *l);
        }
        for (((c, m), &a), &b) in ws
            .factor
            .iter_mut()
            .zip(&ws.moment)
            .zip(&self.size_source)
            .zip(&self.size_target)
        {
            // Branch-free so that it vectorizes: sizeless discs (size 0) keep factor 1.
            let det = m[0] * m[2] - m[1] * m[1];
            let want = (1.0 - t) * a + t * b;
            let ratio = want / det.max(f64::MIN_POSITIVE).sqrt().sqrt();
            *c = if a > 0.0 && b > 0.0 && det > 0.0 {
                ratio
            } else {
                1.0
            };
        }
        let rhs = &mut ws.solve.rhs;
        rhs.fill(0.0);
        let stride = rhs.len() / 2;
        let (rx, ry) = rhs.split_at_mut(stride);
        for (e, &l) in self.terms.iter().zip(&ws.local) {
            let c = 0.5 * (ws.factor[e.vi as usize] + ws.factor[e.vj as usize]);
            let mut l = l * c;
            if let Some(a) = adjust {
                let m = (a[e.vi as usize] + a[e.vj as usize]) * 0.5;
                l = Point::new(m.x * l.x - m.y * l.y, m.y * l.x + m.x * l.y);
            }
            rx[e.rj as usize] += l.x;
            ry[e.rj as usize] += l.y;
            rx[e.ri as usize] -= l.x;
            ry[e.ri as usize] -= l.y;
        }
        for (row, &j) in self.extra.iter().zip(targets) {
            for &(v, c) in &row.coeffs {
                let r = self.system.rhs_index(v);
                rx[r] += row.weight * c * j.x;
                ry[r] += row.weight * c * j.y;
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

/// Adds `l lᵀ` to the second moments of both end points of `e`, as `[xx, xy, yy]`.
#[inline]
fn add_moment(moment: &mut [[f64; 3]], e: &EdgeTerm, l: Point) {
    let m = [l.x * l.x, l.x * l.y, l.y * l.y];
    for v in [e.vi, e.vj] {
        let acc = &mut moment[v as usize];
        acc[0] += m[0];
        acc[1] += m[1];
        acc[2] += m[2];
    }
}

/// A disc's size `det(M)^¼` from its second moment `M` (module docs); 0 when its vectors are
/// (numerically) collinear, so it has no size to keep.
fn size(m: [f64; 3]) -> f64 {
    let det = m[0] * m[2] - m[1] * m[1];
    let trace = m[0] + m[2];
    if det > 1e-12 * trace * trace {
        det.sqrt().sqrt()
    } else {
        0.0
    }
}

/// Every disc's size for the per-term vectors `local` (`moment` is scratch).
fn disc_sizes(
    terms: &[EdgeTerm],
    local: &[Point],
    n: usize,
    moment: &mut Vec<[f64; 3]>,
) -> Vec<f64> {
    moment.clear();
    moment.resize(n, [0.0; 3]);
    for (e, &l) in terms.iter().zip(local) {
        add_moment(moment, e, l);
    }
    moment.iter().map(|&m| size(m)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
