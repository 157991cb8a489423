//! The morph as a Lottie animation (JSON, and the dotLottie archive that wraps it): the format
//! apps, the web and design tools play (lottie-web, dotLottie/ThorVG, rlottie).
//!
//! Written from the frame model ([`crate::frame`]): the keyframes of the timeline
//! ([`Timeline::keyframes`], at most 120 a second) are made with the same structure
//! ([`crate::export::Morph::keyframe_at`]), and every item of every layer becomes a Lottie shape
//! group whose properties are keyframed:
//! - each path's contours as `sh` shapes whose keyframes share their vertex counts, fitted with
//!   cubics that hold a quarter pixel in every keyframe (as the animated SVG's);
//! - fills (`fl`) and strokes (`st`) with colour, opacity and width keyframes; linear and radial
//!   gradients (`gf`, `gs`) with keyframed end points and stops;
//! - each side of a cross-dissolve as a layer (a precomposition when it needs several) whose
//!   opacity follows [`crate::frame::dissolve`]; clip paths as layer masks.
//!
//! **Timing.** Keyframe `i` sits at `τ_i·duration` and holds the frame at `t_i = ease(τ_i)`. A
//! player eases between two keyframes by a cubic bezier; crmorph gives each span the cubic that
//! makes the value move linearly in `t` while `t` follows the easing — exact, since the easings
//! are cubics in `τ` ([`Easing::slope`]). Keyframes that the span between their neighbours already
//! reproduces (a quarter pixel for geometry, 1/1000 for colours and opacities) are dropped,
//! per property. The composition ends one frame after the last keyframe, since players stop on
//! frame `op − 1`: played once, the animation rests on the target exactly (so it lasts one
//! frame, 1/60 s, longer than the timeline). Yoyo playback is written out (forwards, then back); whether a player loops is
//! the player's setting, and the dotLottie manifest says so for [`Playback::Loop`] and
//! [`Playback::Yoyo`].
//!
//! **What Lottie cannot express** is drawn the nearest way and reported in [`Lottie::notes`]:
//! the exact arithmetic of the raster blend (Lottie has group opacity only, as the animated SVG);
//! embedded images (left out); a translucent group is drawn item by item (its opacity multiplies
//! each item's); only the innermost of nested clip paths clips, and an even-odd clip rule is
//! drawn nonzero; a radial gradient under a skew or a non-uniform scale is drawn round, with no
//! focal radius; gradients `reflect` and `repeat` pad; a pen that is not round is drawn round with
//! the same area.

use super::morph::Morph;
use crate::artwork::{
    Fill, Gradient, GradientKind, Group, Item, LineCap, LineJoin, Paint, Scene, Spread, Stroke,
};
use crate::error::{Error, Result};
use crate::frame::{Frame, FrameLayer};
use crate::render::{Easing, FrameOptions, Playback, Timeline};
use kurbo::{Affine, BezPath, PathEl, Point, Vec2};
use serde_json::{json, Map, Value};
use std::collections::BTreeSet;
use std::io::Write;

/// Frames per second of the composition. Keyframes sit at fractional frames where the timeline
/// puts them; players draw at their own rate between them.
const FRAME_RATE: f64 = 60.0;

/// How far a fitted or dropped keyframe's geometry may stray, in output pixels.
const GEOMETRY_TOLERANCE: f64 = 0.25;

/// How far a dropped keyframe's colour, opacity (as a fraction) or stop offset may stray.
const UNIT_TOLERANCE: f64 = 1e-3;

/// The note on embedded images.
const IMAGES_LEFT_OUT: &str = "embedded images are left out (write GIF, APNG or SVG for them)";

/// A Lottie animation of a morph, and what it could not express.
#[derive(Debug, Clone)]
pub struct Lottie {
    /// The Lottie JSON document.
    pub json: String,
    /// One sentence per kind of artwork drawn the nearest way Lottie allows (module docs), for
    /// the user to read: empty when the animation is what the animated SVG shows.
    pub notes: Vec<String>,
    /// Whether players should loop it ([`Playback::Loop`] and [`Playback::Yoyo`]).
    pub looping: bool,
}

impl Lottie {
    /// The dotLottie archive (a ZIP holding `manifest.json` and `animations/NAME.json`) of this
    /// animation, named `name` in the manifest; its `loop` is [`Lottie::looping`].
    pub fn dotlottie(&self, name: &str) -> Result<Vec<u8>> {
        let id: String = name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let id = if id.is_empty() { "morph".into() } else { id };
        let manifest = json!({
            "version": "1",
            "generator": concat!("crmorph ", env!("CARGO_PKG_VERSION")),
            "author": "crmorph",
            "animations": [{
                "id": id,
                "loop": self.looping,
                "autoplay": true,
                "speed": 1,
                "direction": 1,
                "playMode": "normal",
            }],
            "activeAnimationId": id,
        });
        let io = |e: zip::result::ZipError| Error::internal(format!("writing the archive: {e}"));
        let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        // A fixed time stamp: the same morph gives the same bytes.
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated)
            .last_modified_time(zip::DateTime::default());
        let manifest = serde_json::to_vec(&manifest)
            .map_err(|e| Error::internal(format!("the manifest: {e}")))?;
        for (path, bytes) in [
            ("manifest.json".to_string(), manifest.as_slice()),
            (format!("animations/{id}.json"), self.json.as_bytes()),
        ] {
            zip.start_file(path, options).map_err(io)?;
            zip.write_all(bytes)
                .map_err(|e| Error::internal(format!("writing the archive: {e}")))?;
        }
        Ok(zip.finish().map_err(io)?.into_inner())
    }
}

impl Morph {
    /// The morph as a Lottie animation (module docs), `name` its name in the file.
    pub fn lottie(&self, timeline: &Timeline, name: &str) -> Result<Lottie> {
        let tl = timeline.keyframes();
        let ts = tl.morph_times();
        let opts = *self.frame_options();
        let mut collect = Collector::new(&opts);
        for chunk in (0..ts.len())
            .collect::<Vec<_>>()
            .chunks(crate::render::stream::chunk_len(0))
        {
            let times: Vec<f64> = chunk.iter().map(|&i| ts[i]).collect();
            for frame in self.keyframes_at(&times)? {
                collect.keyframe(&frame)?;
            }
        }
        collect.finish(&tl, name)
    }
}

