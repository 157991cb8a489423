//! One matched pair of shapes as its own CR-Morph problem (issue #7, item 1).
//!
//! A shape is an outline with its holes. Its outline is the boundary of the problem and its
//! matched holes are feature curves inside it, so the mesh covers the shape and nothing else —
//! the paper's setting (§3), where the boundary is the shape's own outline. Each pair climbs a
//! ladder until a rung gives compatible meshes that the disc-based rigid interpolation moves
//! without folding:
//!
//! 1. the paper's compatible triangulation (CDT of one side, composite harmonic mapping through
//!    the barycenter-based shape model, §5) with every matched hole aligned; then from the
//!    other side (Fig. 12); then with holes given up one at a time, the smallest or the one the
//!    failure names first;
//! 2. the triangulation that always exists: both outlines triangulated, embedded in a disc and
//!    overlaid ([`crate::mapping::overlay`]), outline only;
//! 3. last, the outline alone, corresponded and moved as a closed chain of discs with no
//!    interior mesh (intrinsic-like: edge lengths and turning angles interpolate).
//!
//! Holes that are not aligned as features still morph inside the shape (see
//! [`super::geometric`]): carried by the mesh and blended along their own correspondence.

use crate::compatible::{
    build_accepted_from, checked_curve_pairs, Compatible, MorphOptions, MotionChecked,
};
use crate::correspondence::{correspond, CorrespondenceOptions, Correspondences, CurvePair};
use crate::drawing::{Anchor, ControlCurve, Drawing};
use crate::error::{Error, ProblemKind, Result};
use crate::geometry::Point;
use crate::mapping::{Attachments, MappingOptions};
use crate::mesh::{CompatibleMeshes, CurveKind, MeshCurve, Side};
use crate::rigid::{DiscSetup, Interpolator, Repair};
use crate::tolerance::Tolerances;

use super::contours::Contour;

/// Which rung of the ladder (module docs) gave a shape pair its compatible meshes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rung {
    /// The paper's compatible triangulation (§5) with `features` holes aligned, side
    /// `triangulated` triangulated and mapped onto the other (Fig. 12: the target).
    Mapped {
        /// The side that was triangulated.
        triangulated: Side,
        /// Matched holes aligned as feature curves.
        features: usize,
    },
    /// Both outlines' triangulations embedded in a common disc and overlaid: compatible by
    /// construction ([`crate::mapping::overlay`]).
    Overlay,
    /// No interior mesh: the outline moves as a chain of discs.
    Outline,
    /// A stroke: its centre line moves as a chain of discs.
    Stroke,
}

impl std::fmt::Display for Rung {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Rung::Mapped {
                triangulated,
                features,
            } => {
                f.write_str("composite harmonic mapping")?;
                if *triangulated == Side::Target {
                    f.write_str(" from the target")?;
                }
                match features {
                    0 => Ok(()),
                    1 => f.write_str(", 1 hole aligned"),
                    n => write!(f, ", {n} holes aligned"),
                }
            }
            Rung::Overlay => f.write_str("overlaid disc embeddings"),
            Rung::Outline => f.write_str("outline only, no interior mesh"),
            Rung::Stroke => f.write_str("centre line"),
        }
    }
}

/// A matched shape pair: outline contours and matched holes (indices into each drawing's
/// contours).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PartPlan {
    /// The source outline.
    pub(crate) source: usize,
    /// The target outline.
    pub(crate) target: usize,
    /// Matched holes `(source hole, target hole)`.
    pub(crate) holes: Vec<(usize, usize)>,
}

/// A shape pair's compatible meshes (its own vertex numbering) and how they were made.
#[derive(Debug, Clone)]
pub(crate) struct PartMesh {
    /// The meshes: curve 0 is the outline; then the aligned holes. No triangles on the
    /// [`Rung::Outline`] rung.
    pub(crate) meshes: CompatibleMeshes,
    /// The curve pairs of `meshes.curves`.
    pub(crate) pairs: Vec<CurvePair>,
    /// The rung taken.
    pub(crate) rung: Rung,
    /// Matched holes aligned as features, with their curve index in `meshes.curves`.
    pub(crate) features: Vec<((usize, usize), usize)>,
    /// Whether its frames need the disc interpolation's fold repair (`rigid::repair`).
    pub(crate) repair: bool,
}

