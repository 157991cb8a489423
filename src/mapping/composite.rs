//! Composite harmonic mapping (§5, after \[41\]): the triangulation walks from the source curves to
//! the target curves through the intermediate curves of the barycenter-based shape model, one
//! harmonic map per step, and no step may flip a triangle.
//!
//! Each step `t_k → t_{k+1}` moves the curve vertices onto the shape model's curves at `t_{k+1}`
//! and places the other vertices by the harmonic map with the cotangent weights of the mesh at
//! `t_k` (the metric changes every step; the sparsity pattern, and so the symbolic
//! factorization, does not). A step whose harmonic map flips a triangle (exact orientation test)
//! is first repaired by local untangling of the folded triangles' free vertices (`untangle.rs`);
//! if that fails, or the intermediate curves cross, the step is rejected and halved; after a
//! step that needed no untangling, or two accepted steps in a row, the step doubles back. When
//! the BSM path cannot be followed, the same walk is tried with the BSM's features carried by
//! its boundary ([`ShapeModel::carried`]: features in a bending arm swing with it), then with
//! straight-line curves (with features, only where those do not cross halfway). Where every
//! path's curves cross at its first map, the map fails on the curves alone, before any
//! triangulation (`check_curves`). Finally, triangles that the steps left much thinner than they were get
//! their free vertices moved to improve their shapes (`untangle.rs`), never flipping one.
//! When the curves' spatial relation changes between source and target — a feature passing
//! through another or through the boundary, the limitation of the paper's Fig.16 — no flip-free
//! sequence exists, and the mapping reports the curves concerned instead of returning a folded
//! mesh.

use super::carried::Attachments;
use super::harmonic::Harmonic;
use super::shape_model::ShapeModel;
use super::untangle::Untangler;
use crate::correspondence::CurvePair;
use crate::error::ProblemKind;
use crate::geometry::Point;
use crate::mesh::{CompatibleMeshes, Side};
use crate::tolerance::Tolerances;
use crate::triangulation::validate::{crossing_curves, curves_cross, CurveRef};
use crate::triangulation::{validate_curves, Triangulation};
use crate::{Error, Result};

/// Step control of the composite mapping.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct MappingOptions {
    /// Number of equal steps tried first; also bounds the largest step (`1 / initial_steps`).
    /// Default: 4.
    pub initial_steps: usize,
    /// Largest number of harmonic maps one walk computes, accepted or rejected. Default: 2048
    /// (automatic mode, which has other rungs to fall to, takes at most 128 per walk).
    pub max_steps: usize,
    /// Smallest step in `t` before giving up. Default: 1/4096.
    pub min_step: f64,
    /// The last family of intermediate curves tried: the map follows the BSM's
    /// ([`Intermediates::Bsm`]), then, if that folds, the BSM with features carried by the
    /// boundary, then straight lines, stopping after this one. Default:
    /// [`Intermediates::Straight`] (a map is then almost always found); [`Intermediates::Bsm`]
    /// is the paper's method alone.
    pub last_resort: Intermediates,
}

/// A family of intermediate curves the composite map follows from one side to the other (§5),
/// in the order they are tried: the paper's, then two that exist where it folds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Default)]
pub enum Intermediates {
    /// The barycenter-based shape model's curves ([`ShapeModel::new`], §5).
    #[default]
    Bsm,
    /// The BSM with the features carried by the boundary around them
    /// ([`ShapeModel::carried`]): tried when the BSM's intermediate features cross. Needs a
    /// feature curve besides the boundary.
    Carried,
    /// Straight lines from each curve vertex to its twin ([`ShapeModel::linear`]), starting
    /// with one whole step.
    Straight,
}

impl MappingOptions {
    /// The defaults: 4 initial steps, at most 2048 maps, steps no shorter than 1/4096.
    pub const DEFAULT: MappingOptions = MappingOptions {
        initial_steps: 4,
        max_steps: 2048,
        min_step: 1.0 / 4096.0,
        last_resort: Intermediates::Straight,
    };

