//! One frame as a standalone SVG file.
//!
//! Frame t shows the warped source and target renderings `S_t` and `T_t` cross-dissolved:
//! `S_t` at opacity `a(t) = min(1, 2(1 − t))` with `T_t` over it at opacity `b(t) = min(1, 2t)`
//! ([`super::dissolve`]): the target fades in over the source during the first half, and what of
//! the source the target does not cover fades out during the second. Two groups with plain
//! `opacity`, nothing else — unlike the paper's linear blend `(1 − t)·S + t·T`, which plain
//! group opacity cannot express (alpha `1 − t + t²` where both are opaque) and which crmorph
//! used to write as an arithmetic `feComposite` over the two drawings side by side. That needs
//! the target drawn beside the view, which librsvg clips away (its frames came out half
//! transparent), so every renderer — resvg, librsvg, Chromium, Firefox — now draws the same
//! thing from the same two groups, and the raster frames composite the same way. Where the two
//! drawings coincide (most of a morph: both are carried by one mesh) the dissolve shows no
//! see-through half-way frame; at t = 0 and t = 1 the frame is the one drawing.
//!
//! A frame may be a stack of such blends interleaved with unblended artwork ([`Layer`]):
//! automatic mode's matched paths morph as one shape each and sit between the blended parts of
//! the rest of the artwork painted below and above them, so the frame keeps the inputs' paint
//! order. Every blend layer is its own pair of groups.
//!
//! Output is deterministic: elements in paint order, generated ids numbered in that order,
//! coordinates rounded to 1/100 px at the output size. Warped (flattened) outlines are fitted
//! with cubic curves within a tenth of a pixel (`render::fit`); the exact input at t = 0 and
//! t = 1 is written as it is.
//!
//! Frames are built as element trees (`render::tree`); the animated SVG
//! ([`super::animated`]) builds one per keyframe in `Mode::Keyframe` and animates what differs.

use super::tree::{fixed, matrix, Builder, Node, NumFormat, Value};
use super::FrameOptions;
use crate::artwork::{
    Gradient, GradientKind, Group, ImageGrid, ImageItem, Item, LineCap, LineJoin, Paint, PathItem,
    Rgba, Scene, Spread, Stroke,
};
use crate::error::Result;
use crate::frame::{Frame, FrameLayer};
use crate::geometry::Point;
use kurbo::Affine;

/// One drawing alone as a standalone SVG (what frames t = 0 and t = 1 are).
pub fn scene_svg(scene: &Scene, opts: &FrameOptions) -> Result<String> {
    scene_tree(scene, opts).to_svg_string()
}

/// The frame at `t` blending the warped `source` and `target` scenes (see the module docs for
/// how). `t` is clamped to [0, 1]; at the ends the frame is [`scene_svg`] of that side.
pub fn frame_svg(source: &Scene, target: &Scene, t: f64, opts: &FrameOptions) -> Result<String> {
    frame_svg_layers(&[Layer::Blend(source, target)], t, opts)
}

/// One layer of a frame. A frame is a stack of layers painted in order: the artwork that
/// cross-fades and the artwork that morphs as one shape (automatic mode's matched paths)
/// interleaved so that the frame keeps the input drawings' paint order.
#[derive(Debug, Clone, Copy)]
pub enum Layer<'a> {
    /// The warped source and target of one part of the artwork, cross-dissolved on their own
    /// (module docs), then painted over the layers below.
    Blend(&'a Scene, &'a Scene),
    /// Artwork painted as it is over the layers below: paths that morph as one shape.
    Over(&'a Scene),
}

impl<'a> From<&'a FrameLayer> for Layer<'a> {
    fn from(l: &'a FrameLayer) -> Self {
        match l {
            FrameLayer::Blend { source, target } => Layer::Blend(source, target),
            FrameLayer::Over(o) => Layer::Over(o),
        }
    }
}

/// The layers of `frame`, borrowed, as the renderers take them.
pub fn layers_of(frame: &Frame) -> Vec<Layer<'_>> {
    frame.layers.iter().map(Layer::from).collect()
}

