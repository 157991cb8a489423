//! Vertex correspondence between a source curve and its target twin (§3, after \[15\]).
//!
//! Salient points (curvature extrema at a scale) are detected on both curves and associated by an
//! order-preserving dynamic-programming match (cyclic for closed curves); anchors override the
//! association. Between consecutive associated salient points, vertices are distributed by
//! normalized arc length so that both curves get the same vertex count, every original flattened
//! vertex of each curve is kept (so no shape detail is lost), and no edge is longer than the
//! density allows.
//!
//! | file | step |
//! |---|---|
//! | `measure.rs` | arc-length measurement of a polyline: sample, project, insert, re-start |
//! | `orientation.rs` | counter-clockwise closed curves; direction of open targets; best start |
//! | `salient.rs` | salient point detection (turning over an arc-length window) |
//! | `matching.rs` | order-preserving association by dynamic programming (cyclic when closed) |
//! | `resample.rs` | distribution of vertices between associated points |

mod matching;
mod measure;
mod memo;
mod orientation;
mod resample;
mod salient;
#[cfg(test)]
mod tests;

use crate::drawing::{ControlCurve, Controls};
use crate::error::Drawings;
use crate::geometry::Point;
use crate::mesh::CurveKind;
use crate::tolerance::{Tolerances, MAX_COORDINATE};
use crate::{Error, Result};
use matching::Mark;
use measure::Polyline;
use memo::Ask;
pub(crate) use memo::Correspondences;
use salient::Salient;

/// A source curve and its target twin with equal vertex counts: `source[i]` corresponds to
/// `target[i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvePair {
    /// The element id (`boundary`, `feature-eye`, …), as in the source file.
    pub id: String,
    /// Boundary or feature.
    pub kind: CurveKind,
    /// Whether the curve is closed (last vertex connects to the first, not repeated).
    pub closed: bool,
    /// Source vertices (closed curves counter-clockwise).
    pub source: Vec<Point>,
    /// Target vertices, same count, corresponding one to one.
    pub target: Vec<Point>,
    /// Indices (into both vertex lists) of the associated pairs: matched salient points, anchors,
    /// and an open curve's end points; a closed curve's first pair is index 0.
    pub salient: Vec<usize>,
}

/// Settings of the vertex correspondence. Construct with [`Default`] and the `with_*` setters.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CorrespondenceOptions {
    /// Extra vertex density along curves on top of the one `Tolerances` carries: edges are at
    /// most `tol.max_edge / density` long. Default: `1.0`.
    pub density: f64,
    /// Half-width `h` of the window over which the turning at a vertex is measured, as a
    /// fraction of the curve's length (the detection scale of salient points; clamped to at most
    /// `0.25`). Default: `0.03`.
    pub window_fraction: f64,
    /// Smallest turning (degrees) over the window for a vertex to be salient. Default: `25.0`.
    pub salient_angle_deg: f64,
    /// Smallest angle (degrees) between a vertex's two edges for it to count as a sharp corner
    /// even when the window smooths it out. Default: `60.0`.
    pub corner_angle_deg: f64,
    /// Most salient points kept per curve (the strongest). Default: `32`.
    pub max_salient: usize,
    /// Cost of leaving a salient point unmatched, in units of normalized arc length: points
    /// further apart than about twice this are never paired. Default: `0.1`.
    pub skip_cost: f64,
    /// Weight of the turning difference (as a fraction of π) against the position difference in
    /// the pairing cost. Default: `0.25`.
    pub angle_weight: f64,
    /// Largest ratio between the turnings of two paired salient points. Default: `3.0`.
    pub max_turning_ratio: f64,
    /// A source vertex and a target vertex closer than this fraction of the longest edge (after
    /// mapping into each other's curve) become one vertex pair instead of two. Default: `0.2`.
    pub merge_fraction: f64,
    /// Farthest an anchor may be from the curve it pins, as a fraction of the drawing's
    /// diagonal. Default: `0.02`.
    pub anchor_reach: f64,
    /// The turn (radians) that breaks ties between equally good starts of a symmetric closed
    /// curve (an ellipse matches its twin equally well at 0° and 180°): the start whose turn is
    /// nearest to it wins. [`correspond_all`] sets it for every feature to the boundary pair's
    /// best-fit rotation, so that a spot on a shape turning half round turns with it instead of
    /// staying put while everything around it turns (which folds any mapping). Default: `None`,
    /// the least turning.
    pub preferred_rotation: Option<f64>,
    /// The turn (radians) the two shapes make as shapes (`crate::quality::shape_turn` of the
    /// two boundaries), when known: the boundary's salient points are then paired so that the
    /// pairing turns the outline by about that much, and a heart's notch is not paired with a
    /// star's tip a fifth of a turn away (a spin neither end has). Automatic mode sets it per
    /// shape. Default: `None`.
    pub outline_turn: Option<f64>,
}