    /// Sets [`MappingOptions::initial_steps`].
    pub fn with_initial_steps(mut self, n: usize) -> Self {
        self.initial_steps = n;
        self
    }

    /// Sets [`MappingOptions::max_steps`].
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }

    /// Sets [`MappingOptions::last_resort`].
    pub fn with_last_resort(mut self, last: Intermediates) -> Self {
        self.last_resort = last;
        self
    }

    /// Sets [`MappingOptions::min_step`].
    pub fn with_min_step(mut self, h: f64) -> Self {
        self.min_step = h;
        self
    }
}

impl Default for MappingOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What the composite mapping did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MappingStats {
    /// Accepted steps (harmonic maps composed into the result).
    pub steps: usize,
    /// Steps rejected because they flipped a triangle or made curves cross, including every
    /// step of an abandoned path when a fallback path was taken.
    pub rejected_steps: usize,
    /// Vertices of the compatible meshes.
    pub vertices: usize,
    /// Triangles of the compatible meshes.
    pub triangles: usize,
    /// The intermediate curves the accepted map followed.
    pub path: Intermediates,
}

/// Maps the triangulation `tri` of one side of `pairs` onto the other side (§5): returns the
/// compatible meshes — `source` positions in the source drawing and `target` positions in the
/// target drawing whichever side was triangulated — with every curve vertex exactly on its twin
/// and no inverted triangle, or an input error naming the curves whose spatial relation changes
/// (Fig.16) when no flip-free mapping is found.
pub fn composite_map(
    tri: &Triangulation,
    pairs: &[CurvePair],
    tol: &Tolerances,
    opts: &MappingOptions,
) -> Result<(CompatibleMeshes, MappingStats)> {
    composite_map_reusing(tri, pairs, tol, opts, &mut Attachments::default(), None)
}

