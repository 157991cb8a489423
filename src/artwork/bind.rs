//! Binding artwork to a mesh: point location and barycentric coordinates.
//!
//! Every artwork point is expressed once as `(triangle, barycentric coordinates)` in the mesh the
//! artwork belongs to (the source mesh for source artwork, the target mesh for target artwork);
//! placing it in the mesh of a frame is then a weighted sum of three frame vertices (§3: the
//! shapes are "transferred to the intermediate triangulations"). Points outside the mesh (artwork
//! just outside the boundary, stroke overhangs) take the nearest triangle and its affine map:
//! their barycentric coordinates extend that map and may be negative.

use super::{Item, Scene};
use crate::error::{Error, Result};
use crate::geometry::{barycentric, orient2d, point_segment_distance, Point};
use crate::grid::{box_distance_squared, GridFrame};
use kurbo::{Affine, BezPath, ParamCurveArclen, PathEl, Shape};

/// Where a point sits in a mesh: a triangle and barycentric coordinates in it (they sum to one;
/// all non-negative when the point is inside the triangle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Location {
    /// Index into the mesh's triangle list.
    pub triangle: u32,
    /// Weights of the triangle's three vertices.
    pub bary: [f64; 3],
}

impl Location {
    /// The located point placed in a mesh with vertex positions `vertices`.
    pub fn place(&self, triangles: &[[u32; 3]], vertices: &[Point]) -> Point {
        let t = triangles[self.triangle as usize];
        vertices[t[0] as usize] * self.bary[0]
            + vertices[t[1] as usize] * self.bary[1]
            + vertices[t[2] as usize] * self.bary[2]
    }
}

/// A point locator over a triangle mesh: a uniform grid of triangle bounding boxes, with exact
/// orientation tests for containment and a ring search for the nearest triangle.
#[derive(Debug, Clone)]
pub struct PointLocator<'a> {
    points: &'a [Point],
    triangles: &'a [[u32; 3]],
    /// The grid over the triangles' box, about one cell per triangle.
    frame: GridFrame,
    /// Triangle indices per cell (row-major), ascending: cell `k`'s are
    /// `cell_triangles[cell_start[k]..cell_start[k + 1]]` (one allocation for the grid, not one
    /// per cell: a locator is made per part and per binding).
    cell_start: Vec<usize>,
    cell_triangles: Vec<u32>,
}

impl<'a> PointLocator<'a> {
    /// Builds the grid, about one cell per triangle. Degenerate (zero-area) triangles are left
    /// out; an error is returned when no triangle is left or an index is out of range.
    pub fn new(points: &'a [Point], triangles: &'a [[u32; 3]]) -> Result<Self> {
        Self::of_triangles(points, triangles, |_| true)
    }