impl Default for CorrespondenceOptions {
    fn default() -> Self {
        CorrespondenceOptions {
            density: 1.0,
            window_fraction: 0.03,
            salient_angle_deg: 25.0,
            corner_angle_deg: 60.0,
            max_salient: 32,
            skip_cost: 0.1,
            angle_weight: 0.25,
            max_turning_ratio: 3.0,
            merge_fraction: 0.2,
            anchor_reach: 0.02,
            preferred_rotation: None,
            outline_turn: None,
        }
    }
}

impl CorrespondenceOptions {
    /// Sets [`CorrespondenceOptions::density`].
    pub fn with_density(mut self, density: f64) -> Self {
        self.density = density;
        self
    }

    /// Sets [`CorrespondenceOptions::window_fraction`].
    pub fn with_window_fraction(mut self, fraction: f64) -> Self {
        self.window_fraction = fraction;
        self
    }

    /// Sets [`CorrespondenceOptions::salient_angle_deg`].
    pub fn with_salient_angle_deg(mut self, degrees: f64) -> Self {
        self.salient_angle_deg = degrees;
        self
    }

    /// Sets [`CorrespondenceOptions::anchor_reach`].
    pub fn with_anchor_reach(mut self, fraction: f64) -> Self {
        self.anchor_reach = fraction;
        self
    }

    /// The longest edge allowed with tolerances `tol`.
    fn max_edge(&self, tol: &Tolerances) -> f64 {
        let density = if self.density.is_finite() && self.density > 0.0 {
            self.density
        } else {
            1.0
        };
        tol.max_edge / density
    }
}

/// Placeholder file names: stages below [`correspond_all`] do not know the files.
const SRC: Drawings = Drawings::Source;
const TGT: Drawings = Drawings::Target;
const BOTH: Drawings = Drawings::Both;

/// Vertex correspondence for every curve of a pair of drawings (§3): the boundary first, then
/// the features in name order.
///
/// Features are matched by name and anchors by name; each source anchor pins the curve nearest to
/// it, and its twin pins that curve's twin. Errors name the file and the element: a feature or
/// anchor in one file only, a degenerate curve (fewer than two distinct points, zero length, a
/// closed curve with fewer than three points or no area), an anchor farther than
/// [`CorrespondenceOptions::anchor_reach`] from every curve (or from its curve's twin).
/// `tol` is the common tolerance of the two drawings (built from the larger diagonal).
pub fn correspond_all(
    src_file: &str,
    src: &Controls,
    tgt_file: &str,
    tgt: &Controls,
    tol: &Tolerances,
    opts: &CorrespondenceOptions,
) -> Result<Vec<CurvePair>> {
    let made = &mut Correspondences::default();
    correspond_all_reusing(src_file, src, tgt_file, tgt, tol, opts, made)
}

