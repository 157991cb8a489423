//! Automatic mode: icon and logo transitions from plain SVGs with no markup (issues #6 and #7;
//! the paper leaves the extraction of feature curves to future work).
//!
//! When neither drawing has a `boundary` or any `feature-NAME`, crmorph makes the control
//! geometry itself, one CR-Morph problem per shape:
//!
//! 1. [`contours`](mod@contours): every filled path's region by its fill rule — overlapping
//!    subpaths merged, self-crossings resolved — as shapes (an outline and its holes), and
//!    every stroke-only path's centre lines.
//! 2. [`matching`]: outlines pair with outlines and strokes with strokes, as many as can
//!    (an optimal assignment on position, size and elongation); holes pair within paired
//!    outlines.
//! 3. [`part`]: each pair of outlines is its own problem — the outline is the boundary, the
//!    paired holes are feature curves — climbing a ladder from the paper's compatible
//!    triangulation (§5) down to one that always exists, so a pair always morphs as one shape.
//!    A pair of strokes moves as a chain of discs along its centre line.
//! 4. `union`: the shapes' meshes become one pair of meshes with
//!    [`crate::mesh::Parts`], plus a still frame that artwork outside every shape is bound to.
//!    The disc-based rigid interpolation moves the shapes as one figure (their centroids along
//!    the barycenter mesh's rigid path, §5 Fig. 9, and their turns on one branch).
//! 5. [`geometric`]: each source path and target path whose shapes pair morph as one path
//!    ([`crate::morphing`]);
//!    shapes without a partner grow out of or shrink into the nearest paired shape, holes
//!    without one close or open, and only what cannot morph (groups with opacity, images,
//!    dashed strokes) is warped and blended.

pub mod contours;
pub mod geometric;
pub mod matching;
pub mod part;
mod union;

use crate::artwork::{Item, Scene};
use crate::compatible::{common_tolerances, Compatible, MorphOptions};
use crate::drawing::Drawing;
use crate::error::Result;
use crate::geometry::Point;
use contours::{contours, Contour, ContourKind};
use part::{build_part, PartInputs, PartMesh, PartPlan, Rung};

/// Shape pairs the report names before it counts the rest.
const SHOWN: usize = 6;

/// Padding of the still frame around the two view boxes, as a fraction of their larger side.
const PADDING: f64 = 0.05;

/// A shape without a partner farther than this fraction of the drawing's diagonal from every
/// paired shape grows or shrinks where it is instead of into one of them.
const HOST_REACH: f64 = 0.25;

/// How one pair of shapes morphs.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeReport {
    /// The source shape, named as a user would: its element's id, or "path N at (x, y)".
    pub source: String,
    /// The target shape.
    pub target: String,
    /// The rung of the ladder its compatible meshes come from ([`part`]).
    pub rung: Rung,
}

/// A shape with no partner, and what it does.
#[derive(Debug, Clone, PartialEq)]
pub struct LoneReport {
    /// The shape, named as a user would.
    pub shape: String,
    /// A source shape (it shrinks away) rather than a target shape (it grows).
    pub shrinks: bool,
    /// The paired shape it shrinks into or grows out of; `None`: in place.
    pub host: Option<String>,
}

/// What automatic mode did, for the user.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AutoReport {
    /// Contours found in the source and the target.
    pub contours: (usize, usize),
    /// Every pair of shapes (outlines with their holes, or strokes) that morph into each other.
    pub shapes: Vec<ShapeReport>,
    /// Shapes without a partner.
    pub lone: Vec<LoneReport>,
    /// Artwork paths that morph as one shape ([`geometric`]).
    pub morphing: Vec<crate::morphing::MorphingPath>,
    /// Paths (source and target) with a paired shape that still cross-fade: their paint does
    /// not interpolate, they are not plain paths (a group with opacity or a clip, a dashed
    /// stroke), or their paint order differs between the drawings.
    pub blended: usize,
    /// Paths far outside the view, cut at the edge of its reach or left out
    /// ([`crate::artwork::within_reach`]), one phrase each ("path 3 at (1e5, 185) lies far
    /// outside the view: left out").
    pub far: Vec<String>,
}

