//! The artwork of a drawing and how it rides on the morph (the end of the paper's §3: "a sequence
//! of appearance-preserving in-between shapes is obtained by transferring the underlying source and
//! target shapes to the intermediate triangulations").
//!
//! ```text
//! SVG ─usvg─▶ Scene (exact curves, root user space)            scene
//!   ─within reach of the view (far paths cut or left out)─▶      reach
//!   ─flatten at ¼ px, locate in the mesh─▶ Binding              bind
//!   ─frame vertices (mesh at t)─▶ warped Scene (polylines)      warp
//! ```
//!
//! A [`Scene`] keeps what the renderers need and nothing else: paths with their fill and stroke,
//! groups with their opacity (so group opacity composites as in the input), and embedded raster
//! images with their placement (warped piecewise-affinely on a texture grid, `texture`). Geometry lives in the *user space of the root element* (viewBox
//! coordinates), the space the meshes live in. A [`Binding`] expresses every artwork point in
//! barycentric coordinates of the mesh once; [`Binding::warp`] re-places the artwork in the mesh of
//! any frame without re-locating anything.
//!
//! Supported: solid, linear and radial gradient paint (stops, spread, `gradientTransform`), fill
//! rule, fill/stroke opacity, stroke width, caps, joins, miter limit, dashes, `paint-order`, group
//! opacity, clip paths (warped like paths), text (as the glyph outlines usvg produces from the
//! system fonts; without fonts text has no glyphs), embedded PNG/JPEG/GIF/WebP images. Not
//! supported, with a `log::warn!`: a clip path's own `clip-path` (ignored: the outer clip
//! applies alone), masks (content rendered unmasked), filters (content rendered unfiltered),
//! patterns (that paint is dropped), blend modes (rendered as normal), nested SVG images
//! (skipped).

mod bind;
mod pair;
mod reach;
mod scene;
mod texture;
mod warp;

pub use bind::{Binding, Location, PointLocator};
pub use pair::ArtworkPair;
pub use reach::{within_reach, FarPath, REACH};
pub use scene::flatten_tolerance;
pub(crate) use texture::RASTER_SPLIT;
pub use texture::{DecodedImage, ImageGrid, ImagePiece, Texels};
pub(crate) use warp::at_rest;

#[cfg(test)]
pub(crate) use bind::tests as bind_tests;

use crate::geometry::Point;
use kurbo::{Affine, BezPath};
use std::sync::Arc;

/// An RGBA colour with straight (not premultiplied) 8-bit channels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgba {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
    /// Alpha (255 is opaque).
    pub a: u8,
}

impl Rgba {
    /// Fully transparent black.
    pub const TRANSPARENT: Rgba = Rgba {
        r: 0,
        g: 0,
        b: 0,
        a: 0,
    };
}

/// One drawing's artwork, ready to be bound to a mesh or rendered.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The file name used in error messages.
    pub file: String,
    /// The root's viewBox as `(min, max)` corners, in user units.
    pub view_box: (Point, Point),
    /// The drawing's own size in px (the root's `width`/`height`, else the viewBox size).
    pub size: (f64, f64),
    /// Extra transform to apply inside the root, in user space, so that an output with the same
    /// viewBox renders like the input: identity unless the root element has a `transform`.
    pub root_transform: Affine,
    /// The artwork tree, in paint order.
    pub root: Group,
}

/// A group: its children composite together, are clipped, then drawn onto the parent with
/// `opacity`.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The group's id in the input (empty when it had none).
    pub id: String,
    /// Group opacity in [0, 1].
    pub opacity: f64,
    /// The clip path, if any: only what lies inside one of its shapes is drawn.
    pub clip: Option<Clip>,
    /// Children in paint order.
    pub children: Vec<Item>,
}

/// A clip path: the union of its shapes, in root user space.
#[derive(Debug, Clone, PartialEq)]
pub struct Clip {
    /// The shapes; an empty list clips everything away.
    pub shapes: Vec<ClipShape>,
}

/// One shape of a clip path.
#[derive(Debug, Clone, PartialEq)]
pub struct ClipShape {
    /// The outline in root user space.
    pub path: BezPath,
    /// `true` for `clip-rule: evenodd`.
    pub even_odd: bool,
}

/// One artwork element.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A group of elements.
    Group(Group),
    /// A filled and/or stroked path.
    Path(PathItem),
    /// An embedded raster image.
    Image(ImageItem),
}

