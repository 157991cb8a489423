//! Matched artwork morphing as one shape (issue #6, item 3): when every contour of a source path
//! is a feature curve whose partners are every contour of one target path, the two paths are
//! drawn as a single path whose outline is those feature curves in the frame's mesh, with the
//! fill and stroke colours interpolated in Oklab and opacities and widths linearly — a crisp
//! geometric transition, not two shapes cross-fading.
//!
//! Gradients interpolate too (module `paint`): their stops, and their geometry carried along by
//! the outline's motion.
//!
//! A hole with no partner on the other side closes (or opens) inside the morphing path: its
//! outline — its seed feature curve when it has one, else its points carried by the mesh — is
//! shrunk about its centre by `1 − t` (or grown by `t` for a hole of the target), so at t = 1
//! it is a point and nothing pops. The mesh keeps it inside the outline (the outline is a
//! feature curve, which no triangle crosses), so the hole never leaks out of the shape. Why
//! not a fade: a fading hole is a translucent patch mid-morph; a closing one keeps the shape
//! crisp, which is what a designer animates by hand (and what shape tweens cannot do, since
//! they need equal contour counts).
//!
//! Only plain paths qualify: solid or gradient fills and strokes (a gradient facing a colour
//! or a gradient of the same kind), no dashes, no shaped pen, and no ancestor group with
//! opacity or a clip. Anything else keeps the warp-and-blend of the rest of the artwork.

mod paint;

use super::contours::{Contour, ContourKind};
use crate::artwork::{Fill, Group, Item, Location, Paint, PathItem, PointLocator, Scene, Stroke};
use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;
use kurbo::{Affine, BezPath};
use paint::{compatible, fitted_affine, mix_paint};

/// A source path and a target path that morph as one shape.
#[derive(Debug, Clone, PartialEq)]
pub struct MorphingPath {
    /// Index of the source path in `source_scene.items()`.
    pub source_item: usize,
    /// Index of the target path in `target_scene.items()`.
    pub target_item: usize,
    /// Indices into the meshes' curves of the outline's contours, in the source path's order.
    pub curves: Vec<usize>,
    /// The source path's paint (for colours, opacities, widths, caps and joins).
    source: PathItem,
    /// The target path's paint.
    target: PathItem,
    /// The source scene's root transform: its root user space (where the path and its
    /// gradients live) → the mesh's space.
    source_root: Affine,
    /// The same for the target scene.
    target_root: Affine,
    /// Holes closing (source holes without a partner) or opening (target holes without one).
    holes: Vec<ShrinkingHole>,
}

/// A hole of a morphing path that has no partner: it closes to a point (a source hole) or
/// opens from one (a target hole) about its centre (module docs).
#[derive(Debug, Clone, PartialEq)]
struct ShrinkingHole {
    outline: HoleOutline,
    /// A source hole (size `1 − t`) rather than a target hole (size `t`).
    closing: bool,
}

/// Where a shrinking hole's outline comes from in a frame.
#[derive(Debug, Clone, PartialEq)]
enum HoleOutline {
    /// A feature curve of the meshes (a hole matched to a seed spot).
    Curve(usize),
    /// Points bound to the source mesh (closing) or the target mesh (opening).
    Bound(Vec<Location>),
}

impl ShrinkingHole {
    /// The hole's outline at `t` in the frame's mesh `vertices`, sized about its centre.
    fn at(&self, meshes: &CompatibleMeshes, vertices: &[Point], t: f64) -> Vec<Point> {
        let pts: Vec<Point> = match &self.outline {
            HoleOutline::Curve(c) => meshes.curves[*c]
                .vertices
                .iter()
                .map(|&v| vertices[v as usize])
                .collect(),
            HoleOutline::Bound(locs) => locs
                .iter()
                .map(|l| l.place(&meshes.triangles, vertices))
                .collect(),
        };
        let size = if self.closing { 1.0 - t } else { t };
        let centre = crate::geometry::centroid(&pts);
        pts.into_iter()
            .map(|p| centre + (p - centre) * size)
            .collect()
    }
}