/// [`composite_map`], with the carried features' attachments to the boundary taken from
/// `made` where it holds them and kept there (issue 16: automatic mode maps the same curves
/// from both sides and again after giving up each hole), and with what [`check_curves`]
/// found for the same curves, side and options, if it checked them (it has validated them,
/// and its findings spare the walks' first checks).
pub(crate) fn composite_map_reusing(
    tri: &Triangulation,
    pairs: &[CurvePair],
    tol: &Tolerances,
    opts: &MappingOptions,
    made: &mut Attachments,
    checked: Option<Box<Checked>>,
) -> Result<(CompatibleMeshes, MappingStats)> {
    let triangulated = tri.triangulated;
    if checked.is_none() {
        validate_curves(pairs, tol, triangulated.other())?;
    }
    if tri.curves.len() != pairs.len()
        || tri
            .curves
            .iter()
            .zip(pairs)
            .any(|(c, p)| c.vertices.len() != p.source.len())
    {
        return Err(Error::internal(
            "composite map: triangulation does not match the curve pairs",
        ));
    }
    let n = tri.points.len();
    let mut fixed = vec![false; n];
    for v in tri.curves.iter().flat_map(|c| &c.vertices) {
        *fixed
            .get_mut(*v as usize)
            .ok_or_else(|| Error::internal("composite map: bad curve vertex"))? = true;
    }
    let mut harmonic = Harmonic::new(&tri.triangles, n, &fixed)?;

    let mut stats = MappingStats {
        vertices: n,
        triangles: tri.triangles.len(),
        ..Default::default()
    };
    let h_bsm = 1.0 / opts.initial_steps.max(1) as f64;
    // Where `check_curves` checked the curves, the walks start from the path it hands on,
    // with the BSM's error when that path is a later one.
    let (model, start, clear, crossed) = match checked.map(|c| *c) {
        Some(c) => (c.model, c.path, c.clear, c.crossed),
        None => (
            ShapeModel::new(pairs, triangulated)?,
            Intermediates::Bsm,
            None,
            None,
        ),
    };
    // The time the check found clear, on the path it found it on.
    let clear_on = |path| clear.filter(|_| start == path);
    let untangler = Untangler::new(&tri.triangles, &fixed);
    let mut solver = Solver {
        harmonic: &mut harmonic,
        untangler: &untangler,
    };
    // Only the BSM path's failure is reported: the paths tried after it explain nothing. A
    // path the check found crossing at its first map counts that map as its walk would.
    let bsm = match crossed {
        None => {
            let path = Path {
                model: &model,
                h_max: h_bsm,
                clear: clear_on(Intermediates::Bsm),
            };
            walk(tri, pairs, path, &mut solver, opts, &mut stats)
                .map_err(|stop| stop.explain(&model, pairs, tri))
        }
        Some(e) => {
            stats.rejected_steps += 1;
            Err(e)
        }
    };
    let (bsm, model) = match bsm {
        Err(e) if e.is_input() && pairs.len() > 1 && opts.last_resort >= Intermediates::Carried => {
            log::debug!("composite map: BSM path failed ({e}), trying carried features");
            let carried = match start {
                Intermediates::Bsm => model.with_carried(made),
                _ => model,
            };
            let abandoned = std::mem::take(&mut stats.steps);
            stats.rejected_steps += abandoned;
            let r = if start == Intermediates::Straight {
                stats.rejected_steps += 1;
                Err(())
            } else {
                let path = Path {
                    model: &carried,
                    h_max: h_bsm,
                    clear: clear_on(Intermediates::Carried),
                };
                walk(tri, pairs, path, &mut solver, opts, &mut stats).map_err(|_| ())
            };
            if r.is_ok() {
                stats.path = Intermediates::Carried;
            }
            (r.map_err(|()| e), carried)
        }
        r => (r, model),
    };
    let current = match bsm {
        Ok(c) => c,
        Err(e) if e.is_input() && opts.last_resort == Intermediates::Straight => {
            let linear = model.into_linear();
            if start != Intermediates::Straight && straight_lines_cross(&linear, pairs) {
                return Err(e);
            }
            log::debug!("composite map: BSM paths failed ({e}), trying straight lines");
            stats.rejected_steps += std::mem::take(&mut stats.steps);
            // Starting with one whole step: the direct harmonic map, then straight-line halves.
            // With features, halfway was found clear (by the curve check or just above).
            let path = Path {
                model: &linear,
                h_max: 1.0,
                clear: straight_checked_at(pairs),
            };
            let c = walk(tri, pairs, path, &mut solver, opts, &mut stats).map_err(|_| e)?;
            stats.path = Intermediates::Straight;
            c
        }
        Err(e) => return Err(e),
    };
    // Last, the triangles the steps squeezed get their shapes back where their free vertices
    // allow (kept only if the exact test still passes).
    let mut current = current;
    let before = current.clone();
    untangler.improve(&tri.triangles, &tri.points, &mut current);
    if tri.triangles.iter().any(|t| is_bad(t, &current)) {
        current = before;
    }
    // The last step put the curve vertices exactly on the far side's curves.
    let (source, target) = match triangulated {
        Side::Target => (current, tri.points.clone()),
        Side::Source => (tri.points.clone(), current),
    };
    debug_assert!(tri.curves.iter().zip(pairs).all(|(c, p)| c
        .vertices
        .iter()
        .zip(&p.target)
        .all(|(&v, &q)| target[v as usize] == q)));
    let meshes = CompatibleMeshes {
        triangles: tri.triangles.clone(),
        source,
        target,
        curves: tri.curves.clone(),
        parts: None,
    };
    Ok((meshes, stats))
}

/// Whether the intermediate curves of `model` cross at `t` (left in `curves`).
fn cross_at(model: &ShapeModel, pairs: &[CurvePair], t: f64, curves: &mut Vec<Vec<Point>>) -> bool {
    model.curves_at(t, curves);
    curves_cross(&curve_refs(curves, pairs))
}

