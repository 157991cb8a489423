//! A morph ready to export: built once, then asked for any frame or any animation.
//!
//! This is the precompute-then-apply shape of the whole pipeline: the compatible meshes, the
//! rigid interpolator (eq. (1) factored once) and both artworks bound to their meshes are made
//! once; a frame is then one solve, one warp and one render, and frames are independent, so
//! sequences are computed in parallel.

use crate::artwork::{ArtworkPair, Scene};
use crate::error::Result;
use crate::export::apng::write_apng;
use crate::export::gif::write_gif;
use crate::export::{preview_html, PreviewMesh, Timeline};
use crate::frame::{Frame, FrameLayer};
use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;
use crate::morphing::{in_paint_order, overlay_at, MorphingPath};
use crate::render::stream::{chunk_len, in_order};
use crate::render::{
    frame_pixmap_layers, frame_svg_layers, frame_tree, layers_of, write_animated_svg, FrameOptions,
    Mode, Node,
};
use crate::rigid::Interpolator;
use crate::skeleton::SkeletonControl;
use rayon::prelude::*;
use std::borrow::Cow;
use std::io::{Cursor, Seek, Write};
use std::sync::{Arc, OnceLock};
use tiny_skia::Pixmap;

/// What moves the mesh: the rigid interpolation alone, or steered by a skeleton (§4.2).
#[derive(Debug)]
pub enum Motion {
    /// Plain interpolation (§4.1, or a baseline method).
    Plain(Box<Interpolator>),
    /// Disc-based interpolation adjusted to meet control poses (§4.2).
    Skeleton(Box<SkeletonControl>),
}

impl From<Interpolator> for Motion {
    fn from(i: Interpolator) -> Self {
        Motion::Plain(Box::new(i))
    }
}

impl From<SkeletonControl> for Motion {
    fn from(c: SkeletonControl) -> Self {
        Motion::Skeleton(Box::new(c))
    }
}

impl Motion {
    /// The mesh at `t`.
    pub fn at_vec(&self, t: f64) -> Vec<Point> {
        match self {
            Motion::Plain(i) => i.at_vec(t),
            Motion::Skeleton(c) => c.at_vec(t),
        }
    }

    /// Meshes at many times, in parallel.
    pub fn frames(&self, ts: &[f64]) -> Vec<Vec<Point>> {
        match self {
            Motion::Plain(i) => i.frames(ts),
            Motion::Skeleton(c) => c.frames(ts),
        }
    }
}

/// The exports of a [`Morph`] that report frames to its [`Morph::on_frame`] hook (see
/// [`Morph::reports`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Export {
    /// [`Morph::gif`]: every frame shown, twice but for the first few (its colours, then its
    /// indices; a yoyo shows most frames twice, so three times).
    Gif,
    /// [`Morph::apng`]: every frame shown (most twice for a yoyo).
    Apng,
    /// [`Morph::svg_frames`] and [`Morph::pixmap_frames`]: every frame once.
    Frames,
    /// [`Morph::animated_svg`] and [`Morph::html`]: every keyframe once.
    AnimatedSvg,
}

/// The compatible meshes, their motion and the bound artwork, with the frame settings.
pub struct Morph {
    meshes: CompatibleMeshes,
    motion: Motion,
    artwork: WholeArtwork,
    frame: FrameOptions,
    /// Artwork that morphs as one shape, and the rest of the artwork bound without it.
    morphing: Option<Morphing>,
    /// Called after each frame of a sequence or animation (see [`Morph::on_frame`]).
    on_frame: Option<Arc<dyn Fn() + Send + Sync>>,
}

/// Both drawings' whole artwork bound to the meshes ([`ArtworkPair`]), bound when the morph is
/// made, or, when some paths morph as one shape, when a frame first needs it. With morphing
/// paths the in-between frames, the animated SVG and the view fit draw the [`Morphing`] stack
/// and the exact input drawings instead, so the whole binding serves only the other exports'
/// end frames and [`Morph::scenes_at`]; on random icon pairs it was 4–26 % of the CLI's
/// instructions for an animated SVG (issue 16).
struct WholeArtwork {
    bound: OnceLock<Result<ArtworkPair>>,
    /// The scenes to bind, while unbound.
    scenes: Option<Box<(Scene, Scene)>>,
    /// The flattening tolerance of the frame options the morph was made with: a later view
    /// fit does not change how the artwork is bound.
    tolerance: f64,
}

