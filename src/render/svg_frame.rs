//! One frame as a standalone SVG file.
//!
//! Frame t shows the linear blend `(1 − t)·S_t + t·T_t` of the warped source and target
//! renderings, alpha included (end of §3: the transferred shapes are blended). Plain group
//! opacities cannot express this: `S` at opacity `1 − t` under `T` at opacity `t` has alpha
//! `1 − t + t²` where both are opaque, so the mid frame is see-through (and its colour weights are
//! `(1 − t)²` and `t`, not `1 − t` and `t`). So the frame blends the two *renderings* with one
//! filter, which Chromium, Firefox, Safari and resvg all implement:
//!
//! ```text
//! <g filter="url(#crmorph-blend)">            filter region: the view and its copy to the right
//!   <g clip-path=view> S_t </g>               the source, clipped to the view
//!   <g translate(D,0)><g clip-path=view> T_t  the target, clipped, moved right by D: the view's
//! </g>                                        width rounded up to whole output pixels
//! feOffset dx=−D of SourceGraphic             brings T_t over S_t
//! feComposite arithmetic k2=1−t k3=t          (1−t)·S + t·T on premultiplied RGBA, limited to the view
//! ```
//!
//! `color-interpolation-filters="sRGB"` makes the blend happen on the same sRGB values a pixel
//! blend uses (the default, linearRGB, would brighten mid-tones). The clips keep overhanging
//! artwork of one side from being shifted into the view with the other. At t = 0 and t = 1 there
//! is no filter at all: the frame is the one drawing, rendering exactly as the input.
//!
//! Output is deterministic: elements in paint order, generated ids numbered in that order,
//! coordinates rounded to 1/100 px at the output size.

use super::FrameOptions;
use crate::artwork::{
    Gradient, GradientKind, Group, ImageItem, Item, LineCap, LineJoin, Paint, PathItem, Rgba,
    Scene, Spread, Stroke,
};
use crate::error::{Error, Result};
use crate::geometry::Point;
use kurbo::{Affine, PathEl};
use quick_xml::events::{BytesEnd, BytesStart, Event};
use quick_xml::Writer;

/// One drawing alone as a standalone SVG (what frames t = 0 and t = 1 are).
pub fn scene_svg(scene: &Scene, opts: &FrameOptions) -> Result<String> {
    let mut doc = Document::new(opts);
    doc.start_root(opts);
    let mut defs = Xml::new();
    let mut body = Xml::new();
    doc.side(scene, "a", &mut defs, &mut body);
    doc.finish(defs, body)
}

/// The frame at `t` blending the warped `source` and `target` scenes (see the module docs for
/// how). `t` is clamped to [0, 1]; at the ends the frame is [`scene_svg`] of that side.
pub fn frame_svg(source: &Scene, target: &Scene, t: f64, opts: &FrameOptions) -> Result<String> {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    if t == 0.0 {
        return scene_svg(source, opts);
    }
    if t == 1.0 {
        return scene_svg(target, opts);
    }
    let mut doc = Document::new(opts);
    doc.start_root(opts);
    let mut defs = Xml::new();
    let mut body = Xml::new();
    let (lo, hi) = opts.view_box;
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    // The target's shift D: at least the view's width, and a whole number of output pixels so
    // that feOffset moves pixels without resampling them (which would blur the target).
    let px = {
        let (sx, sy) = (opts.size.0 as f64 / w, opts.size.1 as f64 / h);
        sx.min(sy) // the uniform scale of the default `xMidYMid meet`
    };
    let shift = if px.is_finite() && px > 0.0 {
        (w * px).ceil() / px
    } else {
        w
    };
    let decimals = doc.decimals;
    let n = |x: f64| fixed(x, decimals);
    // The clip and filter definitions.
    defs.open("clipPath", &[("id", "crmorph-view".into())]);
    defs.empty(
        "rect",
        &[
            ("x", n(lo.x)),
            ("y", n(lo.y)),
            ("width", n(w)),
            ("height", n(h)),
        ],
    );
    defs.close("clipPath");
    defs.open(
        "filter",
        &[
            ("id", "crmorph-blend".into()),
            ("filterUnits", "userSpaceOnUse".into()),
            ("x", n(lo.x)),
            ("y", n(lo.y)),
            ("width", n(w + shift)),
            ("height", n(h)),
            ("color-interpolation-filters", "sRGB".into()),
        ],
    );
    defs.empty(
        "feOffset",
        &[
            ("in", "SourceGraphic".into()),
            ("dx", n(-shift)),
            ("dy", "0".into()),
            ("result", "target".into()),
        ],
    );
    defs.empty(
        "feComposite",
        &[
            ("in", "SourceGraphic".into()),
            ("in2", "target".into()),
            ("operator", "arithmetic".into()),
            ("k1", "0".into()),
            ("k2", sig(1.0 - t)),
            ("k3", sig(t)),
            ("k4", "0".into()),
            ("x", n(lo.x)),
            ("y", n(lo.y)),
            ("width", n(w)),
            ("height", n(h)),
        ],
    );
    defs.close("filter");
    body.open("g", &[("filter", "url(#crmorph-blend)".into())]);
    body.open("g", &[("clip-path", "url(#crmorph-view)".into())]);
    doc.side(source, "s", &mut defs, &mut body);
    body.close("g");
    body.open("g", &[("transform", format!("translate({} 0)", n(shift)))]);
    body.open("g", &[("clip-path", "url(#crmorph-view)".into())]);
    doc.side(target, "t", &mut defs, &mut body);
    body.close("g");
    body.close("g");
    body.close("g");
    doc.finish(defs, body)
}