/// A path with its paint, in root user space.
#[derive(Debug, Clone, PartialEq)]
pub struct PathItem {
    /// The element id in the input (may be empty).
    pub id: String,
    /// The outline in root user space: exact curves when read, polylines once warped.
    pub path: BezPath,
    /// Fill, if any.
    pub fill: Option<Fill>,
    /// Stroke, if any.
    pub stroke: Option<Stroke>,
    /// Whether the stroke is painted before the fill (`paint-order: stroke`).
    pub stroke_first: bool,
}

/// A fill.
#[derive(Debug, Clone, PartialEq)]
pub struct Fill {
    /// What it is painted with.
    pub paint: Paint,
    /// Fill opacity in [0, 1].
    pub opacity: f64,
    /// `true` for `fill-rule: evenodd`, `false` for nonzero.
    pub even_odd: bool,
}

/// A stroke; widths and dashes are in root user units, or in the units of `frame` when set.
#[derive(Debug, Clone, PartialEq)]
pub struct Stroke {
    /// What it is painted with.
    pub paint: Paint,
    /// Stroke opacity in [0, 1].
    pub opacity: f64,
    /// Stroke width in user units.
    pub width: f64,
    /// Line cap.
    pub cap: LineCap,
    /// Line join.
    pub join: LineJoin,
    /// Miter limit (a ratio, unaffected by scale).
    pub miter_limit: f64,
    /// Dash lengths in user units (empty: solid).
    pub dashes: Vec<f64>,
    /// Dash offset in user units.
    pub dash_offset: f64,
    /// For a pen that is not round in user space (the input stroked under a non-uniform scale
    /// or a skew): the local frame (local → user space) in which `width` and the dashes are
    /// measured, so the pen keeps its shape. `None`: they are in user units.
    pub frame: Option<Affine>,
}

/// Line cap of a stroke (`stroke-linecap`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineCap {
    /// `butt`.
    Butt,
    /// `round`.
    Round,
    /// `square`.
    Square,
}

/// Line join of a stroke (`stroke-linejoin`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineJoin {
    /// `miter`.
    Miter,
    /// `miter-clip`.
    MiterClip,
    /// `round`.
    Round,
    /// `bevel`.
    Bevel,
}

/// A paint server.
#[derive(Debug, Clone, PartialEq)]
pub enum Paint {
    /// A solid colour (opaque RGB; opacity is on the fill or stroke).
    Color(Rgba),
    /// A linear or radial gradient.
    Gradient(Arc<Gradient>),
}

/// A gradient in `userSpaceOnUse` units: its geometry, mapped to root user space by `transform`.
#[derive(Debug, Clone, PartialEq)]
pub struct Gradient {
    /// Linear or radial geometry, in gradient space.
    pub kind: GradientKind,
    /// Gradient space → root user space (includes the element's transforms and, once warped, the
    /// local affine map of the mesh).
    pub transform: Affine,
    /// `spreadMethod`.
    pub spread: Spread,
    /// Colour stops, offsets ascending in [0, 1].
    pub stops: Vec<GradientStop>,
}

/// The geometry of a gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GradientKind {
    /// From `(x1, y1)` to `(x2, y2)`.
    Linear {
        /// Start point.
        start: Point,
        /// End point.
        end: Point,
    },
    /// Centre `c`, radius `r`, focal point `f` with focal radius `fr`.
    Radial {
        /// Centre of the end circle.
        center: Point,
        /// Radius of the end circle.
        radius: f64,
        /// Centre of the focal circle.
        focal: Point,
        /// Radius of the focal circle.
        focal_radius: f64,
    },
}

/// `spreadMethod` of a gradient.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spread {
    /// `pad`.
    Pad,
    /// `reflect`.
    Reflect,
    /// `repeat`.
    Repeat,
}

/// One gradient stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GradientStop {
    /// Offset in [0, 1].
    pub offset: f64,
    /// Colour with `a` = 255 (opacity is separate).
    pub color: Rgba,
    /// `stop-opacity` in [0, 1].
    pub opacity: f64,
}

/// An embedded raster image.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageItem {
    /// The element id in the input (may be empty).
    pub id: String,
    /// The encoded image and its MIME type (`image/png`, `image/jpeg`, `image/gif`,
    /// `image/webp`).
    pub data: Arc<Vec<u8>>,
    /// MIME type of `data`.
    pub mime: &'static str,
    /// Pixel size of the image.
    pub width: f64,
    /// Pixel size of the image.
    pub height: f64,
    /// Image pixel rectangle `(0, 0)–(width, height)` → root user space.
    pub transform: Affine,
    /// Whether to sample with nearest neighbour (`image-rendering: pixelated` and the like).
    pub pixelated: bool,
    /// Once bound to a mesh and warped: where the image's texture grid lies in the frame, so
    /// that the image is drawn piecewise-affinely, cell triangle by cell triangle (the paper's
    /// textures, §3 Fig. 2). `None` for the image as read, drawn with `transform` alone.
    pub grid: Option<ImageGrid>,
    /// The decoded pixels, decoded once on first use and shared by every warped copy.
    pub pixels: DecodedImage,
}