    /// [`PointLocator::new`] over the triangles `keep` accepts (by index), e.g. one part of a
    /// mesh made of several; locations still index the whole `triangles` list.
    pub fn of_triangles(
        points: &'a [Point],
        triangles: &'a [[u32; 3]],
        keep: impl Fn(usize) -> bool,
    ) -> Result<Self> {
        let n = points.len();
        let mut lo = Point::splat(f64::INFINITY);
        let mut hi = Point::splat(f64::NEG_INFINITY);
        let mut usable = Vec::with_capacity(triangles.len());
        for (i, t) in triangles.iter().enumerate() {
            if !keep(i) {
                continue;
            }
            if t.iter().any(|&v| v as usize >= n) {
                return Err(Error::internal(format!(
                    "triangle {i} refers to a vertex out of range"
                )));
            }
            let [a, b, c] = t.map(|v| points[v as usize]);
            if !(a.is_finite() && b.is_finite() && c.is_finite()) || orient2d(a, b, c) == 0.0 {
                continue;
            }
            lo = lo.min(a).min(b).min(c);
            hi = hi.max(a).max(b).max(c);
            usable.push(i as u32);
        }
        if usable.is_empty() {
            return Err(Error::internal(
                "the mesh has no usable triangle to bind the artwork to",
            ));
        }
        let frame = GridFrame::covering(lo, hi, usable.len());
        let (nx, ny) = (frame.nx, frame.ny);
        let mut me = PointLocator {
            points,
            triangles,
            frame,
            cell_start: Vec::new(),
            cell_triangles: Vec::new(),
        };
        // Each triangle's range of cells, counted, then filled in triangle order.
        let ranges: Vec<[usize; 4]> = usable
            .iter()
            .map(|&i| {
                let [a, b, c] = triangles[i as usize].map(|v| points[v as usize]);
                let (x0, y0) = me.frame.cell_of(a.min(b).min(c));
                let (x1, y1) = me.frame.cell_of(a.max(b).max(c));
                [x0, y0, x1, y1]
            })
            .collect();
        let mut start = vec![0usize; nx * ny + 1];
        for &[x0, y0, x1, y1] in &ranges {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    start[y * nx + x + 1] += 1;
                }
            }
        }
        for k in 0..nx * ny {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[nx * ny]];
        for (&i, &[x0, y0, x1, y1]) in usable.iter().zip(&ranges) {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let slot = &mut fill[y * nx + x];
                    items[*slot] = i;
                    *slot += 1;
                }
            }
        }
        me.cell_start = start;
        me.cell_triangles = items;
        Ok(me)
    }

    /// The triangles of grid cell `(x, y)`, ascending.
    fn cell(&self, x: usize, y: usize) -> &[u32] {
        let k = y * self.frame.nx + x;
        &self.cell_triangles[self.cell_start[k]..self.cell_start[k + 1]]
    }

    /// The triangle containing `p` (boundary included; the lowest index wins on shared edges),
    /// with barycentric coordinates clamped to be non-negative.
    pub fn containing(&self, p: Point) -> Option<Location> {
        let (cx, cy) = self.frame.cell_of(p);
        for &i in self.cell(cx, cy) {
            let [a, b, c] = self.triangles[i as usize].map(|v| self.points[v as usize]);
            // Outside the triangle's box, outside the triangle: the exact tests below would
            // say so too, at four orientation predicates.
            let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
            if p.x < lo.x || p.y < lo.y || p.x > hi.x || p.y > hi.y {
                continue;
            }
            let s = orient2d(a, b, c).signum();
            if orient2d(a, b, p) * s >= 0.0
                && orient2d(b, c, p) * s >= 0.0
                && orient2d(c, a, p) * s >= 0.0
            {
                let mut w = barycentric(p, a, b, c)?;
                for x in &mut w {
                    *x = x.max(0.0);
                }
                let sum: f64 = w.iter().sum();
                return Some(Location {
                    triangle: i,
                    bary: w.map(|x| x / sum),
                });
            }
        }
        None
    }

    /// The triangle nearest to `p` (distance to its closed region; the lowest index wins ties).
    fn nearest(&self, p: Point) -> u32 {
        let (cx, cy) = self.frame.cell_of(p);
        let mut best: Option<(f64, u32)> = None;
        // A triangle whose bounding box is farther than the best distance by more than the
        // rounding of either distance cannot win, so its distance is not computed. The margin
        // is far above that rounding (a few ulps of the coordinates), so the choice is the one
        // the full scan makes. A whole cell farther than that is passed over: a triangle's
        // nearest point to `p` lies in a cell that lists it, and that cell is no farther from
        // `p` than the triangle is, so a triangle that can win is still met there — which
        // spares the far rings, where a point far from its part met thousands of triangles.
        let scale = p
            .abs()
            .max(self.frame.origin.abs())
            .max(self.frame.far.abs())
            .max_element();
        let reach = |best: f64| best + 1e-9 * (best + scale);
        let max_ring = self.frame.nx.max(self.frame.ny);
        for r in 0..=max_ring {
            let ((x0, x1), (y0, y1)) = self.frame.ring_square((cx, cy), r);
            for (xs, ys) in self.frame.ring_strips((cx, cy), r) {
                // A strip of the ring, then each of its cells, passed over when farther than
                // the best triangle (see above).
                let far = |best: Option<(f64, u32)>, xs, ys| {
                    best.is_some_and(|(bd, _)| {
                        self.frame.cells_distance_squared(p, xs, ys) > reach(bd) * reach(bd)
                    })
                };
                if far(best, xs, ys) {
                    continue;
                }
                for y in ys.0..=ys.1 {
                    for x in xs.0..=xs.1 {
                        if far(best, (x, x), (y, y)) {
                            continue;
                        }
                        for &i in self.cell(x, y) {
                            if let Some((bd, _)) = best {
                                let [a, b, c] =
                                    self.triangles[i as usize].map(|v| self.points[v as usize]);
                                let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
                                if box_distance_squared(p, lo, hi) > reach(bd) * reach(bd) {
                                    continue;
                                }
                            }
                            let d = self.distance_to_triangle(p, i);
                            if best.is_none_or(|(bd, bi)| d < bd || (d == bd && i < bi)) {
                                best = Some((d, i));
                            }
                        }
                    }
                }
            }
            // Stop when every cell beyond ring r is farther than the best triangle. An
            // unsearched triangle's box lies in the grid outside the ring's rectangle, so it is
            // at least as far as the nearest of the four strips of the grid beyond the ring's
            // sides (the grid's own edges have none): for a point far outside a small grid,
            // that is far more than the gap to the ring's side alone.
            if let Some((d, _)) = best {
                let beyond = self.frame.beyond(p, (x0, x1), (y0, y1));
                if d < beyond || beyond == f64::INFINITY {
                    break;
                }
            }
        }
        best.map(|(_, i)| i).unwrap_or(0)
    }

    fn distance_to_triangle(&self, p: Point, i: u32) -> f64 {
        let [a, b, c] = self.triangles[i as usize].map(|v| self.points[v as usize]);
        point_segment_distance(p, a, b)
            .0
            .min(point_segment_distance(p, b, c).0)
            .min(point_segment_distance(p, c, a).0)
    }

    /// Locates `p`: the containing triangle, or else the nearest one, whose affine map the point
    /// then follows (barycentric coordinates extended outside the triangle).
    pub fn locate(&self, p: Point) -> Location {
        if let Some(l) = self.containing(p) {
            return l;
        }
        let i = self.nearest(p);
        let [a, b, c] = self.triangles[i as usize].map(|v| self.points[v as usize]);
        Location {
            triangle: i,
            // Usable triangles are non-degenerate, so this is Some.
            bary: barycentric(p, a, b, c).unwrap_or([1.0, 0.0, 0.0]),
        }
    }
}