/// One keyframe's values of one item: its contours, paints and the opacity its groups give it.
#[derive(Debug, Clone)]
struct ItemSample {
    /// The outline in output pixels (a polyline, the warp's).
    path: BezPath,
    fill: Option<(PaintSample, bool)>,
    stroke: Option<StrokeSample>,
    /// Opacity of the enclosing groups (multiplied in; see the module docs).
    opacity: f64,
}

/// A fill's or stroke's paint at one keyframe, in output pixels, with its opacity in [0, 1].
#[derive(Debug, Clone, PartialEq)]
enum PaintSample {
    /// RGB in [0, 1], opacity.
    Color([f64; 3], f64),
    /// A gradient: `radial`, its start and end (Lottie's `s` and `e`), the highlight (length in
    /// percent, angle in degrees), the stops (offset, r, g, b, then offset, alpha) and opacity.
    Gradient {
        radial: bool,
        points: [f64; 4],
        highlight: [f64; 2],
        stops: Vec<[f64; 5]>,
        opacity: f64,
    },
}

impl PaintSample {
    /// The stops' mean colour: what a gradient becomes where its keyframes disagree in kind.
    fn mean_color(&self) -> ([f64; 3], f64) {
        match self {
            PaintSample::Color(c, o) => (*c, *o),
            PaintSample::Gradient { stops, opacity, .. } => {
                let n = stops.len().max(1) as f64;
                let mut c = [0.0; 3];
                let mut a = 0.0;
                for s in stops {
                    for k in 0..3 {
                        c[k] += s[k + 1] / n;
                    }
                    a += s[4] / n;
                }
                (c, opacity * a)
            }
        }
    }

    /// `(radial, stop count)` of a gradient; `None` for a colour.
    fn shape(&self) -> Option<(bool, usize)> {
        match self {
            PaintSample::Color(..) => None,
            PaintSample::Gradient { radial, stops, .. } => Some((*radial, stops.len())),
        }
    }
}

/// A stroke at one keyframe: its paint, width and dashes in output pixels.
#[derive(Debug, Clone)]
struct StrokeSample {
    paint: PaintSample,
    width: f64,
    cap: u8,
    join: u8,
    miter_limit: f64,
    /// Dash and gap lengths (an even count), then the offset; empty when solid.
    dashes: Vec<f64>,
    /// Painted below the fill (`paint-order: stroke`).
    first: bool,
}

/// The Lottie layers one side of a frame draws: split where a clip path starts or ends.
#[derive(Debug, Clone, Default)]
struct LayerSample {
    /// The clip's outlines in output pixels, when the layer is clipped.
    clip: Option<Vec<BezPath>>,
    items: Vec<ItemSample>,
    /// Ids of the items, for the shapes' names (from the first keyframe).
    names: Vec<String>,
}

/// One side of a frame (a blend's source or target, or a layer painted over) at one keyframe.
#[derive(Debug, Clone)]
struct SideSample {
    opacity: f64,
    layers: Vec<LayerSample>,
}

/// Walks keyframes into per-keyframe samples with one structure, collecting what Lottie cannot
/// express from the first.
struct Collector {
    to_px: Affine,
    opts: FrameOptions,
    samples: Vec<Vec<SideSample>>,
    notes: BTreeSet<&'static str>,
    /// Sides' names (from the first keyframe): "source 1", "target 1", "shapes 2", …
    side_names: Vec<String>,
    /// The file that names the morph in errors.
    file: String,
}

impl Collector {
    fn new(opts: &FrameOptions) -> Self {
        Collector {
            to_px: crate::render::view_transform(opts),
            opts: *opts,
            samples: Vec::new(),
            notes: BTreeSet::new(),
            side_names: Vec::new(),
            file: String::new(),
        }
    }

    /// Adds one keyframe.
    fn keyframe(&mut self, frame: &Frame) -> Result<()> {
        let first = self.samples.is_empty();
        if first {
            self.file = frame.file().to_string();
        }
        let (a, b) = frame.weights();
        let mut sides = Vec::new();
        for (k, layer) in frame.layers.iter().enumerate() {
            let parts: Vec<(&Scene, f64, &str)> = match layer {
                FrameLayer::Blend { source, target } => {
                    vec![(source, a, "source"), (target, b, "target")]
                }
                FrameLayer::Over(o) => vec![(o, 1.0, "shapes")],
            };
            for (scene, opacity, what) in parts {
                let mut walk = Walk {
                    to_px: self.to_px * scene.root_transform,
                    notes: &mut self.notes,
                    layers: vec![LayerSample::default()],
                    clip_depth: 0,
                };
                walk.group(&scene.root, 1.0, None);
                let mut layers = walk.layers;
                layers.retain(|l| !l.items.is_empty());
                if first {
                    self.side_names.push(format!("{what} {}", k + 1));
                }
                sides.push(SideSample { opacity, layers });
            }
        }
        if let Some(first) = self.samples.first() {
            let same = first.len() == sides.len()
                && first.iter().zip(&sides).all(|(p, q)| {
                    p.layers.len() == q.layers.len()
                        && p.layers.iter().zip(&q.layers).all(|(x, y)| {
                            x.items.len() == y.items.len()
                                && x.clip.as_ref().map(Vec::len) == y.clip.as_ref().map(Vec::len)
                        })
                });
            if !same {
                return Err(Error::internal(
                    "Lottie keyframes differ in structure (the warped artwork should not)",
                ));
            }
        }
        self.samples.push(sides);
        Ok(())
    }