/// The frame at `t` made of `layers`, bottom first: each [`Layer::Blend`] dissolved on its own
/// as in [`frame_svg`], each [`Layer::Over`] drawn as it is. At
/// t = 0 (t = 1) a blend layer is its source (target) side as it is.
pub fn frame_svg_layers(layers: &[Layer], t: f64, opts: &FrameOptions) -> Result<String> {
    frame_tree(layers, t, opts, Mode::Still).to_svg_string()
}

/// How far (in output pixels) a curve fitted to warped artwork may stray from the warped
/// polyline. The polyline is itself within a quarter pixel of the exact warp; a tenth more keeps
/// SVG frames visually identical to the raster frames rendered from the polylines.
const FIT_PIXELS: f64 = 0.1;

/// The same for animation keyframes, whose geometry is only ever seen moving: a quarter pixel.
const FIT_PIXELS_IN_MOTION: f64 = 0.25;

/// What a frame tree is built for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mode {
    /// A standalone frame: the ends are the plain input drawings, in-betweens blended.
    Still,
    /// An animation keyframe: always the blend (so every keyframe has the same elements), and
    /// attributes that a still frame omits at their default value always written.
    Keyframe,
}

/// One warped side of an in-between frame alone, outlines fitted as in [`frame_svg`], without
/// background (for the raster blend).
pub(crate) fn side_svg(scene: &Scene, opts: &FrameOptions) -> Result<String> {
    let opts = FrameOptions {
        background: None,
        ..*opts
    };
    let mut doc = Document::new(&opts, Some(FIT_PIXELS / opts.scale()), false);
    let mut defs = Builder::new();
    let mut body = Builder::new();
    doc.side(scene, "a", &mut defs, &mut body);
    doc.finish(&opts, defs, body).to_svg_string()
}

/// One drawing alone, as a tree.
pub(crate) fn scene_tree(scene: &Scene, opts: &FrameOptions) -> Node {
    end_tree(&[Layer::Blend(scene, scene)], true, opts)
}

/// The layers at one end (`source` side or target side) as they are: the blend layers' input
/// artwork exact, overlays fitted.
fn end_tree(layers: &[Layer], source: bool, opts: &FrameOptions) -> Node {
    let mut doc = Document::new(opts, None, false);
    let mut defs = Builder::new();
    let mut body = Builder::new();
    for layer in layers {
        match *layer {
            Layer::Blend(s, g) => {
                doc.fit = None;
                doc.side(if source { s } else { g }, "a", &mut defs, &mut body);
            }
            Layer::Over(o) => {
                doc.fit = Some(FIT_PIXELS / opts.scale());
                doc.side(o, "o", &mut defs, &mut body);
            }
        }
    }
    doc.finish(opts, defs, body)
}

/// The frame at `t` as a tree (see [`frame_svg_layers`]; `Mode::Keyframe` blends at every t).
pub(crate) fn frame_tree(layers: &[Layer], t: f64, opts: &FrameOptions, mode: Mode) -> Node {
    let t = crate::rigid::clamp_time(t);
    if mode == Mode::Still && (t == 0.0 || t == 1.0) {
        return end_tree(layers, t == 0.0, opts);
    }
    let tol = match mode {
        Mode::Still => FIT_PIXELS,
        Mode::Keyframe => FIT_PIXELS_IN_MOTION,
    } / opts.scale();
    let mut doc = Document::new(opts, Some(tol), mode == Mode::Keyframe);
    let mut defs = Builder::new();
    let mut body = Builder::new();
    let (a, b) = super::dissolve(t);
    for layer in layers {
        match *layer {
            Layer::Blend(source, target) => {
                // The class names the layer for tools; the opacities are the dissolve.
                for (scene, prefix, class, opacity) in [
                    (source, "s", "crmorph-source", a),
                    (target, "t", "crmorph-target", b),
                ] {
                    body.open(
                        "g",
                        vec![
                            ("class", class.into()),
                            ("opacity", Value::num(opacity, NumFormat::Sig)),
                        ],
                    );
                    doc.side(scene, prefix, &mut defs, &mut body);
                    body.close();
                }
            }
            Layer::Over(o) => doc.side(o, "o", &mut defs, &mut body),
        }
    }
    doc.finish(opts, defs, body)
}