/// Locates artwork in a mesh that may be made of several parts ([`crate::mesh::Parts`]): each
/// item (a path, a clip shape, an image) is bound as a whole to one part — the shape holding
/// most of its points, or the still part when no shape holds any — so that an item rides with
/// the shape it is drawn on and artwork outside every shape stays where it is, instead of
/// being torn between parts.
pub(crate) struct Locator<'a> {
    whole: PointLocator<'a>,
    parts: Option<PartLocators<'a>>,
}

struct PartLocators<'a> {
    of_triangle: &'a [u32],
    still: Option<u32>,
    /// One locator per part (`None` for a part without usable triangles).
    each: Vec<Option<PointLocator<'a>>>,
}

impl<'a> Locator<'a> {
    pub(crate) fn new(
        points: &'a [Point],
        triangles: &'a [[u32; 3]],
        parts: Option<&'a crate::mesh::Parts>,
    ) -> Result<Self> {
        let whole = PointLocator::new(points, triangles)?;
        let parts = match parts {
            Some(p) if p.of_triangle.len() == triangles.len() && p.count > 1 => {
                let each = (0..p.count)
                    .map(|k| {
                        PointLocator::of_triangles(points, triangles, |i| p.of_triangle[i] == k)
                            .ok()
                    })
                    .collect();
                Some(PartLocators {
                    of_triangle: &p.of_triangle,
                    still: p.still,
                    each,
                })
            }
            _ => None,
        };
        Ok(Locator { whole, parts })
    }

    /// The locator for an item with points `points` (module docs).
    fn for_item(&self, points: &[Point]) -> &PointLocator<'a> {
        let Some(parts) = &self.parts else {
            return &self.whole;
        };
        let mut count = vec![0usize; parts.each.len()];
        for &p in points {
            if let Some(l) = self.whole.containing(p) {
                let k = parts.of_triangle[l.triangle as usize];
                if Some(k) != parts.still {
                    count[k as usize] += 1;
                }
            }
        }
        let best = (0..count.len())
            .filter(|&k| count[k] > 0)
            .max_by_key(|&k| (count[k], std::cmp::Reverse(k)));
        let part = best.map(|k| k as u32).or(parts.still);
        part.and_then(|k| parts.each[k as usize].as_ref())
            .unwrap_or(&self.whole)
    }
}

/// One subpath of a flattened path: a range of points and whether it is closed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Subpath {
    pub(crate) start: usize,
    pub(crate) len: usize,
    pub(crate) closed: bool,
}

/// A path flattened and located once.
#[derive(Debug, Clone)]
pub(crate) struct BoundPath {
    pub(crate) subpaths: Vec<Subpath>,
    pub(crate) locations: Vec<Location>,
    /// Where the path's paint geometry (gradients) is anchored: its bounding-box centre.
    pub(crate) anchor: Location,
}

/// A path item bound to the mesh: its outline, and for a dashed stroke the dashes themselves.
///
/// Dashes are cut on the exact curve once and then carried by the mesh like any other
/// geometry, so in a morph they travel with the artwork instead of sliding along the path, and
/// flattening cannot shift them.
#[derive(Debug, Clone)]
pub(crate) struct BoundPathItem {
    pub(crate) outline: BoundPath,
    pub(crate) dashes: Option<BoundPath>,
}

/// An image's texture grid bound to the mesh: `(columns + 1) × (rows + 1)` grid vertices.
#[derive(Debug, Clone)]
pub(crate) struct BoundImage {
    pub(crate) columns: u32,
    pub(crate) rows: u32,
    pub(crate) locations: Vec<Location>,
}