impl std::fmt::Display for AutoReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "automatic mode: {} source and {} target contours; {} shape{} morph",
            self.contours.0,
            self.contours.1,
            self.shapes.len(),
            if self.shapes.len() == 1 { "" } else { "s" }
        )?;
        // One line however many shapes: the first few pairs by name, then a count.
        for (k, s) in self.shapes.iter().take(SHOWN).enumerate() {
            let sep = if k == 0 { " (" } else { "; " };
            write!(f, "{sep}{} → {}: {}", s.source, s.target, s.rung)?;
        }
        if self.shapes.len() > SHOWN {
            write!(f, "; {} more", self.shapes.len() - SHOWN)?;
        }
        if !self.shapes.is_empty() {
            f.write_str(")")?;
        }
        // Shapes without a partner, grouped by what they do and where.
        let mut groups: Vec<(bool, Option<&String>, Vec<&String>)> = Vec::new();
        for l in &self.lone {
            match groups
                .iter_mut()
                .find(|g| g.0 == l.shrinks && g.1 == l.host.as_ref())
            {
                Some(g) => g.2.push(&l.shape),
                None => groups.push((l.shrinks, l.host.as_ref(), vec![&l.shape])),
            }
        }
        for (shrinks, host, shapes) in groups {
            let one = shapes.len() == 1;
            let who = if one {
                shapes[0].clone()
            } else {
                format!("{} shapes", shapes.len())
            };
            let verb = match (shrinks, one) {
                (true, true) => "shrinks",
                (true, false) => "shrink",
                (false, true) => "grows",
                (false, false) => "grow",
            };
            match host {
                Some(h) if shrinks => write!(f, "; {who} {verb} into {h}")?,
                Some(h) => write!(f, "; {who} {verb} out of {h}")?,
                None => write!(f, "; {who} {verb} in place")?,
            }
        }
        match self.blended {
            0 => {}
            1 => f.write_str("; 1 path cross-fades")?,
            n => write!(f, "; {n} paths cross-fade")?,
        }
        for far in self.far.iter().take(SHOWN) {
            write!(f, "; {far}")?;
        }
        if self.far.len() > SHOWN {
            write!(
                f,
                "; {} more paths far outside the view",
                self.far.len() - SHOWN
            )?;
        }
        Ok(())
    }
}

/// Whether a drawing carries no control geometry of its own (no boundary, no feature curve).
pub fn is_unmarked(d: &Drawing) -> bool {
    d.controls.boundary_from_view_box && d.controls.features.is_empty()
}

/// A shape without a partner: its outline (or stroke) and holes, on one side, and the paired
/// shape it grows out of or shrinks into.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Lone {
    /// Index of the outline (or stroke) contour.
    pub(crate) contour: usize,
    /// Its holes.
    pub(crate) holes: Vec<usize>,
    /// A source shape (shrinking) rather than a target shape (growing).
    pub(crate) source: bool,
    /// The index of the part it goes into or comes out of, and the point in that part's rest
    /// shape (source side for a source shape) it shrinks into; `None`: in place, about its own
    /// centroid.
    pub(crate) host: Option<(usize, Point)>,
}

/// Everything automatic mode matched, for [`geometric`]: the parts (pairs of shapes) with
/// their meshes, where they sit in the union, and the shapes without a partner.
#[derive(Debug, Clone)]
pub(crate) struct Matched {
    pub(crate) plans: Vec<PartPlan>,
    pub(crate) parts: Vec<PartMesh>,
    pub(crate) curve_offset: Vec<usize>,
    pub(crate) lone: Vec<Lone>,
}