    /// The document.
    fn finish(self, tl: &Timeline, name: &str) -> Result<Lottie> {
        let Some(first) = self.samples.first() else {
            return Err(Error::internal("no Lottie keyframes"));
        };
        if first.iter().all(|side| side.layers.is_empty()) && self.notes.contains(IMAGES_LEFT_OUT) {
            return Err(Error::input(
                &self.file,
                "a morph of raster images cannot be written as Lottie (it has no warped \
                 images); write .gif, .png or .svg",
            ));
        }
        let play = Play::new(tl);
        let (w, h) = (self.opts.size.0 as f64, self.opts.size.1 as f64);
        let mut found = self.notes.clone();
        let mut assets = Vec::new();
        // Lottie layers are listed top first.
        let mut layers = Vec::new();
        let mut index = 0usize;
        let mut next_index = || {
            index += 1;
            index
        };
        // The background, at the bottom.
        if let Some(bg) = self.opts.background {
            let mut layer = layer_header(4, "background", &play);
            let rect = BezPath::from_vec(vec![
                PathEl::MoveTo(Point::ZERO),
                PathEl::LineTo(Point::new(w, 0.0)),
                PathEl::LineTo(Point::new(w, h)),
                PathEl::LineTo(Point::new(0.0, h)),
                PathEl::ClosePath,
            ]);
            let mut it: Vec<Value> = contours(&rect)
                .into_iter()
                .map(|c| json!({"ty": "sh", "ks": {"a": 0, "k": shape_json(&c.0, c.1)}}))
                .collect();
            it.push(json!({"ty": "fl", "c": {"a": 0, "k": rgb_json(&rgb(bg))}, "o": {"a": 0, "k": 100 * bg.a as u32 / 255}, "r": 1}));
            it.push(transform_json());
            layer["shapes"] = json!([{"ty": "gr", "nm": "background", "it": it}]);
            layer["ind"] = json!(next_index());
            layers.push(layer);
        }
        for (s, side) in first.iter().enumerate() {
            let opacity = play.track(
                self.samples
                    .iter()
                    .map(|k| vec![100.0 * k[s].opacity])
                    .collect(),
                100.0 * UNIT_TOLERANCE,
                Format::Scalar,
            );
            let mut shape_layers = Vec::new();
            for l in 0..side.layers.len() {
                let keys: Vec<&LayerSample> =
                    self.samples.iter().map(|k| &k[s].layers[l]).collect();
                shape_layers.push(shape_layer(
                    &keys,
                    &play,
                    &self.side_names[s],
                    l,
                    &mut found,
                )?);
            }
            let name = &self.side_names[s];
            match shape_layers.len() {
                0 => continue,
                1 => {
                    let mut layer = shape_layers.pop().unwrap_or(Value::Null);
                    layer["ks"]["o"] = opacity;
                    layer["ind"] = json!(next_index());
                    layer["nm"] = json!(name);
                    layers.push(layer);
                }
                _ => {
                    let id = format!("side{}", s + 1);
                    let mut inner: Vec<Value> = shape_layers;
                    inner.reverse();
                    for (i, l) in inner.iter_mut().enumerate() {
                        l["ind"] = json!(i + 1);
                        l["op"] = json!(play.out_point());
                    }
                    assets.push(json!({"id": id, "nm": name, "layers": inner}));
                    let mut layer = layer_header(0, name, &play);
                    layer["refId"] = json!(id);
                    layer["w"] = num(w);
                    layer["h"] = num(h);
                    layer["ks"]["o"] = opacity;
                    layer["ind"] = json!(next_index());
                    layers.push(layer);
                }
            }
        }
        layers.reverse();
        let doc = json!({
            "v": "5.12.0",
            "nm": name,
            "fr": num(FRAME_RATE),
            "ip": 0,
            "op": play.out_point(),
            "w": self.opts.size.0,
            "h": self.opts.size.1,
            "assets": assets,
            "layers": layers,
        });
        let json = serde_json::to_string(&doc)
            .map_err(|e| Error::internal(format!("writing Lottie JSON: {e}")))?;
        Ok(Lottie {
            json,
            notes: found.into_iter().map(String::from).collect(),
            looping: tl.playback != Playback::Once,
        })
    }
}

/// Walks one scene into layers of items (module docs: groups flattened, clips as layers).
struct Walk<'a> {
    to_px: Affine,
    notes: &'a mut BTreeSet<&'static str>,
    layers: Vec<LayerSample>,
    clip_depth: usize,
}

impl Walk<'_> {
    fn group(&mut self, g: &Group, opacity: f64, clip: Option<&Vec<BezPath>>) {
        let opacity = opacity * g.opacity;
        if g.opacity < 1.0 && g.children.len() > 1 {
            self.notes.insert(
                "a translucent group is drawn item by item: where its items overlap, the \
                 overlap is darker than in the SVG",
            );
        }
        let own_clip = g.clip.as_ref().map(|c| {
            if c.shapes.iter().any(|s| s.even_odd) {
                self.notes
                    .insert("an even-odd clip rule is drawn as nonzero (Lottie masks have none)");
            }
            c.shapes
                .iter()
                .map(|s| self.to_px * s.path.clone())
                .collect::<Vec<_>>()
        });
        // Items with a clip go to a layer of their own, masked (`current`).
        if own_clip.is_some() {
            if self.clip_depth > 0 {
                self.notes.insert(
                    "of nested clip paths only the innermost clips (Lottie masks do not nest)",
                );
            }
            self.clip_depth += 1;
        }
        let clip = own_clip.as_ref().or(clip);
        for item in &g.children {
            match item {
                Item::Group(inner) => self.group(inner, opacity, clip),
                Item::Path(p) => {
                    let to_px = self.to_px;
                    let pen = pen_scale(to_px);
                    let notes = &mut *self.notes;
                    let fill = p
                        .fill
                        .as_ref()
                        .map(|f| (fill_paint(f, to_px, notes), f.even_odd));
                    let stroke = p
                        .stroke
                        .as_ref()
                        .map(|s| stroke_sample(s, to_px, pen, p.stroke_first, notes));
                    let layer = self.current(clip);
                    layer.items.push(ItemSample {
                        path: to_px * p.path.clone(),
                        fill,
                        stroke,
                        opacity,
                    });
                    layer.names.push(p.id.clone());
                }
                Item::Image(_) => {
                    self.notes.insert(IMAGES_LEFT_OUT);
                }
            }
        }
        if own_clip.is_some() {
            self.clip_depth -= 1;
        }
    }

    /// The layer items with clip `clip` go into: the last one if it has that clip, else a new one.
    fn current(&mut self, clip: Option<&Vec<BezPath>>) -> &mut LayerSample {
        let fits = self.layers.last().is_some_and(|l| l.clip.as_ref() == clip);
        if !fits {
            self.layers.push(LayerSample {
                clip: clip.cloned(),
                ..LayerSample::default()
            });
        }
        let n = self.layers.len() - 1;
        &mut self.layers[n]
    }
}

