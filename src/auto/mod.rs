//! Automatic mode: icon and logo transitions from plain SVGs with no markup (issue #6; the paper
//! leaves the extraction of feature curves to future work).
//!
//! When neither drawing has a `boundary` or any `feature-NAME`, crmorph makes the control
//! geometry itself:
//! - the domain boundary is the viewBox rectangle of each drawing, padded by 5 % of its larger
//!   side so that artwork touching the edge stays inside;
//! - the artwork's contours ([`contours`](mod@contours): fill outlines, their holes, stroke centre lines) are
//!   matched across the drawings ([`matching`]) and every matched pair becomes a feature curve
//!   `feature-auto-K` in both;
//! - a pair that cannot be a feature — it crosses another feature, itself, or the boundary, or the
//!   composite mapping cannot keep it flip-free (the paper's Fig.16) — is dropped, the fewest
//!   needed, and reported; its artwork is still warped and blended. The morph never fails
//!   because of a feature it chose itself.

pub mod contours;
pub mod geometric;
pub mod matching;
mod seed;

use crate::artwork::Scene;
use crate::compatible::{build, Compatible, MorphOptions};
use crate::drawing::{ControlCurve, Drawing};
use crate::error::{Error, Result};
use crate::geometry::Point;
use crate::mesh::CurveKind;
use contours::{contours, Contour};

/// Padding of the automatic boundary around the viewBox, as a fraction of its larger side.
const PADDING: f64 = 0.05;

/// What automatic mode did, for the user.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AutoReport {
    /// Contours found in the source and the target.
    pub contours: (usize, usize),
    /// Feature names made, with the source and target contour indices (`usize::MAX` for a seed:
    /// a hole closing to, or opening from, a small spot).
    pub features: Vec<(String, usize, usize)>,
    /// Features dropped, with the reason.
    pub dropped: Vec<(String, String)>,
    /// Artwork paths that morph as one shape ([`geometric`]).
    pub morphing: Vec<geometric::MorphingPath>,
}

impl std::fmt::Display for AutoReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "automatic mode: {} source and {} target contours, {} matched as feature curves",
            self.contours.0,
            self.contours.1,
            self.features.len()
        )?;
        let seeds = self
            .features
            .iter()
            .filter(|f| f.1 == usize::MAX || f.2 == usize::MAX)
            .count();
        if seeds > 0 {
            write!(f, " ({seeds} of them holes closing or opening)")?;
        }
        if !self.morphing.is_empty() {
            write!(f, "; {} paths morph as one shape", self.morphing.len())?;
        }
        for (name, why) in &self.dropped {
            write!(f, "; dropped feature-{name} ({why})")?;
        }
        Ok(())
    }
}

/// Whether a drawing carries no control geometry of its own (no boundary, no feature curve).
pub fn is_unmarked(d: &Drawing) -> bool {
    d.controls.boundary_from_view_box && d.controls.features.is_empty()
}