/// Intermediate `curves` (one per pair) as the crossing tests take them, each closed or open
/// as its pair is.
fn curve_refs<'c>(curves: &'c [Vec<Point>], pairs: &[CurvePair]) -> Vec<CurveRef<'c>> {
    curves
        .iter()
        .zip(pairs)
        .map(|(c, p)| (c.as_slice(), p.closed))
        .collect()
}

/// Whether the straight-line path is left out: it has feature curves and its curves cross
/// halfway. The straight walk starts with one whole step, the direct harmonic map to t = 1,
/// and halves it when that map folds: its next map is at t = ½, where crossing curves stop
/// the walk. With features, the direct map must also land every feature where the target
/// has it, and on the random icon corpora (640 pairs) it never did where the straight lines
/// cross halfway, while each attempt cost a triangulation and an untangling (issue 16: the
/// slowest pairs give up holes one at a time). A boundary alone is still tried: its direct
/// map does succeed sometimes (two corpus parts), and with it the part keeps a mesh.
fn straight_lines_cross(linear: &ShapeModel, pairs: &[CurvePair]) -> bool {
    straight_checked_at(pairs).is_some_and(|t| cross_at(linear, pairs, t, &mut Vec::new()))
}

/// The time [`straight_lines_cross`] checks, and so finds clear when the straight path is
/// walked: halfway, for curves with features; none for a lone boundary.
fn straight_checked_at(pairs: &[CurvePair]) -> Option<f64> {
    (pairs.len() > 1).then_some(0.5)
}

/// What the curves alone tell of a composite map ([`check_curves`]).
pub(crate) enum CurveCheck {
    /// The map fails with this error, whatever the triangulation.
    Fails(Error),
    /// A map has to be tried; what the check found, when it got that far (give it to
    /// [`composite_map_reusing`]).
    Try(Option<Box<Checked>>),
}

/// The first path a composite map has to walk, as [`check_curves`] found it.
pub(crate) struct Checked {
    /// The path: the BSM, or a later one when the paths before it cross at their first map.
    path: Intermediates,
    /// Its shape model (carried features or straight lines applied).
    model: ShapeModel,
    /// A time its curves were found not to cross at: its first map's (for straight lines,
    /// halfway, checked only with features).
    clear: Option<f64>,
    /// The error of the BSM path when it crosses at its first map (so exactly when `path` is a
    /// later one).
    crossed: Option<Error>,
}

/// Whether [`composite_map_reusing`] fails for `pairs` triangulated on side `triangulated`
/// whatever the triangulation: every path's curves cross where its first map would go (the
/// BSM's and the carried features' at the first step, the straight lines halfway, see
/// [`straight_lines_cross`]), and it returns the error the map would. Callers then skip the
/// triangulation (issue 16: automatic mode gives up holes one at a time, and the rungs whose
/// holes cross at once spent most of their time triangulating). Otherwise the first path to
/// walk is handed on, so the map checks nothing twice. Curves that fail the checks the map
/// starts with are left to it (the triangulation reports those first).
pub(crate) fn check_curves(
    pairs: &[CurvePair],
    tol: &Tolerances,
    opts: &MappingOptions,
    triangulated: Side,
    made: &mut Attachments,
) -> CurveCheck {
    if opts.max_steps == 0 || validate_curves(pairs, tol, triangulated.other()).is_err() {
        return CurveCheck::Try(None);
    }
    let Ok(model) = ShapeModel::new(pairs, triangulated) else {
        return CurveCheck::Try(None);
    };
    let first = step_end(1.0 / opts.initial_steps.max(1) as f64);
    let start = |path, model, clear, crossed| {
        CurveCheck::Try(Some(Box::new(Checked {
            path,
            model,
            clear,
            crossed,
        })))
    };
    let mut curves = Vec::new();
    if !cross_at(&model, pairs, first, &mut curves) {
        return start(Intermediates::Bsm, model, Some(first), None);
    }
    // As the walk's `Stop::Crossing` explains itself.
    let e = failure(&model, pairs, first, &mut curves, "");
    let model = if pairs.len() > 1 && opts.last_resort >= Intermediates::Carried {
        let carried = model.with_carried(made);
        if !cross_at(&carried, pairs, first, &mut curves) {
            return start(Intermediates::Carried, carried, Some(first), Some(e));
        }
        carried
    } else {
        model
    };
    if opts.last_resort == Intermediates::Straight {
        let linear = model.into_linear();
        if !straight_lines_cross(&linear, pairs) {
            let halfway = straight_checked_at(pairs);
            return start(Intermediates::Straight, linear, halfway, Some(e));
        }
    }
    CurveCheck::Fails(e)
}