/// A small quick-xml writer that remembers a write failure instead of returning it at every call.
struct Xml {
    w: Writer<Vec<u8>>,
    failed: bool,
}

impl Xml {
    fn new() -> Self {
        Xml {
            w: Writer::new(Vec::new()),
            failed: false,
        }
    }

    fn start(name: &str, attrs: &[(&str, String)]) -> BytesStart<'static> {
        let mut e = BytesStart::new(name.to_string());
        for (k, v) in attrs {
            e.push_attribute((*k, v.as_str()));
        }
        e
    }

    fn open(&mut self, name: &str, attrs: &[(&str, String)]) {
        let e = Self::start(name, attrs);
        self.failed |= self.w.write_event(Event::Start(e)).is_err();
    }

    fn empty(&mut self, name: &str, attrs: &[(&str, String)]) {
        let e = Self::start(name, attrs);
        self.failed |= self.w.write_event(Event::Empty(e)).is_err();
    }

    fn close(&mut self, name: &str) {
        self.failed |= self
            .w
            .write_event(Event::End(BytesEnd::new(name.to_string())))
            .is_err();
    }

    fn raw(&mut self, text: &str) {
        use std::io::Write;
        self.failed |= self.w.get_mut().write_all(text.as_bytes()).is_err();
    }
}

/// Shared state of one output document: number precision and generated-id counters.
struct Document {
    root: Xml,
    decimals: usize,
    background: Option<Rgba>,
    view_box: (Point, Point),
    next_id: usize,
}

impl Document {
    fn new(opts: &FrameOptions) -> Self {
        let d = opts.view_box.1 - opts.view_box.0;
        let scale = (opts.size.0 as f64 / d.x).max(opts.size.1 as f64 / d.y);
        // 1/100 px in user units, as a count of decimals.
        let step = 0.01 / scale;
        let decimals = if step.is_finite() && step > 0.0 {
            (-step.log10()).ceil().clamp(0.0, 12.0) as usize
        } else {
            3
        };
        Document {
            root: Xml::new(),
            decimals,
            background: opts.background,
            view_box: opts.view_box,
            next_id: 0,
        }
    }

    /// A coordinate rounded to the output's precision, without trailing zeros.
    fn num(&self, x: f64) -> String {
        fixed(x, self.decimals)
    }

    fn start_root(&mut self, opts: &FrameOptions) {
        let (lo, hi) = opts.view_box;
        let vb = format!(
            "{} {} {} {}",
            self.num(lo.x),
            self.num(lo.y),
            self.num(hi.x - lo.x),
            self.num(hi.y - lo.y)
        );
        self.root.open(
            "svg",
            &[
                ("xmlns", "http://www.w3.org/2000/svg".into()),
                ("xmlns:xlink", "http://www.w3.org/1999/xlink".into()),
                ("width", opts.size.0.to_string()),
                ("height", opts.size.1.to_string()),
                ("viewBox", vb),
            ],
        );
    }

    fn finish(mut self, defs: Xml, body: Xml) -> Result<String> {
        let defs_bytes = defs.w.into_inner();
        if !defs_bytes.is_empty() {
            self.root.open("defs", &[]);
            self.root
                .raw(std::str::from_utf8(&defs_bytes).unwrap_or_default());
            self.root.close("defs");
        }
        if let Some(bg) = self.background {
            let (lo, hi) = self.view_box;
            let mut a = vec![
                ("x", self.num(lo.x)),
                ("y", self.num(lo.y)),
                ("width", self.num(hi.x - lo.x)),
                ("height", self.num(hi.y - lo.y)),
                ("fill", hex(bg)),
            ];
            if bg.a != 255 {
                a.push(("fill-opacity", sig(bg.a as f64 / 255.0)));
            }
            self.root.empty("rect", &a);
        }
        let body_bytes = body.w.into_inner();
        self.root
            .raw(std::str::from_utf8(&body_bytes).unwrap_or_default());
        self.root.close("svg");
        if self.root.failed || defs.failed || body.failed {
            return Err(Error::internal("writing the SVG frame failed"));
        }
        String::from_utf8(self.root.w.into_inner())
            .map_err(|_| Error::internal("the SVG frame is not UTF-8"))
    }