impl MorphingPath {
    /// The path at `t` whose mesh is `vertices`.
    pub fn at(&self, meshes: &CompatibleMeshes, vertices: &[Point], t: f64) -> PathItem {
        let mut path = BezPath::new();
        for &c in &self.curves {
            let curve = &meshes.curves[c];
            for (k, &v) in curve.vertices.iter().enumerate() {
                let p = vertices[v as usize];
                let q = kurbo::Point::new(p.x, p.y);
                if k == 0 {
                    path.move_to(q);
                } else {
                    path.line_to(q);
                }
            }
            if curve.closed {
                path.close_path();
            }
        }
        // Every frame has the same subpaths (the animated SVG animates one `d`); a hole of
        // size 0 paints nothing.
        for hole in &self.holes {
            let pts = hole.at(meshes, vertices, t);
            for (k, p) in pts.iter().enumerate() {
                let q = kurbo::Point::new(p.x, p.y);
                if k == 0 {
                    path.move_to(q);
                } else {
                    path.line_to(q);
                }
            }
            path.close_path();
        }
        let lerp = |a: f64, b: f64| a + (b - a) * t;
        // Gradients ride with the outline: each side's by the affine map that best carries
        // its rest outline to the outline at t.
        let gradients = [&self.source, &self.target].iter().any(|p| {
            let g = |x: &Paint| matches!(x, Paint::Gradient(_));
            p.fill.as_ref().is_some_and(|f| g(&f.paint))
                || p.stroke.as_ref().is_some_and(|s| g(&s.paint))
        });
        let (source_map, target_map) = if gradients {
            let outline = |mesh: &[Point]| -> Vec<Point> {
                self.curves
                    .iter()
                    .flat_map(|&c| meshes.curves[c].vertices.iter().map(|&v| mesh[v as usize]))
                    .collect()
            };
            let now = outline(vertices);
            (
                fitted_affine(&outline(&meshes.source), &now) * self.source_root,
                fitted_affine(&outline(&meshes.target), &now) * self.target_root,
            )
        } else {
            (self.source_root, self.target_root)
        };
        let colour = |a: &Paint, b: &Paint| mix_paint(a, b, t, source_map, target_map);
        let fill = match (&self.source.fill, &self.target.fill) {
            (Some(a), Some(b)) => Some(Fill {
                paint: colour(&a.paint, &b.paint),
                opacity: lerp(a.opacity, b.opacity),
                even_odd: true,
            }),
            _ => None,
        };
        let stroke = match (&self.source.stroke, &self.target.stroke) {
            (Some(a), Some(b)) => Some(Stroke {
                paint: colour(&a.paint, &b.paint),
                opacity: lerp(a.opacity, b.opacity),
                width: lerp(a.width, b.width),
                miter_limit: lerp(a.miter_limit, b.miter_limit),
                ..a.clone()
            }),
            _ => None,
        };
        PathItem {
            id: self.source.id.clone(),
            path,
            fill,
            stroke,
            stroke_first: self.source.stroke_first,
        }
    }
}

/// The scene of morphing paths `paths` at frame `t` (one [`crate::render::Layer::Over`] of
/// the stack [`crate::export::Morph`] paints), at `vertices`, in paint order,
/// with `header`'s view and transform.
pub fn overlay_at(
    paths: &[MorphingPath],
    meshes: &CompatibleMeshes,
    vertices: &[Point],
    t: f64,
    header: &Scene,
) -> Scene {
    Scene {
        file: header.file.clone(),
        view_box: header.view_box,
        size: header.size,
        // Feature curves are already in the root's user space after its transform.
        root_transform: kurbo::Affine::IDENTITY,
        root: Group {
            id: String::new(),
            opacity: 1.0,
            clip: None,
            children: paths
                .iter()
                .map(|p| Item::Path(p.at(meshes, vertices, t)))
                .collect(),
        },
    }
}

/// Every item of `scene.items()` with whether it may morph as one shape: a filled or stroked
/// path with no dashes or shaped pen, under groups without opacity or clip (whether its paints
/// interpolate with its partner's is checked per pair).
fn plain_paths(scene: &Scene) -> Vec<Option<PathItem>> {
    fn walk(g: &Group, plain: bool, out: &mut Vec<Option<PathItem>>) {
        for c in &g.children {
            match c {
                Item::Group(sub) => {
                    out.push(None);
                    walk(sub, plain && sub.opacity == 1.0 && sub.clip.is_none(), out);
                }
                Item::Path(p) => {
                    let ok = plain
                        && p.stroke
                            .as_ref()
                            .is_none_or(|s| s.dashes.is_empty() && s.frame.is_none())
                        && (p.fill.is_some() || p.stroke.is_some());
                    out.push(ok.then(|| p.clone()));
                }
                Item::Image(_) => out.push(None),
            }
        }
    }
    let mut out = Vec::new();
    walk(&scene.root, scene.root.opacity == 1.0, &mut out);
    out
}