/// The free-vertex placement of one step: the harmonic map, untangled locally where it folds.
struct Solver<'a> {
    harmonic: &'a mut Harmonic,
    untangler: &'a Untangler,
}

/// Why a walk stopped short of t = 1. Only the first path's failure is reported to the user,
/// so the error that names curves (dear to find: the crossings at `t`, the curves nearest the
/// folds) is built only for it ([`Stop::explain`]).
enum Stop {
    /// The map could not be computed.
    Broken(Error),
    /// The intermediate curves cross at `t`.
    Crossing { t: f64 },
    /// The maximum number of maps was reached before `t`.
    TooManyMaps { t: f64 },
    /// The step fell below the smallest at `t`; `attempt` is the last rejected map.
    Folded { t: f64, attempt: Vec<Point> },
}

impl Stop {
    /// The error for the user: names the curves that cross or that the mesh folds near.
    fn explain(self, model: &ShapeModel, pairs: &[CurvePair], tri: &Triangulation) -> Error {
        let mut curves = Vec::new();
        match self {
            Stop::Broken(e) => e,
            Stop::Crossing { t } => failure(model, pairs, t, &mut curves, ""),
            Stop::TooManyMaps { t } => failure(
                model,
                pairs,
                t,
                &mut curves,
                " within the maximum number of steps",
            ),
            Stop::Folded { t, attempt } => flip_report(model, pairs, tri, t, &attempt, &mut curves),
        }
    }
}

/// One family of intermediate curves for [`walk`] to follow.
#[derive(Clone, Copy)]
struct Path<'m> {
    model: &'m ShapeModel,
    /// The largest step.
    h_max: f64,
    /// A time whose curves are known not to cross ([`check_curves`] checked the first step's).
    clear: Option<f64>,
}

/// The time a map one step ahead goes to (`t + h` given): 1 when within 1e-12 of it, so
/// that the last step lands exactly on the target curves.
fn step_end(t_plus_h: f64) -> f64 {
    if t_plus_h >= 1.0 - 1e-12 {
        1.0
    } else {
        t_plus_h
    }
}