    /// Writes one scene's artwork into `body`, its gradients into `defs`, with ids prefixed by
    /// `prefix` (so the two sides of a frame never share an id).
    fn side(&mut self, scene: &Scene, prefix: &str, defs: &mut Xml, body: &mut Xml) {
        let wrap = scene.root_transform != Affine::IDENTITY;
        if wrap {
            body.open("g", &[("transform", matrix(scene.root_transform))]);
        }
        self.children(&scene.root, prefix, defs, body);
        if wrap {
            body.close("g");
        }
    }

    fn children(&mut self, g: &Group, prefix: &str, defs: &mut Xml, body: &mut Xml) {
        for c in &g.children {
            match c {
                Item::Group(sub) => {
                    let mut a = Vec::new();
                    if sub.opacity != 1.0 {
                        a.push(("opacity", sig(sub.opacity)));
                    }
                    if let Some(clip) = &sub.clip {
                        let id = format!("{prefix}{}", self.next_id);
                        self.next_id += 1;
                        defs.open("clipPath", &[("id", id.clone())]);
                        for shape in &clip.shapes {
                            let mut sa = vec![("d", self.path_data(&shape.path, self.decimals))];
                            if shape.even_odd {
                                sa.push(("clip-rule", "evenodd".into()));
                            }
                            defs.empty("path", &sa);
                        }
                        defs.close("clipPath");
                        a.push(("clip-path", format!("url(#{id})")));
                    }
                    body.open("g", &a);
                    self.children(sub, prefix, defs, body);
                    body.close("g");
                }
                Item::Path(p) => self.path(p, prefix, defs, body),
                Item::Image(img) => self.image(img, body),
            }
        }
    }

