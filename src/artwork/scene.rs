//! Reading a drawing's artwork with usvg into a [`Scene`] in the root's user space.
//!
//! usvg resolves styles, `use`, shapes, text and units, and bakes the root's viewBox→viewport
//! mapping (and the root's own `transform`) into every absolute transform. crmorph's meshes live
//! in the root's user space (viewBox coordinates), so that mapping is computed here from the
//! root's `viewBox`, `preserveAspectRatio` and `transform` and undone.

use super::{
    Clip, ClipShape, Fill, Gradient, GradientKind, GradientStop, Group, ImageItem, Item, LineCap,
    LineJoin, Paint, PathItem, Rgba, Scene, Spread, Stroke,
};
use crate::error::{Error, Result};
use crate::geometry::Point;
use crate::input::InputPolicy;
use kurbo::{Affine, BezPath};
use std::path::Path;
use std::str::FromStr;
use std::sync::{Arc, OnceLock};

/// The flattening tolerance, in user units, that keeps the output error under a quarter pixel
/// when `view_box` is rendered at `size` px (the finer of the two axis scales is used).
pub fn flatten_tolerance(view_box: (Point, Point), size: (f64, f64)) -> f64 {
    let d = view_box.1 - view_box.0;
    let scale = (size.0 / d.x).max(size.1 / d.y);
    if scale.is_finite() && scale > 0.0 {
        0.25 / scale
    } else {
        // A degenerate view: any positive tolerance will do, nothing is visible.
        d.length().max(1.0) * 1e-3
    }
}

/// The system fonts, loaded once per process for text (usvg turns text into glyph paths), and
/// the family used for text that names none (the serif family, as in browsers).
fn fonts() -> (Arc<usvg::fontdb::Database>, String) {
    static FONTS: OnceLock<(Arc<usvg::fontdb::Database>, String)> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = usvg::fontdb::Database::new();
            db.load_system_fonts();
            set_generic_families(&mut db);
            let serif = db.family_name(&usvg::fontdb::Family::Serif).to_string();
            (Arc::new(db), serif)
        })
        .clone()
}

/// Points the generic families (`serif`, `sans-serif`, `monospace`) at installed fonts when
/// fontdb's defaults (Times New Roman, Arial, Courier New) are missing, as on most Linux systems,
/// so that text in a generic family still gets glyphs. Candidates are tried in a fixed order.
fn set_generic_families(db: &mut usvg::fontdb::Database) {
    let mut installed: Vec<String> = db
        .faces()
        .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
        .collect();
    installed.sort();
    installed.dedup();
    let has = |name: &str| installed.binary_search(&name.to_string()).is_ok();
    let pick = |wanted: &[&str]| -> Option<String> {
        wanted.iter().find(|n| has(n)).map(|n| n.to_string())
    };
    if !has("Times New Roman") {
        if let Some(f) = pick(&[
            "DejaVu Serif",
            "Liberation Serif",
            "Noto Serif",
            "FreeSerif",
        ]) {
            db.set_serif_family(f);
        }
    }
    if !has("Arial") {
        if let Some(f) = pick(&["DejaVu Sans", "Liberation Sans", "Noto Sans", "FreeSans"]) {
            db.set_sans_serif_family(f);
        }
    }
    if !has("Courier New") {
        let mono = [
            "DejaVu Sans Mono",
            "Liberation Mono",
            "Noto Sans Mono",
            "FreeMono",
        ];
        if let Some(f) = pick(&mono) {
            db.set_monospace_family(f);
        }
    }
}

/// usvg parse options for reading a drawing: images resolved under `policy`
/// ([`crate::input::usvg_options`]) and the system fonts (loaded once per process, and only for
/// drawings with text).
fn usvg_options(
    file: &str,
    svg: &str,
    dir: Option<&Path>,
    policy: &InputPolicy,
) -> usvg::Options<'static> {
    let mut o = crate::input::usvg_options(file, dir, policy);
    if svg.contains("<text") || svg.contains(":text") {
        (o.fontdb, o.font_family) = fonts();
    }
    o
}

/// The nodes of a usvg group, counted up to `stop`.
fn count_nodes(g: &usvg::Group, stop: usize) -> usize {
    let mut n = 0;
    let mut todo = vec![g];
    while let Some(g) = todo.pop() {
        for c in g.children() {
            n += 1;
            if n >= stop {
                return n;
            }
            if let usvg::Node::Group(sub) = c {
                todo.push(sub);
            }
        }
    }
    n
}