impl WholeArtwork {
    /// The artwork bound to `meshes` now.
    fn bind(
        source: &Scene,
        target: &Scene,
        meshes: &CompatibleMeshes,
        tolerance: f64,
    ) -> Result<Self> {
        let pair = ArtworkPair::new(source, target, meshes, tolerance)?;
        Ok(WholeArtwork {
            bound: OnceLock::from(Ok(pair)),
            scenes: None,
            tolerance,
        })
    }

    /// The artwork to bind when it is first asked for.
    fn later(source: &Scene, target: &Scene, tolerance: f64) -> Self {
        WholeArtwork {
            bound: OnceLock::new(),
            scenes: Some(Box::new((source.clone(), target.clone()))),
            tolerance,
        }
    }

    /// The bound artwork, bound now if it was not (once, whichever thread asks first).
    fn get(&self, meshes: &CompatibleMeshes) -> Result<&ArtworkPair> {
        self.bound
            .get_or_init(|| match self.scenes.as_deref() {
                Some((source, target)) => ArtworkPair::new(source, target, meshes, self.tolerance),
                None => Err(crate::Error::internal("the artwork has no scenes to bind")),
            })
            .as_ref()
            .map_err(Clone::clone)
    }
}

/// The in-between frames' split of the artwork when some paths morph as one shape: a stack
/// of parts in the inputs' paint order.
struct Morphing {
    /// The morphing paths, in paint order (the same in both drawings).
    paths: Vec<MorphingPath>,
    /// Bottom first; never two [`Part::Paths`] in a row, no empty [`Part::Rest`].
    stack: Vec<Part>,
    header: Scene,
}

/// One part of the stack of a frame with morphing paths.
enum Part {
    /// The artwork painted between two morphing paths (in the source and in the target),
    /// bound on its own: blended as one layer.
    Rest(Box<ArtworkPair>),
    /// Consecutive morphing paths (indices into [`Morphing::paths`]), drawn unblended.
    Paths(std::ops::Range<usize>),
}

impl Morph {
    /// Binds both scenes to the meshes (flattened for a quarter pixel at `frame`'s size) and
    /// keeps the motion (an [`Interpolator`] or a [`SkeletonControl`]) for every later frame.
    pub fn new(
        meshes: CompatibleMeshes,
        motion: impl Into<Motion>,
        source: &Scene,
        target: &Scene,
        frame: FrameOptions,
    ) -> Result<Self> {
        let artwork = WholeArtwork::bind(source, target, &meshes, frame.flatten_tolerance())?;
        Ok(Morph::with_artwork(meshes, motion.into(), artwork, frame))
    }

    /// The morph of `meshes` moved by `motion` with the whole artwork `artwork`, no morphing
    /// paths and no frame hook: what [`Morph::new`] and [`Morph::with_morphing_paths`] start
    /// from.
    fn with_artwork(
        meshes: CompatibleMeshes,
        motion: Motion,
        artwork: WholeArtwork,
        frame: FrameOptions,
    ) -> Self {
        Morph {
            meshes,
            motion,
            artwork,
            frame,
            morphing: None,
            on_frame: None,
        }
    }

    /// The whole artwork bound to the meshes ([`WholeArtwork`]).
    fn artwork(&self) -> Result<&ArtworkPair> {
        self.artwork.get(&self.meshes)
    }

    /// Calls `hook` once for every frame that [`Morph::svg_frames`], [`Morph::pixmap_frames`],
    /// [`Morph::gif`] and [`Morph::apng`] (and their streaming forms) render and every keyframe
    /// that [`Morph::animated_svg`] (and so [`Morph::html`]) builds, as soon as it is done —
    /// from the worker threads, in no particular order. The streaming encoders render some
    /// frames more than once; [`Morph::reports`] says how many calls an export makes in all.
    /// For progress reports on long exports: a 600-frame GIF at 1024² takes half a minute.
    /// Replaces an earlier hook.
    pub fn on_frame(&mut self, hook: impl Fn() + Send + Sync + 'static) {
        self.on_frame = Some(Arc::new(hook));
    }

    /// How many times `export` of `timeline` calls the [`Morph::on_frame`] hook at these frame
    /// options: the total of a progress bar.
    pub fn reports(&self, export: Export, timeline: &Timeline) -> u64 {
        use crate::export::gif::{gif_renders, playback_schedule, APNG_MIN_DELAY};
        let tl = timeline.sanitized();
        (match export {
            Export::Gif => gif_renders(&tl, self.frame.size),
            Export::Apng => playback_schedule(&tl, APNG_MIN_DELAY).len(),
            Export::Frames => tl.frames,
            Export::AnimatedSvg => tl.keyframes().frames,
        }) as u64
    }