    fn path(&mut self, p: &PathItem, prefix: &str, defs: &mut Xml, body: &mut Xml) {
        // A shaped pen is drawn in its own frame: the outline mapped back into it, the frame as
        // the element's transform, gradients re-expressed in it.
        let frame = p
            .stroke
            .as_ref()
            .and_then(|s| s.frame)
            .filter(|f| f.determinant().is_finite() && f.determinant() != 0.0);
        let (d, to_local) = match frame {
            None => (self.path_data(&p.path, self.decimals), Affine::IDENTITY),
            Some(f) => {
                let inv = f.inverse();
                let [a, b, c, dd, _, _] = f.as_coeffs();
                // Local units are this many user units at most: keep 1/100 px in them too.
                let stretch = (a * a + b * b).max(c * c + dd * dd).sqrt().max(1e-12);
                let extra = stretch.log10().ceil().clamp(0.0, 12.0) as usize;
                (
                    self.path_data(&(inv * p.path.clone()), self.decimals + extra),
                    inv,
                )
            }
        };
        if d.is_empty() {
            return;
        }
        let mut a = vec![("d", d)];
        if let Some(f) = frame {
            a.push(("transform", matrix(f)));
        }
        match &p.fill {
            Some(f) => {
                a.push(("fill", self.paint(&f.paint, to_local, prefix, defs)));
                if f.opacity != 1.0 {
                    a.push(("fill-opacity", sig(f.opacity)));
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
        body.empty("path", &a);
    }

    fn stroke_attrs(
        &mut self,
        s: &Stroke,
        to_local: Affine,
        prefix: &str,
        defs: &mut Xml,
        a: &mut Vec<(&'static str, String)>,
    ) {
        a.push(("stroke", self.paint(&s.paint, to_local, prefix, defs)));
        // Stroke widths keep two more decimals than coordinates: hairlines matter. In a pen's
        // own frame, units are not pixels: keep significant digits instead.
        let len = |x: f64| {
            if s.frame.is_some() {
                sig(x)
            } else {
                fixed(x, self.decimals + 2)
            }
        };
        a.push(("stroke-width", len(s.width)));
        if s.opacity != 1.0 {
            a.push(("stroke-opacity", sig(s.opacity)));
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
        if s.miter_limit != 4.0 {
            a.push(("stroke-miterlimit", sig(s.miter_limit)));
        }
        if !s.dashes.is_empty() {
            let d: Vec<String> = s.dashes.iter().map(|x| len(*x)).collect();
            a.push(("stroke-dasharray", d.join(" ")));
            if s.dash_offset != 0.0 {
                a.push(("stroke-dashoffset", len(s.dash_offset)));
            }
        }
    }

    fn path_data(&self, path: &kurbo::BezPath, decimals: usize) -> String {
        let mut d = String::new();
        let pt = |q: kurbo::Point| format!("{} {}", fixed(q.x, decimals), fixed(q.y, decimals));
        for el in path.elements() {
            if !d.is_empty() {
                d.push(' ');
            }
            match *el {
                PathEl::MoveTo(q) => d.push_str(&format!("M{}", pt(q))),
                PathEl::LineTo(q) => d.push_str(&format!("L{}", pt(q))),
                PathEl::QuadTo(q1, q) => d.push_str(&format!("Q{} {}", pt(q1), pt(q))),
                PathEl::CurveTo(q1, q2, q) => {
                    d.push_str(&format!("C{} {} {}", pt(q1), pt(q2), pt(q)))
                }
                PathEl::ClosePath => d.push('Z'),
            }
        }
        d
    }

    /// A paint attribute value; gradients are written to `defs`, their geometry mapped by
    /// `to_local` into the element's coordinates.
    fn paint(&mut self, paint: &Paint, to_local: Affine, prefix: &str, defs: &mut Xml) -> String {
        match paint {
            Paint::Color(c) => hex(*c),
            Paint::Gradient(g) => {
                let id = format!("{prefix}{}", self.next_id);
                self.next_id += 1;
                self.gradient(g, to_local * g.transform, &id, defs);
                format!("url(#{id})")
            }
        }
    }

    fn gradient(&self, g: &Gradient, transform: Affine, id: &str, defs: &mut Xml) {
        let mut a = vec![
            ("id", id.to_string()),
            ("gradientUnits", "userSpaceOnUse".into()),
        ];
        let name = match g.kind {
            GradientKind::Linear { start, end } => {
                a.extend([
                    ("x1", sig(start.x)),
                    ("y1", sig(start.y)),
                    ("x2", sig(end.x)),
                    ("y2", sig(end.y)),
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
                    ("cx", sig(center.x)),
                    ("cy", sig(center.y)),
                    ("r", sig(radius)),
                    ("fx", sig(focal.x)),
                    ("fy", sig(focal.y)),
                ]);
                if focal_radius != 0.0 {
                    a.push(("fr", sig(focal_radius)));
                }
                "radialGradient"
            }
        };
        if transform != Affine::IDENTITY {
            a.push(("gradientTransform", matrix(transform)));
        }
        match g.spread {
            Spread::Pad => {}
            Spread::Reflect => a.push(("spreadMethod", "reflect".into())),
            Spread::Repeat => a.push(("spreadMethod", "repeat".into())),
        }
        defs.open(name, &a);
        for s in &g.stops {
            let mut sa = vec![("offset", sig(s.offset)), ("stop-color", hex(s.color))];
            if s.opacity != 1.0 {
                sa.push(("stop-opacity", sig(s.opacity)));
            }
            defs.empty("stop", &sa);
        }
        defs.close(name);
    }

    fn image(&self, img: &ImageItem, body: &mut Xml) {
        let mut a = vec![
            ("width", sig(img.width)),
            ("height", sig(img.height)),
            ("preserveAspectRatio", "none".into()),
            ("transform", matrix(img.transform)),
        ];
        if img.pixelated {
            a.push(("image-rendering", "optimizeSpeed".into()));
        }
        a.push((
            "xlink:href",
            format!("data:{};base64,{}", img.mime, base64(&img.data)),
        ));
        body.empty("image", &a);
    }
}

/// `x` with at most `decimals` decimals, trailing zeros dropped, no negative zero.
fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// `x` to 9 significant digits (for scale-free values: opacities, gradient geometry, matrices).
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return "0".into();
    }
    let r: f64 = format!("{x:.8e}").parse().unwrap_or(x);
    let s = format!("{r}");
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

fn matrix(m: Affine) -> String {
    let c = m.as_coeffs();
    format!(
        "matrix({} {} {} {} {} {})",
        sig(c[0]),
        sig(c[1]),
        sig(c[2]),
        sig(c[3]),
        sig(c[4]),
        sig(c[5])
    )
}

fn hex(c: Rgba) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)
}

/// Standard base64 with padding (RFC 4648), for embedded images.
pub(crate) fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(data.len().div_ceil(3) * 4);
    for chunk in data.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(A[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_formats() {
        assert_eq!(fixed(1.23456, 2), "1.23");
        assert_eq!(fixed(-0.001, 2), "0");
        assert_eq!(fixed(10.0, 2), "10");
        assert_eq!(fixed(3.5, 0), "4");
        assert_eq!(sig(0.1 + 0.2), "0.3");
        assert_eq!(sig(-1.0), "-1");
        assert_eq!(sig(123456789.123), "123456789");
    }

    #[test]
    fn base64_matches_rfc4648_vectors() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }
}