/// Output pixels per user unit of a stroke width under `m` (the square root of its area scale).
fn pen_scale(m: Affine) -> f64 {
    m.determinant().abs().sqrt()
}

/// Whether `m` maps circles to circles within 2 % (a similarity): what a round pen and
/// Lottie's round radial gradients can follow. The local maps of a mesh are never exactly
/// similarities; a difference of a few percent does not show.
fn round(m: Affine) -> bool {
    let [a, b, c, d, _, _] = m.as_coeffs();
    let (sx, sy) = ((a * a + b * b).sqrt(), (c * c + d * d).sqrt());
    (sx - sy).abs() <= 0.02 * sx.max(sy) && (a * c + b * d).abs() <= 0.02 * sx * sy
}

fn rgb(c: crate::artwork::Rgba) -> [f64; 3] {
    [c.r as f64 / 255.0, c.g as f64 / 255.0, c.b as f64 / 255.0]
}

fn fill_paint(f: &Fill, to_px: Affine, notes: &mut BTreeSet<&'static str>) -> PaintSample {
    paint(&f.paint, f.opacity, to_px, notes)
}

fn stroke_sample(
    s: &Stroke,
    to_px: Affine,
    pen: f64,
    first: bool,
    notes: &mut BTreeSet<&'static str>,
) -> StrokeSample {
    let pen = match s.frame {
        Some(frame) => {
            if !round(frame) {
                notes.insert(
                    "a stroke drawn with a pen that is not round is drawn round, of the same area",
                );
            }
            pen * pen_scale(frame)
        }
        None => pen,
    };
    let mut dashes: Vec<f64> = s.dashes.iter().map(|d| d * pen).collect();
    if dashes.len() % 2 == 1 {
        dashes.extend_from_within(..);
    }
    if !dashes.is_empty() {
        dashes.push(s.dash_offset * pen);
    }
    StrokeSample {
        paint: paint(&s.paint, s.opacity, to_px, notes),
        width: s.width * pen,
        cap: match s.cap {
            LineCap::Butt => 1,
            LineCap::Round => 2,
            LineCap::Square => 3,
        },
        join: match s.join {
            LineJoin::Miter | LineJoin::MiterClip => 1,
            LineJoin::Round => 2,
            LineJoin::Bevel => 3,
        },
        miter_limit: s.miter_limit,
        dashes,
        first,
    }
}

/// A paint in output pixels.
fn paint(
    p: &Paint,
    opacity: f64,
    to_px: Affine,
    notes: &mut BTreeSet<&'static str>,
) -> PaintSample {
    match p {
        Paint::Color(c) => PaintSample::Color(rgb(*c), opacity),
        Paint::Gradient(g) => gradient(g, opacity, to_px, notes),
    }
}

fn gradient(
    g: &Gradient,
    opacity: f64,
    to_px: Affine,
    notes: &mut BTreeSet<&'static str>,
) -> PaintSample {
    if g.spread != Spread::Pad {
        notes.insert("gradients that reflect or repeat are padded (Lottie has no spread method)");
    }
    let m = to_px * g.transform;
    let stops: Vec<[f64; 5]> = g
        .stops
        .iter()
        .map(|s| {
            let [r, gg, b] = rgb(s.color);
            [s.offset, r, gg, b, s.opacity]
        })
        .collect();
    let last = |stops: &[[f64; 5]]| {
        stops.last().map_or(PaintSample::Color([0.0; 3], 0.0), |s| {
            PaintSample::Color([s[1], s[2], s[3]], opacity * s[4])
        })
    };
    let det = m.determinant();
    if stops.is_empty() || !det.is_finite() || det.abs() < 1e-12 {
        return last(&stops);
    }
    match g.kind {
        GradientKind::Linear { start, end } => {
            let v = Vec2::new(end.x - start.x, end.y - start.y);
            let len2 = v.hypot2();
            if len2 <= 0.0 {
                return last(&stops);
            }
            // The paint is f(p) = ∇·p + c: ∇ = A⁻ᵀ v / |v|², A the linear part of `m`; Lottie's
            // gradient from s to e has ∇ = (e − s) / |e − s|², so e = s + ∇ / |∇|².
            let [a, b, c, d, _, _] = m.as_coeffs();
            let inv = 1.0 / det;
            // A = [[a, c], [b, d]]; A⁻ᵀ = inv · [[d, −b], [−c, a]].
            let grad = Vec2::new(d * v.x - b * v.y, -c * v.x + a * v.y) * (inv / len2);
            let g2 = grad.hypot2();
            if g2 <= 0.0 || !g2.is_finite() {
                return last(&stops);
            }
            let s = m * Point::new(start.x, start.y);
            let e = s + grad / g2;
            PaintSample::Gradient {
                radial: false,
                points: [s.x, s.y, e.x, e.y],
                highlight: [0.0, 0.0],
                stops,
                opacity,
            }
        }
        GradientKind::Radial {
            center,
            radius,
            focal,
            focal_radius,
        } => {
            if !round(m) {
                notes
                    .insert("a radial gradient under a skew or a non-uniform scale is drawn round");
            }
            if focal_radius > 0.0 {
                notes.insert("a radial gradient's focal radius is drawn as zero");
            }
            let r = radius * det.abs().sqrt();
            let s = m * Point::new(center.x, center.y);
            let f = m * Point::new(focal.x, focal.y);
            let off = f - s;
            let h = if r > 0.0 {
                (off.hypot() / r * 100.0).min(99.0)
            } else {
                0.0
            };
            let angle = if h > 0.0 {
                off.y.atan2(off.x).to_degrees()
            } else {
                0.0
            };
            PaintSample::Gradient {
                radial: true,
                points: [s.x, s.y, s.x + r, s.y],
                highlight: [h, angle],
                stops,
                opacity,
            }
        }
    }
}

/// One contour of a path: vertices, in-tangents and out-tangents (relative), flattened as
/// `[vx, vy, ix, iy, ox, oy]` per vertex, and whether it is closed.
type Contour = (Vec<f64>, bool);