/// The morphing paths among matched contours. `pairs` are the features made, `(name, source
/// contour, target contour)`; their mesh curves are named `feature-NAME`.
pub(crate) fn morphing_paths(
    source_scene: &Scene,
    target_scene: &Scene,
    cs: &[Contour],
    ct: &[Contour],
    pairs: &[(String, usize, usize)],
    meshes: &CompatibleMeshes,
) -> Vec<MorphingPath> {
    let (ps, pt) = (plain_paths(source_scene), plain_paths(target_scene));
    let curve_of = |name: &str| {
        meshes
            .curves
            .iter()
            .position(|c| c.name == format!("feature-{name}"))
    };
    let locators = (
        PointLocator::new(&meshes.source, &meshes.triangles).ok(),
        PointLocator::new(&meshes.target, &meshes.triangles).ok(),
    );
    // A hole without a partner: its seed curve, or its points bound in its own mesh.
    let lone_hole = |c: &Contour, pair: Option<&(String, usize, usize)>, closing: bool| {
        if c.kind != ContourKind::Hole {
            return None;
        }
        let outline = match pair {
            Some(p) => HoleOutline::Curve(curve_of(&p.0)?),
            None => {
                let locator = if closing { &locators.0 } else { &locators.1 };
                HoleOutline::Bound(
                    c.points
                        .iter()
                        .map(|&q| locator.as_ref().map(|l| l.locate(q)))
                        .collect::<Option<_>>()?,
                )
            }
        };
        Some(ShrinkingHole { outline, closing })
    };
    let mut out = Vec::new();
    let mut items: Vec<usize> = cs.iter().map(|c| c.path).collect();
    items.sort_unstable();
    items.dedup();
    'paths: for i in items {
        // Source contours: a real partner (its curve), or a lone hole that will close.
        let mut partners: Vec<(usize, usize)> = Vec::new();
        let mut holes = Vec::new();
        for k in (0..cs.len()).filter(|&k| cs[k].path == i) {
            let pair = pairs.iter().find(|p| p.1 == k);
            match pair {
                Some(p) if p.2 != usize::MAX => match curve_of(&p.0) {
                    Some(c) => partners.push((p.2, c)),
                    None => match lone_hole(&cs[k], None, true) {
                        Some(h) => holes.push(h),
                        None => continue 'paths,
                    },
                },
                _ => match lone_hole(&cs[k], pair, true) {
                    Some(h) => holes.push(h),
                    None => continue 'paths,
                },
            }
        }
        let Some(j) = partners.first().map(|p| ct[p.0].path) else {
            continue;
        };
        if partners.iter().any(|p| ct[p.0].path != j) {
            continue;
        }
        // Target contours of path j: a partner, or a lone hole that will open.
        for k in (0..ct.len()).filter(|&k| ct[k].path == j) {
            if partners.iter().any(|p| p.0 == k) {
                continue;
            }
            let seed = pairs.iter().find(|p| p.2 == k && p.1 == usize::MAX);
            match lone_hole(&ct[k], seed, false) {
                Some(h) => holes.push(h),
                None => continue 'paths,
            }
        }
        let (Some(Some(a)), Some(Some(b))) = (ps.get(i), pt.get(j)) else {
            continue;
        };
        if paints_interpolate(a, b) {
            out.push(MorphingPath {
                source_item: i,
                target_item: j,
                curves: partners.iter().map(|p| p.1).collect(),
                source: a.clone(),
                target: b.clone(),
                source_root: source_scene.root_transform,
                target_root: target_scene.root_transform,
                holes,
            });
        }
    }
    in_paint_order(out)
}

/// Whether two paths' paints can interpolate: fill with fill and stroke with stroke, each pair
/// colours or compatible gradients ([`paint`]).
fn paints_interpolate(a: &PathItem, b: &PathItem) -> bool {
    let paints = |x: Option<&Paint>, y: Option<&Paint>| match (x, y) {
        (Some(x), Some(y)) => compatible(x, y),
        (x, y) => x.is_none() && y.is_none(),
    };
    paints(
        a.fill.as_ref().map(|f| &f.paint),
        b.fill.as_ref().map(|f| &f.paint),
    ) && paints(
        a.stroke.as_ref().map(|s| &s.paint),
        b.stroke.as_ref().map(|s| &s.paint),
    )
}