    /// Reports one finished frame to the [`Morph::on_frame`] hook, if any.
    fn frame_done(&self) {
        if let Some(hook) = &self.on_frame {
            hook();
        }
    }

    /// [`Morph::new`] where `paths` (automatic mode's matched artwork,
    /// [`crate::morphing`]) morph as one shape each. In-between frames keep the inputs'
    /// paint order: they are a stack of the rest of the artwork painted below the first
    /// morphing path (blended), that path, the rest painted between it and the next one
    /// (blended), and so on. Paths whose order differs between the drawings are left to the
    /// blend (the largest consistently ordered subset morphs). Frames t = 0 and t = 1 stay
    /// the exact input drawings, and frames near them converge to them.
    pub fn with_morphing_paths(
        meshes: CompatibleMeshes,
        motion: impl Into<Motion>,
        source: &Scene,
        target: &Scene,
        frame: FrameOptions,
        paths: Vec<MorphingPath>,
    ) -> Result<Self> {
        let paths = in_paint_order(paths);
        if paths.is_empty() {
            return Morph::new(meshes, motion, source, target, frame);
        }
        let artwork = WholeArtwork::later(source, target, frame.flatten_tolerance());
        let mut m = Morph::with_artwork(meshes, motion.into(), artwork, frame);
        let mut stack = Vec::new();
        // Items some morphing path draws besides its own (shapes riding in another path).
        let covered_source: Vec<usize> = paths.iter().flat_map(|p| p.covers.0.clone()).collect();
        let covered_target: Vec<usize> = paths.iter().flat_map(|p| p.covers.1.clone()).collect();
        // Each rest item is painted once, right after the last path (in stack order) whose
        // item on its side comes before it; items that morph, or ride in a morphing path, are
        // not rest. With the paths in both drawings' order this is "the items strictly between
        // two consecutive paths".
        let bounds = |k: usize, item: fn(&MorphingPath) -> Option<usize>, covered: &[usize]| {
            let mine: Vec<Option<usize>> = paths.iter().map(item).collect();
            let covered = covered.to_vec();
            move |i: usize| {
                let slot = mine
                    .iter()
                    .rposition(|x| x.is_some_and(|x| x < i))
                    .map_or(0, |p| p + 1);
                slot == k && !mine.contains(&Some(i)) && !covered.contains(&i)
            }
        };
        for k in 0..=paths.len() {
            let s = source.retain_items(bounds(k, |p| p.source_item, &covered_source));
            let g = target.retain_items(bounds(k, |p| p.target_item, &covered_target));
            if !s.root.children.is_empty() || !g.root.children.is_empty() {
                let pair = ArtworkPair::new(&s, &g, &m.meshes, frame.flatten_tolerance())?;
                stack.push(Part::Rest(Box::new(pair)));
            }
            if k < paths.len() {
                match stack.last_mut() {
                    Some(Part::Paths(r)) => r.end = k + 1,
                    _ => stack.push(Part::Paths(k..k + 1)),
                }
            }
        }
        m.morphing = Some(Morphing {
            paths,
            stack,
            header: source.clone(),
        });
        Ok(m)
    }

    /// The frame at `t` whose mesh is `v`: the exact inputs at the ends (`warped` false) and
    /// in between, with morphing paths, the stack of parts. `warped` warps even at the ends,
    /// so that every animation keyframe has the same structure.
    fn frame_of(&self, v: &[Point], t: f64, warped: bool) -> Result<Frame> {
        let t = crate::rigid::clamp_time(t);
        let whole = |pair: &ArtworkPair| -> Result<FrameLayer> {
            let (source, target) = if warped {
                pair.warped_at(v)?
            } else {
                pair.at(v)?
            };
            Ok(FrameLayer::Blend { source, target })
        };
        let layers = match &self.morphing {
            Some(m) if warped || (t > 0.0 && t < 1.0) => m
                .stack
                .iter()
                .map(|part| match part {
                    Part::Rest(pair) => whole(pair),
                    Part::Paths(r) => Ok(FrameLayer::Over(overlay_at(
                        &m.paths[r.clone()],
                        &self.meshes,
                        v,
                        t,
                        &m.header,
                    ))),
                })
                .collect::<Result<_>>()?,
            _ => vec![whole(self.artwork()?)?],
        };
        Ok(Frame { t, layers })
    }

