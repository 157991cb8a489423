//! Matched artwork morphing as one shape (issues #6 and #7): a source path and a target path
//! whose shapes pair are drawn, in between, as a single path — the paired outlines and aligned
//! holes taken from the frame's meshes, the fill and stroke colours interpolated in Oklab and
//! opacities and widths linearly — a crisp geometric transition, not two shapes cross-fading.
//!
//! Gradients interpolate too (module `paint`): their stops, and their geometry carried along by
//! the outline's motion.
//!
//! What has no mesh curve of its own still morphs inside the path instead of fading:
//! - a hole paired with a hole but not aligned as a feature curve is carried by its shape
//!   (source hole by the source mesh, target hole by the target mesh) and the two are blended
//!   along their own correspondence, `(1 − t)·A(t) + t·B(t)`, exact at both ends;
//! - a hole with no partner closes (or opens): carried by its shape and shrunk about its centre
//!   by `1 − t` (grown by `t`), a point at the far end, so nothing pops;
//! - a shape with no partner shrinks into (grows out of) a filled point of the nearest paired
//!   shape, riding that shape's best-fit similarity motion, or where it is when no paired shape
//!   is near.
//!
//! Why not a fade: a fading part is a translucent patch mid-morph; a closing one keeps the shape
//! crisp, which is what a designer animates by hand (and what shape tweens cannot do, since they
//! need equal contour counts).
//!
//! Rings are written with outlines and holes wound opposite ways and filled by the non-zero
//! rule, so shapes that overlap mid-morph stay filled and holes stay holes.
//!
//! Only plain paths qualify: solid or gradient fills and strokes (a gradient facing a colour or a
//! gradient of the same kind), no dashes, no shaped pen, and no ancestor group with opacity or a
//! clip. Anything else keeps the warp-and-blend of the rest of the artwork.

mod paint;

use crate::artwork::{Fill, Group, Item, Location, Paint, PathItem, Scene, Stroke};
use crate::geometry::{polygon_area, Point};
use crate::mesh::CompatibleMeshes;
use kurbo::{Affine, BezPath};
use paint::{compatible, fitted_affine, mix_paint};

/// A source path and a target path that morph as one shape.
#[derive(Debug, Clone, PartialEq)]
pub struct MorphingPath {
    /// Index of the source path in `source_scene.items()`; `None` for a target shape with no
    /// partner growing on its own.
    pub source_item: Option<usize>,
    /// Index of the target path in `target_scene.items()`; `None` for a source shape with no
    /// partner shrinking on its own.
    pub target_item: Option<usize>,
    /// Indices into the meshes' curves of the outline's contours, in the source path's order.
    pub curves: Vec<usize>,
    /// For each of `curves`, whether it is a hole (wound against the outlines).
    pub(crate) curve_holes: Vec<bool>,
    /// The source path's paint (for colours, opacities, widths, caps and joins).
    pub(crate) source: PathItem,
    /// The target path's paint.
    pub(crate) target: PathItem,
    /// The source scene's root transform: its root user space (where the path and its
    /// gradients live) → the mesh's space.
    pub(crate) source_root: Affine,
    /// The same for the target scene.
    pub(crate) target_root: Affine,
    /// Rings that morph without a mesh curve of their own (module docs).
    pub(crate) rings: Vec<Ring>,
    /// Motions of the shapes that carry rings without a mesh (see [`Rider`]).
    pub(crate) riders: Vec<Rider>,
    /// Further source and target items this path draws (shapes without a partner of paths
    /// that have no morphing path, riding here because their paint is the same).
    pub(crate) covers: (Vec<usize>, Vec<usize>),
    /// A path of shapes without a partner only: its stroke width shrinks with them (`Some(true)`,
    /// by `1 − t`) or grows (`Some(false)`, by `t`), so that a stroke shrunk to a point leaves no
    /// dot of its caps.
    pub(crate) sized_stroke: Option<bool>,
}