/// [`correspond_all`], taking from `made` the correspondences of curve pairs it made before
/// (the same curves, anchors, tolerances and options) and keeping there the ones made now
/// (issue 16: automatic mode corresponds a part again for every hole it gives up).
pub(crate) fn correspond_all_reusing(
    src_file: &str,
    src: &Controls,
    tgt_file: &str,
    tgt: &Controls,
    tol: &Tolerances,
    opts: &CorrespondenceOptions,
    made: &mut Correspondences,
) -> Result<Vec<CurvePair>> {
    let twin_of = |f: &ControlCurve, others: &[ControlCurve]| {
        others.iter().find(|g| g.name == f.name).cloned()
    };
    check_boundaries((src_file, src), (tgt_file, tgt))?;
    let mut curves: Vec<(&ControlCurve, &ControlCurve)> = vec![(&src.boundary, &tgt.boundary)];
    for f in &src.features {
        if twin_of(f, &tgt.features).is_none() {
            return Err(missing(&f.id, (src_file, src), (tgt_file, tgt)));
        }
    }
    for f in &tgt.features {
        if twin_of(f, &src.features).is_none() {
            return Err(missing(&f.id, (tgt_file, tgt), (src_file, src)));
        }
    }
    for f in &src.features {
        if let Some(g) = tgt.features.iter().find(|g| g.name == f.name) {
            curves.push((f, g));
        }
    }
    // Validate every curve first, so that a degenerate one is reported as such.
    let mut lines: Vec<(Polyline, Polyline)> = Vec::with_capacity(curves.len());
    for (s, t) in &curves {
        let a = clean(s, tol).map_err(|e| e.in_file(src_file))?;
        let b = clean(t, tol).map_err(|e| e.in_file(tgt_file))?;
        lines.push((Polyline::new(a, s.closed), Polyline::new(b, t.closed)));
    }
    let reach = opts.anchor_reach * tol.diagonal;
    let mut pins: Vec<Vec<(Point, Point)>> = vec![Vec::new(); curves.len()];
    for a in &src.anchors {
        let twin = tgt
            .anchors
            .iter()
            .find(|b| b.name == a.name)
            .ok_or_else(|| no_twin(&a.id, src_file, (tgt_file, tgt)))?;
        let mut best = (f64::INFINITY, 0);
        for (k, (line, _)) in lines.iter().enumerate() {
            let d = line.project(a.point).0;
            if d < best.0 {
                best = (d, k);
            }
        }
        if best.0.is_nan() || best.0 > reach {
            return Err(Error::at(
                src_file,
                &a.id,
                format!("is farther than {reach:.4} from every boundary and feature curve"),
            )
            .with_hint("place the anchor on the curve it should pin"));
        }
        let k = best.1;
        let d = lines[k].1.project(twin.point).0;
        if d.is_nan() || d > reach {
            return Err(Error::at(
                tgt_file,
                &twin.id,
                format!(
                    "is farther than {reach:.4} from {}, the curve its twin pins",
                    curves[k].1.id
                ),
            )
            .with_hint("place the anchor on the same curve in both files"));
        }
        pins[k].push((a.point, twin.point));
    }
    for b in &tgt.anchors {
        if !src.anchors.iter().any(|a| a.name == b.name) {
            return Err(no_twin(&b.id, tgt_file, (src_file, src)));
        }
    }
    // The boundary first: the turn of its part nearest each feature breaks the ties of
    // symmetric features (see `CorrespondenceOptions::preferred_rotation`). When the boundary
    // matches its twin equally well in several ways, the features decide: the one that carries
    // them along with their surroundings wins (`feature_misfit`).
    // Every correspondence below goes through `made`.
    let corresponded = |made: &mut Correspondences,
                        s: &ControlCurve,
                        t: &ControlCurve,
                        anchors: &[(Point, Point)],
                        o: &CorrespondenceOptions,
                        reverse: Option<bool>| {
        let ask = Ask {
            src: s,
            tgt: t,
            anchors,
            tol,
            opts: o,
            reverse,
        };
        made.get_or_make(ask, || correspond_with(s, t, anchors, tol, o, reverse))
            .map_err(|e| name_files(e, src_file, tgt_file))
    };
    let boundary = corresponded(made, curves[0].0, curves[0].1, &pins[0], opts, None)?;
    let mut best: Option<(f64, Vec<CurvePair>)> = None;
    for b in boundary {
        let mut out: Vec<CurvePair> = Vec::with_capacity(curves.len());
        out.push(b);
        for ((s, t), p) in curves.iter().zip(&pins).skip(1) {
            let mut o = opts.clone();
            // A feature turns with its surroundings, not with the whole outline.
            o.outline_turn = None;
            if o.preferred_rotation.is_none() {
                o.preferred_rotation = Some(local_turn(&out[0], &s.points));
            }
            let mut pair = first_candidate(corresponded(made, s, t, p, &o, None)?)?;
            // An open feature whose direction its anchors do not fix runs the way that moves
            // with the surrounding boundary (`misfit_of`); the shape fit only breaks ties. The
            // shape alone is a poor guide when it hardly tells (a nearly straight stroke against
            // an arc), and a feature turned round against its surroundings folds any mapping.
            if !s.closed && p.len() < 2 {
                let shape_reversed =
                    pair.source
                        .first()
                        .zip(pair.target.first())
                        .is_some_and(|(_, &q0)| {
                            t.points.last().is_some_and(|&l| {
                                let first = t.points[0];
                                q0.distance(l) < q0.distance(first)
                            })
                        });
                let other =
                    first_candidate(corresponded(made, s, t, p, &o, Some(!shape_reversed))?)?;
                if made.misfit(&out[0], &other) < made.misfit(&out[0], &pair) - 1e-9 {
                    pair = other;
                }
            }
            out.push(pair);
        }
        // Candidates come least-turning first; a later one must fit the features clearly better
        // (by 1 %), so that a tie between symmetric boundaries is not broken by rounding noise
        // into a quarter turn.
        let misfit = feature_misfit(&out, made);
        if best
            .as_ref()
            .is_none_or(|(m, _)| misfit < *m * (1.0 - 0.01) - 1e-12)
        {
            best = Some((misfit, out));
        }
    }
    best.map(|b| b.1)
        .ok_or_else(|| Error::internal("correspondence: no boundary candidate"))
}