/// What a part's problem is built from: the two drawings (for file names and settings), the
/// morph options, the anchors, and the tolerances of the part.
pub(crate) struct PartInputs<'a> {
    pub(crate) source: &'a Drawing,
    pub(crate) target: &'a Drawing,
    pub(crate) opts: &'a MorphOptions,
    /// Extra vertex spacing along straight runs (see [`densify`]).
    pub(crate) step: f64,
    /// The turn of the whole figure (the best-fit turn of the paired outlines' centroids), when
    /// it has several spread-out parts: a symmetric part takes it (`quality::shape_turn_near`).
    pub(crate) figure_turn: Option<f64>,
}

/// The tolerances of a part: relative to its own size, so that a small part gets a mesh as
/// fine relative to itself as a large one, but not finer than a quarter of the drawing
/// (tiny parts keep their flattened outline vertices and a coarse interior).
pub(crate) fn part_tolerances(
    a: &Contour,
    b: &Contour,
    drawing_diagonal: f64,
    density: f64,
) -> Tolerances {
    let size = |c: &Contour| {
        crate::geometry::bounding_box(c.points.iter().copied())
            .map_or(0.0, |(lo, hi)| lo.distance(hi))
    };
    let d = size(a).max(size(b)).max(0.25 * drawing_diagonal);
    Tolerances::new(d, density)
}

/// A contour as a control curve.
fn curve(id: &str, kind: CurveKind, c: &Contour, step: f64) -> ControlCurve {
    ControlCurve {
        id: id.to_string(),
        name: id.strip_prefix("feature-").unwrap_or(id).to_string(),
        kind,
        closed: c.closed,
        points: densify(&c.points, c.closed, step),
    }
}

/// `points` with every edge longer than `step` split evenly: straight runs get vertices along
/// them, so that the correspondence may start a closed contour anywhere on them, not only at a
/// corner (a circle → square pair would otherwise turn by the angle to the nearest corner).
pub(crate) fn densify(points: &[Point], closed: bool, step: f64) -> Vec<Point> {
    let n = points.len();
    let edges = if closed { n } else { n.saturating_sub(1) };
    let mut out = Vec::with_capacity(n);
    for i in 0..edges {
        let (a, b) = (points[i], points[(i + 1) % n]);
        let k = if step > 0.0 {
            ((a.distance(b) / step).ceil() as usize).clamp(1, 10_000)
        } else {
            1
        };
        for j in 0..k {
            out.push(a + (b - a) * (j as f64 / k as f64));
        }
    }
    if !closed {
        if let Some(&last) = points.last() {
            out.push(last);
        }
    }
    out
}

/// The anchors of `d` that pin a curve of this part: within reach of the source outline or a
/// hole (`curves`).
fn anchors_near(anchors: &[Anchor], curves: &[&Contour], reach: f64) -> Vec<Anchor> {
    anchors
        .iter()
        .filter(|a| {
            curves.iter().any(|c| {
                let n = c.points.len();
                (0..n).any(|i| {
                    crate::geometry::point_segment_distance(
                        a.point,
                        c.points[i],
                        c.points[(i + 1) % n],
                    )
                    .0 <= reach
                })
            })
        })
        .cloned()
        .collect()
}

/// The most harmonic maps one walk of a part's composite mapping may take (accepted or
/// rejected) before that path counts as failed, in place of the library's 2048: a part has
/// rungs below to fall to, and a walk that crawls with ever shorter steps mostly ends below
/// the smallest step anyway, after the dearest maps of the whole ladder (issue 16: one such
/// walk took 291 maps, 60 % of the CPU of the slowest corpus pair, and failed). On the random
/// icon corpora (seeds 2026 and 7, 640 pairs), no walk that reached its end took more than 99.
const PART_MAX_MAPS: usize = 128;

/// The mapping options of a part's ladder: `mapping` with at most [`PART_MAX_MAPS`] maps per
/// walk (a lower setting is kept).
fn part_mapping(mapping: MappingOptions) -> MappingOptions {
    mapping.with_max_steps(mapping.max_steps.min(PART_MAX_MAPS))
}