/// The one plain, single-subpath item of `paths` with element id `id`, if exactly one has it.
fn item_with_id<'a>(paths: &'a [Option<PathItem>], id: &str) -> Option<(usize, &'a PathItem)> {
    let mut found = paths
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.as_ref().filter(|p| p.id == id).map(|p| (i, p)));
    let (i, p) = found.next()?;
    (found.next().is_none() && crate::artwork::subpath_count(&p.path) == 1).then_some((i, p))
}

/// Marked-up drawings (issue #6, item 3): an artwork path that is itself the boundary or a
/// feature curve — the same element id in both drawings, a single subpath, plain paint that
/// interpolates — morphs as one shape along that curve, like automatic mode's matched paths.
/// `compatible.pairs[k].id` is the element id of `compatible.meshes.curves[k]`.
pub fn named_morphing_paths(
    source_scene: &Scene,
    target_scene: &Scene,
    compatible: &crate::compatible::Compatible,
) -> Vec<MorphingPath> {
    let (ps, pt) = (plain_paths(source_scene), plain_paths(target_scene));
    let mut out = Vec::new();
    for (k, pair) in compatible.pairs.iter().enumerate() {
        let (Some((i, a)), Some((j, b))) =
            (item_with_id(&ps, &pair.id), item_with_id(&pt, &pair.id))
        else {
            continue;
        };
        if k < compatible.meshes.curves.len() && paints_interpolate(a, b) {
            out.push(MorphingPath {
                source_item: i,
                target_item: j,
                curves: vec![k],
                source: a.clone(),
                target: b.clone(),
                source_root: source_scene.root_transform,
                target_root: target_scene.root_transform,
                holes: Vec::new(),
            });
        }
    }
    in_paint_order(out)
}

/// The largest subset of `paths` whose paint order is the same in both drawings, sorted by
/// source item: a longest strictly increasing subsequence of the target items taken in source
/// order (earliest-ending choice on ties, so the result is deterministic). In-between frames
/// interleave morphing paths with the blended rest of the artwork in one stack
/// ([`crate::export::Morph`]), which needs one order; the paths left out cross-fade with the
/// rest instead.
pub(crate) fn in_paint_order(mut paths: Vec<MorphingPath>) -> Vec<MorphingPath> {
    paths.sort_by_key(|p| p.source_item);
    // tails[k]: index of the path ending the best increasing run of length k + 1 found so far
    // (the one with the smallest target item); back[i]: the path before i in its run.
    let mut tails: Vec<usize> = Vec::new();
    let mut back: Vec<Option<usize>> = vec![None; paths.len()];
    for i in 0..paths.len() {
        let key = paths[i].target_item;
        let k = tails.partition_point(|&j| paths[j].target_item < key);
        back[i] = k.checked_sub(1).map(|k| tails[k]);
        if k == tails.len() {
            tails.push(i);
        } else {
            tails[k] = i;
        }
    }
    let mut keep = vec![false; paths.len()];
    let mut at = tails.last().copied();
    while let Some(i) = at {
        keep[i] = true;
        at = back[i];
    }
    paths
        .into_iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(source_item: usize, target_item: usize) -> MorphingPath {
        let p = PathItem {
            id: String::new(),
            path: BezPath::new(),
            fill: None,
            stroke: None,
            stroke_first: false,
        };
        MorphingPath {
            source_item,
            target_item,
            curves: Vec::new(),
            source: p.clone(),
            target: p,
            source_root: Affine::IDENTITY,
            target_root: Affine::IDENTITY,
            holes: Vec::new(),
        }
    }

    fn order(pairs: &[(usize, usize)]) -> Vec<(usize, usize)> {
        let paths = pairs.iter().map(|&(s, t)| path(s, t)).collect();
        in_paint_order(paths)
            .iter()
            .map(|p| (p.source_item, p.target_item))
            .collect()
    }

    #[test]
    fn paint_order_keeps_the_largest_consistent_subset() {
        assert_eq!(order(&[]), []);
        assert_eq!(
            order(&[(2, 5), (0, 1)]),
            [(0, 1), (2, 5)],
            "sorted by source"
        );
        // Source order 0..4 with targets 3 1 2 0: the run 1 2 is the longest.
        assert_eq!(order(&[(0, 3), (1, 1), (2, 2), (3, 0)]), [(1, 1), (2, 2)]);
        // Swapped pair in the middle: one of the two goes.
        let kept = order(&[(0, 0), (1, 4), (2, 3), (3, 6)]);
        assert_eq!(kept.len(), 3);
        assert!(kept.windows(2).all(|w| w[0].1 < w[1].1));
        // A target claimed twice is kept once.
        assert_eq!(order(&[(0, 2), (1, 2)]).len(), 1);
    }
}