/// How badly the features' correspondence disagrees with the boundary's around them: for every
/// feature vertex, the distance between its target twin and where the best-fit similarity of the
/// nearest boundary vertices (source → target, as in [`local_turn`]) carries it, relative to the
/// size of those boundary vertices' target spread; averaged over features. A boundary
/// correspondence that turns a symmetric shape the other way round than its features moves them
/// across the shape, which no mapping can follow without folding.
/// Each feature's misfit is taken from `made` when it holds it ([`Correspondences::misfit`]).
fn feature_misfit(pairs: &[CurvePair], made: &mut Correspondences) -> f64 {
    let Some((boundary, features)) = pairs.split_first() else {
        return 0.0;
    };
    if features.is_empty() {
        return 0.0;
    }
    let total: f64 = features.iter().map(|f| made.misfit(boundary, f)).sum();
    total / features.len() as f64
}

/// [`feature_misfit`] of one feature `f` against `boundary`.
fn misfit_of(boundary: &CurvePair, f: &CurvePair) -> f64 {
    let k = LOCAL_TURN_VERTICES
        .max(boundary.source.len() / 10)
        .min(boundary.source.len());
    if k == 0 {
        return 0.0;
    }
    let n = boundary.source.len();
    // Per feature vertex: the boundary's squared distances to it, measured once (not at every
    // comparison), and the same selection from the same starting order.
    let mut d2 = vec![0.0; n];
    let mut idx: Vec<usize> = Vec::with_capacity(n);
    let (mut a, mut b) = (Vec::with_capacity(k), Vec::with_capacity(k));
    let mut sum = 0.0;
    for (&p, &q) in f.source.iter().zip(&f.target) {
        for (d, v) in d2.iter_mut().zip(&boundary.source) {
            *d = v.distance_squared(p);
        }
        idx.clear();
        idx.extend(0..n);
        idx.select_nth_unstable_by(k - 1, |&x, &y| d2[x].total_cmp(&d2[y]).then(x.cmp(&y)));
        a.clear();
        a.extend(idx[..k].iter().map(|&i| boundary.source[i]));
        b.clear();
        b.extend(idx[..k].iter().map(|&i| boundary.target[i]));
        let (predicted, spread) = orientation::similarity_apply(&a, &b, p);
        sum += predicted.distance(q) / spread.max(f64::MIN_POSITIVE);
    }
    sum / f.source.len().max(1) as f64
}

/// How many of the boundary's corresponded vertices nearest a feature measure its surroundings'
/// turn.
const LOCAL_TURN_VERTICES: usize = 24;

