//! Disc-based rigidity-preserving interpolation with globally consistent rotation (§4.1), and the
//! baselines it is compared with.
//!
//! Given compatible source and target point sets, an [`Interpolator`] is set up once and then
//! evaluated at any `t ∈ [0, 1]`:
//!
//! - [`Method::Disc`] (the paper's method): per-disc local rotations and scales
//!   (`disc.rs`), made globally consistent for turns beyond 180° (`rotation.rs`, §4.1.1), assembled
//!   by the least squares of eq. (1) whose matrix is factored once (`assembly.rs`); on triangle
//!   meshes each part's area then follows the similarity curve between its end areas
//!   (`area.rs`, a deviation that removes the swell of unevenly stretched regions).
//! - [`Method::Triangle`]: triangle-to-triangle as-rigid-as-possible interpolation
//!   (`triangle.rs`), the classical baseline of Fig. 13.
//! - [`Method::Linear`]: straight-line vertex paths (`linear.rs`).
//!
//! All methods reproduce the source at `t = 0` and the target at `t = 1`. Each connected part
//! moves its vertex centroid along the straight line between its end centroids.

mod area;
mod assembly;
mod disc;
mod factor;
mod linear;
pub(crate) mod repair;
mod rotation;
mod simd;
mod sincos;
mod triangle;

use crate::error::{Error, Result};
use crate::geometry::Point;
pub(crate) use disc::{DiscRigid, ExtraRow, FrameScratch};
use factor::MAX_LANES;
use triangle::TriangleRigid;

/// A polyline of points whose consecutive points are each other's disc neighbours: a curve
/// that morphs without a mesh (a stroke's centre line, an outline with no interior mesh).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chain {
    /// Point indices along the curve.
    pub vertices: Vec<u32>,
    /// Whether the last point links back to the first.
    pub closed: bool,
}

/// What the disc method is set up on ([`Interpolator::disc`]). Default: no triangles, no
/// chains, the area rule on every triangle, parts moving independently.
#[derive(Debug, Clone, Copy, Default)]
pub struct DiscSetup<'a> {
    /// Triangles (counter-clockwise in the source) whose one-rings are discs.
    pub triangles: &'a [[u32; 3]],
    /// Curves without a mesh: consecutive points are disc neighbours.
    pub chains: &'a [Chain],
    /// The triangles whose area the area rule keeps per part. Default: all of them.
    pub area_region: Option<&'a [[u32; 3]]>,
    /// A flag per point: the connected parts whose points are flagged move as one figure
    /// (centroids on the barycenter mesh's rigid path, rotations on its branch; automatic
    /// mode's shapes of one icon). Default: every part on its own straight centroid line.
    pub together: Option<&'a [bool]>,
    /// Fold repair after each solve (a deviation from the paper, `repair.rs`): the triangles
    /// to keep unfolded, and a flag per point for those that must not move (curve vertices).
    /// Default: none.
    pub repair: Option<(&'a [[u32; 3]], &'a [bool])>,
    /// Whether the repair may, as a last resort, move the flagged points too, where the
    /// curves themselves fold (a marked-up drawing's features bend a little in that frame).
    /// Automatic mode keeps its outlines exact and drops a mesh that folds instead.
    pub repair_curves: bool,
    /// An interpolator set up on the same triangles and chains, whose factored matrix this
    /// set-up reuses: eq. (1)'s matrix depends on the discs alone, not on the points, so two
    /// meshes with one connectivity share it, bit for bit. Ignored when its discs differ.
    /// Default: none.
    pub system_of: Option<&'a Interpolator>,
}

/// Which interpolation to use (CLI: `--method disc|triangle|linear`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Disc-based rigidity-preserving interpolation with consistent rotation (§4.1, §4.1.1).
    #[default]
    Disc,
    /// Triangle-based as-rigid-as-possible interpolation (Alexa et al. 2000), the baseline the
    /// paper compares with (Fig. 13).
    Triangle,
    /// Linear vertex interpolation.
    Linear,
}

#[derive(Debug)]
enum Kind {
    Disc(DiscRigid),
    Triangle(TriangleRigid, Vec<f64>),
    Linear(Vec<Point>, Vec<Point>, Vec<f64>),
}