/// A ring's rest points and how they are carried into a frame.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Place {
    /// Bound to the mesh the ring was drawn on (source mesh for source rings).
    Mesh(Vec<Location>),
    /// Carried by rider `rider`'s similarity motion.
    Rider(usize, Vec<Point>),
    /// Where it is.
    Still(Vec<Point>),
    /// About a point that moves: each point keeps its offset from `anchor`, turned with rider
    /// `rider` (its rotation only, not its scale) and carried to where `centre` is in the frame.
    About {
        centre: Box<Place>,
        rider: Option<usize>,
        anchor: Point,
        points: Vec<Point>,
    },
}

impl Place {
    fn at(&self, meshes: &CompatibleMeshes, vertices: &[Point], riders: &[Rider]) -> Vec<Point> {
        match self {
            Place::Mesh(locs) => locs
                .iter()
                .map(|l| l.place(&meshes.triangles, vertices))
                .collect(),
            Place::Rider(k, pts) => {
                let m = riders[*k].motion(vertices);
                pts.iter().map(|&p| m.apply(p)).collect()
            }
            Place::Still(pts) => pts.clone(),
            Place::About {
                centre,
                rider,
                anchor,
                points,
            } => {
                let c = centre.at(meshes, vertices, riders)[0];
                let (cos, sin) = match rider {
                    Some(k) => {
                        let m = riders[*k].motion(vertices);
                        let r = m.a.hypot(m.b);
                        if r > 0.0 {
                            (m.a / r, m.b / r)
                        } else {
                            (1.0, 0.0)
                        }
                    }
                    None => (1.0, 0.0),
                };
                points
                    .iter()
                    .map(|&p| {
                        let d = p - *anchor;
                        c + Point::new(cos * d.x - sin * d.y, sin * d.x + cos * d.y)
                    })
                    .collect()
            }
        }
    }
}

/// A shape's motion without a mesh: the similarity that best carries the rest positions of
/// some of its vertices to where a frame puts them (least squares over rotation, uniform scale
/// and translation; O(vertices) per frame).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Rider {
    vertices: Vec<u32>,
    rest: Vec<Point>,
}

/// `q = centre_now + M (p − centre_rest)` with `M = [[a, −b], [b, a]]`.
#[derive(Debug, Clone, Copy)]
struct Similarity {
    from: Point,
    to: Point,
    a: f64,
    b: f64,
}

impl Similarity {
    fn apply(&self, p: Point) -> Point {
        let d = p - self.from;
        self.to + Point::new(self.a * d.x - self.b * d.y, self.b * d.x + self.a * d.y)
    }
}

/// Most vertices a rider fits (evenly spaced along its outline).
const RIDER_VERTICES: usize = 64;

impl Rider {
    pub(crate) fn new(curve: &[u32], rest: &[Point]) -> Rider {
        let n = curve.len();
        let step = n.div_ceil(RIDER_VERTICES).max(1);
        let vertices: Vec<u32> = curve.iter().step_by(step).copied().collect();
        let rest = vertices.iter().map(|&v| rest[v as usize]).collect();
        Rider { vertices, rest }
    }

    fn motion(&self, vertices: &[Point]) -> Similarity {
        let n = self.rest.len().max(1) as f64;
        let from = self.rest.iter().copied().sum::<Point>() / n;
        let to = self
            .vertices
            .iter()
            .map(|&v| vertices[v as usize])
            .sum::<Point>()
            / n;
        let (mut a, mut b, mut rr) = (0.0, 0.0, 0.0);
        for (&r, &v) in self.rest.iter().zip(&self.vertices) {
            let (r, q) = (r - from, vertices[v as usize] - to);
            a += r.dot(q);
            b += r.perp_dot(q);
            rr += r.length_squared();
        }
        if rr > 0.0 {
            Similarity {
                from,
                to,
                a: a / rr,
                b: b / rr,
            }
        } else {
            Similarity {
                from,
                to,
                a: 1.0,
                b: 0.0,
            }
        }
    }
}