/// Converts a usvg/tiny-skia transform to a kurbo affine map.
pub(crate) fn affine(t: usvg::Transform) -> Affine {
    Affine::new([
        t.sx as f64,
        t.ky as f64,
        t.kx as f64,
        t.sy as f64,
        t.tx as f64,
        t.ty as f64,
    ])
}

/// The root element's own attributes that usvg folds into every transform.
struct RootFrame {
    view_box: (Point, Point),
    /// Root user space → canvas (px).
    canvas_from_user: Affine,
    /// The extra in-root transform that reproduces the root's `transform` attribute.
    root_transform: Affine,
}

fn root_frame(file: &str, svg: &str, size: (f64, f64)) -> Result<RootFrame> {
    let doc = usvg::roxmltree::Document::parse(svg)
        .map_err(|e| Error::input(file, format!("not an SVG file: {e}")))?;
    let root = doc.root_element();
    let vb = match root.attribute("viewBox") {
        Some(s) => {
            let v = svgtypes::ViewBox::from_str(s)
                .map_err(|_| Error::input(file, format!("bad viewBox \"{s}\"")))?;
            if !(v.w > 0.0 && v.h > 0.0 && v.x.is_finite() && v.y.is_finite()) {
                return Err(Error::input(file, format!("bad viewBox \"{s}\"")));
            }
            (Point::new(v.x, v.y), Point::new(v.x + v.w, v.y + v.h))
        }
        None => (Point::ZERO, Point::new(size.0, size.1)),
    };
    let aspect = root
        .attribute("preserveAspectRatio")
        .and_then(|s| svgtypes::AspectRatio::from_str(s).ok())
        .unwrap_or_default();
    let root_ts = match root.attribute("transform") {
        Some(s) => {
            let t = svgtypes::Transform::from_str(s)
                .map_err(|_| Error::input(file, format!("bad root transform \"{s}\"")))?;
            Affine::new([t.a, t.b, t.c, t.d, t.e, t.f])
        }
        None => Affine::IDENTITY,
    };
    let vb_ts = view_box_transform(vb, aspect, size);
    let root_transform = if root_ts == Affine::IDENTITY {
        Affine::IDENTITY
    } else {
        vb_ts.inverse() * root_ts * vb_ts
    };
    Ok(RootFrame {
        view_box: vb,
        canvas_from_user: root_ts * vb_ts,
        root_transform,
    })
}

/// The viewBox → viewport mapping of SVG's `preserveAspectRatio`.
fn view_box_transform(
    vb: (Point, Point),
    aspect: svgtypes::AspectRatio,
    size: (f64, f64),
) -> Affine {
    use svgtypes::Align;
    let d = vb.1 - vb.0;
    let (sx, sy) = (size.0 / d.x, size.1 / d.y);
    if aspect.align == Align::None {
        return Affine::new([sx, 0.0, 0.0, sy, -vb.0.x * sx, -vb.0.y * sy]);
    }
    let s = if aspect.slice { sx.max(sy) } else { sx.min(sy) };
    let (free_x, free_y) = (size.0 - d.x * s, size.1 - d.y * s);
    let (fx, fy) = match aspect.align {
        Align::None | Align::XMinYMin => (0.0, 0.0),
        Align::XMidYMin => (0.5, 0.0),
        Align::XMaxYMin => (1.0, 0.0),
        Align::XMinYMid => (0.0, 0.5),
        Align::XMidYMid => (0.5, 0.5),
        Align::XMaxYMid => (1.0, 0.5),
        Align::XMinYMax => (0.0, 1.0),
        Align::XMidYMax => (0.5, 1.0),
        Align::XMaxYMax => (1.0, 1.0),
    };
    Affine::new([
        s,
        0.0,
        0.0,
        s,
        -vb.0.x * s + free_x * fx,
        -vb.0.y * s + free_y * fy,
    ])
}

impl Scene {
    /// Reads the artwork of an SVG drawing: every visible element in paint order except the
    /// subtree of the group with id `guides_group_id` (the `controls` guides, DESIGN.md §1).
    /// `file` names the drawing in errors. Only data-URI images are read, and the text is
    /// prepared under the default limits ([`Scene::from_svg_with`]). Unsupported features are
    /// reported with `log::warn!` (see the [module docs](super)).
    pub fn from_svg(file: &str, svg: &str, guides_group_id: &str) -> Result<Scene> {
        Self::from_svg_with(file, svg, guides_group_id, None, &InputPolicy::default())
    }