/// Gives two unmarked drawings automatic control geometry from their artwork scenes and builds
/// their compatible triangulation: one per pair of shapes, joined with a still frame
/// (module docs). Every pair of shapes morphs; errors only on degenerate input.
///
/// Returns the meshes, the report, and the two drawings.
pub fn build_auto(
    source: &Drawing,
    target: &Drawing,
    source_scene: &Scene,
    target_scene: &Scene,
    opts: &MorphOptions,
) -> Result<(Compatible, AutoReport, Drawing, Drawing)> {
    // Far-away artwork cut to the reach of the view (`artwork::within_reach`), so that no
    // stage below works in proportion to its coordinates.
    let (source_scene, far_s) = crate::artwork::within_reach(source_scene);
    let (target_scene, far_t) = crate::artwork::within_reach(target_scene);
    let (source_scene, target_scene) = (&source_scene, &target_scene);
    let tol = source.tolerances.flatten.min(target.tolerances.flatten);
    let (cs, ct) = (
        contours(source_scene, tol, &source.policy.limits)?,
        contours(target_scene, tol, &target.policy.limits)?,
    );
    for (d, c) in [(source, &cs), (target, &ct)] {
        let limits = &d.policy.limits;
        if c.len() > limits.shapes {
            let what = format!("{} shapes to pair in automatic mode", c.len());
            return Err(crate::input::Limit::Shapes.exceeded(&d.file, &what, limits));
        }
    }
    let diagonal = source.tolerances.diagonal.max(target.tolerances.diagonal);
    let pairs = matching::match_shapes(&cs, &ct, diagonal);
    let mut plans: Vec<PartPlan> = pairs
        .iter()
        .filter(|&&(a, _)| cs[a].kind != ContourKind::Hole)
        .map(|&(a, b)| PartPlan {
            source: a,
            target: b,
            holes: pairs
                .iter()
                .filter(|&&(h, g)| cs[h].parent == Some(a) && ct[g].parent == Some(b))
                .copied()
                .collect(),
        })
        .collect();
    // Larger shapes first: they are the hosts of shapes without a partner and lead the report.
    plans.sort_by(|x, y| {
        cs[y.source]
            .area
            .max(cs[y.source].length * 1e-9)
            .total_cmp(&cs[x.source].area.max(cs[x.source].length * 1e-9))
            .then(x.source.cmp(&y.source))
    });
    let step = source.tolerances.max_edge.min(target.tolerances.max_edge) * 0.5;
    check_vertex_budget(&plans, &cs, &ct, step, source, target, opts)?;
    let inputs = PartInputs {
        source,
        target,
        opts,
        step,
        figure_turn: figure_turn(&plans, &cs, &ct, diagonal),
    };
    // A part's set-up (triangulation, mapping, fold checks) takes milliseconds even for a
    // small shape: two parts are worth rayon's threads, one alone is not.
    let work = if plans.len() > 1 {
        crate::parallel::MIN_WORK
    } else {
        0
    };
    let built: Vec<Result<PartMesh>> =
        crate::parallel::map(&plans, work, |plan| build_part(plan, &cs, &ct, &inputs));
    // A pair whose outlines cannot even be corresponded (degenerate) is not a pair: its shapes
    // grow and shrink instead.
    let mut parts = Vec::with_capacity(built.len());
    let mut kept = Vec::with_capacity(built.len());
    for (plan, b) in plans.into_iter().zip(built) {
        match b {
            Ok(m) => {
                parts.push(m);
                kept.push(plan);
            }
            Err(e) => log::debug!("automatic mode: pair {plan:?} left unpaired: {e}"),
        }
    }
    let plans = kept;
    let frame = still_frame(source_scene, target_scene);
    let (meshes, curve_pairs, placed) = union::union(&parts, frame);
    let lone = lone_shapes(&cs, &ct, &plans, &parts, diagonal);
    let area_region: Vec<[u32; 3]> = meshes
        .triangles
        .iter()
        .zip(
            &meshes
                .parts
                .as_ref()
                .map(|p| p.of_triangle.clone())
                .unwrap_or_default(),
        )
        .filter(|(_, &k)| k as usize != parts.len())
        .map(|(t, _)| *t)
        .collect();
    let stats = crate::mapping::MappingStats {
        vertices: meshes.source.len(),
        triangles: meshes.triangles.len(),
        ..Default::default()
    };
    let matched = Matched {
        plans,
        parts,
        curve_offset: placed.curve_offset,
        lone,
    };
    let morphing =
        geometric::morphing_paths(source_scene, target_scene, &cs, &ct, &matched, &meshes);
    // Paths with a paired shape that no morphing path draws: they cross-fade.
    let blended = {
        let drawn = |source: bool, item: usize| {
            morphing.iter().any(|p| {
                let (mine, covers) = if source {
                    (p.source_item, &p.covers.0)
                } else {
                    (p.target_item, &p.covers.1)
                };
                mine == Some(item) || covers.contains(&item)
            })
        };
        let mut s: Vec<usize> = matched.plans.iter().map(|p| cs[p.source].path).collect();
        let mut t: Vec<usize> = matched.plans.iter().map(|p| ct[p.target].path).collect();
        s.sort_unstable();
        s.dedup();
        t.sort_unstable();
        t.dedup();
        s.iter().filter(|&&i| !drawn(true, i)).count()
            + t.iter().filter(|&&j| !drawn(false, j)).count()
    };
    let name_s = |c: usize| shape_name(source_scene, &cs, c);
    let name_t = |c: usize| shape_name(target_scene, &ct, c);
    let report = AutoReport {
        contours: (cs.len(), ct.len()),
        shapes: matched
            .plans
            .iter()
            .zip(&matched.parts)
            .map(|(p, m)| ShapeReport {
                source: name_s(p.source),
                target: name_t(p.target),
                rung: m.rung,
            })
            .collect(),
        lone: matched
            .lone
            .iter()
            .map(|l| LoneReport {
                shape: if l.source {
                    name_s(l.contour)
                } else {
                    name_t(l.contour)
                },
                shrinks: l.source,
                host: l.host.map(|(k, _)| {
                    let p = &matched.plans[k];
                    if l.source {
                        name_s(p.source)
                    } else {
                        name_t(p.target)
                    }
                }),
            })
            .collect(),
        morphing,
        blended,
        far: far_s
            .iter()
            .map(|f| far_note(source_scene, f))
            .chain(far_t.iter().map(|f| far_note(target_scene, f)))
            .collect(),
    };
    let c = Compatible {
        meshes,
        pairs: curve_pairs,
        stats,
        tolerances: common_tolerances(source, target, opts.density),
        area_region: Some(area_region),
    };
    Ok((c, report, source.clone(), target.clone()))
}