/// The contours of `path` in Lottie's vertex-and-tangent form (quadratics raised to cubics).
fn contours(path: &BezPath) -> Vec<Contour> {
    let mut out: Vec<Contour> = Vec::new();
    let mut current: Option<Contour> = None;
    let mut last = Point::ZERO;
    for el in path.elements() {
        match *el {
            PathEl::MoveTo(p) => {
                out.extend(current.take());
                current = Some((vec![p.x, p.y, 0.0, 0.0, 0.0, 0.0], false));
                last = p;
            }
            PathEl::LineTo(p) => {
                let c = current
                    .get_or_insert_with(|| (vec![last.x, last.y, 0.0, 0.0, 0.0, 0.0], false));
                c.0.extend([p.x, p.y, 0.0, 0.0, 0.0, 0.0]);
                last = p;
            }
            PathEl::QuadTo(q, p) => {
                let c1 = last + (q - last) * (2.0 / 3.0);
                let c2 = p + (q - p) * (2.0 / 3.0);
                cubic(&mut current, last, c1, c2, p);
                last = p;
            }
            PathEl::CurveTo(c1, c2, p) => {
                cubic(&mut current, last, c1, c2, p);
                last = p;
            }
            PathEl::ClosePath => {
                if let Some(mut c) = current.take() {
                    c.1 = true;
                    last = Point::new(c.0[0], c.0[1]);
                    out.push(c);
                }
            }
        }
    }
    out.extend(current);
    out
}

fn cubic(current: &mut Option<Contour>, last: Point, c1: Point, c2: Point, p: Point) {
    let c = current.get_or_insert_with(|| (vec![last.x, last.y, 0.0, 0.0, 0.0, 0.0], false));
    let n = c.0.len();
    c.0[n - 2] = c1.x - last.x;
    c.0[n - 1] = c1.y - last.y;
    c.0.extend([p.x, p.y, c2.x - p.x, c2.y - p.y, 0.0, 0.0]);
}

/// A number as JSON: to a thousandth, whole numbers without a fraction, non-finite as 0.
fn num(x: f64) -> Value {
    let r = (x * 1000.0).round() / 1000.0;
    if !r.is_finite() || r == 0.0 {
        return json!(0);
    }
    if r.fract() == 0.0 && r.abs() < 1e15 {
        json!(r as i64)
    } else {
        json!(r)
    }
}

fn rgb_json(c: &[f64; 3]) -> Value {
    json!([num(c[0]), num(c[1]), num(c[2]), 1])
}

fn shape_json(v: &[f64], closed: bool) -> Value {
    let pts = |k: usize| -> Vec<Value> {
        v.chunks_exact(6)
            .map(|c| json!([num(c[k]), num(c[k + 1])]))
            .collect()
    };
    json!({"c": closed, "v": pts(0), "i": pts(2), "o": pts(4)})
}

/// The identity transform every Lottie shape group ends with.
fn transform_json() -> Value {
    json!({
        "ty": "tr",
        "p": {"a": 0, "k": [0, 0]},
        "a": {"a": 0, "k": [0, 0]},
        "s": {"a": 0, "k": [100, 100]},
        "r": {"a": 0, "k": 0},
        "o": {"a": 0, "k": 100},
        "sk": {"a": 0, "k": 0},
        "sa": {"a": 0, "k": 0},
    })
}

/// A layer of type `ty` (4 shapes, 0 precomposition) with an identity transform, shown for
/// the whole animation.
fn layer_header(ty: u8, name: &str, play: &Play) -> Value {
    json!({
        "ty": ty,
        "nm": name,
        "sr": 1,
        "ks": {
            "o": {"a": 0, "k": 100},
            "r": {"a": 0, "k": 0},
            "p": {"a": 0, "k": [0, 0, 0]},
            "a": {"a": 0, "k": [0, 0, 0]},
            "s": {"a": 0, "k": [100, 100, 100]},
        },
        "ao": 0,
        "ip": 0,
        "op": play.out_point(),
        "st": 0,
    })
}

/// How a keyframed value is written.
#[derive(Debug, Clone, Copy)]
enum Format {
    /// One number.
    Scalar,
    /// Numbers as an array (points, colours, gradient stops).
    Vector,
    /// A contour ([`Contour`]), closed or not.
    Shape(bool),
}

/// The played keyframes: which timeline frame each shows, when, and the spans' easing.
struct Play {
    /// Timeline frame of each played keyframe, in play order.
    order: Vec<usize>,
    /// Animation time of each timeline frame, as a fraction of the duration.
    taus: Vec<f64>,
    /// The morph's t of each timeline frame.
    ts: Vec<f64>,
    easing: Easing,
    /// Lottie frames per timeline step (one step: a 1/(N − 1) of the duration).
    frames_per_step: f64,
    /// The played position where the sequence turns (yoyo, at the target), never merged
    /// across.
    turn: Option<usize>,
}

impl Play {
    fn new(tl: &Timeline) -> Self {
        let mut order = tl.sequence();
        let turn = (tl.playback == Playback::Yoyo).then_some(tl.frames - 1);
        if turn.is_some() {
            order.push(0);
        }
        Play {
            order,
            taus: tl.times(),
            ts: tl.morph_times(),
            easing: tl.easing,
            frames_per_step: tl.duration * FRAME_RATE / (tl.frames - 1) as f64,
            turn,
        }
    }

    /// The composition's out point: one frame after the last keyframe, so that the last frame
    /// (`op − 1`, where players stop) shows it.
    fn out_point(&self) -> Value {
        num((self.order.len() - 1) as f64 * self.frames_per_step + 1.0)
    }