    /// [`Scene::from_svg`] that also reads the local images inside `resources_dir` (normally
    /// the drawing's folder), relative references resolving against it.
    pub fn from_svg_in(
        file: &str,
        svg: &str,
        guides_group_id: &str,
        resources_dir: Option<&Path>,
    ) -> Result<Scene> {
        let mut policy = InputPolicy::default();
        if let Some(dir) = resources_dir {
            policy.local_files = crate::input::LocalFiles::Within(dir.to_path_buf());
        }
        Self::from_svg_with(file, svg, guides_group_id, resources_dir, &policy)
    }

    /// The artwork of a drawing read with [`Drawing::open`](crate::drawing::Drawing::open) or
    /// `from_str`, under the drawing's own policy and folder.
    pub fn from_drawing(d: &crate::drawing::Drawing) -> Result<Scene> {
        // `d.svg` was prepared when the drawing was read: not again.
        Self::from_prepared(
            &d.file,
            &d.svg,
            &d.guides_group,
            d.dir.as_deref(),
            &d.policy,
        )
    }

    /// [`Scene::from_svg`] under `policy` (which images may be read, and the limits the text
    /// is prepared under, [`crate::input::prepare`]) for a drawing in folder `dir`.
    pub fn from_svg_with(
        file: &str,
        svg: &str,
        guides_group_id: &str,
        dir: Option<&Path>,
        policy: &InputPolicy,
    ) -> Result<Scene> {
        let svg = &*crate::input::prepare(file, svg, &policy.limits)?;
        Self::from_prepared(file, svg, guides_group_id, dir, policy)
    }

    /// [`Scene::from_svg_with`] for text that has been through [`crate::input::prepare`].
    fn from_prepared(
        file: &str,
        svg: &str,
        guides_group_id: &str,
        dir: Option<&Path>,
        policy: &InputPolicy,
    ) -> Result<Scene> {
        let tree = usvg::Tree::from_str(svg, &usvg_options(file, svg, dir, policy))
            .map_err(|e| Error::input(file, format!("not a usable SVG file: {e}")))?;
        // `<use>` copies what it references: a small file can expand to many elements.
        let expanded = count_nodes(tree.root(), policy.limits.elements + 1);
        if expanded > policy.limits.elements {
            let what = format!(
                "more than {} elements once <use> is expanded",
                policy.limits.elements
            );
            return Err(crate::input::Limit::Elements.exceeded(file, &what, &policy.limits));
        }
        let size = (tree.size().width() as f64, tree.size().height() as f64);
        let frame = root_frame(file, svg, size)?;
        let reader = Reader {
            file,
            guides: guides_group_id,
            user_from_canvas: frame.canvas_from_user.inverse(),
        };
        let mut root = Group {
            id: String::new(),
            opacity: 1.0,
            clip: None,
            children: Vec::new(),
        };
        reader.children(tree.root(), &mut root.children)?;
        Ok(Scene {
            file: file.to_string(),
            view_box: frame.view_box,
            size,
            root_transform: frame.root_transform,
            root,
        })
    }
}

impl Scene {
    /// The scene with only the paths and images whose indices into [`Scene::items`] satisfy
    /// `keep`, each in its groups (transform-free, so the groups are just nesting with their
    /// opacity and clip); groups left without any kept path or image are dropped. Used to split
    /// the artwork into paint-order layers: painting the layers of a partition of the items in
    /// order paints the scene, as long as no group with opacity or a clip is split.
    pub fn retain_items(&self, keep: impl Fn(usize) -> bool) -> Scene {
        fn walk(g: &Group, next: &mut usize, keep: &dyn Fn(usize) -> bool) -> Group {
            let mut children = Vec::new();
            for c in &g.children {
                let index = *next;
                *next += 1;
                match c {
                    Item::Group(sub) => {
                        let kept = walk(sub, next, keep);
                        if !kept.children.is_empty() {
                            children.push(Item::Group(kept));
                        }
                    }
                    other => {
                        if keep(index) {
                            children.push(other.clone());
                        }
                    }
                }
            }
            Group {
                children,
                ..g.clone()
            }
        }
        let mut next = 0;
        Scene {
            root: walk(&self.root, &mut next, &keep),
            ..self.clone()
        }
    }
}