/// Builds the compatible meshes of one matched shape pair, climbing the ladder of the module
/// docs. Errors only when even the outline alone cannot be corresponded (a degenerate
/// outline).
pub(crate) fn build_part(
    plan: &PartPlan,
    cs: &[Contour],
    ct: &[Contour],
    inputs: &PartInputs<'_>,
) -> Result<PartMesh> {
    let (a, b) = (&cs[plan.source], &ct[plan.target]);
    let diagonal = inputs
        .source
        .tolerances
        .diagonal
        .max(inputs.target.tolerances.diagonal);
    let tol = part_tolerances(a, b, diagonal, inputs.opts.density);
    // The shapes' own turn steers the outline's correspondence, so that the morph does not
    // spin where neither end is turned (issue #7, item 7).
    let mut opts = inputs.opts.clone();
    opts.mapping = part_mapping(opts.mapping);
    if a.closed && b.closed {
        opts.correspondence.outline_turn = Some(crate::quality::shape_turn_near(
            &a.points,
            &b.points,
            inputs.figure_turn.unwrap_or(0.0),
        ));
    }
    let inputs = &PartInputs {
        opts: &opts,
        ..*inputs
    };
    let reach = inputs.opts.correspondence.anchor_reach * diagonal;
    let drawing =
        |d: &Drawing, outline: &Contour, holes: Vec<(&str, &Contour)>, others: &[&Contour]| {
            let mut d = d.clone();
            d.tolerances = tol;
            d.controls.boundary = curve("boundary", CurveKind::Boundary, outline, inputs.step);
            d.controls.boundary_from_view_box = false;
            d.controls.features = holes
                .iter()
                .map(|(id, h)| curve(id, CurveKind::Feature, h, inputs.step))
                .collect();
            d.controls.features.sort_by(|x, y| x.name.cmp(&y.name));
            let mut near: Vec<&Contour> = vec![outline];
            near.extend(others.iter().copied());
            d.controls.anchors = anchors_near(&d.controls.anchors, &near, reach);
            d.controls.skeleton.clear();
            d
        };
    // Rung 1: the paper's mapping, holes given up one at a time (strokes have no inside).
    let stroke = a.kind == super::contours::ContourKind::Stroke;
    let mut holes: Vec<(usize, usize)> = plan.holes.clone();
    // Every rung corresponds the same outline and holes, and every map attaches the same holes
    // to the same outline.
    let correspondences = &mut Correspondences::default();
    let made = &mut Attachments::default();
    loop {
        if stroke {
            break;
        }
        let names: Vec<String> = (0..holes.len())
            .map(|k| format!("feature-hole-{k}"))
            .collect();
        let hs: Vec<&Contour> = holes.iter().map(|&(h, _)| &cs[h]).collect();
        let ht: Vec<&Contour> = holes.iter().map(|&(_, h)| &ct[h]).collect();
        let s = drawing(
            inputs.source,
            a,
            names
                .iter()
                .map(String::as_str)
                .zip(hs.iter().copied())
                .collect(),
            &hs,
        );
        let t = drawing(
            inputs.target,
            b,
            names
                .iter()
                .map(String::as_str)
                .zip(ht.iter().copied())
                .collect(),
            &ht,
        );
        // Anchors must pin the same names on both sides.
        let keep: Vec<String> = s
            .controls
            .anchors
            .iter()
            .filter(|x| t.controls.anchors.iter().any(|y| y.name == x.name))
            .map(|x| x.name.clone())
            .collect();
        let (mut s, mut t) = (s, t);
        s.controls.anchors.retain(|x| keep.contains(&x.name));
        t.controls.anchors.retain(|x| keep.contains(&x.name));
        let mut failure: Option<Error> = None;
        // One correspondence for both sides: it does not depend on the side triangulated, so
        // where it fails, both would.
        let corresponded = match checked_curve_pairs(&s, &t, inputs.opts, correspondences) {
            Ok(pairs) => Some(pairs),
            Err(e) => {
                log::debug!("part {}→{}: {e}", plan.source, plan.target);
                failure = Some(e);
                None
            }
        };
        let sides = corresponded
            .iter()
            .flat_map(|p| [(Side::Source, p), (Side::Target, p)]);
        for (triangulated, pairs) in sides {
            let mut o = inputs.opts.clone();
            o.triangulated = triangulated;
            let checked =
                build_accepted_from(&s, &t, &o, pairs.clone(), made, moves_without_folding);
            match checked {
                Ok((c, NeedsRepair(repair))) => {
                    let features = holes
                        .iter()
                        .enumerate()
                        .filter_map(|(k, &h)| {
                            let id = format!("feature-hole-{k}");
                            c.meshes
                                .curves
                                .iter()
                                .position(|m| m.name == id)
                                .map(|i| (h, i))
                        })
                        .collect::<Vec<_>>();
                    return Ok(PartMesh {
                        rung: Rung::Mapped {
                            triangulated,
                            features: features.len(),
                        },
                        features,
                        pairs: c.pairs,
                        meshes: c.meshes,
                        repair,
                    });
                }
                Err(e) => {
                    log::debug!("part {}→{}: {e}", plan.source, plan.target);
                    failure.get_or_insert(e);
                }
            }
        }
        if holes.is_empty() {
            break;
        }
        // Give up the hole the failure concerns (the last of them): one that crosses, is
        // unusable itself, or that the mapping folds near. Else the smallest.
        let curves = match failure.as_ref().and_then(|e| e.kind().map(|k| (e, k))) {
            Some((
                e,
                ProblemKind::Element | ProblemKind::Crossing | ProblemKind::NoFlipFreeMapping,
            )) => e.curves(),
            _ => &[],
        };
        let named = (0..holes.len())
            .rev()
            .find(|k| curves.contains(&format!("feature-hole-{k}")));
        let k = named.unwrap_or_else(|| {
            (0..holes.len())
                .min_by(|&x, &y| cs[holes[x].0].length.total_cmp(&cs[holes[y].0].length))
                .unwrap_or(0)
        });
        holes.remove(k);
    }
    // Rungs 2 and 3 work on the outline alone.
    let s = drawing(inputs.source, a, Vec::new(), &[]);
    let t = drawing(inputs.target, b, Vec::new(), &[]);
    let copts = CorrespondenceOptions {
        density: 1.0,
        ..inputs.opts.correspondence.clone()
    };
    let pins: Vec<(Point, Point)> = s
        .controls
        .anchors
        .iter()
        .filter_map(|x| {
            t.controls
                .anchors
                .iter()
                .find(|y| y.name == x.name)
                .map(|y| (x.point, y.point))
        })
        .collect();
    let outline = correspond(
        &s.controls.boundary,
        &t.controls.boundary,
        &pins,
        &tol,
        &copts,
    )
    .map_err(|e| e.in_file(format!("{} → {}", inputs.source.file, inputs.target.file)))?;
    let overlaid = if stroke {
        None
    } else {
        match crate::mapping::overlay::compatible_outlines(&outline, &tol) {
            Ok(m) => Some(m),
            Err(e) => {
                log::debug!("overlay of {}→{}: {e}", plan.source, plan.target);
                None
            }
        }
    };
    if let Some(m) = overlaid {
        let c = Compatible {
            meshes: m,
            pairs: vec![outline.clone()],
            stats: Default::default(),
            tolerances: tol,
            area_region: None,
        };
        let r = moves_without_folding(&c, None);
        if let Err(e) = &r {
            log::debug!(
                "overlay of {}→{} ({} vertices): {e}",
                plan.source,
                plan.target,
                c.meshes.source.len()
            );
        }
        if let Ok(NeedsRepair(repair)) = r {
            return Ok(PartMesh {
                meshes: c.meshes,
                pairs: c.pairs,
                rung: Rung::Overlay,
                features: Vec::new(),
                repair,
            });
        }
    }
    let n = outline.source.len() as u32;
    let meshes = CompatibleMeshes {
        triangles: Vec::new(),
        source: outline.source.clone(),
        target: outline.target.clone(),
        curves: vec![MeshCurve {
            name: outline.id.clone(),
            kind: CurveKind::Boundary,
            closed: outline.closed,
            vertices: (0..n).collect(),
        }],
        parts: None,
    };
    Ok(PartMesh {
        meshes,
        pairs: vec![outline],
        rung: if stroke { Rung::Stroke } else { Rung::Outline },
        features: Vec::new(),
        repair: false,
    })
}