/// The one rule for times outside the morph, shared by every motion (plain interpolation,
/// skeleton control) and every frame writer: `t` is clamped to [0, 1], so a morph holds the
/// source before it and the target after it (exactly, §4.1's ends), and NaN counts as 0. No
/// motion extrapolates: the disc method's rotations past t = 1 would keep turning, the
/// skeleton's tracks would not, and the two would disagree.
pub fn clamp_time(t: f64) -> f64 {
    if t.is_nan() {
        0.0
    } else {
        t.clamp(0.0, 1.0)
    }
}

/// How a frame of the disc method applies its fold repair (`repair.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Repair {
    /// As the interpolator was set up (none, free vertices, or curve vertices too).
    AsSetUp,
    /// Free vertices only, even where the set-up lets curve vertices move.
    FreeOnly,
    /// None: the solve of eq. (1) and the area rule alone.
    Off,
}

/// An interpolation between two compatible point sets, set up once (local transformations,
/// consistent rotations, factored normal equations) and evaluated per frame.
#[derive(Debug)]
pub struct Interpolator {
    kind: Kind,
    n: usize,
    /// Tells this interpolator's workspaces from others' ([`Interpolator::at`]).
    id: u64,
    /// Workspaces of earlier [`Interpolator::frames`] calls, lent to the next ones: automatic
    /// mode asks for its fold check's frames a few at a time, and a new workspace allocates and
    /// zeroes a batch row per vertex (issue 16). At most one per thread that ran a batch, and
    /// only up to [`SPARE_VERTICES`] vertices.
    spare: std::sync::Mutex<Vec<Workspace>>,
}

/// A fresh [`Interpolator::id`].
fn next_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// Per-thread scratch buffers for [`Interpolator::at`], so evaluating a frame does not allocate.
/// Get one from [`Interpolator::workspace`]; given to another interpolator, it is remade for
/// that one on first use (an allocation, not a panic).
#[derive(Debug)]
pub struct Workspace {
    /// The [`Interpolator::id`] it was made for.
    owner: u64,
    scratch: Option<FrameScratch>,
}

/// The most vertices for which an interpolator keeps the workspaces of its `frames` calls
/// (about 4 MB each): beyond, making one costs little beside the frames it serves, and a
/// morph kept in memory should not hold hundreds of megabytes of scratch.
const SPARE_VERTICES: usize = 1 << 15;

/// A workspace lent by [`Interpolator::lend`], given back to its spares (if any) when dropped.
struct Lent<'a> {
    ws: Workspace,
    to: Option<&'a std::sync::Mutex<Vec<Workspace>>>,
}

impl Drop for Lent<'_> {
    fn drop(&mut self) {
        // What stays behind is never used: a workspace of no interpolator, with no buffers.
        let empty = Workspace {
            owner: u64::MAX,
            scratch: None,
        };
        let ws = std::mem::replace(&mut self.ws, empty);
        if let Some(Ok(mut spare)) = self.to.map(|m| m.lock()) {
            spare.push(ws);
        }
    }
}

fn check_triangles(triangles: &[[u32; 3]], n: usize) -> Result<()> {
    for (f, t) in triangles.iter().enumerate() {
        if t.iter().any(|&v| v as usize >= n) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            return Err(Error::input(
                crate::error::Drawings::Source,
                format!("triangle {f} has invalid vertex indices {t:?} ({n} vertices)"),
            ));
        }
    }
    Ok(())
}

impl Interpolator {
    /// Sets up `method` for compatible triangle meshes (one connectivity `triangles`,
    /// counter-clockwise in the source). The disc method uses one-ring discs (§4.1).
    ///
    /// Errors (input errors on `crate::error::Drawings::Source`/`crate::error::Drawings::Target`): mismatched lengths, non-finite
    /// coordinates, invalid triangle indices, coincident neighbouring points, and for the triangle
    /// method zero-area source triangles.
    pub fn new(
        method: Method,
        source: &[Point],
        target: &[Point],
        triangles: &[[u32; 3]],
    ) -> Result<Self> {
        disc::validate_points(source, target)?;
        let n = source.len();
        check_triangles(triangles, n)?;
        let kind = match method {
            Method::Disc => return Self::with_area_region(source, target, triangles, triangles),
            Method::Triangle => {
                let rings = crate::mesh::one_rings(triangles, n);
                let angles = linear::best_fit_angles(source, target, &rings);
                Kind::Triangle(TriangleRigid::new(source, target, triangles)?, angles)
            }
            Method::Linear => {
                let rings = crate::mesh::one_rings(triangles, n);
                let angles = linear::best_fit_angles(source, target, &rings);
                Kind::Linear(source.to_vec(), target.to_vec(), angles)
            }
        };
        Ok(Interpolator {
            kind,
            n,
            id: next_id(),
            spare: Default::default(),
        })
    }