/// What each path or image of the scene (depth first, paint order) is bound to.
#[derive(Debug, Clone)]
pub(crate) enum BoundItem {
    Path(BoundPathItem),
    /// An image: its texture grid's vertices, row-major (`super::texture`).
    Image(BoundImage),
    /// A group's clip path, one bound path per shape (comes before the group's children).
    Clip(Vec<BoundPath>),
}

/// A scene bound to a mesh: computed once per artwork, then [`Binding::warp`] places it in the
/// mesh of any frame (the precompute-then-apply split of DESIGN.md).
#[derive(Debug, Clone)]
pub struct Binding {
    pub(crate) scene: Scene,
    pub(crate) triangles: Vec<[u32; 3]>,
    /// Rest positions of the mesh vertices the artwork was bound in.
    pub(crate) rest: Vec<Point>,
    /// Paths and images in depth-first paint order.
    pub(crate) items: Vec<BoundItem>,
}

impl Binding {
    /// Binds `scene` to the mesh `(mesh_vertices, triangles)` it was drawn on (the source mesh for
    /// the source artwork, the target mesh for the target's). Curves are flattened at `tolerance`
    /// user units (use [`super::flatten_tolerance`] for a quarter pixel at the output size).
    pub fn new(
        scene: &Scene,
        mesh_vertices: &[Point],
        triangles: &[[u32; 3]],
        tolerance: f64,
    ) -> Result<Binding> {
        Self::with_parts(scene, mesh_vertices, triangles, None, tolerance)
    }

    /// [`Binding::new`] on a mesh made of `parts` (automatic mode): each item is bound to one
    /// part (the shape holding most of its points, else the still part).
    pub fn with_parts(
        scene: &Scene,
        mesh_vertices: &[Point],
        triangles: &[[u32; 3]],
        parts: Option<&crate::mesh::Parts>,
        tolerance: f64,
    ) -> Result<Binding> {
        let tolerance = if tolerance.is_finite() && tolerance > 0.0 {
            tolerance
        } else {
            super::flatten_tolerance(scene.view_box, scene.size)
        };
        // Far-away artwork is cut to the reach of the view first (`reach`): its points would
        // otherwise grow with its coordinates, and each be located far from the mesh.
        let (scene, _) = super::within_reach(scene);
        let locator = Locator::new(mesh_vertices, triangles, parts)?;
        // Half the mesh's mean edge length: straight artwork segments bend with the mesh.
        let (sum, count) = triangles.iter().fold((0.0, 0usize), |(s, c), t| {
            let e = |a: u32, b: u32| mesh_vertices[a as usize].distance(mesh_vertices[b as usize]);
            (s + e(t[0], t[1]) + e(t[1], t[2]) + e(t[2], t[0]), c + 3)
        });
        let max_segment = if count > 0 && sum > 0.0 {
            0.5 * sum / count as f64
        } else {
            f64::INFINITY
        };
        let resolution = within_budget(
            &scene,
            Resolution {
                tolerance,
                max_segment,
                image_points: IMAGE_POINTS / count_images(&scene.root).max(1),
            },
        );
        let mut items = Vec::new();
        bind_items(&scene.root.children, &locator, resolution, &mut items);
        Ok(Binding {
            scene,
            triangles: triangles.to_vec(),
            rest: mesh_vertices.to_vec(),
            items,
        })
    }

    /// The scene this binding carries.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Number of flattened artwork points bound to the mesh.
    pub fn point_count(&self) -> usize {
        self.items
            .iter()
            .map(|i| match i {
                BoundItem::Path(p) => {
                    p.outline.locations.len() + p.dashes.as_ref().map_or(0, |d| d.locations.len())
                }
                BoundItem::Image(b) => b.locations.len(),
                BoundItem::Clip(c) => c.iter().map(|p| p.locations.len()).sum(),
            })
            .sum()
    }
}

fn bind_items(items: &[Item], locator: &Locator, tol: Resolution, out: &mut Vec<BoundItem>) {
    for item in items {
        match item {
            Item::Group(g) => {
                if let Some(c) = &g.clip {
                    let shapes = c
                        .shapes
                        .iter()
                        .map(|s| bind_path(&s.path, locator, tol))
                        .collect();
                    out.push(BoundItem::Clip(shapes));
                }
                bind_items(&g.children, locator, tol, out)
            }
            Item::Path(p) => {
                let dashes = p
                    .stroke
                    .as_ref()
                    .and_then(|st| cut_dashes(&p.path, st, &p.id))
                    .map(|d| bind_path(&d, locator, tol));
                out.push(BoundItem::Path(BoundPathItem {
                    outline: bind_path(&p.path, locator, tol),
                    dashes,
                }));
            }
            Item::Image(img) => {
                // Cells twice as long as the mesh's mean edge (four times `max_segment`) for
                // the SVG outputs, each split 4 × 4 for raster frames (`texture`).
                let (columns, rows) = super::ImageGrid::size_for(img, 4.0 * tol.max_segment);
                let (columns, rows) = grid_within(columns, rows, tol.image_points);
                let points = super::ImageGrid::rest_points(img, columns, rows);
                let located = locator.for_item(&points);
                out.push(BoundItem::Image(BoundImage {
                    columns,
                    rows,
                    locations: points.iter().map(|&p| located.locate(p)).collect(),
                }));
            }
        }
    }
}

