//! Matched artwork morphing as one shape (issue #6, item 3): when every contour of a source path
//! is a feature curve whose partners are every contour of one target path, the two paths are
//! drawn as a single path whose outline is those feature curves in the frame's mesh, with the
//! fill and stroke colours interpolated in Oklab and opacities and widths linearly — a crisp
//! geometric transition, not two shapes cross-fading.
//!
//! Only plain paths qualify: solid fills and strokes, no dashes, no shaped pen, and no
//! ancestor group with opacity or a clip. Anything else keeps the warp-and-blend of the rest of
//! the artwork.

use super::contours::Contour;
use crate::artwork::{Fill, Group, Item, Paint, PathItem, Scene, Stroke};
use crate::color::mix;
use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;
use kurbo::BezPath;

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
        let lerp = |a: f64, b: f64| a + (b - a) * t;
        let colour = |a: &Paint, b: &Paint| match (a, b) {
            (Paint::Color(x), Paint::Color(y)) => Paint::Color(mix(*x, *y, t)),
            _ => a.clone(),
        };
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

/// The overlay scene of frame `t`: every morphing path at `vertices`, in source paint order,
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

/// Every item of `scene.items()` with whether it may morph as one shape: a path with solid
/// paint, no dashes or shaped pen, under groups without opacity or clip.
fn plain_paths(scene: &Scene) -> Vec<Option<PathItem>> {
    fn walk(g: &Group, plain: bool, out: &mut Vec<Option<PathItem>>) {
        for c in &g.children {
            match c {
                Item::Group(sub) => {
                    out.push(None);
                    walk(sub, plain && sub.opacity == 1.0 && sub.clip.is_none(), out);
                }
                Item::Path(p) => {
                    let solid = |paint: &Paint| matches!(paint, Paint::Color(_));
                    let ok = plain
                        && p.fill.as_ref().is_none_or(|f| solid(&f.paint))
                        && p.stroke.as_ref().is_none_or(|s| {
                            solid(&s.paint) && s.dashes.is_empty() && s.frame.is_none()
                        })
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
    let mut out = Vec::new();
    let mut items: Vec<usize> = cs.iter().map(|c| c.path).collect();
    items.sort_unstable();
    items.dedup();
    for i in items {
        let mine: Vec<usize> = (0..cs.len()).filter(|&k| cs[k].path == i).collect();
        let partners: Option<Vec<(usize, usize)>> = mine
            .iter()
            .map(|&k| {
                pairs
                    .iter()
                    .find(|p| p.1 == k && p.2 != usize::MAX)
                    .and_then(|p| Some((p.2, curve_of(&p.0)?)))
            })
            .collect();
        let Some(partners) = partners else { continue };
        let Some(j) = partners.first().map(|p| ct[p.0].path) else {
            continue;
        };
        let theirs = (0..ct.len()).filter(|&k| ct[k].path == j).count();
        let one_target = partners.iter().all(|p| ct[p.0].path == j) && theirs == partners.len();
        let (Some(Some(a)), Some(Some(b))) = (ps.get(i), pt.get(j)) else {
            continue;
        };
        let same_paint =
            a.fill.is_some() == b.fill.is_some() && a.stroke.is_some() == b.stroke.is_some();
        if one_target && same_paint {
            out.push(MorphingPath {
                source_item: i,
                target_item: j,
                curves: partners.iter().map(|p| p.1).collect(),
                source: a.clone(),
                target: b.clone(),
            });
        }
    }
    out
}