    /// The disc method on compatible triangle meshes whose area rule measures only the
    /// triangles of `region` ([`crate::compatible::Compatible::area_region`]): automatic mode's
    /// padded frame is no part of the shape, so the icons' own area is kept, not the frame's.
    pub fn with_area_region(
        source: &[Point],
        target: &[Point],
        triangles: &[[u32; 3]],
        region: &[[u32; 3]],
    ) -> Result<Self> {
        Self::disc(
            source,
            target,
            &DiscSetup {
                triangles,
                area_region: Some(region),
                ..DiscSetup::default()
            },
        )
    }

    /// The disc method (§4.1) set up as `setup` says: one-ring discs of its triangles, chain
    /// discs along its curves without a mesh, the area rule on its region, and its parts moving
    /// together.
    pub fn disc(source: &[Point], target: &[Point], setup: &DiscSetup<'_>) -> Result<Self> {
        disc::validate_points(source, target)?;
        let n = source.len();
        check_triangles(setup.triangles, n)?;
        let region = setup.area_region.unwrap_or(setup.triangles);
        check_triangles(region, n)?;
        // Closed chains are outlines without a mesh: the area rule measures them too, wound
        // counter-clockwise in the source.
        let mut cycles: Vec<(u32, u32)> = Vec::new();
        for chain in setup.chains.iter().filter(|c| c.closed) {
            let pts: Vec<Point> = chain
                .vertices
                .iter()
                .filter_map(|&v| source.get(v as usize).copied())
                .collect();
            let forward = crate::geometry::polygon_area(&pts) >= 0.0;
            let k = chain.vertices.len();
            for i in 0..k {
                let (a, b) = (chain.vertices[i], chain.vertices[(i + 1) % k]);
                cycles.push(if forward { (a, b) } else { (b, a) });
            }
        }
        // The chains' links join the discs of their ends, as mesh edges do.
        let mut links: Vec<(u32, u32)> = Vec::new();
        for chain in setup.chains {
            let k = chain.vertices.len();
            let count = if chain.closed { k } else { k.saturating_sub(1) };
            for i in 0..count {
                let (a, b) = (chain.vertices[i], chain.vertices[(i + 1) % k]);
                if a as usize >= n || b as usize >= n || a == b {
                    return Err(Error::internal(format!(
                        "chain link {a}–{b} is not a pair of distinct points of {n}"
                    )));
                }
                links.push((a, b));
            }
        }
        let (start, neighbours) = crate::mesh::ring_rows(setup.triangles, n, links.into_iter());
        let rings: Vec<&[u32]> = (0..n)
            .map(|v| &neighbours[start[v]..start[v + 1]])
            .collect();
        let like = setup.system_of.and_then(|i| match &i.kind {
            Kind::Disc(d) => Some(d),
            _ => None,
        });
        let mut d = DiscRigid::with_area_rule(source, target, &rings, region, &cycles, like)?;
        if let Some(together) = setup.together {
            d.group_parts(together);
        }
        if let Some((triangles, fixed)) = setup.repair {
            check_triangles(triangles, n)?;
            d.repair = Some(Box::new(repair::FoldRepair::new(
                triangles,
                n,
                fixed,
                Some(source),
                setup.repair_curves,
            )));
        }
        Ok(Interpolator {
            kind: Kind::Disc(d),
            n,
            id: next_id(),
            spare: Default::default(),
        })
    }

    /// The disc method over general compatible point sets with given neighbour lists (`discs[i]`
    /// = indices of the points in `p_i`'s disc, without `i`), e.g. the barycenter mesh of the
    /// shape model (§5), whose discs are "all other points".
    pub fn from_discs(source: &[Point], target: &[Point], discs: &[Vec<u32>]) -> Result<Self> {
        let d = DiscRigid::new(source, target, discs)?;
        Ok(Interpolator {
            n: d.vertex_count(),
            kind: Kind::Disc(d),
            id: next_id(),
            spare: Default::default(),
        })
    }

    /// Number of vertices of every frame.
    pub fn vertex_count(&self) -> usize {
        self.n
    }