/// Frames checked for folds at a time ([`moves_without_folding`]): enough to keep the cores
/// busy, few enough that a failing mesh stops early.
const FOLD_CHUNK: usize = 4;

/// The times [`moves_without_folding`] reads plain frames at: t = k/16, k = 1…15.
fn plain_check_times() -> Vec<f64> {
    (1..16).map(|i| i as f64 / 16.0).collect()
}

/// What [`moves_without_folding`] found: whether the mesh's frames need the fold repair.
#[derive(Debug, Clone, Copy)]
struct NeedsRepair(bool);

/// A mesh that needs no repair inverted no triangle in any plain frame the check read.
impl MotionChecked for NeedsRepair {
    fn unfolded_at(&self) -> Vec<f64> {
        if self.0 {
            Vec::new()
        } else {
            plain_check_times()
        }
    }
}

/// Checks that the disc-based rigid interpolation of `c` inverts no triangle at t = k/16
/// (k = 1…15), and with the fold repair of `rigid::repair` when the plain frames fold a few, at
/// t = k/64 (repaired folds come and go between samples): a mesh whose frames fold even so is
/// no better than a failed mapping. Returns whether the repair is needed. `motion` is the
/// disc interpolation of `c` as [`Compatible::interpolator`] sets it up, when the caller has
/// it: the checks read its frames without the repair, and with the repair of free vertices
/// only, instead of setting up two more.
fn moves_without_folding(c: &Compatible, motion: Option<&Interpolator>) -> Result<NeedsRepair> {
    let m = &c.meshes;
    let ts = plain_check_times();
    // The first sample (in the order given) whose frame folds: a few frames at a time, in
    // parallel, stopping at the first chunk with a fold, so a mesh that fails costs a few
    // frames, not all of them.
    let folds = |interp: &Interpolator, repair: Repair, ts: &[f64]| -> Option<(f64, usize)> {
        ts.chunks(FOLD_CHUNK).find_map(|chunk| {
            chunk
                .iter()
                .zip(interp.frames_repairing(chunk, repair))
                .map(|(&t, f)| (t, crate::mesh::count_inverted(&m.triangles, &f)))
                .find(|&(_, n)| n > 0)
        })
    };
    // The disc interpolation with the repair of free vertices (curve vertices held), read
    // without it for the plain frames. Set up here unless the caller has it.
    let own;
    let motion = match motion {
        Some(m) => m,
        None => {
            let mut on_curve = vec![false; m.source.len()];
            for &v in m.curves.iter().flat_map(|c| &c.vertices) {
                on_curve[v as usize] = true;
            }
            own = Interpolator::disc(
                &m.source,
                &m.target,
                &DiscSetup {
                    triangles: &m.triangles,
                    repair: Some((&m.triangles, &on_curve)),
                    ..Default::default()
                },
            )?;
            &own
        }
    };
    let Some((t, folded)) = folds(motion, Repair::Off, &ts) else {
        return Ok(NeedsRepair(false));
    };
    // Nearest the plain fold first: where a repair fails, it fails there.
    let mut fine: Vec<f64> = (1..64).map(|i| i as f64 / 64.0).collect();
    fine.sort_by(|a, b| (a - t).abs().total_cmp(&(b - t).abs()).then(a.total_cmp(b)));
    match folds(motion, Repair::FreeOnly, &fine) {
        None => Ok(NeedsRepair(true)),
        Some((t2, left)) => Err(Error::input(
            "<auto>",
            format!(
                "the rigid interpolation folds {folded} triangles at t = {t} ({left} at t = {t2} \
                 after repair)"
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parts_walks_take_at_most_the_part_cap_or_a_lower_setting() {
        let default = MappingOptions::default();
        assert!(default.max_steps > PART_MAX_MAPS);
        assert_eq!(part_mapping(default).max_steps, PART_MAX_MAPS);
        let lower = default.with_max_steps(40);
        assert_eq!(part_mapping(lower).max_steps, 40);
        // Everything else is the caller's.
        let other = default.with_min_step(1e-3).with_initial_steps(6);
        let capped = part_mapping(other);
        assert_eq!(capped.with_max_steps(other.max_steps), other);
    }
}