/// The turn of the surroundings of a feature: the best-fit rotation of the boundary vertices
/// nearest to the feature's centroid (source side), carried to their target twins.
fn local_turn(boundary: &CurvePair, feature: &[Point]) -> f64 {
    let c = crate::geometry::centroid(feature);
    let d: Vec<f64> = boundary.source.iter().map(|v| v.distance(c)).collect();
    let mut idx: Vec<usize> = (0..boundary.source.len()).collect();
    // The nearest, in order of distance then index (a total order: selecting them first and
    // sorting only those gives what sorting the whole boundary gave).
    let k = LOCAL_TURN_VERTICES
        .max(boundary.source.len() / 10)
        .min(idx.len());
    let by_distance = |x: &usize, y: &usize| d[*x].total_cmp(&d[*y]).then(x.cmp(y));
    if k > 0 && k < idx.len() {
        idx.select_nth_unstable_by(k - 1, by_distance);
    }
    idx.truncate(k);
    idx.sort_unstable_by(by_distance);
    let a: Vec<Point> = idx.iter().map(|&i| boundary.source[i]).collect();
    let b: Vec<Point> = idx.iter().map(|&i| boundary.target[i]).collect();
    orientation::best_fit_rotation(&a, &b)
}

/// The error for feature curve `id` of `here` without a twin in `there`; the hint names the
/// near miss in `there` when it has one (`Feature-eye` for `feature-eye`), or a feature there
/// without a twin here whose name is a typo of this one.
fn missing(id: &str, (here, ours): (&str, &Controls), (there, theirs): (&str, &Controls)) -> Error {
    let e = Error::at(here, id, format!("{id} is in {here} but not in {there}"));
    if let Some(n) = theirs.near_miss_of(id) {
        return e.with_hint(n.hint(there));
    }
    // A feature of the other file without a twin either, whose name is a typo of this one's
    // (`feature-vin`).
    let name = theirs
        .features
        .iter()
        .filter(|g| !ours.features.iter().any(|f| f.name == g.name))
        .map(|g| g.id.as_str())
        .find(|g| crate::drawing::resembles(g, id));
    match name {
        Some(g) => e.with_hint(format!(
            "{there} has '{g}' instead: give the two the same name"
        )),
        None => e.with_hint(format!("add {id} to {there} or remove it from {here}")),
    }
}

/// The error for anchor `id` of `here` without a twin in `there`, naming a near miss.
fn no_twin(id: &str, here: &str, (there, theirs): (&str, &Controls)) -> Error {
    let e = Error::at(here, id, format!("has no twin in {there}"));
    match theirs.near_miss_of(id) {
        Some(n) => e.with_hint(n.hint(there)),
        None => e.with_hint(format!("add {id} to {there} or remove it")),
    }
}

/// Both drawings have a boundary element, or neither has (both take their viewBox rectangle):
/// an outline paired with a rectangle is almost always a boundary missing from one file, or
/// misspelt there, and otherwise surfaces as an unrelated error much later (an anchor off its
/// curve, a mapping that folds).
fn check_boundaries(
    (src_file, src): (&str, &Controls),
    (tgt_file, tgt): (&str, &Controls),
) -> Result<()> {
    let (without, without_file, with_file) =
        match (src.boundary_from_view_box, tgt.boundary_from_view_box) {
            (true, false) => (src, src_file, tgt_file),
            (false, true) => (tgt, tgt_file, src_file),
            _ => return Ok(()),
        };
    let id = &without.boundary.id;
    let e = Error::input(
        without_file,
        format!("has no '{id}' element, but {with_file} has one"),
    );
    Err(match without.near_miss_of(id) {
        Some(n) => e.with_hint(n.hint(without_file)),
        None => e.with_hint(format!(
            "give {without_file} a '{id}' too, or remove {with_file}'s to morph the two viewBox rectangles"
        )),
    })
}

/// Names the drawings of an input error ([`Error::with_files`]).
fn name_files(err: Error, src_file: &str, tgt_file: &str) -> Error {
    err.with_files(src_file, tgt_file)
}

/// Vertex correspondence for one curve pair (§3, after \[15\]).
///
/// 1. Orientation: closed curves are made counter-clockwise; an open target is reversed when
///    that fits the source better (anchors decide when there are two or more, else a best-fit
///    similarity of arc-length resamplings).
/// 2. Anchors (`(source point, target point)`, already assigned to this curve) become forced
///    pairs at their nearest points, inserted as vertices.
/// 3. Salient points (curvature extrema at a scale) are associated by an order-preserving
///    dynamic-programming match between consecutive forced pairs — cyclic for a closed curve
///    without anchors, whose start then is the first associated pair.
/// 4. Between associated points both curves get the same number of vertices, each keeping all
///    of its own, with no edge longer than the density allows.
///
/// Errors use the file placeholders `<source>` / `<target>` (see [`Error::in_file`]).
pub fn correspond(
    src: &ControlCurve,
    tgt: &ControlCurve,
    anchors: &[(Point, Point)],
    tol: &Tolerances,
    opts: &CorrespondenceOptions,
) -> Result<CurvePair> {
    first_candidate(correspond_candidates(src, tgt, anchors, tol, opts)?)
}