/// Most dashes cut from one path; a pattern finer than this (a dotted hairline around a huge
/// shape) is left to the renderer's own dashing.
const MAX_DASHES: f64 = 20_000.0;

/// The dashes of a dashed stroke as open subpaths in user space, cut on the exact curve in the
/// space the pattern is measured in (user space, or the pen's frame). `None` for a solid
/// stroke, an invalid pattern (SVG then draws it solid; usvg already drops those), or too many
/// dashes.
pub(crate) fn cut_dashes(path: &BezPath, stroke: &super::Stroke, id: &str) -> Option<BezPath> {
    let d = &stroke.dashes;
    let period: f64 = d.iter().sum();
    if d.is_empty()
        || d.iter().any(|x| !x.is_finite() || *x < 0.0)
        || period.is_nan()
        || period <= 0.0
    {
        return None;
    }
    let frame = stroke.frame.unwrap_or(Affine::IDENTITY);
    let local = frame.inverse() * path.clone();
    let length: f64 = local.segments().map(|s| s.arclen(1e-3 * period)).sum();
    if (length / period).is_nan() || length / period > MAX_DASHES {
        log::warn!("element '{id}': dash pattern too fine to cut; left to the renderer");
        return None;
    }
    let cut = BezPath::from_vec(kurbo::dash(local.iter(), stroke.dash_offset, d).collect());
    Some(frame * cut)
}

/// How finely artwork is flattened before it is bound: within `tolerance` of the exact curves,
/// and with no segment longer than `max_segment`, so that straight segments bend with the mesh
/// (a two-point segment across a bending mesh would stay straight).
#[derive(Debug, Clone, Copy)]
struct Resolution {
    tolerance: f64,
    max_segment: f64,
    /// Most texture-grid vertices one image may bind ([`IMAGE_POINTS`] shared by all).
    image_points: usize,
}

/// Most texture-grid vertices one binding makes over all its images (about 16 MB of
/// locations): a drawing of a hundred thousand tiny images gets a one-cell grid each instead
/// of gigabytes of grids.
const IMAGE_POINTS: usize = 500_000;

/// Number of images in `g`, at any depth.
fn count_images(g: &super::Group) -> usize {
    g.children
        .iter()
        .map(|c| match c {
            Item::Group(sub) => count_images(sub),
            Item::Image(_) => 1,
            Item::Path(_) => 0,
        })
        .sum()
}

/// The bound grid of an image whose SVG grid is `columns × rows` cells: split
/// [`super::texture::RASTER_SPLIT`] times a side for raster frames when at most `budget`
/// vertices allow it, else not split, else coarsened until they do (at least one cell).
fn grid_within(columns: u32, rows: u32, budget: usize) -> (u32, u32) {
    let points = |c: u32, r: u32| (c as usize + 1) * (r as usize + 1);
    let split = super::texture::RASTER_SPLIT;
    if points(split * columns, split * rows) <= budget {
        return (split * columns, split * rows);
    }
    let (mut c, mut r) = (columns, rows);
    while points(c, r) > budget && (c > 1 || r > 1) {
        c = c.div_ceil(2);
        r = r.div_ceil(2);
    }
    (c, r)
}

/// Most artwork points one binding makes (about 100 MB of locations). Artwork is cut to the
/// reach of the view first, so only a great many segments can come near it; then the
/// resolution is coarsened to fit rather than the morph refused: it is how finely the artwork
/// bends with the mesh, not what the morph is.
const ARTWORK_POINTS: f64 = 3_000_000.0;