struct Reader<'a> {
    file: &'a str,
    guides: &'a str,
    user_from_canvas: Affine,
}

impl Reader<'_> {
    fn children(&self, g: &usvg::Group, out: &mut Vec<Item>) -> Result<()> {
        for node in g.children() {
            match node {
                usvg::Node::Group(sub) => {
                    if !self.guides.is_empty() && sub.id() == self.guides {
                        continue;
                    }
                    if let Some(mut g) = self.group(sub)? {
                        if g.id.is_empty() && g.opacity == 1.0 && g.clip.is_none() {
                            // An anonymous opaque group (usvg's viewBox wrapper, a bare
                            // transform) composites exactly like its children alone.
                            out.append(&mut g.children);
                        } else {
                            out.push(Item::Group(g));
                        }
                    }
                }
                usvg::Node::Path(p) => {
                    if let Some(p) = self.path(p)? {
                        out.push(Item::Path(p));
                    }
                }
                usvg::Node::Image(img) => {
                    if let Some(i) = self.image(img) {
                        out.push(Item::Image(i));
                    }
                }
                usvg::Node::Text(text) => {
                    if let Some(g) = self.group(text.flattened())? {
                        out.push(Item::Group(g));
                    }
                }
            }
        }
        Ok(())
    }

    fn group(&self, g: &usvg::Group) -> Result<Option<Group>> {
        let what = if g.id().is_empty() {
            "a group".to_string()
        } else {
            format!("group '{}'", g.id())
        };
        if g.mask().is_some() {
            log::warn!(
                "{}: {what}: masks are not supported; rendered unmasked",
                self.file
            );
        }
        if !g.filters().is_empty() {
            log::warn!(
                "{}: {what}: filters are not supported; rendered unfiltered",
                self.file
            );
        }
        if g.blend_mode() != usvg::BlendMode::Normal {
            log::warn!(
                "{}: {what}: blend modes are not supported; rendered normally",
                self.file
            );
        }
        let mut children = Vec::new();
        self.children(g, &mut children)?;
        if children.is_empty() {
            return Ok(None);
        }
        let clip = g.clip_path().map(|cp| {
            let base = self.user_from_canvas * affine(g.abs_transform()) * affine(cp.transform());
            if cp.clip_path().is_some() {
                log::warn!(
                    "{}: {what}: a clip path's own clip-path is not supported; ignored",
                    self.file
                );
            }
            let mut shapes = Vec::new();
            self.clip_shapes(cp.root(), base, &what, &mut shapes);
            Clip { shapes }
        });
        Ok(Some(Group {
            id: g.id().to_string(),
            opacity: g.opacity().get() as f64,
            clip,
            children,
        }))
    }

    /// The shapes of a clip path's content, `to_user` mapping `g`'s coordinates to user space.
    fn clip_shapes(&self, g: &usvg::Group, to_user: Affine, what: &str, out: &mut Vec<ClipShape>) {
        for node in g.children() {
            match node {
                usvg::Node::Path(p) if p.is_visible() => out.push(ClipShape {
                    path: bez_path(p.data(), to_user),
                    even_odd: p
                        .fill()
                        .is_some_and(|f| f.rule() == usvg::FillRule::EvenOdd),
                }),
                usvg::Node::Text(t) => self.clip_shapes(t.flattened(), to_user, what, out),
                usvg::Node::Group(sub) => {
                    if sub.clip_path().is_some() {
                        log::warn!(
                            "{}: {what}: clip-path inside a clip path is not supported; ignored",
                            self.file
                        );
                    }
                    self.clip_shapes(sub, to_user * affine(sub.transform()), what, out);
                }
                _ => {}
            }
        }
    }

    fn path(&self, p: &usvg::Path) -> Result<Option<PathItem>> {
        if !p.is_visible() || (p.fill().is_none() && p.stroke().is_none()) {
            return Ok(None);
        }
        let to_user = self.user_from_canvas * affine(p.abs_transform());
        let path = bez_path(p.data(), to_user);
        let finite = path.elements().iter().all(|el| {
            el.end_point()
                .is_none_or(|q| q.x.is_finite() && q.y.is_finite())
        });
        if !finite {
            return Err(Error::at(
                self.file,
                p.id(),
                "has a coordinate that is not finite",
            ));
        }
        let fill = p.fill().and_then(|f| {
            Some(Fill {
                paint: self.paint(f.paint(), to_user, p.id())?,
                opacity: f.opacity().get() as f64,
                even_odd: f.rule() == usvg::FillRule::EvenOdd,
            })
        });
        // A pen that stays round in user space is measured in user units; otherwise it keeps
        // the element's frame so that its shape survives.
        let (scale, frame) = if is_conformal(to_user) {
            (to_user.determinant().abs().sqrt(), None)
        } else {
            (1.0, Some(to_user))
        };
        let stroke = p.stroke().and_then(|s| {
            Some(Stroke {
                paint: self.paint(s.paint(), to_user, p.id())?,
                opacity: s.opacity().get() as f64,
                width: s.width().get() as f64 * scale,
                cap: match s.linecap() {
                    usvg::LineCap::Butt => LineCap::Butt,
                    usvg::LineCap::Round => LineCap::Round,
                    usvg::LineCap::Square => LineCap::Square,
                },
                join: match s.linejoin() {
                    usvg::LineJoin::Miter => LineJoin::Miter,
                    usvg::LineJoin::MiterClip => LineJoin::MiterClip,
                    usvg::LineJoin::Round => LineJoin::Round,
                    usvg::LineJoin::Bevel => LineJoin::Bevel,
                },
                miter_limit: s.miterlimit().get() as f64,
                dashes: s
                    .dasharray()
                    .map(|d| d.iter().map(|x| *x as f64 * scale).collect())
                    .unwrap_or_default(),
                dash_offset: s.dashoffset() as f64 * scale,
                frame,
            })
        });
        if fill.is_none() && stroke.is_none() {
            return Ok(None);
        }
        Ok(Some(PathItem {
            id: p.id().to_string(),
            path,
            fill,
            stroke,
            stroke_first: p.paint_order() == usvg::PaintOrder::StrokeAndFill,
        }))
    }

    fn paint(&self, paint: &usvg::Paint, to_user: Affine, id: &str) -> Option<Paint> {
        let base = |g: &usvg::BaseGradient, kind| {
            let spread = match g.spread_method() {
                usvg::SpreadMethod::Pad => Spread::Pad,
                usvg::SpreadMethod::Reflect => Spread::Reflect,
                usvg::SpreadMethod::Repeat => Spread::Repeat,
            };
            let stops = g
                .stops()
                .iter()
                .map(|s| GradientStop {
                    offset: s.offset().get() as f64,
                    color: rgb(s.color()),
                    opacity: s.opacity().get() as f64,
                })
                .collect();
            Paint::Gradient(Arc::new(Gradient {
                kind,
                transform: to_user * affine(g.transform()),
                spread,
                stops,
            }))
        };
        match paint {
            usvg::Paint::Color(c) => Some(Paint::Color(rgb(*c))),
            usvg::Paint::LinearGradient(g) => Some(base(
                g,
                GradientKind::Linear {
                    start: Point::new(g.x1() as f64, g.y1() as f64),
                    end: Point::new(g.x2() as f64, g.y2() as f64),
                },
            )),
            usvg::Paint::RadialGradient(g) => Some(base(
                g,
                GradientKind::Radial {
                    center: Point::new(g.cx() as f64, g.cy() as f64),
                    radius: g.r().get() as f64,
                    focal: Point::new(g.fx() as f64, g.fy() as f64),
                    focal_radius: g.fr().get() as f64,
                },
            )),
            usvg::Paint::Pattern(_) => {
                log::warn!(
                    "{}: element '{id}': pattern paint is not supported; that paint is dropped",
                    self.file
                );
                None
            }
        }
    }

    fn image(&self, img: &usvg::Image) -> Option<ImageItem> {
        if !img.is_visible() {
            return None;
        }
        let (data, mime) = match img.kind() {
            usvg::ImageKind::PNG(d) => (d.clone(), "image/png"),
            usvg::ImageKind::JPEG(d) => (d.clone(), "image/jpeg"),
            usvg::ImageKind::GIF(d) => (d.clone(), "image/gif"),
            usvg::ImageKind::WEBP(d) => (d.clone(), "image/webp"),
            usvg::ImageKind::SVG(_) => {
                log::warn!(
                    "{}: image '{}': nested SVG images are not supported; skipped",
                    self.file,
                    img.id()
                );
                return None;
            }
        };
        Some(ImageItem {
            id: img.id().to_string(),
            data,
            mime,
            width: img.size().width() as f64,
            height: img.size().height() as f64,
            transform: self.user_from_canvas * affine(img.abs_transform()),
            pixelated: matches!(
                img.rendering_mode(),
                usvg::ImageRendering::OptimizeSpeed
                    | usvg::ImageRendering::CrispEdges
                    | usvg::ImageRendering::Pixelated
            ),
            grid: None,
            pixels: Default::default(),
        })
    }
}