    /// The method this interpolator runs.
    pub fn method(&self) -> Method {
        match self.kind {
            Kind::Disc(_) => Method::Disc,
            Kind::Triangle(..) => Method::Triangle,
            Kind::Linear(..) => Method::Linear,
        }
    }

    /// Fresh scratch buffers for [`Interpolator::at`] (one per thread).
    pub fn workspace(&self) -> Workspace {
        Workspace {
            owner: self.id,
            scratch: match &self.kind {
                Kind::Disc(d) => Some(d.scratch()),
                Kind::Triangle(tr, _) => Some(tr.scratch()),
                Kind::Linear(..) => None,
            },
        }
    }

    /// Vertices at `t ∈ [0, 1]` into `out` (`out.len() == vertex_count()`), without allocating
    /// (but once, when `ws` was made by another interpolator). A `t` outside [0, 1] is clamped
    /// ([`clamp_time`]): every motion holds its ends.
    ///
    /// # Panics
    /// If `out` has the wrong length (a programming error, not a data error).
    pub fn at(&self, t: f64, out: &mut [Point], ws: &mut Workspace) {
        self.at_repairing(t, out, ws, Repair::AsSetUp);
    }

    /// [`Interpolator::at`] with the disc method's fold repair as `repair` says.
    fn at_repairing(&self, t: f64, out: &mut [Point], ws: &mut Workspace, repair: Repair) {
        assert_eq!(
            out.len(),
            self.n,
            "output buffer length must equal vertex_count()"
        );
        let t = clamp_time(t);
        if ws.owner != self.id {
            *ws = self.workspace();
        }
        match &self.kind {
            Kind::Disc(d) => {
                let scratch = ws.scratch.get_or_insert_with(|| d.scratch());
                d.at_adjusted(t, &[], None, out, scratch, repair);
            }
            Kind::Triangle(tr, _) => tr.at(t, out, ws.scratch.get_or_insert_with(|| tr.scratch())),
            Kind::Linear(p, q, _) => linear::blend(p, q, t, out),
        }
    }

    /// Frames at every `t` of `ts` into `out`, laid end to end (frame `k` at
    /// `out[k·n..(k + 1)·n]`, `n` = [`Interpolator::vertex_count`]), the same bits as one
    /// [`Interpolator::at`] call each, without allocating (but once per workspace). The disc
    /// method solves up to eight frames in one pass over its factor (§4.1: the matrix is the
    /// same for every `t`), which on large meshes costs a third of solving them one by one.
    ///
    /// # Panics
    /// If `out.len() != ts.len() · vertex_count()` (a programming error, not a data error).
    pub fn at_many(&self, ts: &[f64], out: &mut [Point], ws: &mut Workspace) {
        self.many_repairing(ts, out, ws, Repair::AsSetUp);
    }

    /// [`Interpolator::at_many`] with the disc method's fold repair as `repair` says.
    fn many_repairing(&self, ts: &[f64], out: &mut [Point], ws: &mut Workspace, repair: Repair) {
        assert_eq!(
            out.len(),
            ts.len().saturating_mul(self.n),
            "output buffer length must equal ts.len() · vertex_count()"
        );
        if self.n > 0 {
            self.many_into(ts, out.chunks_mut(self.n), ws, repair);
        }
    }