    /// The frame at `t` (the frame model, [`crate::frame`]): what [`Morph::svg_at`] and
    /// [`Morph::pixmap_at`] draw. At t = 0 and t = 1 its scenes are the exact input drawings.
    pub fn frame_at(&self, t: f64) -> Result<Frame> {
        self.frame_of(&self.vertices_at(t), t, false)
    }

    /// The keyframe at `t`: [`Morph::frame_at`] with the artwork warped even at the ends, so
    /// that keyframes at every `t` have the same layers, items and path structure (what an
    /// animation interpolates between: the animated SVG and Lottie).
    pub fn keyframe_at(&self, t: f64) -> Result<Frame> {
        self.frame_of(&self.vertices_at(t), t, true)
    }

    /// The keyframes at `ts` ([`Morph::keyframe_at`]), solved and warped in parallel when
    /// there is enough work (about half a millisecond or more: below that, waking rayon's
    /// threads costs more than it saves), each reported to the [`Morph::on_frame`] hook.
    pub fn keyframes_at(&self, ts: &[f64]) -> Result<Vec<Frame>> {
        let meshes = self.motion.frames(ts);
        let items: Vec<(&Vec<Point>, f64)> = meshes.iter().zip(ts.iter().copied()).collect();
        let work = ts.len().saturating_mul(self.frame_work());
        crate::parallel::map(&items, work, |&(v, t)| {
            let frame = self.frame_of(v, t, true);
            self.frame_done();
            frame
        })
        .into_iter()
        .collect()
    }

    /// The work of one frame in [`crate::parallel`]'s units: the mesh's vertices solved and
    /// both drawings' bound points warped.
    fn frame_work(&self) -> usize {
        let bound = |pair: &ArtworkPair| pair.source.point_count() + pair.target.point_count();
        let drawn = match &self.morphing {
            // The stack: its blended parts' points and the morphing paths' outlines.
            Some(m) => m
                .stack
                .iter()
                .map(|part| match part {
                    Part::Rest(pair) => bound(pair),
                    Part::Paths(r) => m.paths[r.clone()]
                        .iter()
                        .flat_map(|p| &p.curves)
                        .map(|&c| self.meshes.curves.get(c).map_or(0, |c| c.vertices.len()))
                        .sum(),
                })
                .sum(),
            None => self.artwork().map_or(0, bound),
        };
        self.meshes.source.len() + drawn
    }

    /// The box of what the frames at `ts` draw, both drawings' warped artwork where the
    /// dissolve shows it and the morphing paths (the union over the frames): the view a fit
    /// must hold.
    pub fn drawn_bounds(&self, ts: &[f64]) -> Result<crate::artwork::Bounds> {
        use crate::artwork::union_bounds;
        let mut b = None;
        // Solved together (eight to a pass over the factor), with the bits of one
        // `frame_at` each.
        let meshes = self.motion.frames(ts);
        for (vertices, &t) in meshes.iter().zip(ts) {
            if let Some(end) = self.exact_end(vertices, t) {
                b = union_bounds(b, end.bounds());
                continue;
            }
            let frame = self.frame_of(vertices, t, false)?;
            // A side the dissolve leaves out (the source at t = 1, the target at t = 0) draws
            // nothing, however far its warp throws it.
            let (ws, wt) = frame.weights();
            for layer in &frame.layers {
                let seen = |on: bool, s: &Scene| if on { s.bounds() } else { None };
                b = match layer {
                    FrameLayer::Blend { source, target } => union_bounds(
                        b,
                        union_bounds(seen(ws > 0.0, source), seen(wt > 0.0, target)),
                    ),
                    FrameLayer::Over(o) => union_bounds(b, o.bounds()),
                };
            }
        }
        Ok(b)
    }

    /// What the frame at an end draws where the dissolve shows it, for a morph that binds its
    /// whole artwork only when drawn ([`WholeArtwork`]): at t = 0 with `v` the source mesh, the source drawing
    /// as binding keeps it ([`crate::artwork::within_reach`]), which [`Binding::place`] gives
    /// there (the target side has opacity 0); at t = 1 the target's likewise. `None`
    /// otherwise, and the frame itself is made. So a view fit binds nothing it does not draw.
    ///
    /// [`Binding::place`]: crate::artwork::Binding::place
    fn exact_end(&self, v: &[Point], t: f64) -> Option<Scene> {
        let (source, target) = self.artwork.scenes.as_deref()?;
        let t = crate::rigid::clamp_time(t);
        let (scene, rest) = if t == 0.0 {
            (source, &self.meshes.source)
        } else if t == 1.0 {
            (target, &self.meshes.target)
        } else {
            return None;
        };
        crate::artwork::at_rest(v, rest).then(|| crate::artwork::within_reach(scene).0)
    }