/// `res`, coarsened when binding `scene` at it would make more than [`ARTWORK_POINTS`] points
/// (estimated from the control points before anything is flattened): first the splitting of
/// long segments, then the flattening tolerance.
fn within_budget(scene: &Scene, res: Resolution) -> Resolution {
    let (mut flat, mut length) = (0.0, 0.0);
    let mut add = |path: &BezPath| {
        flat += crate::drawing::flattened_count(path, res.tolerance);
        let mut last = kurbo::Point::ORIGIN;
        for el in path.elements() {
            let (pts, n): ([kurbo::Point; 3], usize) = match *el {
                PathEl::MoveTo(p) => {
                    last = p;
                    continue;
                }
                PathEl::LineTo(p) => ([p, p, p], 1),
                PathEl::QuadTo(a, p) => ([a, p, p], 2),
                PathEl::CurveTo(a, b, p) => ([a, b, p], 3),
                PathEl::ClosePath => continue,
            };
            for &q in &pts[..n] {
                length += last.distance(q);
                last = q;
            }
        }
    };
    fn walk(g: &super::Group, add: &mut dyn FnMut(&BezPath)) {
        for s in g.clip.iter().flat_map(|c| &c.shapes) {
            add(&s.path);
        }
        for c in &g.children {
            match c {
                Item::Group(sub) => walk(sub, add),
                Item::Path(p) => add(&p.path),
                Item::Image(_) => {}
            }
        }
    }
    walk(&scene.root, &mut add);
    let splits = length / res.max_segment;
    // NaN (no artwork) or within budget: as asked.
    if flat + splits <= ARTWORK_POINTS || (flat + splits).is_nan() {
        return res;
    }
    let mut out = res;
    if flat < 0.5 * ARTWORK_POINTS {
        out.max_segment = res.max_segment * splits / (ARTWORK_POINTS - flat);
    } else {
        // Wang's count goes with 1/√tolerance.
        out.max_segment = f64::INFINITY;
        out.tolerance = res.tolerance * (flat / (0.5 * ARTWORK_POINTS)).powi(2);
    }
    log::warn!(
        "{}: artwork of about {:.1e} points bound more coarsely (segments up to {:.3e},          flattened within {:.3e} user units)",
        scene.file,
        flat + splits,
        out.max_segment,
        out.tolerance
    );
    out
}

/// Appends the points that split the segment from `a` to `b` into pieces no longer than
/// `max_len` (not `a` itself, not `b`); returns how many.
fn split_segment(points: &mut Vec<Point>, a: Point, b: Point, max_len: f64) -> usize {
    let n = (a.distance(b) / max_len).ceil();
    if n.is_nan() || n <= 1.0 || !n.is_finite() {
        return 0;
    }
    let n = n.min(1e6) as usize;
    points.extend((1..n).map(|k| a.lerp(b, k as f64 / n as f64)));
    n - 1
}