/// Whether an affine map is a similarity (rotation, uniform scale, reflection, translation):
/// it maps round pens to round pens.
fn is_conformal(m: Affine) -> bool {
    let [a, b, c, d, _, _] = m.as_coeffs();
    let (p, q, r) = (a * a + b * b, c * c + d * d, a * c + b * d);
    let eps = 1e-9 * (p + q);
    (p - q).abs() <= eps && r.abs() <= eps
}

/// A usvg path's data mapped by `to_user`, as a kurbo path.
fn bez_path(data: &usvg::tiny_skia_path::Path, to_user: Affine) -> BezPath {
    use usvg::tiny_skia_path::PathSegment as S;
    let k = |q: usvg::tiny_skia_path::Point| to_user * kurbo::Point::new(q.x as f64, q.y as f64);
    let mut path = BezPath::new();
    for seg in data.segments() {
        match seg {
            S::MoveTo(a) => path.move_to(k(a)),
            S::LineTo(a) => path.line_to(k(a)),
            S::QuadTo(a, b) => path.quad_to(k(a), k(b)),
            S::CubicTo(a, b, c) => path.curve_to(k(a), k(b), k(c)),
            S::Close => path.close_path(),
        }
    }
    path
}

fn rgb(c: usvg::Color) -> Rgba {
    Rgba {
        r: c.red,
        g: c.green,
        b: c.blue,
        a: 255,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ART: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="10 20 100 50">
      <defs><linearGradient id="lg" x1="0" y1="0" x2="1" y2="0">
        <stop offset="0" stop-color="#f00"/><stop offset="1" stop-color="#00f" stop-opacity="0.5"/>
      </linearGradient></defs>
      <rect id="r" x="20" y="30" width="40" height="20" fill="url(#lg)" stroke="#000" stroke-width="2"/>
      <g id="grp" opacity="0.5" transform="translate(10 0) scale(2)">
        <circle id="c" cx="30" cy="20" r="5" fill="green" stroke="black" stroke-dasharray="1 2"/>
      </g>
      <g id="controls"><path id="boundary" d="M10 20 H110 V70 H10 Z" fill="red"/></g>
    </svg>"##;

    #[test]
    fn reads_in_user_space_and_skips_guides() {
        let s = Scene::from_svg("a.svg", ART, "controls").unwrap();
        assert_eq!(s.size, (200.0, 100.0));
        assert_eq!(
            s.view_box,
            (Point::new(10.0, 20.0), Point::new(110.0, 70.0))
        );
        assert_eq!(s.root_transform, Affine::IDENTITY);
        assert_eq!(s.root.children.len(), 2, "the guides group is skipped");
        let Item::Path(r) = &s.root.children[0] else {
            panic!("rect first")
        };
        let bb = kurbo::Shape::bounding_box(&r.path);
        assert!(
            (bb.x0 - 20.0).abs() < 1e-4 && (bb.y1 - 50.0).abs() < 1e-4,
            "{bb:?}"
        );
        let st = r.stroke.as_ref().unwrap();
        assert!((st.width - 2.0).abs() < 1e-5);
        let Some(Fill {
            paint: Paint::Gradient(g),
            ..
        }) = &r.fill
        else {
            panic!("gradient fill")
        };
        // objectBoundingBox units resolved: gradient x=0 maps to the rect's left edge.
        let p0 = g.transform * kurbo::Point::new(0.0, 0.0);
        let p1 = g.transform * kurbo::Point::new(1.0, 0.0);
        assert!(
            (p0.x - 20.0).abs() < 1e-4 && (p1.x - 60.0).abs() < 1e-4,
            "{p0:?} {p1:?}"
        );
        assert_eq!(g.stops.len(), 2);
        assert!((g.stops[1].opacity - 0.5).abs() < 1e-6);
        let Item::Group(grp) = &s.root.children[1] else {
            panic!("group second")
        };
        assert_eq!(grp.id, "grp");
        assert!((grp.opacity - 0.5).abs() < 1e-6);
        let Item::Path(c) = &grp.children[0] else {
            panic!("circle")
        };
        let cb = kurbo::Shape::bounding_box(&c.path);
        assert!((cb.center().x - 70.0).abs() < 1e-3 && (cb.width() - 20.0).abs() < 1e-3);
        let cs = c.stroke.as_ref().unwrap();
        assert!((cs.width - 2.0).abs() < 1e-5, "width scales with the group");
        assert_eq!(cs.dashes, vec![2.0, 4.0]);
    }

    #[test]
    fn aspect_ratio_and_root_transform_are_undone() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="300" height="100" viewBox="0 0 10 10" preserveAspectRatio="xMaxYMid meet">
          <rect x="2" y="3" width="4" height="5" fill="red"/></svg>"#;
        let s = Scene::from_svg("b.svg", svg, "controls").unwrap();
        let Item::Path(r) = &s.root.children[0] else {
            panic!()
        };
        let bb = kurbo::Shape::bounding_box(&r.path);
        assert!(
            (bb.x0 - 2.0).abs() < 1e-4 && (bb.y0 - 3.0).abs() < 1e-4,
            "{bb:?}"
        );
        let svg2 = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="100" viewBox="0 0 50 50" transform="translate(10 0)">
          <rect x="2" y="3" width="4" height="5" fill="red"/></svg>"#;
        let s2 = Scene::from_svg("c.svg", svg2, "controls").unwrap();
        let Item::Path(r2) = &s2.root.children[0] else {
            panic!()
        };
        let bb2 = kurbo::Shape::bounding_box(&r2.path);
        assert!((bb2.x0 - 2.0).abs() < 1e-4, "{bb2:?}");
        // translate(10px) inside a 2× viewBox is 5 user units.
        let t = s2.root_transform.as_coeffs();
        assert!((t[4] - 5.0).abs() < 1e-9 && t[5].abs() < 1e-9, "{t:?}");
    }

    #[test]
    fn tolerance_is_a_quarter_pixel() {
        let vb = (Point::ZERO, Point::new(100.0, 50.0));
        assert!((flatten_tolerance(vb, (400.0, 200.0)) - 0.0625).abs() < 1e-12);
        assert!(flatten_tolerance(vb, (0.0, 0.0)) > 0.0);
    }

    #[test]
    fn text_becomes_glyph_paths_when_fonts_exist() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="100" height="40">
          <text x="5" y="30" font-size="20" fill="navy" font-family="sans-serif">Hi</text>
          <text x="50" y="30" font-size="20" fill="navy">Ho</text></svg>"#;
        let s = Scene::from_svg("t.svg", svg, "controls").unwrap();
        let paths = s
            .items()
            .iter()
            .filter(|i| matches!(i, Item::Path(_)))
            .count();
        if fonts().0.is_empty() {
            assert_eq!(paths, 0, "no fonts, no glyphs");
        } else {
            assert!(
                paths >= 2,
                "both the generic and the default family resolve"
            );
        }
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        assert!(Scene::from_svg("x.svg", "not svg", "controls").is_err());
    }

    #[test]
    fn retained_items_partition_the_scene_in_paint_order() {
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40">
          <rect id="a" width="10" height="10"/>
          <g id="g"><rect id="b" width="5" height="5"/><rect id="c" width="6" height="6"/></g>
          <g id="empty-after-split" opacity="0.5"><rect id="d" width="7" height="7"/></g></svg>"##;
        let s = Scene::from_svg("r.svg", svg, "controls").unwrap();
        let ids = |sc: &Scene| -> Vec<String> {
            sc.items()
                .iter()
                .map(|i| match i {
                    Item::Group(g) => g.id.clone(),
                    Item::Path(p) => p.id.clone(),
                    Item::Image(m) => m.id.clone(),
                })
                .collect()
        };
        assert_eq!(ids(&s), ["a", "g", "b", "c", "empty-after-split", "d"]);
        // Items 0..3 (a, g, b) and the rest: the plain group is split, the other kept whole.
        let lo = s.retain_items(|i| i < 3);
        let hi = s.retain_items(|i| i >= 3);
        assert_eq!(ids(&lo), ["a", "g", "b"]);
        assert_eq!(ids(&hi), ["g", "c", "empty-after-split", "d"]);
        assert!(s.retain_items(|_| false).root.children.is_empty());
        assert_eq!(s.retain_items(|_| true).root, s.root);
    }
}