/// Gives two unmarked drawings automatic control geometry from their artwork scenes and builds
/// their compatible triangulation, dropping features that cannot be kept. Errors only when even
/// the boundaries alone cannot be mapped.
pub fn build_auto(
    source: &Drawing,
    target: &Drawing,
    source_scene: &Scene,
    target_scene: &Scene,
    opts: &MorphOptions,
) -> Result<(Compatible, AutoReport, Drawing, Drawing)> {
    let (mut s, mut t) = (source.clone(), target.clone());
    pad_boundary(&mut s);
    pad_boundary(&mut t);
    let tol = s.tolerances.flatten.min(t.tolerances.flatten);
    let (cs, ct) = (contours(source_scene, tol), contours(target_scene, tol));
    let diagonal = s.tolerances.diagonal.max(t.tolerances.diagonal);
    let pairs = matching::match_contours(&cs, &ct, diagonal);
    let mut report = AutoReport {
        contours: (cs.len(), ct.len()),
        ..AutoReport::default()
    };
    // Straight runs are split finely, so that the correspondence may start a closed contour
    // anywhere along them, not only at a corner (a circle → square pair would otherwise turn by
    // the angle to the nearest corner).
    let step = s.tolerances.max_edge.min(t.tolerances.max_edge) * 0.5;
    for (k, &(a, b)) in pairs.iter().enumerate() {
        let name = format!("auto-{k}");
        s.controls.features.push(feature(&name, &cs[a], step));
        t.controls.features.push(feature(&name, &ct[b], step));
        report.features.push((name, a, b));
    }
    // A hole with no partner inside a matched outline closes to a small spot (or opens from
    // one): a seed contour on the other side, where the outline pair carries the hole's centre.
    let mut k = report.features.len();
    for (holes, others, forward) in [(&cs, &ct, true), (&ct, &cs, false)] {
        for (h, hole) in holes.iter().enumerate() {
            let Some(parent) = hole.parent else { continue };
            let taken = report
                .features
                .iter()
                .any(|f| if forward { f.1 == h } else { f.2 == h });
            let partner = report.features.iter().find_map(|f| {
                let (mine, theirs) = if forward { (f.1, f.2) } else { (f.2, f.1) };
                (mine == parent).then_some(theirs)
            });
            let (Some(other_parent), false) = (partner, taken) else {
                continue;
            };
            let (pa, pb) = (&holes[parent], &others[other_parent]);
            let scale = (pb.area / pa.area.max(1e-300)).sqrt();
            let want = pb.centroid + (hole.centroid - pa.centroid) * scale;
            let their_holes: Vec<&Contour> = others
                .iter()
                .filter(|c| c.parent == Some(other_parent))
                .collect();
            let Some((centre, room)) = seed::seed_place(pb, &their_holes, want) else {
                continue;
            };
            let floor = 4.0 * s.tolerances.snap.max(t.tolerances.snap);
            let radius = (0.15 * (hole.area / std::f64::consts::PI).sqrt() * scale)
                .min(room)
                .max(floor);
            let seed = seed::seed_circle(centre, radius, hole.points.len().clamp(12, 64));
            let name = format!("auto-{k}");
            k += 1;
            let real = feature(&name, hole, step);
            let spot = ControlCurve {
                points: seed,
                ..real.clone()
            };
            if forward {
                s.controls.features.push(real);
                t.controls.features.push(spot);
                report.features.push((name, h, usize::MAX));
            } else {
                s.controls.features.push(spot);
                t.controls.features.push(real);
                report.features.push((name, usize::MAX, h));
            }
        }
    }
    // Drop features that break the layout rules (crossing, outside, self-crossing).
    loop {
        let err = crate::drawing::check_layout(&s.controls, &s.file)
            .and_then(|_| crate::drawing::check_layout(&t.controls, &t.file));
        match err {
            Ok(()) => break,
            Err(e) => {
                let Some(name) = named_feature(&e, &s) else {
                    return Err(e);
                };
                drop_feature(&mut s, &mut t, &mut report, (&cs, &ct), &name, &e);
            }
        }
    }
    // Map; a failure names curves: drop the smallest feature it names (or the smallest of all)
    // and try again.
    loop {
        // The disc interpolation must be able to run on the result too (no coincident
        // neighbouring vertices): checked here, so that a feature it cannot take is dropped.
        // It must also move without folding: frames at eighths of the morph are checked, and
        // a feature whose alignment makes the interpolation fold is dropped like one the
        // mapping cannot keep.
        let built = build(&s, &t, opts).and_then(|c| {
            let m = &c.meshes;
            let interp = crate::rigid::Interpolator::new(
                crate::rigid::Method::Disc,
                &m.source,
                &m.target,
                &m.triangles,
            )?;
            let ts: Vec<f64> = (1..8).map(|i| i as f64 / 8.0).collect();
            for (t, f) in ts.iter().zip(interp.frames(&ts)) {
                let folded = crate::mesh::count_inverted(&m.triangles, &f);
                if folded > 0 {
                    return Err(Error::input(
                        "<auto>",
                        format!("the rigid interpolation folds {folded} triangles at t = {t}"),
                    ));
                }
            }
            Ok(c)
        });
        match built {
            Ok(mut c) => {
                c.area_region = covered_region(&c.meshes, &report, (&cs, &ct));
                report.morphing = geometric::morphing_paths(
                    source_scene,
                    target_scene,
                    &cs,
                    &ct,
                    &report.features,
                    &c.meshes,
                );
                return Ok((c, report, s, t));
            }
            Err(e) => {
                if s.controls.features.is_empty() {
                    return Err(e);
                }
                let name = named_feature(&e, &s).unwrap_or_else(|| smallest(&s));
                drop_feature(&mut s, &mut t, &mut report, (&cs, &ct), &name, &e);
            }
        }
    }
}

