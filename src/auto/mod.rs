//! Automatic mode: icon and logo transitions from plain SVGs with no markup (issue #6; the paper
//! leaves the extraction of feature curves to future work).
//!
//! When neither drawing has a `boundary` or any `feature-NAME`, crmorph makes the control
//! geometry itself:
//! - the domain boundary is the viewBox rectangle of each drawing, padded by 5 % of its larger
//!   side so that artwork touching the edge stays inside;
//! - the artwork's contours ([`contours`]: fill outlines, their holes, stroke centre lines) are
//!   matched across the drawings ([`matching`]) and every matched pair becomes a feature curve
//!   `feature-auto-K` in both;
//! - a pair that cannot be a feature — it crosses another feature, itself, or the boundary, or the
//!   composite mapping cannot keep it flip-free (the paper's Fig.16) — is dropped, the fewest
//!   needed, and reported; its artwork is still warped and blended. The morph never fails
//!   because of a feature it chose itself.

pub mod contours;
pub mod matching;

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
    /// Feature names made, with the source and target contour indices.
    pub features: Vec<(String, usize, usize)>,
    /// Features dropped, with the reason.
    pub dropped: Vec<(String, String)>,
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
    for (k, &(a, b)) in pairs.iter().enumerate() {
        let name = format!("auto-{k}");
        s.controls.features.push(feature(&name, &cs[a]));
        t.controls.features.push(feature(&name, &ct[b]));
        report.features.push((name, a, b));
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
                drop_feature(&mut s, &mut t, &mut report, &name, &e);
            }
        }
    }
    // Map; a failure names curves: drop the smallest feature it names (or the smallest of all)
    // and try again.
    loop {
        match build(&s, &t, opts) {
            Ok(c) => return Ok((c, report, s, t)),
            Err(e) => {
                if s.controls.features.is_empty() {
                    return Err(e);
                }
                let name = named_feature(&e, &s).unwrap_or_else(|| smallest(&s));
                drop_feature(&mut s, &mut t, &mut report, &name, &e);
            }
        }
    }
}

fn feature(name: &str, c: &Contour) -> ControlCurve {
    ControlCurve {
        id: format!("feature-{name}"),
        name: name.to_string(),
        kind: CurveKind::Feature,
        closed: c.closed,
        points: c.points.clone(),
    }
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
        *p = c + Point::new(
            d.x + pad * d.x.signum(),
            d.y + pad * d.y.signum(),
        );
    }
}

/// The feature of `d` an error names (longest matching name, so `auto-12` beats `auto-1`).
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
        .max_by_key(|f| f.id.len())
        .map(|f| f.name.clone())
}

/// The name of the feature with the shortest outline.
fn smallest(d: &Drawing) -> String {
    let len = |c: &ControlCurve| -> f64 {
        c.points
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .sum()
    };
    d.controls
        .features
        .iter()
        .min_by(|a, b| len(a).total_cmp(&len(b)))
        .map(|f| f.name.clone())
        .unwrap_or_default()
}

fn drop_feature(s: &mut Drawing, t: &mut Drawing, report: &mut AutoReport, name: &str, why: &Error) {
    s.controls.features.retain(|f| f.name != name);
    t.controls.features.retain(|f| f.name != name);
    report.features.retain(|f| f.0 != name);
    let reason = match why {
        Error::Input(i) => i.problem.clone(),
        other => other.to_string(),
    };
    report.dropped.push((name.to_string(), reason));
}