/// The first (least turning) of a curve pair's candidate correspondences; an internal error,
/// not a panic, when there is none.
fn first_candidate(all: Vec<CurvePair>) -> Result<CurvePair> {
    all.into_iter()
        .next()
        .ok_or_else(|| Error::internal("correspondence: no candidate"))
}

/// [`correspond`] with every equally good correspondence of a closed curve without anchors whose
/// salient points match in several equally cheap ways (a shape with a half-turn symmetry, such
/// as an S, matches its twin started at either end): the first is the one [`correspond`]
/// returns (least turning), the others follow in order of turning. [`correspond_all`] lets the
/// features decide between them.
fn correspond_candidates(
    src: &ControlCurve,
    tgt: &ControlCurve,
    anchors: &[(Point, Point)],
    tol: &Tolerances,
    opts: &CorrespondenceOptions,
) -> Result<Vec<CurvePair>> {
    correspond_with(src, tgt, anchors, tol, opts, None)
}

/// [`correspond_candidates`], with an open target's direction forced when `reverse` is given
/// (`Some(true)`: reversed against its drawn direction) instead of chosen by anchors or shape.
fn correspond_with(
    src: &ControlCurve,
    tgt: &ControlCurve,
    anchors: &[(Point, Point)],
    tol: &Tolerances,
    opts: &CorrespondenceOptions,
    reverse: Option<bool>,
) -> Result<Vec<CurvePair>> {
    let a = clean(src, tol).map_err(|e| e.in_file(SRC))?;
    let b = clean(tgt, tol).map_err(|e| e.in_file(TGT))?;
    if src.closed != tgt.closed {
        return Err(Error::at(
            BOTH,
            &src.id,
            "is closed in one file and open in the other",
        ));
    }
    if let Some((p, q)) = anchors
        .iter()
        .find(|(p, q)| !p.is_finite() || !q.is_finite())
    {
        return Err(Error::at(
            BOTH,
            &src.id,
            format!("has an anchor out of range ({p} ↦ {q})"),
        ));
    }
    let closed = src.closed;
    let mut sp = Polyline::new(a, closed);
    let mut tp = Polyline::new(b, closed);
    if closed {
        sp = orientation::counter_clockwise(sp);
        tp = orientation::counter_clockwise(tp);
    }
    let project = |sp: &Polyline, tp: &Polyline| -> Vec<(f64, f64)> {
        anchors
            .iter()
            .map(|&(p, q)| (sp.project(p).1, tp.project(q).1))
            .collect()
    };
    if !closed {
        let pins = project(&sp, &tp);
        let reverse = match reverse.or_else(|| anchor_direction(&pins)) {
            Some(r) => r,
            None => orientation::open_target_reversed(&sp, &tp),
        };
        if reverse {
            tp = tp.reversed();
        }
    }
    let mut pins = project(&sp, &tp);
    pins.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
    let snap = tol.snap;
    let (sp2, src_idx) = sp.with_vertices_at(&pins.iter().map(|p| p.0).collect::<Vec<_>>(), snap);
    let (tp2, tgt_idx) = tp.with_vertices_at(&pins.iter().map(|p| p.1).collect::<Vec<_>>(), snap);
    let (mut sp, mut tp) = (sp2, tp2);
    let mut forced: Vec<(usize, usize)> = src_idx.into_iter().zip(tgt_idx).collect();
    let candidates: Vec<Candidate> = if closed && forced.is_empty() {
        cyclic_pairs(&sp, &tp, opts)
    } else {
        if closed {
            let (i, j) = forced[0];
            sp = sp.rotated(i);
            tp = tp.rotated(j);
            let (n, m) = (sp.len(), tp.len());
            for f in &mut forced {
                *f = ((f.0 + n - i) % n, (f.1 + m - j) % m);
            }
        } else {
            forced.insert(0, (0, 0));
            forced.push((sp.len() - 1, tp.len() - 1));
        }
        forced.dedup();
        if forced
            .windows(2)
            .any(|w| w[1].0 <= w[0].0 || w[1].1 <= w[0].1)
        {
            return Err(Error::at(
                BOTH,
                &src.id,
                "its anchors are in a different order along the curve in the two files",
            )
            .with_hint("check the anchor names, or remove crossing anchors"));
        }
        let pairs = spans_pairs(&sp, &tp, &forced, opts);
        vec![(sp, tp, pairs)]
    };
    candidates
        .into_iter()
        .map(|(sp, tp, pairs)| {
            let (source, target, salient) = resample::distribute(
                &sp,
                &tp,
                &pairs,
                opts.max_edge(tol),
                opts.merge_fraction * opts.max_edge(tol),
                snap,
            )
            .map_err(|e| match e {
                Error::Input(mut ie) => {
                    ie.element = Some(src.id.clone());
                    Error::Input(ie)
                }
                other => other,
            })?;
            Ok(CurvePair {
                id: src.id.clone(),
                kind: src.kind,
                closed,
                source,
                target,
                salient,
            })
        })
        .collect()
}