/// Follows the intermediate curves of `path` from t = 0 to 1 with adaptive steps no longer
/// than its `h_max`; returns the vertex positions at t = 1.
fn walk(
    tri: &Triangulation,
    pairs: &[CurvePair],
    path: Path<'_>,
    solver: &mut Solver<'_>,
    opts: &MappingOptions,
    stats: &mut MappingStats,
) -> std::result::Result<Vec<Point>, Stop> {
    let mut current = tri.points.clone();
    let mut next = current.clone();
    // The first triangle inverted or a sliver, if any (a bad triangle includes every inverted
    // one, so this is also the exact orientation test).
    let first_bad = |v: &[Point]| tri.triangles.iter().position(|t| is_bad(t, v));
    let mut curves: Vec<Vec<Point>> = Vec::new();
    let min_step = opts.min_step.max(f64::EPSILON);
    let (mut t, mut maps) = (0.0f64, 0usize);
    let (model, mut step) = (path.model, Step::new(path.h_max));
    while t < 1.0 {
        if maps >= opts.max_steps {
            return Err(Stop::TooManyMaps { t: t + step.h });
        }
        maps += 1;
        let t1 = step_end(t + step.h);
        // Curves that cross at t1 block this path whatever the step: the walk must pass t1.
        let crossing = if path.clear == Some(t1) {
            model.curves_at(t1, &mut curves);
            false
        } else {
            cross_at(model, pairs, t1, &mut curves)
        };
        if crossing {
            stats.rejected_steps += 1;
            return Err(Stop::Crossing { t: t1 });
        }
        let (ok, clean) = {
            next.copy_from_slice(&current);
            for (c, pts) in tri.curves.iter().zip(&curves) {
                for (&v, &q) in c.vertices.iter().zip(pts) {
                    next[v as usize] = q;
                }
            }
            solver
                .harmonic
                .solve(&current, &mut next)
                .map_err(Stop::Broken)?;
            match first_bad(&next) {
                None => (true, true),
                Some(f) => {
                    // `untangle` returns true only when no triangle is bad: none would be found.
                    let untangler = solver.untangler;
                    let untangled = untangler.untangle(&tri.triangles, &mut next, is_bad, f);
                    (untangled, false)
                }
            }
        };
        if ok {
            std::mem::swap(&mut current, &mut next);
            t = t1;
            stats.steps += 1;
            step.accepted(clean);
        } else {
            stats.rejected_steps += 1;
            step.rejected();
            if step.h < min_step {
                return Err(Stop::Folded {
                    t: t1,
                    attempt: next,
                });
            }
        }
    }
    Ok(current)
}

/// The step control of a walk: halved when a map is rejected; doubled back (up to the largest
/// step) after a map that needed no untangling, or after `patience` accepted maps in a row at
/// the same step. A step that folded and was untangled is at the edge of what the mesh takes:
/// doubling it at once mostly costs a rejected map whose untangling ran every sweep before it
/// failed, the dearest map of a walk (issue 16: such rejected maps took about a sixth of the
/// random icon corpus's whole-CLI CPU). Where a doubled step is rejected at once, the walk is
/// in a stretch that takes no more: the patience doubles (2, 4, 8, 16 maps) until a clean map
/// shows the stretch is over. On the slowest corpus pairs 44 % of all maps were rejected, 77 of
/// one walk's 202 right after a doubling.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Step {
    /// The step in `t` the next map tries.
    h: f64,
    /// The largest step.
    h_max: f64,
    /// Accepted maps in a row since the step last changed.
    streak: u32,
    /// Accepted maps in a row that needed untangling before the step doubles: 2, doubled (up
    /// to 16) each time a doubled step is rejected at once, back to 2 after a clean map.
    patience: u32,
    /// Whether the step was just doubled (no map at it accepted yet).
    grown: bool,
}

impl Step {
    fn new(h_max: f64) -> Self {
        Step {
            h: h_max,
            h_max,
            streak: 0,
            patience: 2,
            grown: false,
        }
    }

    /// After an accepted map; `clean` when it needed no untangling.
    fn accepted(&mut self, clean: bool) {
        self.grown = false;
        self.streak += 1;
        if clean {
            self.patience = 2;
        }
        if clean || self.streak >= self.patience {
            self.grow();
        }
    }

    fn grow(&mut self) {
        let h = (2.0 * self.h).min(self.h_max);
        self.grown = h > self.h;
        self.h = h;
        self.streak = 0;
    }

    /// After a rejected map.
    fn rejected(&mut self) {
        if self.grown {
            self.patience = (2 * self.patience).min(16);
        }
        self.h *= 0.5;
        self.streak = 0;
        self.grown = false;
    }
}

/// Whether a triangle is inverted or a sliver ([`crate::geometry::inverted_or_sliver`]): such a
/// mesh is not accepted as a step, because the next step's metric needs it.
fn is_bad(t: &[u32; 3], points: &[Point]) -> bool {
    let [a, b, c] = t.map(|v| points[v as usize]);
    crate::geometry::inverted_or_sliver(a, b, c)
}

const FIG16: &str = "the curves change their spatial relation between source and target, which the composite \
                     mapping cannot follow without folding the mesh (the paper's Fig.16 limitation)";