    /// Shows every frame with `frame`'s view, size and background instead (the artwork stays
    /// bound as it was: change the view, not the scale, or flattening is coarser or finer
    /// than the quarter pixel it was made for).
    pub fn set_frame_options(&mut self, frame: FrameOptions) {
        self.frame = frame;
    }

    /// The compatible meshes.
    pub fn meshes(&self) -> &CompatibleMeshes {
        &self.meshes
    }

    /// View, size and background of every frame.
    pub fn frame_options(&self) -> &FrameOptions {
        &self.frame
    }

    /// The motion driving the mesh.
    pub fn motion(&self) -> &Motion {
        &self.motion
    }

    /// The mesh at `t` (§4.1).
    pub fn vertices_at(&self, t: f64) -> Vec<Point> {
        self.motion.at_vec(t)
    }

    /// The mesh at every frame of `timeline` (at its eased times), computed in parallel.
    pub fn vertex_frames(&self, timeline: &Timeline) -> Vec<Vec<Point>> {
        self.motion.frames(&timeline.sanitized().morph_times())
    }

    /// Every frame's mesh as the JSON of [`crate::json::frames_json`] (byte for byte), written
    /// to `out` as the meshes are solved, a chunk of frames at a time.
    pub fn write_frames_json(&self, timeline: &Timeline, mut out: impl Write) -> Result<()> {
        let ts = timeline.sanitized().morph_times();
        let io = |e: std::io::Error| crate::Error::internal(format!("writing JSON failed: {e}"));
        out.write_all(b"{\"frames\":[").map_err(io)?;
        for (c, chunk) in ts.chunks(chunk_len(0)).enumerate() {
            let meshes = self.motion.frames(chunk);
            let docs: Vec<String> = meshes
                .par_iter()
                .zip(chunk)
                .map(|(v, &t)| crate::json::frame_json(&self.meshes, t, v))
                .collect();
            for (k, doc) in docs.iter().enumerate() {
                if c > 0 || k > 0 {
                    out.write_all(b",").map_err(io)?;
                }
                out.write_all(doc.as_bytes()).map_err(io)?;
            }
        }
        out.write_all(b"]}").map_err(io)?;
        out.flush().map_err(io)
    }

    /// The source and target artwork placed in the mesh at `t`: the exact input drawings at
    /// t = 0 and t = 1.
    pub fn scenes_at(&self, t: f64) -> Result<(Scene, Scene)> {
        self.artwork()?.at(&self.vertices_at(t))
    }

    /// Frame `t` as a standalone SVG.
    pub fn svg_at(&self, t: f64) -> Result<String> {
        let frame = self.frame_at(t)?;
        frame_svg_layers(&layers_of(&frame), frame.t, &self.frame)
    }

    /// Frame `t` rendered (premultiplied RGBA over the background).
    pub fn pixmap_at(&self, t: f64) -> Result<Pixmap> {
        let frame = self.frame_at(t)?;
        frame_pixmap_layers(&layers_of(&frame), frame.t, &self.frame)
    }

    /// Every frame of `timeline` as a standalone SVG, in frame order.
    pub fn svg_frames(&self, timeline: &Timeline) -> Result<Vec<String>> {
        let mut out = Vec::new();
        self.for_each_svg_frame(timeline, |_, svg| {
            out.push(svg);
            Ok(())
        })?;
        Ok(out)
    }

    /// Every frame of `timeline` rendered, in frame order, in parallel.
    pub fn pixmap_frames(&self, timeline: &Timeline) -> Result<Vec<Pixmap>> {
        let mut out = Vec::new();
        self.for_each_pixmap_frame(timeline, |_, px| {
            out.push(px);
            Ok(())
        })?;
        Ok(out)
    }