    /// The keyframed property of `values` (one per timeline frame): static when they all
    /// agree within `tol`, else the played keyframes with those the span between their
    /// neighbours reproduces dropped.
    fn track(&self, values: Vec<Vec<f64>>, tol: f64, format: Format) -> Value {
        let write = |v: &[f64]| -> Value {
            match format {
                Format::Scalar => num(v.first().copied().unwrap_or(0.0)),
                Format::Vector => Value::Array(v.iter().map(|&x| num(x)).collect()),
                Format::Shape(closed) => shape_json(v, closed),
            }
        };
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol);
        if values.iter().all(|v| close(v, &values[0])) {
            return json!({"a": 0, "k": write(&values[0])});
        }
        // Played positions kept: greedy, from each kept one as far as the span holds.
        let n = self.order.len();
        let mut kept = vec![0usize];
        let mut a = 0;
        while a < n - 1 {
            let mut b = a + 1;
            while b + 1 < n && Some(b) != self.turn && self.holds(&values, a, b + 1, tol) {
                b += 1;
            }
            kept.push(b);
            a = b;
        }
        let mut keys = Vec::with_capacity(kept.len());
        for (j, &p) in kept.iter().enumerate() {
            let frame = self.order[p];
            // A keyframe's value is an array: one number, a shape, or the vector itself.
            let s = match format {
                Format::Shape(_) | Format::Scalar => json!([write(&values[frame])]),
                Format::Vector => write(&values[frame]),
            };
            let mut key = Map::new();
            key.insert("t".into(), num(p as f64 * self.frames_per_step));
            key.insert("s".into(), s);
            if let Some(&q) = kept.get(j + 1) {
                let (y1, y2) = self.handles(p, q);
                key.insert("o".into(), json!({"x": num(1.0 / 3.0), "y": num(y1)}));
                key.insert("i".into(), json!({"x": num(2.0 / 3.0), "y": num(y2)}));
            }
            keys.push(Value::Object(key));
        }
        json!({"a": 1, "k": keys})
    }

    /// Whether every played keyframe strictly between positions `a` and `b` is, within `tol`,
    /// the value the span from `a` to `b` gives it (linear in the morph's t).
    fn holds(&self, values: &[Vec<f64>], a: usize, b: usize, tol: f64) -> bool {
        let (fa, fb) = (self.order[a], self.order[b]);
        let (ta, tb) = (self.ts[fa], self.ts[fb]);
        (a + 1..b).all(|k| {
            let fk = self.order[k];
            let u = if (tb - ta).abs() > 1e-12 {
                (self.ts[fk] - ta) / (tb - ta)
            } else {
                // No change of t across the span: nothing between may differ.
                0.0
            };
            values[fk]
                .iter()
                .zip(values[fa].iter().zip(&values[fb]))
                .all(|(v, (x, y))| (v - (x + (y - x) * u)).abs() <= tol)
        })
    }

    /// The bezier easing `(y1, y2)` of the span from played position `p` to `q` (with
    /// `x1 = 1/3`, `x2 = 2/3`): the cubic of the morph's progress across the span, normalised.
    fn handles(&self, p: usize, q: usize) -> (f64, f64) {
        let (fp, fq) = (self.order[p], self.order[q]);
        let (tp, tq) = (self.ts[fp], self.ts[fq]);
        let dt = tq - tp;
        if dt.abs() < 1e-12 {
            return (1.0 / 3.0, 2.0 / 3.0);
        }
        let dtau = self.taus[fq] - self.taus[fp];
        let start = dtau * self.easing.slope(self.taus[fp]) / dt;
        let end = dtau * self.easing.slope(self.taus[fq]) / dt;
        (start / 3.0, 1.0 - end / 3.0)
    }
}

/// The Lottie shape layer of one layer of a side (its keyframes `keys`), its shape groups top
/// first; with masks when it is clipped.
fn shape_layer(
    keys: &[&LayerSample],
    play: &Play,
    side: &str,
    l: usize,
    notes: &mut BTreeSet<&'static str>,
) -> Result<Value> {
    let first = keys[0];
    let mut layer = layer_header(4, &format!("{side} part {}", l + 1), play);
    if let Some(clip) = &first.clip {
        let mut masks = Vec::new();
        let paths: Vec<Vec<BezPath>> = keys
            .iter()
            .map(|k| k.clip.clone().unwrap_or_default())
            .collect();
        for c in 0..clip.len() {
            let shapes: Vec<BezPath> = paths
                .iter()
                .map(|p| p.get(c).cloned().unwrap_or_default())
                .collect();
            for track in shape_tracks(&shapes, play)? {
                masks.push(json!({
                    "inv": false,
                    "mode": "a",
                    "pt": track,
                    "o": {"a": 0, "k": 100},
                    "x": {"a": 0, "k": 0},
                    "nm": "clip",
                }));
            }
        }
        layer["hasMask"] = json!(true);
        layer["masksProperties"] = Value::Array(masks);
    }
    let mut groups = Vec::new();
    for i in 0..first.items.len() {
        let samples: Vec<&ItemSample> = keys.iter().map(|k| &k.items[i]).collect();
        if let Some(g) = item_group(&samples, play, &first.names[i], notes)? {
            groups.push(g);
        }
    }
    groups.reverse();
    layer["shapes"] = Value::Array(groups);
    Ok(layer)
}

/// The `sh` tracks of one path through the keyframes: fitted with cubics that hold in every
/// keyframe, one per contour.
fn shape_tracks(paths: &[BezPath], play: &Play) -> Result<Vec<Value>> {
    let fitted = crate::render::fit_paths(paths, GEOMETRY_TOLERANCE);
    let per_key: Vec<Vec<Contour>> = fitted.iter().map(contours).collect();
    let n = per_key[0].len();
    let same = per_key.iter().all(|c| {
        c.len() == n
            && c.iter()
                .zip(&per_key[0])
                .all(|(x, y)| x.0.len() == y.0.len() && x.1 == y.1)
    });
    if !same {
        return Err(Error::internal(
            "Lottie keyframes of a path differ in vertex count (the warped artwork should not)",
        ));
    }
    Ok((0..n)
        .map(|c| {
            let values: Vec<Vec<f64>> = per_key.iter().map(|k| k[c].0.clone()).collect();
            play.track(values, GEOMETRY_TOLERANCE, Format::Shape(per_key[0][c].1))
        })
        .collect())
}

/// The paints of one fill or stroke through the keyframes, made alike: gradients of one kind and
/// stop count, else every keyframe's mean colour.
fn uniform_paints(
    paints: Vec<PaintSample>,
    notes: &mut BTreeSet<&'static str>,
) -> Vec<PaintSample> {
    let shape = paints[0].shape();
    if paints.iter().all(|p| p.shape() == shape) {
        return paints;
    }
    notes.insert(
        "a paint that changes between a colour and a gradient, or between gradients of other \
         kinds, is drawn as its mean colour",
    );
    paints
        .iter()
        .map(|p| {
            let (c, o) = p.mean_color();
            PaintSample::Color(c, o)
        })
        .collect()
}