/// A part's side for [`crate::budget::mesh_vertices`]: its outline, then its holes.
fn part_side(c: &[Contour], outline: usize, holes: Vec<usize>) -> Vec<(&[Point], bool)> {
    std::iter::once(outline)
        .chain(holes)
        .map(|k| (&c[k].points[..], c[k].closed))
        .collect()
}

/// Refuses, before any part is built, shape pairs whose meshes would pass the vertex budget
/// in all ([`crate::budget`]): each part's curves densified at `step` and corresponded at its
/// own tolerances, and its inside refined.
fn check_vertex_budget(
    plans: &[PartPlan],
    cs: &[Contour],
    ct: &[Contour],
    step: f64,
    source: &Drawing,
    target: &Drawing,
    opts: &MorphOptions,
) -> Result<()> {
    let diagonal = source.tolerances.diagonal.max(target.tolerances.diagonal);
    let mut total = 0.0;
    for p in plans {
        let tol = part::part_tolerances(&cs[p.source], &ct[p.target], diagonal, opts.density);
        let edge = tol.max_edge.min(step);
        let tol = crate::tolerance::Tolerances {
            max_edge: edge,
            ..tol
        };
        let s = part_side(cs, p.source, p.holes.iter().map(|h| h.0).collect());
        let t = part_side(ct, p.target, p.holes.iter().map(|h| h.1).collect());
        total += crate::budget::mesh_vertices(&s, &t, &tol);
    }
    let files = format!("{} → {}", source.file, target.file);
    crate::budget::check(total, opts.density, &files, &source.policy.limits)
}

/// The best-fit turn of the paired outlines' centroids from source to target, when there are
/// two or more and they are spread out (beyond a tenth of the diagonal from their mean): how
/// the figure as a whole turns.
fn figure_turn(plans: &[PartPlan], cs: &[Contour], ct: &[Contour], diagonal: f64) -> Option<f64> {
    let closed: Vec<&PartPlan> = plans
        .iter()
        .filter(|p| cs[p.source].closed && ct[p.target].closed)
        .collect();
    if closed.len() < 2 {
        return None;
    }
    let a: Vec<Point> = closed.iter().map(|p| cs[p.source].centroid).collect();
    let b: Vec<Point> = closed.iter().map(|p| ct[p.target].centroid).collect();
    let f = crate::geometry::SimilarityFit::new(&a, &b);
    let spread = |s: f64| (s / closed.len() as f64).sqrt();
    (spread(f.from_spread) > 0.1 * diagonal && spread(f.to_spread) > 0.1 * diagonal)
        .then(|| f.rotation())
}

/// The still frame: both view boxes' union, padded.
fn still_frame(a: &Scene, b: &Scene) -> (Point, Point) {
    let lo = a.view_box.0.min(b.view_box.0);
    let hi = a.view_box.1.max(b.view_box.1);
    let pad = PADDING * (hi - lo).max_element().max(1e-9);
    (lo - Point::splat(pad), hi + Point::splat(pad))
}

/// The shapes (outlines and strokes) that no part pairs, each with the paired shape it goes
/// into or comes out of: the part whose outline on its side is nearest, within
/// [`HOST_REACH`] of the diagonal, and there the point of its outline (or centre line) nearest
/// the lone shape's centre — so that the shape slides into the host's edge as it shrinks
/// rather than across the host.
fn lone_shapes(
    cs: &[Contour],
    ct: &[Contour],
    plans: &[PartPlan],
    parts: &[PartMesh],
    diagonal: f64,
) -> Vec<Lone> {
    let mut out = Vec::new();
    for (contours, source) in [(cs, true), (ct, false)] {
        let paired = |c: usize| {
            plans
                .iter()
                .any(|p| if source { p.source == c } else { p.target == c })
        };
        for (c, contour) in contours.iter().enumerate() {
            if contour.kind == ContourKind::Hole || paired(c) {
                continue;
            }
            let holes: Vec<usize> = (0..contours.len())
                .filter(|&h| contours[h].parent == Some(c))
                .collect();
            let mut best: Option<(f64, usize)> = None;
            for (k, p) in plans.iter().enumerate() {
                let _ = &parts[k];
                let host = &contours[if source { p.source } else { p.target }];
                // Strokes go into strokes, filled shapes into filled shapes.
                if (host.kind == ContourKind::Stroke) != (contour.kind == ContourKind::Stroke) {
                    continue;
                }
                let d = gap(contour, host);
                if d <= HOST_REACH * diagonal && best.is_none_or(|(bd, _)| d < bd) {
                    best = Some((d, k));
                }
            }
            let host = best.map(|(_, k)| {
                let p = &plans[k];
                let outline = &contours[if source { p.source } else { p.target }];
                (k, nearest_on(outline, contour.centroid))
            });
            out.push(Lone {
                contour: c,
                holes,
                source,
                host,
            });
        }
    }
    out
}