const HINT: &str =
    "keep features on the same side of each other and of the boundary in both drawings, \
                    reduce the change between them, or remove one of them";

/// The error for a failed mapping at time `t`: names the curve pairs whose intermediate curves
/// cross there, if any.
fn failure(
    model: &ShapeModel,
    pairs: &[CurvePair],
    t: f64,
    curves: &mut Vec<Vec<Point>>,
    why: &str,
) -> Error {
    match crossing_names(model, pairs, t, curves) {
        Some((names, ids)) => Error::input(
            crate::error::Drawings::Pair,
            format!("no flip-free mapping{why}: at t = {t:.3} {names}; {FIG16}"),
        )
        .with_hint(HINT)
        .concerning(ids)
        .of_kind(ProblemKind::NoFlipFreeMapping),
        None => Error::input(
            crate::error::Drawings::Pair,
            format!("no flip-free mapping{why} (t = {t:.3}); {FIG16}"),
        )
        .with_hint(HINT)
        .of_kind(ProblemKind::NoFlipFreeMapping),
    }
}

fn crossing_names(
    model: &ShapeModel,
    pairs: &[CurvePair],
    t: f64,
    curves: &mut Vec<Vec<Point>>,
) -> Option<(String, Vec<String>)> {
    model.curves_at(t.min(1.0), curves);
    let crossing = crossing_curves(&curve_refs(curves, pairs));
    if crossing.is_empty() {
        return None;
    }
    let names: Vec<String> = crossing
        .iter()
        .map(|&(a, b)| {
            if a == b {
                format!("{} intersects itself", pairs[a].id)
            } else {
                format!("{} crosses {}", pairs[b].id, pairs[a].id)
            }
        })
        .collect();
    let mut ids: Vec<String> = Vec::new();
    for &(a, b) in &crossing {
        for k in [b, a] {
            if !ids.contains(&pairs[k].id) {
                ids.push(pairs[k].id.clone());
            }
        }
    }
    Some((names.join(", "), ids))
}

/// The error after step halving failed at `t`: crossing intermediate curves if there are any,
/// else the curves nearest to the flipped triangles of the rejected step (`attempt`).
fn flip_report(
    model: &ShapeModel,
    pairs: &[CurvePair],
    tri: &Triangulation,
    t: f64,
    attempt: &[Point],
    curves: &mut Vec<Vec<Point>>,
) -> Error {
    if crossing_names(model, pairs, t, curves).is_some() {
        return failure(model, pairs, t, curves, "");
    }
    let mut near: Vec<usize> = Vec::new();
    for tr in &tri.triangles {
        if !is_bad(tr, attempt) {
            continue;
        }
        let [a, b, c] = tr.map(|v| attempt[v as usize]);
        let centre = (a + b + c) / 3.0;
        let nearest = tri
            .curves
            .iter()
            .enumerate()
            .map(|(i, cv)| {
                let d = cv
                    .vertices
                    .iter()
                    .map(|&v| attempt[v as usize].distance(centre))
                    .fold(f64::INFINITY, f64::min);
                (d, i)
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((_, i)) = nearest {
            if !near.contains(&i) {
                near.push(i);
            }
        }
    }
    near.sort_unstable();
    let names: Vec<&str> = near.iter().take(4).map(|&i| pairs[i].id.as_str()).collect();
    Error::input(
        crate::error::Drawings::Pair,
        format!(
            "no flip-free mapping (t = {t:.3}): the mesh folds near {} when following the change of \
             the curves' layout (too large a relative rotation or deformation between neighbouring \
             curves; a limitation of the composite mapping, cf. the paper's Fig.16)",
            if names.is_empty() { "the curves".to_string() } else { names.join(", ") }
        ),
    )
    .with_hint(HINT)
    .concerning(names.iter().copied())
    .of_kind(ProblemKind::NoFlipFreeMapping)
}

#[cfg(test)]
mod tests;