/// The style items (`fl`/`gf` or `st`/`gs`) of one paint through the keyframes, `opacity` the
/// groups' opacity of each keyframe.
fn paint_items(
    paints: Vec<PaintSample>,
    opacity: &[f64],
    play: &Play,
    notes: &mut BTreeSet<&'static str>,
) -> Map<String, Value> {
    let paints = uniform_paints(paints, notes);
    let mut m = Map::new();
    match &paints[0] {
        PaintSample::Color(..) => {
            let colors = paints
                .iter()
                .map(|p| match p {
                    PaintSample::Color(c, _) => c.to_vec(),
                    _ => vec![0.0; 3],
                })
                .map(|mut c| {
                    c.push(1.0);
                    c
                })
                .collect();
            m.insert(
                "c".into(),
                play.track(colors, UNIT_TOLERANCE, Format::Vector),
            );
        }
        PaintSample::Gradient { radial, stops, .. } => {
            let alpha = paints.iter().any(|p| match p {
                PaintSample::Gradient { stops, .. } => stops.iter().any(|s| s[4] < 1.0),
                _ => false,
            });
            let values = |f: &dyn Fn(&PaintSample) -> Vec<f64>| paints.iter().map(f).collect();
            let points = |k: usize| -> Vec<Vec<f64>> {
                values(&|p| match p {
                    PaintSample::Gradient { points, .. } => vec![points[k], points[k + 1]],
                    _ => vec![0.0; 2],
                })
            };
            m.insert(
                "s".into(),
                play.track(points(0), GEOMETRY_TOLERANCE, Format::Vector),
            );
            m.insert(
                "e".into(),
                play.track(points(2), GEOMETRY_TOLERANCE, Format::Vector),
            );
            m.insert("t".into(), json!(if *radial { 2 } else { 1 }));
            let colors = values(&|p| match p {
                PaintSample::Gradient { stops, .. } => {
                    let mut v: Vec<f64> = stops
                        .iter()
                        .flat_map(|s| [s[0], s[1], s[2], s[3]])
                        .collect();
                    if alpha {
                        v.extend(stops.iter().flat_map(|s| [s[0], s[4]]));
                    }
                    v
                }
                _ => Vec::new(),
            });
            m.insert(
                "g".into(),
                json!({"p": stops.len(), "k": play.track(colors, UNIT_TOLERANCE, Format::Vector)}),
            );
            if *radial {
                let h = |k: usize| -> Vec<Vec<f64>> {
                    values(&|p| match p {
                        PaintSample::Gradient { highlight, .. } => vec![highlight[k]],
                        _ => vec![0.0],
                    })
                };
                m.insert(
                    "h".into(),
                    play.track(h(0), 100.0 * UNIT_TOLERANCE, Format::Scalar),
                );
                m.insert("a".into(), play.track(h(1), 0.1, Format::Scalar));
            }
        }
    }
    let opacities = paints
        .iter()
        .zip(opacity)
        .map(|(p, g)| {
            let o = match p {
                PaintSample::Color(_, o) => *o,
                PaintSample::Gradient { opacity, .. } => *opacity,
            };
            vec![100.0 * o * g]
        })
        .collect();
    m.insert(
        "o".into(),
        play.track(opacities, 100.0 * UNIT_TOLERANCE, Format::Scalar),
    );
    m
}