    /// Hands frame `i` of `timeline` as a standalone SVG to `sink(i, svg)`, in frame order:
    /// frames are made in parallel a chunk at a time, so memory holds two chunks (the one
    /// being handed on and the next) however long the timeline. Stops at the first error (of a frame or of `sink`).
    pub fn for_each_svg_frame(
        &self,
        timeline: &Timeline,
        sink: impl FnMut(usize, String) -> Result<()>,
    ) -> Result<()> {
        self.each_frame(timeline, 0, |t| self.svg_at(t), sink)
    }

    /// Hands frame `i` of `timeline` rendered to `sink(i, pixmap)`, in frame order, like
    /// [`Morph::for_each_svg_frame`].
    pub fn for_each_pixmap_frame(
        &self,
        timeline: &Timeline,
        sink: impl FnMut(usize, Pixmap) -> Result<()>,
    ) -> Result<()> {
        let bytes = 4 * self.frame.pixels() as usize;
        self.each_frame(timeline, bytes, |t| self.pixmap_at(t), sink)
    }

    /// `f(t)` of every frame of `timeline` to `sink`, in order, in chunks of frames of
    /// `item_bytes` each (see [`chunk_len`]).
    fn each_frame<T: Send>(
        &self,
        timeline: &Timeline,
        item_bytes: usize,
        f: impl Fn(f64) -> Result<T> + Sync + Send,
        mut sink: impl FnMut(usize, T) -> Result<()>,
    ) -> Result<()> {
        let ts = timeline.sanitized().morph_times();
        let frames: Vec<usize> = (0..ts.len()).collect();
        in_order(
            &frames,
            chunk_len(item_bytes),
            |&i| {
                let frame = f(ts[i]);
                self.frame_done();
                Ok((i, frame?))
            },
            |(i, frame)| sink(i, frame),
        )
    }