/// Whether anchors say the open target runs backwards: `Some(true)` when more anchor pairs are
/// in the opposite order than in the same order, `None` when they do not tell (fewer than two).
fn anchor_direction(pins: &[(f64, f64)]) -> Option<bool> {
    let (mut same, mut opposite) = (0usize, 0usize);
    for i in 0..pins.len() {
        for j in i + 1..pins.len() {
            let d = (pins[j].0 - pins[i].0) * (pins[j].1 - pins[i].1);
            if d > 0.0 {
                same += 1;
            } else if d < 0.0 {
                opposite += 1;
            }
        }
    }
    (same != opposite).then_some(opposite > same)
}

/// Salient-point association between consecutive forced pairs (rotated so the first is `(0, 0)`
/// on a closed curve): the forced pairs plus the matched salient points, in order.
fn spans_pairs(
    sp: &Polyline,
    tp: &Polyline,
    forced: &[(usize, usize)],
    opts: &CorrespondenceOptions,
) -> Vec<(usize, usize)> {
    let ss = salient::detect(sp, opts);
    let ts = salient::detect(tp, opts);
    let (hs, ht) = (salient::window(sp, opts), salient::window(tp, opts));
    let mut ends: Vec<(usize, usize, f64, f64)> = forced
        .iter()
        .map(|&(a, b)| (a, b, sp.s(a), tp.s(b)))
        .collect();
    if sp.closed() {
        ends.push((sp.len(), tp.len(), sp.length(), tp.length()));
    }
    let mut pairs = Vec::new();
    for w in ends.windows(2) {
        let ((a0, b0, s0, t0), (a1, b1, s1, t1)) = (w[0], w[1]);
        pairs.push((a0, b0));
        // Salient points closer than the window to a forced pair are suppressed by it, as a
        // weaker extremum is by a stronger one.
        let inside = |pts: &[Salient],
                      lo: usize,
                      hi: usize,
                      x0: f64,
                      x1: f64,
                      h: f64|
         -> (Vec<usize>, Vec<Mark>) {
            pts.iter()
                .filter(|p| p.index > lo && p.index < hi && p.s - x0 >= h && x1 - p.s >= h)
                .map(|p| {
                    (
                        p.index,
                        Mark {
                            u: (p.s - x0) / (x1 - x0),
                            turning: p.turning,
                            bearing: None,
                        },
                    )
                })
                .unzip()
        };
        let (si, sm) = inside(&ss, a0, a1, s0, s1, hs);
        let (ti, tm) = inside(&ts, b0, b1, t0, t1, ht);
        let (_, matched) = matching::associate_span(&sm, &tm, opts);
        pairs.extend(matched.into_iter().map(|(x, y)| (si[x], ti[y])));
    }
    if !sp.closed() {
        if let Some(&last) = forced.last() {
            pairs.push(last);
        }
    }
    pairs
}

/// Both curves re-started at a match's first pair, and the matched `(source, target)` vertex
/// index pairs.
type Candidate = (Polyline, Polyline, Vec<(usize, usize)>);