/// The point of `c`'s polyline nearest to `p`.
fn nearest_on(c: &Contour, p: Point) -> Point {
    let n = c.points.len();
    let edges = if c.closed { n } else { n.saturating_sub(1) };
    let mut best = (f64::INFINITY, c.points[0]);
    for i in 0..edges {
        let (a, b) = (c.points[i], c.points[(i + 1) % n]);
        let (d, u) = crate::geometry::point_segment_distance(p, a, b);
        if d < best.0 {
            best = (d, a + (b - a) * u);
        }
    }
    best.1
}

/// The smallest distance between the points of two contours (0 when one's first point is
/// inside the other's outline).
fn gap(a: &Contour, b: &Contour) -> f64 {
    if b.closed && crate::geometry::point_in_polygon(a.points[0], &b.points) {
        return 0.0;
    }
    let n = b.points.len();
    let edges = if b.closed { n } else { n.saturating_sub(1) };
    a.points
        .iter()
        .map(|&p| {
            (0..edges)
                .map(|i| {
                    crate::geometry::point_segment_distance(p, b.points[i], b.points[(i + 1) % n]).0
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min)
}

/// What [`crate::artwork::within_reach`] did to one path of `scene`, for the report: the path
/// named as [`shape_name`] names paths (its id, or "path N"), where it is, and what was done.
fn far_note(scene: &Scene, far: &crate::artwork::FarPath) -> String {
    let items = scene.items();
    let id = match items.get(far.item) {
        Some(Item::Path(p)) => p.id.clone(),
        _ => String::new(),
    };
    let name = if id.is_empty() {
        let n = items[..far.item.min(items.len())]
            .iter()
            .filter(|i| matches!(i, Item::Path(_)))
            .count()
            + 1;
        format!("path {n}")
    } else {
        format!("'{}'", crate::error::printable(&id))
    };
    let num = |x: f64| {
        if x.abs() < 1e6 {
            format!("{x:.0}")
        } else {
            format!("{x:.1e}")
        }
    };
    if far.not_finite {
        format!("{name} has a coordinate that is not finite: left out")
    } else if far.left_out {
        format!(
            "{name} at ({}, {}) lies far outside the view: left out",
            num(far.at.x),
            num(far.at.y)
        )
    } else {
        format!(
            "{name} at ({}, {}) reaches far outside the view: cut off there",
            num(far.at.x),
            num(far.at.y)
        )
    }
}

/// A shape named as a user would name it: its element's id (with where it is when the element
/// has several shapes), or "path N at (x, y)" (N counting the drawing's paths from 1).
pub(crate) fn shape_name(scene: &Scene, contours: &[Contour], c: usize) -> String {
    let contour = &contours[c];
    let items = scene.items();
    let id = match items.get(contour.path) {
        Some(Item::Path(p)) => p.id.clone(),
        _ => String::new(),
    };
    let at = format!("({:.0}, {:.0})", contour.centroid.x, contour.centroid.y);
    let siblings = contours
        .iter()
        .filter(|o| o.path == contour.path && o.kind != ContourKind::Hole)
        .count();
    let what = if contour.kind == ContourKind::Stroke {
        "stroke"
    } else {
        "shape"
    };
    if id.is_empty() {
        let n = items[..contour.path.min(items.len())]
            .iter()
            .filter(|i| matches!(i, Item::Path(_)))
            .count()
            + 1;
        if siblings > 1 {
            format!("path {n}'s {what} at {at}")
        } else {
            format!("path {n} at {at}")
        }
    } else if siblings > 1 {
        format!("'{}' {what} at {at}", crate::error::printable(&id))
    } else {
        format!("'{}'", crate::error::printable(&id))
    }
}

#[cfg(test)]
mod tests;