/// A ring of the path that has no mesh curve of its own (module docs).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Ring {
    /// A paired hole not aligned as a feature: source and target rings, point for point,
    /// blended `(1 − t)·A + t·B`.
    Blended { source: Place, target: Place },
    /// A ring shrinking (`closing`, size `1 − t`) or growing (size `t`) about `centre`, or
    /// about its own centroid when `centre` is `None` (a hole without a partner).
    Sized {
        ring: Place,
        centre: Option<Place>,
        closing: bool,
        hole: bool,
        closed: bool,
    },
}

/// The size of a shrinking (`closing`) or growing ring at `t`: `√(1 − t)` or `√t`, so that its
/// area — and a stroke's ink, length times width — moves linearly between its ends, as the
/// area of the rest of the morph does, instead of dipping with `(1 − t)²`.
fn shrink(closing: bool, t: f64) -> f64 {
    let t = t.clamp(0.0, 1.0);
    if closing {
        (1.0 - t).sqrt()
    } else {
        t.sqrt()
    }
}

/// A polyline's orientation set: positive signed area for an outline, negative for a hole.
fn oriented(mut pts: Vec<Point>, hole: bool) -> Vec<Point> {
    let a = polygon_area(&pts);
    if (a < 0.0) != hole && a != 0.0 {
        pts.reverse();
    }
    pts
}

fn push_ring(path: &mut BezPath, pts: &[Point], closed: bool) {
    for (k, p) in pts.iter().enumerate() {
        let q = kurbo::Point::new(p.x, p.y);
        if k == 0 {
            path.move_to(q);
        } else {
            path.line_to(q);
        }
    }
    if closed && !pts.is_empty() {
        path.close_path();
    }
}

/// `path` with each subpath wound by its nesting depth (the number of other subpaths around
/// its first point): even depth counter-clockwise, odd depth clockwise, so that the nonzero
/// rule fills what the even-odd rule filled (exactly so for subpaths that do not cross).
fn wound_for_nonzero(path: &BezPath) -> BezPath {
    use kurbo::Shape;
    let mut subpaths: Vec<BezPath> = Vec::new();
    for el in path.elements() {
        if matches!(el, kurbo::PathEl::MoveTo(_)) || subpaths.is_empty() {
            subpaths.push(BezPath::new());
        }
        if let Some(last) = subpaths.last_mut() {
            last.push(*el);
        }
    }
    let first = |p: &BezPath| match p.elements().first() {
        Some(kurbo::PathEl::MoveTo(q)) => Some(*q),
        _ => None,
    };
    let mut out = BezPath::new();
    for (i, sp) in subpaths.iter().enumerate() {
        let depth = first(sp).map_or(0, |q| {
            subpaths
                .iter()
                .enumerate()
                .filter(|&(j, other)| j != i && other.winding(q) != 0)
                .count()
        });
        let ccw = sp.area() > 0.0;
        let keep = ccw == (depth % 2 == 0);
        let sp = if keep {
            sp.clone()
        } else {
            sp.reverse_subpaths()
        };
        for el in sp.elements() {
            out.push(*el);
        }
    }
    out
}

impl MorphingPath {
    /// The source path's own geometry in the mesh's space: what the path is at t = 0 when it
    /// alone draws its source path (its frames at t = 0 are the meshes' outline polylines).
    ///
    /// Under `fill-rule: evenodd` its subpaths are rewound so that the path, drawn with the
    /// morphing path's nonzero rule, fills what the source fills: a subpath inside an even
    /// number of others runs counter-clockwise, inside an odd number clockwise.
    pub fn exact_source_path(&self) -> BezPath {
        self.exact_source_path_with(&[])
    }

    /// [`MorphingPath::exact_source_path`] with the source paths of the shapes riding in it
    /// (`riders`, the source items the path covers besides its own) as further
    /// subpaths: what the path draws at t = 0 when shapes without a partner shrink into it.
    pub fn exact_source_path_with(&self, riders: &[&PathItem]) -> BezPath {
        let mut out = BezPath::new();
        for item in std::iter::once(&self.source).chain(riders.iter().copied()) {
            let path = self.source_root * item.path.clone();
            let path = match &item.fill {
                Some(f) if f.even_odd => wound_for_nonzero(&path),
                _ => path,
            };
            for el in path.elements() {
                out.push(*el);
            }
        }
        out
    }