/// Cyclic association of a closed pair without anchors: the candidate matches, each as both
/// curves re-started at its first associated pair and the pairs; without any associable salient
/// point, the one candidate re-starts the target where it fits the source best
/// ([`orientation::best_closed_start`]).
///
/// Equally cheap matches (a square and a rotated square, an S and an S turned half round) are
/// all returned, distinct ones only, ordered by how well their matched points fit by scale and
/// translation alone: the correspondence that needs the least turning first.
fn cyclic_pairs(sp: &Polyline, tp: &Polyline, opts: &CorrespondenceOptions) -> Vec<Candidate> {
    let ss = salient::detect(sp, opts);
    let ts = salient::detect(tp, opts);
    let bearings = |line: &Polyline, pts: &[Salient]| -> Vec<f64> {
        if opts.outline_turn.is_none() {
            return Vec::new();
        }
        let c = crate::geometry::centroid(line.points());
        pts.iter()
            .map(|q| {
                let d = line.points()[q.index] - c;
                d.y.atan2(d.x)
            })
            .collect()
    };
    let (bs, bt) = (bearings(sp, &ss), bearings(tp, &ts));
    let found = matching::associate_cyclic(&ss, sp.length(), &ts, tp.length(), (&bs, &bt), opts);
    let mut scored: Vec<(f64, Vec<(usize, usize)>)> = Vec::new();
    for pairs in found {
        // The same match started at another of its pairs is the same correspondence.
        let mut key = pairs.clone();
        key.sort_unstable();
        if scored.iter().any(|(_, p)| {
            let mut k = p.clone();
            k.sort_unstable();
            k == key
        }) {
            continue;
        }
        let a: Vec<Point> = pairs
            .iter()
            .map(|&(x, _)| sp.points()[ss[x].index])
            .collect();
        let b: Vec<Point> = pairs
            .iter()
            .map(|&(_, y)| tp.points()[ts[y].index])
            .collect();
        scored.push((
            orientation::turn_residual(&a, &b, opts.outline_turn.or(opts.preferred_rotation)),
            pairs,
        ));
    }
    // Stable: equal residuals keep the match order.
    scored.sort_by(|x, y| x.0.total_cmp(&y.0));
    if scored.is_empty() {
        let j =
            orientation::best_closed_start(sp, tp, opts.outline_turn.or(opts.preferred_rotation));
        return vec![(sp.clone(), tp.rotated(j), vec![(0, 0)])];
    }
    let (n, m) = (sp.len(), tp.len());
    scored
        .into_iter()
        .map(|(_, pairs)| {
            let (i, j) = (ss[pairs[0].0].index, ts[pairs[0].1].index);
            let out = pairs
                .iter()
                .map(|&(x, y)| ((ss[x].index + n - i) % n, (ts[y].index + m - j) % m))
                .collect();
            (sp.rotated(i), tp.rotated(j), out)
        })
        .collect()
}

/// A curve's points checked and cleaned: finite and within range, consecutive points closer than
/// the snap tolerance merged (and a closed curve's repeated first point dropped); errors for a
/// degenerate curve, located at its id (file left to the caller).
fn clean(curve: &ControlCurve, tol: &Tolerances) -> Result<Vec<Point>> {
    let err = |problem: String| Error::at("", &curve.id, problem);
    if let Some(p) = curve
        .points
        .iter()
        .find(|p| !p.is_finite() || p.abs().max_element() > MAX_COORDINATE)
    {
        return Err(err(format!("has a point out of range ({}, {})", p.x, p.y)));
    }
    let mut pts: Vec<Point> = Vec::with_capacity(curve.points.len());
    for &p in &curve.points {
        if pts.last().is_none_or(|q| q.distance(p) > tol.snap) {
            pts.push(p);
        }
    }
    if curve.closed {
        while pts.len() > 1 && pts[pts.len() - 1].distance(pts[0]) <= tol.snap {
            pts.pop();
        }
    }
    if pts.len() < 2 {
        return Err(err("has fewer than 2 distinct points".into()));
    }
    if curve.closed && pts.len() < 3 {
        return Err(err("is closed but has fewer than 3 distinct points".into()));
    }
    if crate::geometry::polyline_length(&pts, curve.closed) <= tol.snap {
        return Err(err("has zero length".into()));
    }
    if curve.closed && crate::geometry::polygon_area(&pts).abs() <= tol.snap * tol.diagonal {
        return Err(err("is closed but encloses no area".into()));
    }
    Ok(pts)
}