type Attrs = Vec<(&'static str, Value)>;

/// Shared state of one output document: number precision, fitting and generated-id counters.
struct Document {
    decimals: usize,
    /// Curve-fitting tolerance for warped outlines (user units), `None` for the exact input.
    fit: Option<f64>,
    /// Write every attribute that can vary between frames, even at its default value.
    uniform: bool,
    next_id: usize,
    /// Output pixels per user unit.
    px_per_unit: f64,
}

impl Document {
    fn new(opts: &FrameOptions, fit: Option<f64>, uniform: bool) -> Self {
        // 1/100 px in user units, as a count of decimals.
        let step = 0.01 / opts.scale();
        let decimals = if step.is_finite() && step > 0.0 {
            (-step.log10()).ceil().clamp(0.0, 12.0) as usize
        } else {
            3
        };
        Document {
            decimals,
            fit,
            uniform,
            next_id: 0,
            px_per_unit: opts.scale(),
        }
    }

    fn num(&self, x: f64) -> Value {
        Value::num(x, NumFormat::Fixed(self.decimals))
    }

    fn finish(self, opts: &FrameOptions, defs: Builder, body: Builder) -> Node {
        let (lo, hi) = opts.view_box;
        let vb = [lo.x, lo.y, hi.x - lo.x, hi.y - lo.y]
            .map(|x| fixed(x, self.decimals))
            .join(" ");
        let mut root = Node::new(
            "svg",
            vec![
                ("xmlns", "http://www.w3.org/2000/svg".into()),
                ("xmlns:xlink", "http://www.w3.org/1999/xlink".into()),
                ("width", opts.size.0.to_string().into()),
                ("height", opts.size.1.to_string().into()),
                ("viewBox", vb.into()),
            ],
        );
        if !defs.is_empty() {
            let mut d = Node::new("defs", Vec::new());
            d.children = defs.finish();
            root.children.push(d);
        }
        if let Some(bg) = opts.background {
            let mut a = vec![
                ("x", self.num(lo.x)),
                ("y", self.num(lo.y)),
                ("width", self.num(hi.x - lo.x)),
                ("height", self.num(hi.y - lo.y)),
                ("fill", hex(bg).into()),
            ];
            if bg.a != 255 {
                a.push((
                    "fill-opacity",
                    Value::num(bg.a as f64 / 255.0, NumFormat::Sig),
                ));
            }
            root.children.push(Node::new("rect", a));
        }
        root.children.extend(body.finish());
        root
    }

    fn path_value(&self, path: kurbo::BezPath, decimals: usize) -> Value {
        Value::Path {
            path,
            decimals,
            fit: self.fit,
        }
    }

    /// Writes one scene's artwork into `body`, its gradients into `defs`, with ids prefixed by
    /// `prefix` (so the two sides of a frame never share an id).
    fn side(&mut self, scene: &Scene, prefix: &str, defs: &mut Builder, body: &mut Builder) {
        let wrap = scene.root_transform != Affine::IDENTITY;
        if wrap {
            body.open(
                "g",
                vec![("transform", matrix(scene.root_transform).into())],
            );
        }
        self.children(&scene.root, prefix, defs, body);
        if wrap {
            body.close();
        }
    }

    fn children(&mut self, g: &Group, prefix: &str, defs: &mut Builder, body: &mut Builder) {
        for c in &g.children {
            match c {
                Item::Group(sub) => {
                    let mut a = Vec::new();
                    if sub.opacity != 1.0 {
                        a.push(("opacity", Value::num(sub.opacity, NumFormat::Sig)));
                    }
                    if let Some(clip) = &sub.clip {
                        let id = format!("{prefix}{}", self.next_id);
                        self.next_id += 1;
                        defs.open("clipPath", vec![("id", id.clone().into())]);
                        for shape in &clip.shapes {
                            let mut sa =
                                vec![("d", self.path_value(shape.path.clone(), self.decimals))];
                            if shape.even_odd {
                                sa.push(("clip-rule", "evenodd".into()));
                            }
                            defs.empty("path", sa);
                        }
                        defs.close();
                        a.push(("clip-path", format!("url(#{id})").into()));
                    }
                    body.open("g", a);
                    self.children(sub, prefix, defs, body);
                    body.close();
                }
                Item::Path(p) => self.path(p, prefix, defs, body),
                Item::Image(img) => self.image(img, prefix, defs, body),
            }
        }
    }

    fn path(&mut self, p: &PathItem, prefix: &str, defs: &mut Builder, body: &mut Builder) {
        if p.path.elements().is_empty() {
            return;
        }
        // A shaped pen is drawn in its own frame: the outline mapped back into it, the frame as
        // the element's transform, gradients re-expressed in it. (A degenerate frame falls back
        // to the identity, so keyframes keep their structure.)
        let frame = p.stroke.as_ref().and_then(|s| s.frame).map(|f| {
            if f.determinant().is_finite() && f.determinant() != 0.0 {
                f
            } else {
                Affine::IDENTITY
            }
        });
        let (d, to_local) = match frame {
            None => (
                self.path_value(p.path.clone(), self.decimals),
                Affine::IDENTITY,
            ),
            Some(f) => {
                let inv = f.inverse();
                let [a, b, c, dd, _, _] = f.as_coeffs();
                // Local units are this many user units at most: keep 1/100 px in them too.
                let stretch = (a * a + b * b).max(c * c + dd * dd).sqrt().max(1e-12);
                let extra = stretch.log10().ceil().clamp(0.0, 12.0) as usize;
                let mut v = self.path_value(inv * p.path.clone(), self.decimals + extra);
                if let Value::Path { fit: Some(tol), .. } = &mut v {
                    *tol /= stretch;
                }
                (v, inv)
            }
        };
        let mut a = vec![("d", d)];
        if let Some(f) = frame {
            a.push(("transform", Value::Matrix(f)));
        }
        match &p.fill {
            Some(f) => {
                a.push(("fill", self.paint(&f.paint, to_local, prefix, defs)));
                if f.opacity != 1.0 || self.uniform {
                    a.push(("fill-opacity", Value::num(f.opacity, NumFormat::Sig)));
                }
                if f.even_odd {
                    a.push(("fill-rule", "evenodd".into()));
                }
            }
            None => a.push(("fill", "none".into())),
        }
        if let Some(s) = &p.stroke {
            self.stroke_attrs(s, to_local, prefix, defs, &mut a);
            if p.stroke_first && p.fill.is_some() {
                a.push(("paint-order", "stroke".into()));
            }
        }
        body.empty("path", a);
    }

    fn stroke_attrs(
        &mut self,
        s: &Stroke,
        to_local: Affine,
        prefix: &str,
        defs: &mut Builder,
        a: &mut Attrs,
    ) {
        a.push(("stroke", self.paint(&s.paint, to_local, prefix, defs)));
        // Stroke widths keep two more decimals than coordinates: hairlines matter. In a pen's
        // own frame, units are not pixels: keep significant digits instead.
        let format = if s.frame.is_some() {
            NumFormat::Sig
        } else {
            NumFormat::Fixed(self.decimals + 2)
        };
        a.push(("stroke-width", Value::num(s.width, format)));
        if s.opacity != 1.0 || self.uniform {
            a.push(("stroke-opacity", Value::num(s.opacity, NumFormat::Sig)));
        }
        match s.cap {
            LineCap::Butt => {}
            LineCap::Round => a.push(("stroke-linecap", "round".into())),
            LineCap::Square => a.push(("stroke-linecap", "square".into())),
        }
        match s.join {
            LineJoin::Miter => {}
            LineJoin::MiterClip => a.push(("stroke-linejoin", "miter-clip".into())),
            LineJoin::Round => a.push(("stroke-linejoin", "round".into())),
            LineJoin::Bevel => a.push(("stroke-linejoin", "bevel".into())),
        }
        if s.miter_limit != 4.0 || self.uniform {
            a.push((
                "stroke-miterlimit",
                Value::num(s.miter_limit, NumFormat::Sig),
            ));
        }
        if !s.dashes.is_empty() {
            a.push(("stroke-dasharray", Value::Nums(s.dashes.clone(), format)));
            if s.dash_offset != 0.0 || self.uniform {
                a.push(("stroke-dashoffset", Value::num(s.dash_offset, format)));
            }
        }
    }

    /// A paint attribute value; gradients are written to `defs`, their geometry mapped by
    /// `to_local` into the element's coordinates.
    fn paint(
        &mut self,
        paint: &Paint,
        to_local: Affine,
        prefix: &str,
        defs: &mut Builder,
    ) -> Value {
        match paint {
            Paint::Color(c) => Value::Color(*c),
            Paint::Gradient(g) => {
                let id = format!("{prefix}{}", self.next_id);
                self.next_id += 1;
                self.gradient(g, to_local * g.transform, &id, defs);
                format!("url(#{id})").into()
            }
        }
    }

    fn gradient(&self, g: &Gradient, transform: Affine, id: &str, defs: &mut Builder) {
        let mut a: Attrs = vec![
            ("id", id.into()),
            ("gradientUnits", "userSpaceOnUse".into()),
        ];
        let s = |x: f64| Value::num(x, NumFormat::Sig);
        let name = match g.kind {
            GradientKind::Linear { start, end } => {
                a.extend([
                    ("x1", s(start.x)),
                    ("y1", s(start.y)),
                    ("x2", s(end.x)),
                    ("y2", s(end.y)),
                ]);
                "linearGradient"
            }
            GradientKind::Radial {
                center,
                radius,
                focal,
                focal_radius,
            } => {
                a.extend([
                    ("cx", s(center.x)),
                    ("cy", s(center.y)),
                    ("r", s(radius)),
                    ("fx", s(focal.x)),
                    ("fy", s(focal.y)),
                ]);
                if focal_radius != 0.0 || self.uniform {
                    a.push(("fr", s(focal_radius)));
                }
                "radialGradient"
            }
        };
        if transform != Affine::IDENTITY || self.uniform {
            a.push(("gradientTransform", Value::Matrix(transform)));
        }
        match g.spread {
            Spread::Pad => {}
            Spread::Reflect => a.push(("spreadMethod", "reflect".into())),
            Spread::Repeat => a.push(("spreadMethod", "repeat".into())),
        }
        defs.open(name, a);
        for st in &g.stops {
            let mut sa: Attrs = vec![
                ("offset", s(st.offset)),
                ("stop-color", hex(st.color).into()),
            ];
            if st.opacity != 1.0 || self.uniform {
                sa.push(("stop-opacity", s(st.opacity)));
            }
            defs.empty("stop", sa);
        }
        defs.close();
    }

    /// An image: as it is in the input's geometry (`fit` unset: the ends of a still frame),
    /// else warped by its texture grid, piece by piece (`texture`).
    fn image(&mut self, img: &ImageItem, prefix: &str, defs: &mut Builder, body: &mut Builder) {
        match &img.grid {
            Some(grid) if self.fit.is_some() => self.texture(img, grid, prefix, defs, body),
            _ => self.plain_image(img, body),
        }
    }

    /// A warped image: the image once in `defs`, then one `<use>` of it per triangle of its
    /// texture grid, clipped to that triangle (in the image's pixels, so the clip never moves)
    /// and placed by the triangle's affine map. Only the maps change from frame to frame, so
    /// the animated SVG animates transforms alone. The clip triangles overlap their
    /// neighbours by half an output pixel (at the image's rest scale), so that renderers that
    /// antialias each clip leave no seam between them; the image's own edge is not grown.
    fn texture(
        &mut self,
        img: &ImageItem,
        grid: &ImageGrid,
        prefix: &str,
        defs: &mut Builder,
        body: &mut Builder,
    ) {
        let id = format!("{prefix}{}", self.next_id);
        self.next_id += 1;
        let a = image_attrs(img, vec![("id", id.clone().into())], None);
        defs.empty("image", a);
        // Half an output pixel in image pixels, at the image's rest placement.
        let px = self.px_per_unit * img.transform.determinant().abs().sqrt();
        let overlap = if px.is_finite() && px > 0.0 {
            0.5 / px
        } else {
            0.0
        };
        let decimals = if overlap > 0.0 {
            (-(overlap / 10.0).log10()).ceil().clamp(0.0, 12.0) as usize
        } else {
            3
        };
        body.open("g", Vec::new());
        for piece in grid.pieces_every(img, crate::artwork::RASTER_SPLIT) {
            let clip = format!("{prefix}{}", self.next_id);
            self.next_id += 1;
            let tri = grown(piece.image, overlap, img.width, img.height);
            let mut outline = kurbo::BezPath::new();
            outline.move_to((tri[0].x, tri[0].y));
            outline.line_to((tri[1].x, tri[1].y));
            outline.line_to((tri[2].x, tri[2].y));
            outline.close_path();
            defs.open("clipPath", vec![("id", clip.clone().into())]);
            defs.empty(
                "path",
                vec![(
                    "d",
                    Value::Path {
                        path: outline,
                        decimals,
                        fit: None,
                    },
                )],
            );
            defs.close();
            // A degenerate placement draws nothing but keeps the element (keyframes line up).
            let m = piece.transform().unwrap_or(Affine::scale(0.0));
            body.empty(
                "use",
                vec![
                    ("xlink:href", format!("#{id}").into()),
                    ("transform", Value::Matrix(m)),
                    ("clip-path", format!("url(#{clip})").into()),
                ],
            );
        }
        body.close();
    }

    /// An image drawn with its own transform.
    fn plain_image(&self, img: &ImageItem, body: &mut Builder) {
        let a = image_attrs(img, Vec::new(), Some(img.transform));
        body.empty("image", a);
    }
}

/// The attributes of an `<image>` element of `img`: `lead` first, then its size, its
/// placement `transform` if any, its sampling and its data.
fn image_attrs(img: &ImageItem, lead: Attrs, transform: Option<Affine>) -> Attrs {
    let s = |x: f64| Value::num(x, NumFormat::Sig);
    let mut a = lead;
    a.extend([
        ("width", s(img.width)),
        ("height", s(img.height)),
        ("preserveAspectRatio", "none".into()),
    ]);
    if let Some(m) = transform {
        a.push(("transform", Value::Matrix(m)));
    }
    if img.pixelated {
        a.push(("image-rendering", "optimizeSpeed".into()));
    }
    a.push((
        "xlink:href",
        format!(
            "data:{};base64,{}",
            img.mime,
            crate::base64::encode(&img.data)
        )
        .into(),
    ));
    a
}

/// Triangle `tri` (image pixels) with every edge that is not on the image's edge (`0 ≤ x ≤
/// width`, `0 ≤ y ≤ height`) moved out by `by`.
fn grown(tri: [Point; 3], by: f64, width: f64, height: f64) -> [Point; 3] {
    if by <= 0.0 {
        return tri;
    }
    let on_edge = |a: Point, b: Point| {
        (a.x == 0.0 && b.x == 0.0)
            || (a.y == 0.0 && b.y == 0.0)
            || (a.x == width && b.x == width)
            || (a.y == height && b.y == height)
    };
    let ccw = crate::geometry::orient2d(tri[0], tri[1], tri[2]) > 0.0;
    // Each edge i (from corner i to corner i + 1) as a line n·p = c with n pointing out.
    let lines: Vec<(Point, f64)> = (0..3)
        .map(|i| {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            let d = (b - a).normalize_or_zero();
            let n = if ccw {
                Point::new(d.y, -d.x)
            } else {
                Point::new(-d.y, d.x)
            };
            let shift = if on_edge(a, b) { 0.0 } else { by };
            (n, n.dot(a) + shift)
        })
        .collect();
    // Corner i is where edges i − 1 and i meet.
    let mut out = tri;
    for (i, corner) in out.iter_mut().enumerate() {
        let (n1, c1) = lines[(i + 2) % 3];
        let (n2, c2) = lines[i];
        let det = n1.x * n2.y - n1.y * n2.x;
        if det.abs() > 1e-12 {
            *corner = Point::new((c1 * n2.y - c2 * n1.y) / det, (n1.x * c2 - n2.x * c1) / det);
        }
    }
    out
}

fn hex(c: Rgba) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_triangles_grow_inside_the_image_only() {
        // The top-left triangle of a 10 × 10 cell in the image's corner: its top and left
        // edges are the image's edge and stay; its diagonal moves out by 0.5.
        let tri = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(0.0, 10.0),
        ];
        let g = grown(tri, 0.5, 100.0, 100.0);
        assert_eq!(g[0], Point::new(0.0, 0.0));
        assert!(g[1].y == 0.0 && g[2].x == 0.0);
        // The diagonal x + y = 10 moved to x + y = 10 + 0.5·√2.
        let want = 10.0 + 0.5 * std::f64::consts::SQRT_2;
        assert!((g[1].x - want).abs() < 1e-12 && (g[2].y - want).abs() < 1e-12);
        // Nothing to grow by: as it was.
        assert_eq!(grown(tri, 0.0, 100.0, 100.0), tri);
    }
}