    /// The path at `t` whose mesh is `vertices`.
    pub fn at(&self, meshes: &CompatibleMeshes, vertices: &[Point], t: f64) -> PathItem {
        let mut path = BezPath::new();
        for (&c, &hole) in self.curves.iter().zip(&self.curve_holes) {
            let curve = &meshes.curves[c];
            let pts: Vec<Point> = curve
                .vertices
                .iter()
                .map(|&v| vertices[v as usize])
                .collect();
            let pts = if curve.closed {
                oriented(pts, hole)
            } else {
                pts
            };
            push_ring(&mut path, &pts, curve.closed);
        }
        // Every frame has the same subpaths (the animated SVG animates one `d`); a ring of
        // size 0 paints nothing.
        for ring in &self.rings {
            match ring {
                Ring::Blended { source, target } => {
                    let a = source.at(meshes, vertices, &self.riders);
                    let b = target.at(meshes, vertices, &self.riders);
                    let pts: Vec<Point> =
                        a.iter().zip(&b).map(|(p, q)| *p + (*q - *p) * t).collect();
                    push_ring(&mut path, &oriented(pts, true), true);
                }
                Ring::Sized {
                    ring,
                    centre,
                    closing,
                    hole,
                    closed,
                } => {
                    let pts = ring.at(meshes, vertices, &self.riders);
                    let size = shrink(*closing, t);
                    let c = match centre {
                        Some(c) => c.at(meshes, vertices, &self.riders)[0],
                        None => crate::geometry::centroid(&pts),
                    };
                    let pts: Vec<Point> = pts.into_iter().map(|p| c + (p - c) * size).collect();
                    let pts = if *closed { oriented(pts, *hole) } else { pts };
                    push_ring(&mut path, &pts, *closed);
                }
            }
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
                even_odd: false,
            }),
            _ => None,
        };
        let size = self.sized_stroke.map_or(1.0, |closing| shrink(closing, t));
        let stroke = match (&self.source.stroke, &self.target.stroke) {
            (Some(a), Some(b)) => Some(Stroke {
                paint: colour(&a.paint, &b.paint),
                opacity: lerp(a.opacity, b.opacity),
                width: lerp(a.width, b.width) * size,
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
pub(crate) fn plain_paths(scene: &Scene) -> Vec<Option<PathItem>> {
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

/// Resamples two closed rings to the same number of points by arc length, the second started
/// where it best fits the first (after moving both centroids together) and wound the same way:
/// the correspondence of a paired hole that is not a feature curve.
pub(crate) fn paired_rings(a: &[Point], b: &[Point]) -> (Vec<Point>, Vec<Point>) {
    let n = a.len().max(b.len()).clamp(8, 512);
    let resample = |r: &[Point]| crate::quality::ring_samples(&oriented(r.to_vec(), false), n);
    let (ra, rb) = (resample(a), resample(b));
    let (ca, cb) = (
        crate::geometry::centroid(&ra),
        crate::geometry::centroid(&rb),
    );
    let shift = (0..n)
        .min_by(|&x, &y| {
            let cost = |s: usize| -> f64 {
                (0..n)
                    .map(|i| ((ra[i] - ca) - (rb[(i + s) % n] - cb)).length_squared())
                    .sum()
            };
            cost(x).total_cmp(&cost(y))
        })
        .unwrap_or(0);
    let rb = (0..n).map(|i| rb[(i + shift) % n]).collect();
    (ra, rb)
}

/// Whether two paths paint the same (fill and stroke), so that a shape of one may be drawn
/// with the other.
pub(crate) fn same_paint(a: &PathItem, b: &PathItem) -> bool {
    // The fill rule is no part of the look of a morphing path (its rings are wound explicitly).
    let fill = |x: &PathItem, y: &PathItem| match (&x.fill, &y.fill) {
        (Some(f), Some(g)) => f.paint == g.paint && f.opacity == g.opacity,
        (f, g) => f.is_none() && g.is_none(),
    };
    fill(a, b) && a.stroke == b.stroke
}

/// Whether two paths' paints can interpolate: fill with fill and stroke with stroke, each pair
/// colours or compatible gradients ([`paint`]).
pub(crate) fn paints_interpolate(a: &PathItem, b: &PathItem) -> bool {
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
                source_item: Some(i),
                target_item: Some(j),
                curves: vec![k],
                source: a.clone(),
                target: b.clone(),
                source_root: source_scene.root_transform,
                target_root: target_scene.root_transform,
                curve_holes: vec![false],
                rings: Vec::new(),
                riders: Vec::new(),
                covers: (Vec::new(), Vec::new()),
                sized_stroke: None,
            });
        }
    }
    in_paint_order(out)
}