/// Flattens `path` to polylines at resolution `tol` and locates every point.
fn bind_path(path: &BezPath, locator: &Locator, tol: Resolution) -> BoundPath {
    let mut points: Vec<Point> = Vec::new();
    let mut subpaths: Vec<Subpath> = Vec::new();
    kurbo::flatten(path, tol.tolerance, |el| match el {
        PathEl::MoveTo(p) => {
            subpaths.push(Subpath {
                start: points.len(),
                len: 1,
                closed: false,
            });
            points.push(Point::new(p.x, p.y));
        }
        PathEl::LineTo(p) => {
            if let (Some(s), Some(&last)) = (subpaths.last_mut(), points.last()) {
                let q = Point::new(p.x, p.y);
                s.len += split_segment(&mut points, last, q, tol.max_segment) + 1;
                points.push(q);
            }
        }
        PathEl::ClosePath => {
            if let (Some(s), Some(&last)) = (subpaths.last_mut(), points.last()) {
                let first = points[s.start];
                s.len += split_segment(&mut points, last, first, tol.max_segment);
                s.closed = true;
            }
        }
        // flatten only emits the three above.
        PathEl::QuadTo(..) | PathEl::CurveTo(..) => {}
    });
    let bb = path.bounding_box().center();
    let locator = locator.for_item(&points);
    BoundPath {
        subpaths,
        locations: points.iter().map(|&p| locator.locate(p)).collect(),
        anchor: locator.locate(Point::new(bb.x, bb.y)),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proptest::prelude::*;

    /// An `nx` × `ny` grid of squares over `[0, w] × [0, h]`, two triangles each, counter-clockwise.
    pub(crate) fn grid(nx: usize, ny: usize, w: f64, h: f64) -> (Vec<Point>, Vec<[u32; 3]>) {
        let mut pts = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                pts.push(Point::new(
                    w * i as f64 / nx as f64,
                    h * j as f64 / ny as f64,
                ));
            }
        }
        let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        let mut tris = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (pts, tris)
    }

    fn affine_map_of(
        l: &Location,
        tris: &[[u32; 3]],
        rest: &[Point],
        moved: &[Point],
        p: Point,
    ) -> Point {
        // The affine map of triangle l.triangle, applied to p, computed independently.
        let [a, b, c] = tris[l.triangle as usize].map(|v| rest[v as usize]);
        let [a2, b2, c2] = tris[l.triangle as usize].map(|v| moved[v as usize]);
        let m0 = glam::DMat2::from_cols(b - a, c - a);
        let m1 = glam::DMat2::from_cols(b2 - a2, c2 - a2);
        a2 + m1 * (m0.inverse() * (p - a))
    }

    #[test]
    fn straight_segments_bend_with_the_mesh() {
        // A long straight segment across a grid whose right half is bent: its flattened points
        // must include interior ones at most half a mean edge apart, so the warp follows the
        // mesh instead of keeping the segment straight between its warped ends.
        let (pts, tris) = grid(8, 2, 80.0, 20.0);
        let loc = Locator::new(&pts, &tris, None).unwrap();
        let mut path = BezPath::new();
        path.move_to((5.0, 10.0));
        path.line_to((75.0, 10.0));
        let bound = bind_path(
            &path,
            &loc,
            Resolution {
                tolerance: 0.1,
                max_segment: 5.0,
                image_points: IMAGE_POINTS,
            },
        );
        assert_eq!(bound.subpaths[0].len, bound.locations.len());
        // Texture grids share a budget: split 4 × 4 when it allows, else plain, else coarser.
        assert_eq!(grid_within(12, 9, IMAGE_POINTS), (48, 36));
        assert_eq!(grid_within(12, 9, 200), (12, 9));
        assert_eq!(grid_within(12, 9, 30), (3, 3));
        assert_eq!(grid_within(12, 9, 1), (1, 1));
        assert!(
            bound.locations.len() >= 15,
            "{} points",
            bound.locations.len()
        );
        let bent: Vec<Point> = pts
            .iter()
            .map(|p| Point::new(p.x, p.y + 0.01 * p.x * p.x))
            .collect();
        let warped: Vec<Point> = bound
            .locations
            .iter()
            .map(|l| l.place(&tris, &bent))
            .collect();
        // The warped midpoint lies on the bent mesh, well off the chord between the warped ends.
        let mid = warped[warped.len() / 2];
        let chord = warped[0].lerp(*warped.last().unwrap(), 0.5);
        assert!(chord.y - mid.y > 5.0, "mid {mid} chord {chord}");
        // A closed square gets its closing edge split too.
        let mut sq = BezPath::new();
        sq.move_to((10.0, 5.0));
        sq.line_to((30.0, 5.0));
        sq.line_to((30.0, 15.0));
        sq.close_path();
        let b = bind_path(
            &sq,
            &loc,
            Resolution {
                tolerance: 0.1,
                max_segment: 5.0,
                image_points: IMAGE_POINTS,
            },
        );
        assert!(b.subpaths[0].closed);
        assert!(b.subpaths[0].len >= 4 + 2 + 4, "{}", b.subpaths[0].len);
    }

    #[test]
    fn outside_points_take_the_nearest_triangle() {
        let (pts, tris) = grid(4, 3, 40.0, 30.0);
        let loc = PointLocator::new(&pts, &tris).unwrap();
        let p = Point::new(43.0, 15.0);
        let l = loc.locate(p);
        let [a, b, c] = tris[l.triangle as usize].map(|v| pts[v as usize]);
        // The nearest triangle touches the right edge x = 40 at y = 15.
        assert!([a, b, c].iter().any(|q| q.x == 40.0));
        assert!(l.bary.iter().any(|w| *w < 0.0));
        let d = loc.distance_to_triangle(p, l.triangle);
        assert!((d - 3.0).abs() < 1e-12);
        // Far away, beyond the grid in both axes.
        let far = loc.locate(Point::new(-100.0, -50.0));
        let [a, _, _] = tris[far.triangle as usize].map(|v| pts[v as usize]);
        assert_eq!(a, Point::ZERO);
    }

    proptest! {
        #[test]
        fn inside_points_reproduce_with_nonnegative_weights(x in 0.0..40.0f64, y in 0.0..30.0f64) {
            let (pts, tris) = grid(5, 4, 40.0, 30.0);
            let loc = PointLocator::new(&pts, &tris).unwrap();
            let p = Point::new(x, y);
            let l = loc.containing(p).expect("inside");
            prop_assert!(l.bary.iter().all(|w| *w >= 0.0));
            prop_assert!((l.bary.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            prop_assert!(l.place(&tris, &pts).distance(p) < 1e-12);
        }

        #[test]
        fn any_point_follows_its_triangles_affine_map(x in -30.0..70.0f64, y in -30.0..60.0f64,
                                                      ang in -1.0..1.0f64, bend in 0.0..0.3f64) {
            let (pts, tris) = grid(5, 4, 40.0, 30.0);
            let loc = PointLocator::new(&pts, &tris).unwrap();
            let p = Point::new(x, y);
            let l = loc.locate(p);
            prop_assert!(l.place(&tris, &pts).distance(p) < 1e-9);
            // Under a non-affine deformation the point moves with its triangle's affine map.
            let moved: Vec<Point> = pts.iter().map(|q| {
                let r = glam::DMat2::from_angle(ang + bend * q.x / 40.0);
                r * *q + Point::new(5.0, -2.0)
            }).collect();
            let want = affine_map_of(&l, &tris, &pts, &moved, p);
            prop_assert!(l.place(&tris, &moved).distance(want) < 1e-9);
            // Brute force: no triangle is nearer than the chosen one.
            let d = loc.distance_to_triangle(p, l.triangle);
            let inside = l.bary.iter().all(|w| *w >= -1e-12);
            for i in 0..tris.len() as u32 {
                if !inside {
                    prop_assert!(loc.distance_to_triangle(p, i) >= d - 1e-12);
                }
            }
        }
    }

    /// A sparse mesh: two small squares of two triangles each, far apart, so that most of
    /// the locator's grid is empty.
    fn two_islands() -> (Vec<Point>, Vec<[u32; 3]>) {
        let mut pts = Vec::new();
        let mut tris = Vec::new();
        for o in [Point::ZERO, Point::new(90.0, 60.0)] {
            let k = pts.len() as u32;
            pts.extend([
                o,
                o + Point::X * 4.0,
                o + Point::new(4.0, 4.0),
                o + Point::Y * 4.0,
            ]);
            tris.extend([[k, k + 1, k + 2], [k, k + 2, k + 3]]);
        }
        (pts, tris)
    }

    proptest! {
        #[test]
        fn the_nearest_triangle_is_the_brute_force_one(x in -300.0..400.0f64,
                                                       y in -300.0..400.0f64,
                                                       far in proptest::bool::ANY,
                                                       shifted in proptest::bool::ANY) {
            // Points in the empty middle of the grid and far outside it, where the ring
            // search stops on the strips of the grid beyond its rings: the same triangle as
            // trying every one (the lowest index among equals), also where the coordinates
            // are large against the distances (the search skips triangles by their boxes
            // with a margin for rounding).
            let (mut pts, tris) = two_islands();
            let offset = if shifted { Point::new(3.0e7, -1.0e7) } else { Point::ZERO };
            for q in &mut pts {
                *q += offset;
            }
            let loc = PointLocator::new(&pts, &tris).unwrap();
            let p = Point::new(x, y) * if far { 40.0 } else { 1.0 } + offset;
            if loc.containing(p).is_none() {
                prop_assert_eq!(loc.locate(p).triangle, nearest_by_scan(&loc, p));
            }
        }
    }

    /// The triangle nearest to `p` by trying every one (the lowest index among equals).
    fn nearest_by_scan(loc: &PointLocator, p: Point) -> u32 {
        (0..loc.triangles.len() as u32)
            .map(|i| (loc.distance_to_triangle(p, i), i))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map_or(0, |(_, i)| i)
    }

    /// A 12 × 12 grid of unit squares, two triangles each, with some squares left out: many
    /// cells, holes inside and a ragged outline.
    fn holed_grid() -> (Vec<Point>, Vec<[u32; 3]>) {
        let n = 13u32;
        let pts = (0..n * n)
            .map(|k| Point::new((k % n) as f64, (k / n) as f64))
            .collect();
        let mut tris = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                if (i * 7 + j * 3) % 5 == 0 || (3..6).contains(&i) && (4..9).contains(&j) {
                    continue;
                }
                let v = |i: u32, j: u32| j * n + i;
                tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        (pts, tris)
    }

    proptest! {
        #[test]
        fn the_nearest_triangle_of_a_holed_mesh_is_the_brute_force_one(
            x in -30.0..45.0f64,
            y in -30.0..45.0f64,
            whole in proptest::bool::ANY,
        ) {
            // Points in holes, beside the ragged outline and far outside, on whole units
            // (equidistant from several triangles: the lowest index must win) or not.
            let (pts, tris) = holed_grid();
            let loc = PointLocator::new(&pts, &tris).unwrap();
            let p = if whole { Point::new(x.round(), y.round()) } else { Point::new(x, y) };
            if loc.containing(p).is_none() {
                prop_assert_eq!(loc.locate(p).triangle, nearest_by_scan(&loc, p));
            }
        }
    }

    #[test]
    fn degenerate_meshes_are_errors() {
        let pts = vec![Point::ZERO, Point::X, Point::new(2.0, 0.0)];
        assert!(PointLocator::new(&pts, &[[0, 1, 2]]).is_err());
        assert!(PointLocator::new(&pts, &[[0, 1, 7]]).is_err());
        assert!(PointLocator::new(&pts, &[]).is_err());
    }
}