    /// The frame at `t` rendered, reported to the hook: what the GIF and APNG writers ask for.
    fn render_frame(&self, t: f64) -> Result<Cow<'static, Pixmap>> {
        let frame = self.pixmap_at(t);
        self.frame_done();
        Ok(Cow::Owned(frame?))
    }

    /// The whole morph as one animated SVG (SMIL; see [`crate::render::animated`]).
    pub fn animated_svg(&self, timeline: &Timeline) -> Result<String> {
        let mut out = Vec::new();
        self.write_animated_svg(timeline, &mut out)?;
        String::from_utf8(out).map_err(|_| crate::Error::internal("the SVG is not UTF-8"))
    }

    /// [`Morph::animated_svg`] written to `out` as it is serialized. The timeline's frames are
    /// the keyframes, at most [`Timeline::keyframes`] of them (120 a second: more are never
    /// drawn, the player interpolates between them). Keyframes are made a
    /// chunk at a time; what stays in memory until the end is every keyframe's attribute
    /// values, packed (see [`crate::render::animated`]): about 16 bytes per vertex of the
    /// warped artwork per frame.
    pub fn write_animated_svg(&self, timeline: &Timeline, out: impl Write) -> Result<()> {
        let tl = timeline.keyframes();
        let ts = tl.morph_times();
        let trees = |frames: &[usize]| -> Result<Vec<Node>> {
            let times: Vec<f64> = frames.iter().map(|&i| ts[i]).collect();
            let keyframes = self.keyframes_at(&times)?;
            let work = keyframes.len().saturating_mul(self.frame_work());
            Ok(crate::parallel::map(&keyframes, work, |f| {
                frame_tree(&layers_of(f), f.t, &self.frame, Mode::Keyframe)
            }))
        };
        // The static values (what a viewer without SMIL shows) are the source drawing exactly.
        let first = self.motion.frames(&ts[..1]);
        let base = self.exact_source_frame(&first[0])?;
        let base = frame_tree(&layers_of(&base), 0.0, &self.frame, Mode::Keyframe);
        write_animated_svg(&tl, &self.frame, trees, Some(base), out)
    }

    /// The layers of the first keyframe (`v` the mesh at t = 0) with the source drawing's own
    /// geometry where the keyframe has a warped copy of it: blended parts as their exact
    /// source scenes, and each morphing path that alone draws its source path as that path,
    /// with the source paths of the shapes riding in it.
    fn exact_source_frame(&self, v: &[Point]) -> Result<Frame> {
        let Some(m) = &self.morphing else {
            let (source, target) = self.artwork()?.at(v)?;
            return Ok(Frame {
                t: 0.0,
                layers: vec![FrameLayer::Blend { source, target }],
            });
        };
        let items = m.header.items();
        // The source paths riding in `p`, or `None` when one is not a plain path.
        let riders = |p: &MorphingPath| -> Option<Vec<&crate::artwork::PathItem>> {
            p.covers
                .0
                .iter()
                .map(|&i| match items.get(i) {
                    Some(crate::artwork::Item::Path(q)) => Some(q),
                    _ => None,
                })
                .collect()
        };
        let alone = |p: &MorphingPath| {
            p.source_item.is_some()
                && m.paths
                    .iter()
                    .filter(|q| q.source_item == p.source_item)
                    .count()
                    == 1
        };
        m.stack
            .iter()
            .map(|part| match part {
                Part::Rest(pair) => {
                    let (source, target) = pair.at(v)?;
                    Ok(FrameLayer::Blend { source, target })
                }
                Part::Paths(r) => {
                    let mut scene =
                        overlay_at(&m.paths[r.clone()], &self.meshes, v, 0.0, &m.header);
                    for (item, p) in scene.root.children.iter_mut().zip(&m.paths[r.clone()]) {
                        if let (crate::artwork::Item::Path(item), true) = (item, alone(p)) {
                            if let Some(r) = riders(p) {
                                item.path = p.exact_source_path_with(&r);
                            }
                        }
                    }
                    Ok(FrameLayer::Over(scene))
                }
            })
            .collect::<Result<_>>()
            .map(|layers| Frame { t: 0.0, layers })
    }

    /// The morph as an animated GIF (frames rendered in parallel; composited over the
    /// background, white when there is none, since GIF has no partial transparency).
    pub fn gif(&self, timeline: &Timeline) -> Result<Vec<u8>> {
        let mut out = Vec::new();
        self.write_gif(timeline, &mut out)?;
        Ok(out)
    }

    /// [`Morph::gif`] written to `out` as frames are encoded ([`crate::export::gif::write_gif`]:
    /// a chunk of frames in memory at a time, each frame rendered twice).
    pub fn write_gif(&self, timeline: &Timeline, out: impl Write) -> Result<()> {
        let tl = timeline.sanitized();
        let ts = tl.morph_times();
        let render = |i: usize| self.render_frame(ts[i]);
        write_gif(self.frame.size, render, &tl, self.frame.background, out)
    }

    /// The morph as an animated PNG (APNG, full alpha; frames rendered in parallel).
    pub fn apng(&self, timeline: &Timeline) -> Result<Vec<u8>> {
        let mut out = Cursor::new(Vec::new());
        self.write_apng(timeline, &mut out)?;
        Ok(out.into_inner())
    }

    /// [`Morph::apng`] written to `out` as frames are compressed
    /// ([`crate::export::apng::write_apng`]: a chunk of frames in memory at a time).
    pub fn write_apng(&self, timeline: &Timeline, out: impl Write + Seek) -> Result<()> {
        let tl = timeline.sanitized();
        let ts = tl.morph_times();
        let render = |i: usize| self.render_frame(ts[i]);
        write_apng(self.frame.size, render, &tl, out)
    }

    /// A standalone HTML page playing the animated SVG, with play/pause, a time slider and a
    /// toggle that overlays the triangulation.
    pub fn html(&self, timeline: &Timeline, title: &str) -> Result<String> {
        let tl = timeline.sanitized();
        let svg = self.animated_svg(&tl)?;
        let mut frames = self.vertex_frames(&tl);
        // With skeleton control the overlay shows the skeleton each frame carries too: its
        // joints appended after the mesh vertices, its bones as extra segments.
        let mut bones = Vec::new();
        if let Motion::Skeleton(c) = &self.motion {
            let n = self.meshes.source.len() as u32;
            bones = c
                .skeleton()
                .bones
                .iter()
                .map(|&[a, b]| [a + n, b + n])
                .collect();
            for f in &mut frames {
                let joints = c.derived(f);
                f.extend(joints);
            }
        }
        // Overlay coordinates to a tenth of an output pixel.
        let precision = 0.1 / self.frame.scale();
        let mesh = PreviewMesh {
            triangles: &self.meshes.triangles,
            frames: &frames,
            precision: if precision.is_finite() && precision > 0.0 {
                precision
            } else {
                0.01
            },
            extra_edges: &bones,
        };
        Ok(preview_html(title, &svg, &tl, &mesh))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rigid::Method;

    fn gourd() -> Morph {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/gourd/");
        let opts = crate::drawing::ReadOptions::default();
        let read = |f: &str| {
            let path = format!("{dir}{f}");
            let text = std::fs::read_to_string(&path).unwrap();
            (
                crate::drawing::Drawing::from_str(&path, &text, &opts).unwrap(),
                Scene::from_svg(&path, &text, "controls").unwrap(),
            )
        };
        let (s, ss) = read("source.svg");
        let (t, ts) = read("target.svg");
        let c = crate::compatible::build(&s, &t, &Default::default()).unwrap();
        let m = &c.meshes;
        let interp = Interpolator::new(Method::Disc, &m.source, &m.target, &m.triangles).unwrap();
        Morph::new(c.meshes, interp, &ss, &ts, FrameOptions::for_scene(&ss)).unwrap()
    }

    #[test]
    fn frames_follow_the_timeline_and_sequences_match_single_frames() {
        let m = gourd();
        let tl = Timeline {
            frames: 3,
            easing: crate::export::Easing::EaseInOut,
            ..Timeline::default()
        };
        let v = m.vertex_frames(&tl);
        assert_eq!(v.len(), 3);
        let worst = v[0]
            .iter()
            .zip(&m.meshes().source)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(worst < 1e-9 * 400.0, "frame 0 is the source mesh: {worst}");
        let svgs = m.svg_frames(&tl).unwrap();
        assert_eq!(svgs[1], m.svg_at(0.5).unwrap());
        let px = m.pixmap_frames(&tl).unwrap();
        assert_eq!(px[2].data(), m.pixmap_at(1.0).unwrap().data());
        let anim = m.animated_svg(&tl).unwrap();
        assert!(anim.contains("<animate attributeName=\"d\""));
        // The hook counts every frame of a sequence and every keyframe of an animation.
        let mut m = m;
        let done = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let counter = done.clone();
        m.on_frame(move || {
            counter.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        });
        m.gif(&tl).unwrap();
        m.svg_frames(&tl).unwrap();
        m.animated_svg(&tl).unwrap();
        let reports = [Export::Gif, Export::Frames, Export::AnimatedSvg].map(|e| m.reports(e, &tl));
        assert_eq!(
            reports,
            [3, 3, 3],
            "a short GIF keeps its frames between its passes"
        );
        let n = done.load(std::sync::atomic::Ordering::Relaxed) as u64;
        assert_eq!(n, reports.iter().sum::<u64>());
        assert_eq!(anim, m.animated_svg(&tl).unwrap(), "deterministic");
    }

    /// With morphing paths, the view fit and the animated SVG draw no frame of the whole
    /// artwork, so it is not bound; the fit's ends measure the drawings the whole artwork
    /// would place there, and binding it later gives the same exports.
    #[test]
    fn morphing_paths_leave_the_whole_artwork_unbound_until_it_is_drawn() {
        let square = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><rect x="20" y="20" width="60" height="60" fill="#c33"/><path d="M5 5h10v10h-10z" stroke="#000" fill="none"/></svg>"##;
        let circle = r##"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><circle cx="50" cy="50" r="32" fill="#36c"/><path d="M85 85h10v10h-10z" stroke="#000" fill="none"/></svg>"##;
        let m = crate::Morpher::from_svg(("a.svg", square), ("b.svg", circle))
            .unwrap()
            .build()
            .unwrap();
        assert!(m.morphing.is_some(), "the shapes morph as paths");
        let tl = Timeline {
            frames: 5,
            ..Timeline::default()
        };
        let anim = m.animated_svg(&tl).unwrap();
        assert!(
            m.artwork.bound.get().is_none(),
            "the fit and the animated SVG bound the whole artwork"
        );
        // The ends as the fit measures them, against the frames of the bound artwork.
        let ends = m.motion.frames(&[0.0, 1.0]);
        for (v, t) in ends.iter().zip([0.0, 1.0]) {
            let exact = m
                .exact_end(v, t)
                .expect("the ends are the drawings' own meshes");
            let frame = m.frame_of(v, t, false).unwrap();
            let (ws, wt) = frame.weights();
            let [FrameLayer::Blend { source, target }] = &frame.layers[..] else {
                panic!("an end frame is one blended layer");
            };
            let seen = if t == 0.0 { (ws, source) } else { (wt, target) };
            assert_eq!(seen.0, 1.0);
            assert_eq!(exact.bounds(), seen.1.bounds(), "t = {t}");
            assert!(exact.bounds().is_some());
        }
        assert!(m.artwork.bound.get().is_some(), "an end frame binds it");
        assert_eq!(anim, m.animated_svg(&tl).unwrap(), "same bytes once bound");
    }
}