/// The triangles inside any closed outline or stroke feature (holes ignored) in the source mesh: the
/// region the matched artwork covers, whose area the disc method keeps
/// ([`Compatible::area_region`]). Holes are left in because a hole closing or opening changes
/// the artwork's area without any part of it growing: a ring becoming a disc keeps its outer
/// circle. `None` without closed outline features.
fn covered_region(
    m: &crate::mesh::CompatibleMeshes,
    report: &AutoReport,
    (cs, ct): (&[Contour], &[Contour]),
) -> Option<Vec<[u32; 3]>> {
    let outline = |name: &str| {
        report.features.iter().any(|f| {
            format!("feature-{}", f.0) == name && {
                let c = if f.1 != usize::MAX {
                    cs.get(f.1)
                } else {
                    ct.get(f.2)
                };
                c.is_some_and(|c| c.kind != contours::ContourKind::Hole)
            }
        })
    };
    let rings: Vec<Vec<Point>> = m
        .curves
        .iter()
        .filter(|c| c.closed && c.kind == CurveKind::Feature && outline(&c.name))
        .map(|c| c.vertices.iter().map(|&v| m.source[v as usize]).collect())
        .collect();
    let inside: Vec<[u32; 3]> = m
        .triangles
        .iter()
        .filter(|t| {
            let c = t.iter().map(|&v| m.source[v as usize]).sum::<Point>() / 3.0;
            rings
                .iter()
                .any(|r| crate::geometry::point_in_polygon(c, r))
        })
        .copied()
        .collect();
    (!inside.is_empty()).then_some(inside)
}

fn feature(name: &str, c: &Contour, step: f64) -> ControlCurve {
    ControlCurve {
        id: format!("feature-{name}"),
        name: name.to_string(),
        kind: CurveKind::Feature,
        closed: c.closed,
        points: densify(&c.points, c.closed, step),
    }
}

/// `points` with every edge longer than `step` split evenly.
fn densify(points: &[Point], closed: bool, step: f64) -> Vec<Point> {
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

/// Pads the viewBox boundary of an unmarked drawing (a rectangle) about its centre.
fn pad_boundary(d: &mut Drawing) {
    let pts = &mut d.controls.boundary.points;
    let Some((lo, hi)) = crate::geometry::bounding_box(pts.iter().copied()) else {
        return;
    };
    let c = (lo + hi) * 0.5;
    let pad = PADDING * (hi - lo).max_element();
    for p in pts.iter_mut() {
        let d = *p - c;
        *p = c + Point::new(d.x + pad * d.x.signum(), d.y + pad * d.y.signum());
    }
}

/// The feature of `d` an error names (longest matching name, so `auto-12` beats `auto-1`).
/// The feature an error names that is cheapest to lose: of the features whose ids the message
/// mentions (two for a crossing), the one with the shortest outline, so that of a small part
/// touching a large one the large one keeps its crisp morph. Ties go to the one listed last.
fn named_feature(e: &Error, d: &Drawing) -> Option<String> {
    let text = e.to_string();
    d.controls
        .features
        .iter()
        .filter(|f| {
            text.match_indices(&f.id).any(|(i, _)| {
                !text[i + f.id.len()..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_digit())
            })
        })
        .rev()
        .min_by(|a, b| outline_length(a).total_cmp(&outline_length(b)))
        .map(|f| f.name.clone())
}

/// Length of a control curve's polyline (closing edge left out).
fn outline_length(c: &ControlCurve) -> f64 {
    c.points.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// The name of the feature with the shortest outline.
fn smallest(d: &Drawing) -> String {
    d.controls
        .features
        .iter()
        .min_by(|a, b| outline_length(a).total_cmp(&outline_length(b)))
        .map(|f| f.name.clone())
        .unwrap_or_default()
}

fn drop_feature(
    s: &mut Drawing,
    t: &mut Drawing,
    report: &mut AutoReport,
    (cs, ct): (&[Contour], &[Contour]),
    name: &str,
    why: &Error,
) {
    let pair = report.features.iter().find(|f| f.0 == name).cloned();
    s.controls.features.retain(|f| f.name != name);
    t.controls.features.retain(|f| f.name != name);
    report.features.retain(|f| f.0 != name);
    let reason = match why {
        Error::Input(i) => i.problem.clone(),
        other => other.to_string(),
    };
    report.dropped.push((name.to_string(), reason));
    // A hole closing to a seed, or opening from one, only means something inside its outline's
    // morph: with the outline's feature gone, its seeds go too.
    let Some((_, a, b)) = pair else { return };
    let orphans: Vec<String> = report
        .features
        .iter()
        .filter(|f| {
            (f.2 == usize::MAX && cs.get(f.1).and_then(|c| c.parent) == Some(a) && a != usize::MAX)
                || (f.1 == usize::MAX
                    && ct.get(f.2).and_then(|c| c.parent) == Some(b)
                    && b != usize::MAX)
        })
        .map(|f| f.0.clone())
        .collect();
    for orphan in orphans {
        let why = Error::input("<auto>", format!("its outline feature-{name} was dropped"));
        drop_feature(s, t, report, (cs, ct), &orphan, &why);
    }
}