    /// The frames at `ts` into `outs`, one slice of [`Interpolator::vertex_count`] points per
    /// time (a flat buffer's chunks, or the vectors [`Interpolator::frames`] returns, so that
    /// nothing is copied), with the disc method's fold repair as `repair` says.
    fn many_into<'o>(
        &self,
        ts: &[f64],
        mut outs: impl Iterator<Item = &'o mut [Point]>,
        ws: &mut Workspace,
        repair: Repair,
    ) {
        if self.n == 0 {
            return;
        }
        match &self.kind {
            Kind::Disc(d) => {
                if ws.owner != self.id {
                    *ws = self.workspace();
                }
                let scratch = ws.scratch.get_or_insert_with(|| d.scratch());
                let mut clamped = [0.0; MAX_LANES];
                for ts in ts.chunks(MAX_LANES) {
                    for (c, &t) in clamped.iter_mut().zip(ts) {
                        *c = clamp_time(t);
                    }
                    let (ts, outs) = (&clamped[..ts.len()], outs.by_ref());
                    d.frames_into(ts, &[], &[], outs, scratch, repair);
                }
            }
            Kind::Triangle(..) | Kind::Linear(..) => {
                for (&t, out) in ts.iter().zip(outs) {
                    self.at_repairing(t, out, ws, repair);
                }
            }
        }
    }

    /// A spare workspace of this interpolator, or a new one; it goes back to the spares when
    /// the loan is dropped, unless the mesh has more than [`SPARE_VERTICES`] vertices.
    fn lend(&self) -> Lent<'_> {
        let to = (self.n <= SPARE_VERTICES).then_some(&self.spare);
        let spare = to.and_then(|m| m.lock().ok()?.pop());
        Lent {
            ws: spare.unwrap_or_else(|| self.workspace()),
            to,
        }
    }

    /// Vertices at `t` in a new vector.
    pub fn at_vec(&self, t: f64) -> Vec<Point> {
        let mut out = vec![Point::ZERO; self.n];
        self.at(t, &mut out, &mut self.workspace());
        out
    }

    /// Many frames, in parallel (rayon) when there is enough work (about half a millisecond or
    /// more), one workspace per worker: `frames[k]` is the frame at `ts[k]`.
    pub fn frames(&self, ts: &[f64]) -> Vec<Vec<Point>> {
        self.frames_repairing(ts, Repair::AsSetUp)
    }

    /// Frames at `ts` like [`Interpolator::frames`], with the disc method's fold repair as
    /// `repair` says rather than as set up (other methods have none). Automatic mode checks one
    /// mesh's motion three ways — plain, repaired by free vertices, repaired as set up — and
    /// sets up the interpolator once for all three.
    pub(crate) fn frames_repairing(&self, ts: &[f64], repair: Repair) -> Vec<Vec<Point>> {
        parallel_frames(
            ts,
            self.n,
            || self.lend(),
            |ts, frames, ws| {
                let outs = frames.iter_mut().map(Vec::as_mut_slice);
                self.many_into(ts, outs, &mut ws.ws, repair)
            },
        )
    }

    /// Rotation angle (radians) of point `i`'s neighbourhood. Disc method: the consistent
    /// rotation (after the 2kπ corrections of §4.1.1) averaged over the disc's local
    /// transformations; the shape model (§5) uses it to pick each curve's rotation branch
    /// consistently with the barycenter mesh. Other methods: the best-fit (least-squares) angle
    /// of the one-ring, in (−π, π].
    pub fn rotation_at(&self, i: usize) -> f64 {
        match &self.kind {
            Kind::Disc(d) => d.rotation_at(i),
            Kind::Triangle(_, a) | Kind::Linear(_, _, a) => a[i],
        }
    }

    /// Bytes of the factored system a frame's triangular solves read per pass (0 for the
    /// linear method, which solves nothing); a frame makes two passes. At large meshes these
    /// reads set a lone frame's floor: at the memory bandwidth of the machine, no frame is
    /// faster than reading twice this many bytes (issue 16; `benches/rigid.rs` measures that
    /// floor beside the frame).
    pub fn factor_bytes(&self) -> usize {
        match &self.kind {
            Kind::Disc(d) => d.factor_bytes(),
            Kind::Triangle(tr, _) => tr.factor_bytes(),
            Kind::Linear(..) => 0,
        }
    }
}

/// Frames at every `t` of `ts`, in parallel when there is enough work
/// ([`crate::parallel`]), each worker with its own workspace from `workspace`:
/// `at_many(ts, frames, ws)` fills the frames of a batch of up to [`MAX_LANES`] times, one
/// vector of `n` points each (the vectors returned, so nothing is copied), so that a motion
/// can share one pass over its factor among them. Shared by every precompute-then-apply
/// motion (the interpolator, skeleton control).
pub(crate) fn parallel_frames<W>(
    ts: &[f64],
    n: usize,
    workspace: impl Fn() -> W + Sync + Send,
    at_many: impl Fn(&[f64], &mut [Vec<Point>], &mut W) + Sync + Send,
) -> Vec<Vec<Point>> {
    let work = ts.len().saturating_mul(n);
    let per_batch = crate::parallel::batch_len(ts.len(), work, MAX_LANES);
    let batches: Vec<&[f64]> = ts.chunks(per_batch).collect();
    crate::parallel::map_init(&batches, work, workspace, |ws, ts| {
        // Each frame solved straight into the vector returned for it.
        let mut frames = vec![vec![Point::ZERO; n]; ts.len()];
        at_many(ts, &mut frames, ws);
        frames
    })
    .into_iter()
    .flatten()
    .collect()
}

#[cfg(test)]
mod tests;