/// `paths` in one paint order for the in-between frames, which interleave morphing paths with
/// the blended rest of the artwork in one stack ([`crate::export::Morph`]): the largest subset
/// of the paths with items on both sides whose order is the same in both drawings (a longest
/// non-decreasing subsequence of the target items taken in source order, earliest-ending
/// choice on ties, so the result is deterministic) — all of them when they share one paint,
/// whose order shows nowhere — with the one-sided paths (shapes without a partner) placed by
/// their own side's order. The paired paths left out cross-fade with the rest instead.
pub(crate) fn in_paint_order(paths: Vec<MorphingPath>) -> Vec<MorphingPath> {
    let (mut both, one): (Vec<MorphingPath>, Vec<MorphingPath>) = paths
        .into_iter()
        .partition(|p| p.source_item.is_some() && p.target_item.is_some());
    both.sort_by_key(|p| (p.source_item, p.target_item));
    // Paths of one paint (a monochrome icon) may pass each other: their order shows nowhere.
    let one_paint = both.windows(2).all(|w| {
        let (a, b) = (&w[0], &w[1]);
        same_paint(&a.source, &b.source) && same_paint(&a.target, &b.target)
    }) && both
        .iter()
        .all(|p| same_paint(&p.source, &p.target) || both.len() == 1);
    // tails[k]: index of the path ending the best non-decreasing run of length k + 1 found so
    // far (the one with the smallest target item); back[i]: the path before i in its run.
    let mut tails: Vec<usize> = Vec::new();
    let mut back: Vec<Option<usize>> = vec![None; both.len()];
    for i in 0..both.len() {
        let key = if one_paint { None } else { both[i].target_item };
        let k = tails.partition_point(|&j| {
            let theirs = if one_paint { None } else { both[j].target_item };
            theirs <= key
        });
        back[i] = k.checked_sub(1).map(|k| tails[k]);
        if k == tails.len() {
            tails.push(i);
        } else {
            tails[k] = i;
        }
    }
    let mut keep = vec![false; both.len()];
    let mut at = tails.last().copied();
    while let Some(i) = at {
        keep[i] = true;
        at = back[i];
    }
    let mut out: Vec<MorphingPath> = both
        .into_iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(p))
        .collect();
    // One-sided paths go after the last path drawn before them on their side.
    let mut one = one;
    one.sort_by_key(|p| (p.source_item, p.target_item));
    for p in one {
        let at = match (p.source_item, p.target_item) {
            (Some(i), _) => out
                .iter()
                .rposition(|q| q.source_item.is_some_and(|s| s < i))
                .map_or(0, |k| k + 1),
            (_, Some(j)) => out
                .iter()
                .rposition(|q| q.target_item.is_some_and(|s| s < j))
                .map_or(0, |k| k + 1),
            _ => out.len(),
        };
        out.insert(at, p);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square with a square hole and an island in the hole, all wound the same way (as
    /// even-odd files often are): rewound, the nonzero rule fills the ring and the island and
    /// leaves the hole empty.
    #[test]
    fn even_odd_subpaths_are_rewound_for_nonzero() {
        use kurbo::Shape;
        let square = |c: f64, r: f64| {
            format!(
                "M{} {} L{} {} L{} {} L{} {} Z",
                c - r,
                c - r,
                c + r,
                c - r,
                c + r,
                c + r,
                c - r,
                c + r
            )
        };
        let d = format!(
            "{} {} {}",
            square(0.0, 10.0),
            square(0.0, 6.0),
            square(0.0, 2.0)
        );
        let path = BezPath::from_svg(&d).unwrap();
        let fills = |p: &BezPath, x: f64| p.winding(kurbo::Point::new(x, 0.0)) != 0;
        assert!(fills(&path, 4.0), "all wound alike: nonzero fills the hole");
        let w = wound_for_nonzero(&path);
        assert!(fills(&w, 8.0) && !fills(&w, 4.0) && fills(&w, 0.0));
        // Already alternating: unchanged.
        assert_eq!(wound_for_nonzero(&w), w);
    }

    /// A morphing path between items; `paint` tells its colour (the same on both sides).
    fn path(source_item: Option<usize>, target_item: Option<usize>, paint: u8) -> MorphingPath {
        let p = PathItem {
            id: String::new(),
            path: BezPath::new(),
            fill: Some(Fill {
                paint: Paint::Color(crate::artwork::Rgba {
                    r: paint,
                    g: 0,
                    b: 0,
                    a: 255,
                }),
                opacity: 1.0,
                even_odd: false,
            }),
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
            curve_holes: Vec::new(),
            rings: Vec::new(),
            riders: Vec::new(),
            covers: (Vec::new(), Vec::new()),
            sized_stroke: None,
        }
    }

    /// Paint order of paths `(source, target)`, each its own colour unless `one_paint`.
    fn order(pairs: &[(usize, usize)], one_paint: bool) -> Vec<(usize, usize)> {
        let paths = pairs
            .iter()
            .map(|&(s, t)| path(Some(s), Some(t), if one_paint { 0 } else { s as u8 }))
            .collect();
        in_paint_order(paths)
            .iter()
            .map(|p| (p.source_item.unwrap(), p.target_item.unwrap()))
            .collect()
    }

    #[test]
    fn paint_order_keeps_the_largest_consistent_subset() {
        assert_eq!(order(&[], false), []);
        assert_eq!(
            order(&[(2, 5), (0, 1)], false),
            [(0, 1), (2, 5)],
            "sorted by source"
        );
        // Source order 0..4 with targets 3 1 2 0: the run 1 2 is the longest.
        assert_eq!(
            order(&[(0, 3), (1, 1), (2, 2), (3, 0)], false),
            [(1, 1), (2, 2)]
        );
        // Swapped pair in the middle: one of the two goes.
        let kept = order(&[(0, 0), (1, 4), (2, 3), (3, 6)], false);
        assert_eq!(kept.len(), 3);
        assert!(kept.windows(2).all(|w| w[0].1 < w[1].1));
        // Two source paths drawing into one target path both morph (non-decreasing).
        assert_eq!(order(&[(0, 2), (1, 2)], false), [(0, 2), (1, 2)]);
        // Of one paint, order shows nowhere: every path morphs.
        assert_eq!(
            order(&[(0, 3), (1, 1), (2, 2), (3, 0)], true),
            [(0, 3), (1, 1), (2, 2), (3, 0)]
        );
    }

    #[test]
    fn one_sided_paths_go_where_their_side_puts_them() {
        let paths = vec![
            path(Some(0), Some(0), 1),
            path(Some(4), Some(2), 2),
            path(Some(2), None, 3),
            path(None, Some(1), 4),
        ];
        let got: Vec<(Option<usize>, Option<usize>)> = in_paint_order(paths)
            .iter()
            .map(|p| (p.source_item, p.target_item))
            .collect();
        // Each side's items come in that side's order, every path kept.
        assert_eq!(got.len(), 4);
        type Items = (Option<usize>, Option<usize>);
        let side =
            |f: fn(&Items) -> Option<usize>| -> Vec<usize> { got.iter().filter_map(f).collect() };
        assert_eq!(side(|p| p.0), [0, 2, 4]);
        assert_eq!(side(|p| p.1), [0, 1, 2]);
    }
}