/// The shape group of one item through the keyframes; `None` when its path is empty.
fn item_group(
    samples: &[&ItemSample],
    play: &Play,
    name: &str,
    notes: &mut BTreeSet<&'static str>,
) -> Result<Option<Value>> {
    let first = samples[0];
    if first.path.elements().is_empty() || (first.fill.is_none() && first.stroke.is_none()) {
        return Ok(None);
    }
    let paths: Vec<BezPath> = samples.iter().map(|s| s.path.clone()).collect();
    let mut it: Vec<Value> = shape_tracks(&paths, play)?
        .into_iter()
        .map(|ks| json!({"ty": "sh", "ks": ks}))
        .collect();
    let opacity: Vec<f64> = samples.iter().map(|s| s.opacity).collect();
    let fill = first.fill.as_ref().map(|(_, even_odd)| {
        let paints = samples
            .iter()
            .map(|s| {
                s.fill
                    .as_ref()
                    .map_or(PaintSample::Color([0.0; 3], 0.0), |f| f.0.clone())
            })
            .collect();
        let mut m = paint_items(paints, &opacity, play, notes);
        let gradient = m.contains_key("g");
        m.insert("ty".into(), json!(if gradient { "gf" } else { "fl" }));
        m.insert("r".into(), json!(if *even_odd { 2 } else { 1 }));
        Value::Object(m)
    });
    let stroke = first.stroke.as_ref().map(|st| {
        let strokes: Vec<&StrokeSample> = samples
            .iter()
            .map(|s| s.stroke.as_ref().unwrap_or(st))
            .collect();
        let paints = strokes.iter().map(|s| s.paint.clone()).collect();
        let mut m = paint_items(paints, &opacity, play, notes);
        let gradient = m.contains_key("g");
        m.insert("ty".into(), json!(if gradient { "gs" } else { "st" }));
        m.insert(
            "w".into(),
            play.track(strokes.iter().map(|s| vec![s.width]).collect(), GEOMETRY_TOLERANCE, Format::Scalar),
        );
        m.insert("lc".into(), json!(st.cap));
        m.insert("lj".into(), json!(st.join));
        m.insert("ml".into(), num(st.miter_limit));
        if !st.dashes.is_empty() {
            let n = st.dashes.len();
            let dashes: Vec<Value> = (0..n)
                .map(|k| {
                    let (code, nm) = match (k + 1 == n, k % 2) {
                        (true, _) => ("o", "offset"),
                        (false, 0) => ("d", "dash"),
                        (false, _) => ("g", "gap"),
                    };
                    let v = strokes.iter().map(|s| vec![s.dashes.get(k).copied().unwrap_or(0.0)]).collect();
                    json!({"n": code, "nm": nm, "v": play.track(v, GEOMETRY_TOLERANCE, Format::Scalar)})
                })
                .collect();
            m.insert("d".into(), Value::Array(dashes));
        }
        (Value::Object(m), st.first)
    });
    // Within a group, the style listed first is drawn on top.
    match (fill, stroke) {
        (Some(f), Some((s, true))) => it.extend([f, s]),
        (Some(f), Some((s, false))) => it.extend([s, f]),
        (Some(f), None) => it.push(f),
        (None, Some((s, _))) => it.push(s),
        (None, None) => return Ok(None),
    }
    it.push(transform_json());
    let np = it.len() - 1;
    Ok(Some(json!({"ty": "gr", "nm": name, "np": np, "it": it})))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contours_keep_curves_as_tangents_and_close() {
        let mut p = BezPath::new();
        p.move_to((0.0, 0.0));
        p.line_to((10.0, 0.0));
        p.curve_to((12.0, 2.0), (12.0, 8.0), (10.0, 10.0));
        p.close_path();
        p.move_to((20.0, 20.0));
        p.quad_to((23.0, 20.0), (23.0, 23.0));
        let c = contours(&p);
        assert_eq!(c.len(), 2);
        assert!(c[0].1 && !c[1].1);
        assert_eq!(
            c[0].0,
            vec![
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0, //
                10.0, 0.0, 0.0, 0.0, 2.0, 2.0, //
                10.0, 10.0, 2.0, -2.0, 0.0, 0.0
            ]
        );
        // A quadratic raised to a cubic: controls two thirds of the way to its one control.
        assert_eq!(c[1].0[4..6], [2.0, 0.0]);
        assert_eq!(c[1].0[8..10], [0.0, -2.0]);
    }

    #[test]
    fn span_easing_follows_the_timeline_easing_exactly() {
        for easing in [Easing::Linear, Easing::EaseInOut] {
            let tl = Timeline {
                frames: 7,
                easing,
                ..Timeline::default()
            };
            let play = Play::new(&tl);
            // The player's value at animation time inside span p → q is the bezier y(x); it
            // must be (ease(τ) − t_p) / (t_q − t_p).
            for (p, q) in [(0, 1), (2, 3), (1, 5), (5, 6)] {
                let (y1, y2) = play.handles(p, q);
                for k in 1..10 {
                    let s = k as f64 / 10.0; // with x1 = 1/3, x2 = 2/3, x(s) = s
                    let y = 3.0 * (1.0 - s) * (1.0 - s) * s * y1
                        + 3.0 * (1.0 - s) * s * s * y2
                        + s * s * s;
                    let tau = play.taus[p] + s * (play.taus[q] - play.taus[p]);
                    let want = (easing.apply(tau) - play.ts[p]) / (play.ts[q] - play.ts[p]);
                    assert!(
                        (y - want).abs() < 1e-12,
                        "{easing:?} {p}→{q} at {s}: {y} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn keyframes_that_their_neighbours_reproduce_are_dropped() {
        let tl = Timeline {
            frames: 5,
            ..Timeline::default()
        };
        let play = Play::new(&tl);
        // Linear in t up to frame 2, then still: frames 1 and 3 are redundant.
        let v: Vec<Vec<f64>> = [0.0, 1.0, 2.0, 2.0, 2.0].iter().map(|&x| vec![x]).collect();
        let track = play.track(v, 1e-6, Format::Scalar);
        let times: Vec<f64> = track["k"]
            .as_array()
            .unwrap()
            .iter()
            .map(|k| k["t"].as_f64().unwrap())
            .collect();
        let step = play.frames_per_step;
        assert_eq!(times, vec![0.0, 2.0 * step, 4.0 * step]);
        let still = play.track(vec![vec![3.0]; 5], 1e-6, Format::Scalar);
        assert_eq!(still, json!({"a": 0, "k": 3}));
    }

    #[test]
    fn yoyo_turns_at_the_target_and_comes_back() {
        let tl = Timeline {
            frames: 3,
            playback: Playback::Yoyo,
            ..Timeline::default()
        };
        let play = Play::new(&tl);
        assert_eq!(play.order, vec![0, 1, 2, 1, 0]);
        let v: Vec<Vec<f64>> = [0.0, 1.0, 2.0].iter().map(|&x| vec![x]).collect();
        let track = play.track(v, 1e-6, Format::Scalar);
        let keys = track["k"].as_array().unwrap();
        // Frame 1 is redundant both ways, but the turn at the target is kept.
        let s: Vec<f64> = keys.iter().map(|k| k["s"][0].as_f64().unwrap()).collect();
        assert_eq!(s, vec![0.0, 2.0, 0.0]);
    }

    #[test]
    fn a_linear_gradient_under_a_skew_keeps_its_isolines() {
        // Gradient along x from 0 to 10, then sheared: isolines x = c become slanted lines, and
        // Lottie's gradient vector must be perpendicular to them, reaching the line x' = 10.
        let g = Gradient {
            kind: GradientKind::Linear {
                start: crate::geometry::Point::new(0.0, 0.0),
                end: crate::geometry::Point::new(10.0, 0.0),
            },
            transform: Affine::new([1.0, 0.0, 1.0, 1.0, 0.0, 0.0]), // x' = x + y, y' = y
            spread: Spread::Pad,
            stops: vec![],
        };
        let mut notes = BTreeSet::new();
        let mut with_stops = g.clone();
        with_stops.stops = vec![crate::artwork::GradientStop {
            offset: 0.0,
            color: crate::artwork::Rgba {
                r: 0,
                g: 0,
                b: 0,
                a: 255,
            },
            opacity: 1.0,
        }];
        let PaintSample::Gradient { points, .. } =
            gradient(&with_stops, 1.0, Affine::IDENTITY, &mut notes)
        else {
            panic!("a gradient")
        };
        let (s, e) = (
            Point::new(points[0], points[1]),
            Point::new(points[2], points[3]),
        );
        // The isoline of offset 1 passes through (10, 0) and (20, 10) in the output; the
        // gradient's end lies on it and the vector is perpendicular to it.
        let dir = Vec2::new(10.0, 10.0);
        assert!(((e - s).dot(dir)).abs() < 1e-9);
        let f = |p: Point| (p - s).dot(e - s) / (e - s).hypot2();
        assert!((f(Point::new(10.0, 0.0)) - 1.0).abs() < 1e-9);
        assert!((f(Point::new(20.0, 10.0)) - 1.0).abs() < 1e-9);
        assert!(f(Point::new(5.0, 5.0)) - 0.0 < 1e-9, "the start isoline");
        assert!(notes.is_empty());
    }
}