/// A bounding box `(min, max)`, or `None` for nothing.
pub type Bounds = Option<(Point, Point)>;

/// The smallest box holding both.
pub fn union_bounds(a: Bounds, b: Bounds) -> Bounds {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

fn rect_bounds(r: kurbo::Rect) -> Bounds {
    let (lo, hi) = (Point::new(r.x0, r.y0), Point::new(r.x1, r.y1));
    (lo.is_finite() && hi.is_finite() && lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
}

/// The box of `b` under `m` (the box of its transformed corners).
fn transformed_bounds(b: Bounds, m: Affine) -> Bounds {
    let (lo, hi) = b?;
    let corners = [(lo.x, lo.y), (hi.x, lo.y), (hi.x, hi.y), (lo.x, hi.y)]
        .map(|(x, y)| m * kurbo::Point::new(x, y))
        .map(|p| Some((Point::new(p.x, p.y), Point::new(p.x, p.y))));
    corners.into_iter().fold(None, union_bounds)
}

impl Group {
    /// The box of what the group draws, in root user space: its children's, strokes with
    /// their half width (more at miter joins and square caps), images by their corners,
    /// limited to the clip's box.
    pub fn bounds(&self) -> Bounds {
        let mut b: Bounds = None;
        for c in &self.children {
            let own = match c {
                Item::Group(g) => g.bounds(),
                Item::Path(p) => {
                    let path = rect_bounds(kurbo::Shape::bounding_box(&p.path));
                    match (&p.stroke, path) {
                        (Some(s), Some((lo, hi))) => {
                            let reach = match (s.join, s.cap) {
                                (LineJoin::Miter | LineJoin::MiterClip, _) => {
                                    s.miter_limit.max(1.0)
                                }
                                (_, LineCap::Square) => std::f64::consts::SQRT_2,
                                _ => 1.0,
                            };
                            let pen = s.frame.map_or(1.0, |f| {
                                let [a, b, c, d, _, _] = f.as_coeffs();
                                (a * a + b * b + c * c + d * d).sqrt()
                            });
                            let r = Point::splat(0.5 * s.width * reach * pen);
                            Some((lo - r, hi + r))
                        }
                        _ => path,
                    }
                }
                Item::Image(i) => transformed_bounds(
                    Some((Point::ZERO, Point::new(i.width, i.height))),
                    i.transform,
                ),
            };
            b = union_bounds(b, own);
        }
        match (&self.clip, b) {
            (Some(clip), Some((lo, hi))) => {
                let c = clip
                    .shapes
                    .iter()
                    .map(|s| rect_bounds(kurbo::Shape::bounding_box(&s.path)))
                    .fold(None, union_bounds)?;
                let (lo, hi) = (lo.max(c.0), hi.min(c.1));
                (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
            }
            _ => b,
        }
    }
}

impl Scene {
    /// The box of everything the scene draws, in the root's user space (after
    /// [`Scene::root_transform`]): what a view must hold for nothing to be cut off.
    pub fn bounds(&self) -> Bounds {
        transformed_bounds(self.root.bounds(), self.root_transform)
    }

    /// Every path and image in paint order, depth first (for tests and statistics).
    pub fn items(&self) -> Vec<&Item> {
        fn walk<'a>(g: &'a Group, out: &mut Vec<&'a Item>) {
            for c in &g.children {
                out.push(c);
                if let Item::Group(sub) = c {
                    walk(sub, out);
                }
            }
        }
        let mut out = Vec::new();
        walk(&self.root, &mut out);
        out
    }
}

/// Converts a crmorph point to a kurbo point.
pub(crate) fn to_kurbo(p: Point) -> kurbo::Point {
    kurbo::Point::new(p.x, p.y)
}

/// Number of subpaths (move-to commands) of `path`.
pub(crate) fn subpath_count(path: &kurbo::BezPath) -> usize {
    path.elements()
        .iter()
        .filter(|e| matches!(e, kurbo::PathEl::MoveTo(_)))
        .count()
}
