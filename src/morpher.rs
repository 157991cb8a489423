//! The front door: two drawings and every choice about their morph, in one builder that makes
//! the [`Morph`] every output is written from.
//!
//! The choices it owns are the ones a morph of two drawings needs and that every caller (the
//! CLI, the demo, the benches, the tests, a library user) would otherwise make by hand:
//!
//! - **automatic or marked-up**: two drawings with neither a boundary nor a feature curve get
//!   control geometry from their artwork ([`crate::auto`]); otherwise their own (§3);
//! - **which drawing is triangulated** ([`Side`], Fig. 12) and the vertex density;
//! - **the motion**: the interpolation of a [`Method`] (the disc method keeping the area of
//!   [`Compatible::area_region`], §4.1), or skeleton control steered by poses (§4.2);
//! - **which artwork paths morph as one shape** (automatic mode's pairs, or in marked-up
//!   drawings the paths that are their own boundary or feature curve);
//! - **the view** every frame shows ([`View`]), its padding, size and background, checked
//!   against the drawings' pixel limit before any work at that size.
//!
//! ```
//! use crmorph::export::Timeline;
//! use crmorph::Morpher;
//!
//! let square = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
//!   <rect x="20" y="20" width="60" height="60" fill="teal"/></svg>"#;
//! let circle = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">
//!   <circle cx="50" cy="50" r="32" fill="orange"/></svg>"#;
//! let morph = Morpher::from_svg(("square.svg", square), ("circle.svg", circle))?.build()?;
//! let svg = morph.animated_svg(&Timeline::default())?;
//! assert!(svg.contains("<animate"));
//! // The same morph for Lottie players (JSON; `.dotlottie(name)` zips it).
//! let lottie = morph.lottie(&Timeline::default(), "square to circle")?;
//! assert!(lottie.json.starts_with('{'));
//! # Ok::<(), crmorph::Error>(())
//! ```

use crate::artwork::{Rgba, Scene};
use crate::compatible::{build, Compatible, MorphOptions};
use crate::drawing::{Drawing, ReadOptions};
use crate::error::{Error, Result};
use crate::export::{Morph, Motion};
use crate::morphing::MorphingPath;
use crate::render::{FrameOptions, Padding};
use crate::rigid::{Interpolator, Method};
use crate::skeleton::{Pose, Skeleton, SkeletonControl};

pub use crate::mesh::Side;

/// What every frame shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    /// The source's view grown to hold the whole morph, so nothing is cut off (a morph that
    /// stays inside keeps the view exactly; [`FrameOptions::fitted`]). Default.
    #[default]
    Fit,
    /// Exactly the source's viewBox, cutting what leaves it.
    Source,
}

/// What the builder is doing, for a progress display: a stage begins, or a note about the
/// input (ids that almost follow a convention, automatic mode's pairing).
#[derive(Debug, Clone, Copy)]
pub enum Progress<'a> {
    /// A stage begins, e.g. `"compatible triangulation"`.
    Stage(&'a str),
    /// A note for the user, already naming its file.
    Note(&'a str),
}

/// What automatic mode paired, in counts (from [`crate::auto::AutoReport`]): whether a morph is
/// crisp (shapes move) or cross-fades.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AutoCounts {
    /// Pairs of shapes that morph into each other.
    pub shapes: usize,
    /// Shapes without a partner (they grow or shrink, they do not cross-fade).
    pub lone: usize,
    /// Paths with a paired shape that still cross-fade.
    pub blended: usize,
}

/// How the artwork of a morph moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shapes {
    /// Automatic mode's counts; `None` for marked-up drawings (a boundary or feature curves).
    pub auto: Option<AutoCounts>,
    /// Artwork paths that morph as one path (unblended) in the frames.
    pub morphing: usize,
}

/// The first half of a morph ([`Morpher::prepare`]): the two drawings (with automatic control
/// geometry when they had none), their compatible triangulation, and in automatic mode the
/// artwork paths that morph as one shape and the counts of its pairing.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The source drawing, as triangulated.
    pub source: Drawing,
    /// The target drawing, as triangulated.
    pub target: Drawing,
    /// Their compatible triangulation (§3, §5).
    pub compatible: Compatible,
    /// Automatic mode's artwork paths that morph as one shape (empty when marked up).
    pub morphing: Vec<MorphingPath>,
    /// Automatic mode's counts; `None` for marked-up drawings.
    pub auto: Option<AutoCounts>,
}

/// Two drawings and every choice about their morph; [`Morpher::build`] makes the [`Morph`].
///
/// Build once, then write as many outputs as needed from the morph (its frames are evaluated
/// on demand: one solve each, §4.1).
#[derive(Debug, Clone)]
pub struct Morpher {
    source: Drawing,
    target: Drawing,
    triangulated: Side,
    density: f64,
    method: Method,
    poses: Vec<(f64, Drawing)>,
    always_skeleton: bool,
    skeleton_id: String,
    size: Option<(u32, u32)>,
    background: Option<Rgba>,
    view: View,
    padding: Padding,
    raster: bool,
}

/// Times at which [`View::Fit`] measures what the morph draws.
const FIT_SAMPLES: usize = 32;

impl Morpher {
    /// A morph of `source` into `target` with the defaults: the source triangulated at the
    /// density the source drawing was read with ([`crate::drawing::ReadOptions::density`],
    /// so one setting serves both), the disc method, no poses, the view fitted to the morph,
    /// the drawing's own size, no background.
    pub fn new(source: Drawing, target: Drawing) -> Morpher {
        Morpher {
            density: source.tolerances.density,
            source,
            target,
            triangulated: Side::Source,
            method: Method::Disc,
            poses: Vec::new(),
            always_skeleton: false,
            skeleton_id: ReadOptions::default().ids.skeleton,
            size: None,
            background: None,
            view: View::Fit,
            padding: Padding::default(),
            raster: false,
        }
    }

    /// [`Morpher::new`] of two SVG texts, each `(file name, text)`, read with the default
    /// [`ReadOptions`] (the file names are what errors name).
    pub fn from_svg(source: (&str, &str), target: (&str, &str)) -> Result<Morpher> {
        Morpher::read_svg(source, target, &ReadOptions::default())
    }

    /// [`Morpher::from_svg`] with `opts`: control ids, density, input policy. The density
    /// is the triangulation's too, unless [`Morpher::density`] sets another.
    pub fn read_svg(
        source: (&str, &str),
        target: (&str, &str),
        opts: &ReadOptions,
    ) -> Result<Morpher> {
        let s = Drawing::from_str(source.0, source.1, opts)?;
        let t = Drawing::from_str(target.0, target.1, opts)?;
        Ok(Morpher::new(s, t).skeleton_id(&opts.ids.skeleton))
    }

    /// Which drawing is triangulated and mapped onto the other.
    pub fn triangulate(mut self, side: Side) -> Morpher {
        self.triangulated = side;
        self
    }

    /// Vertex density multiplier of the correspondence and refinement (2: twice as many
    /// vertices per unit length). Default: the density the source was read with.
    pub fn density(mut self, density: f64) -> Morpher {
        self.density = density;
        self
    }

    /// The interpolation method (default: the disc method, §4.1; the others are baselines).
    pub fn method(mut self, method: Method) -> Morpher {
        self.method = method;
        self
    }

    /// A control pose for the frame at `t` (§4.2): a drawing whose skeleton polylines move the
    /// source's joints. Poses need the disc method and a skeleton on the source.
    pub fn pose(mut self, t: f64, pose: Drawing) -> Morpher {
        self.poses.push((t, pose));
        self
    }

    /// Skeleton control even without poses (its motion is then the plain disc
    /// interpolation), so that the derived skeleton can be read at any frame.
    pub fn always_skeleton(mut self, on: bool) -> Morpher {
        self.always_skeleton = on;
        self
    }

    /// The id (and prefix) of the skeleton polylines the drawings were read with, for the
    /// message when the source has none. Default: `skeleton`.
    pub fn skeleton_id(mut self, id: &str) -> Morpher {
        self.skeleton_id = id.to_string();
        self
    }

    /// Output size in pixels (default: the drawing's own size).
    pub fn size(mut self, size: Option<(u32, u32)>) -> Morpher {
        self.size = size;
        self
    }

    /// Background colour under every frame (default: none, transparent).
    pub fn background(mut self, background: Option<Rgba>) -> Morpher {
        self.background = background;
        self
    }

    /// What the frames show (default: [`View::Fit`]).
    pub fn view(mut self, view: View) -> Morpher {
        self.view = view;
        self
    }

    /// Room around the view on every side (default: none).
    pub fn padding(mut self, padding: Padding) -> Morpher {
        self.padding = padding;
        self
    }

    /// Whether the output is pixels: the frame size is then checked against the drawings'
    /// pixel limit before any work at that size (again after the view is fitted).
    pub fn raster(mut self, raster: bool) -> Morpher {
        self.raster = raster;
        self
    }

    /// The compatible triangulation of the two drawings, automatic when neither is marked up.
    pub fn prepare(&self, progress: &mut dyn FnMut(Progress)) -> Result<Prepared> {
        let (s, t) = (&self.source, &self.target);
        // Ids that almost follow a convention are plain artwork; say so before anything they
        // cause.
        for d in [s, t] {
            for n in &d.controls.near_misses {
                progress(Progress::Note(&format!("{}: {}", d.file, n.note())));
            }
            for n in &d.notes {
                progress(Progress::Note(n));
            }
        }
        let opts = MorphOptions {
            triangulated: self.triangulated,
            density: self.density,
            ..MorphOptions::default()
        };
        progress(Progress::Stage("compatible triangulation"));
        if crate::auto::is_unmarked(s) && crate::auto::is_unmarked(t) {
            // Plain SVGs: control geometry from the artwork (automatic mode).
            let (ss, ts) = (Scene::from_drawing(s)?, Scene::from_drawing(t)?);
            let (c, report, s, t) = crate::auto::build_auto(s, t, &ss, &ts, &opts)?;
            progress(Progress::Note(&format!("{}: {report}", s.file)));
            let auto = AutoCounts {
                shapes: report.shapes.len(),
                lone: report.lone.len(),
                blended: report.blended,
            };
            return Ok(Prepared {
                source: s,
                target: t,
                compatible: c,
                morphing: report.morphing,
                auto: Some(auto),
            });
        }
        let c = build(s, t, &opts)?;
        Ok(Prepared {
            source: s.clone(),
            target: t.clone(),
            compatible: c,
            morphing: Vec::new(),
            auto: None,
        })
    }

    /// The interpolator of the method for `prepared`'s meshes, its errors naming both files.
    pub fn interpolator(&self, prepared: &Prepared) -> Result<Interpolator> {
        prepared
            .compatible
            .interpolator(self.method)
            .map_err(|e| e.in_file(format!("{} → {}", self.source.file, self.target.file)))
    }

    /// The motion of `prepared`'s mesh: the interpolation of the method, or skeleton control
    /// (§4.2) when there are poses or [`Morpher::always_skeleton`] is set.
    pub fn motion(&self, prepared: &Prepared) -> Result<Motion> {
        if self.poses.is_empty() && !self.always_skeleton {
            return Ok(self.interpolator(prepared)?.into());
        }
        let file = &self.source.file;
        if self.method != Method::Disc {
            return Err(Error::input(file, "poses steer the disc method only"));
        }
        let source = &prepared.source;
        if source.controls.skeleton.is_empty() {
            let id = &self.skeleton_id;
            return Err(Error::input(
                file,
                format!(
                    "has no skeleton (polylines with id '{id}' or '{id}-NAME'); skeleton \
                     control needs one on the source drawing"
                ),
            ));
        }
        let c = &prepared.compatible;
        let skeleton =
            Skeleton::from_chains(&source.file, &source.controls.skeleton, c.tolerances.snap)?;
        let mut poses: Vec<Pose> = Vec::with_capacity(self.poses.len());
        for (t, pose) in &self.poses {
            let joints = skeleton.pose_from_chains(&pose.file, &pose.controls.skeleton)?;
            if poses.iter().any(|p| (p.t - t).abs() < 1e-9) {
                return Err(Error::input(&pose.file, format!("two poses at t = {t}")));
            }
            poses.push(Pose { t: *t, joints });
        }
        Ok(SkeletonControl::new(&c.meshes, skeleton, &poses)
            .map_err(|e| e.in_file(file.clone()))?
            .into())
    }

    /// The morph, with how its artwork moves ([`Morpher::build`] reporting its progress).
    pub fn build_with(&self, progress: &mut dyn FnMut(Progress)) -> Result<(Morph, Shapes)> {
        let prepared = self.prepare(progress)?;
        self.finish(prepared, progress)
    }

    /// The second half of [`Morpher::build_with`], from the compatible triangulation that
    /// [`Morpher::prepare`] made (for callers that also show or measure it): the motion, the
    /// artwork bound to the meshes, the view.
    pub fn finish(
        &self,
        prepared: Prepared,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<(Morph, Shapes)> {
        progress(Progress::Stage("interpolation"));
        let motion = self.motion(&prepared)?;
        progress(Progress::Stage("binding the artwork"));
        let Prepared {
            source,
            target,
            compatible: c,
            morphing,
            auto,
        } = prepared;
        let (ss, ts) = (Scene::from_drawing(&source)?, Scene::from_drawing(&target)?);
        let mut opts = FrameOptions::for_scene(&ss);
        if let Some(size) = self.size {
            opts.size = size;
        }
        opts.background = self.background;
        opts.max_pixels = source.policy.limits.pixels;
        let file = &self.source.file;
        if self.raster {
            opts.check_pixels(file)?;
        }
        // Paths morphing as one shape follow the plain interpolation's mesh; with the disc
        // method only (the baselines are for comparing the mesh motion). In marked-up
        // drawings they are the artwork paths that are their own boundary or feature curve.
        let paths = if self.method != Method::Disc {
            Vec::new()
        } else if morphing.is_empty() {
            crate::morphing::named_morphing_paths(&ss, &ts, &c)
        } else {
            morphing
        };
        let shapes = Shapes {
            auto,
            morphing: paths.len(),
        };
        let mut morph = Morph::with_morphing_paths(c.meshes, motion, &ss, &ts, opts, paths)?;
        let drawn = match self.view {
            View::Fit => {
                let ts: Vec<f64> = (0..=FIT_SAMPLES)
                    .map(|k| k as f64 / FIT_SAMPLES as f64)
                    .collect();
                morph.drawn_bounds(&ts)?
            }
            View::Source => None,
        };
        let fitted = morph.frame_options().fitted(drawn, self.padding, self.size);
        if self.raster {
            fitted.check_pixels(file)?;
        }
        morph.set_frame_options(fitted);
        Ok((morph, shapes))
    }

    /// The morph: compatible triangulation, motion, the artwork bound to the meshes, the
    /// view. Every output (animated SVG, frames, GIF, APNG, HTML, JSON) is written from it.
    pub fn build(&self) -> Result<Morph> {
        self.build_with(&mut |_| {}).map(|(m, _)| m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><rect x="20" y="20" width="60" height="60"/></svg>"#;
    const CIRCLE: &str = r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><circle cx="50" cy="50" r="32"/></svg>"#;

    fn vertices(m: &Morpher) -> usize {
        m.prepare(&mut |_| {})
            .unwrap()
            .compatible
            .meshes
            .source
            .len()
    }

    #[test]
    fn one_density_reads_and_triangulates() {
        // Drawings read at density 2 are triangulated at 2 unless told otherwise: the reading's
        // density is the front door's default, not a second setting left at 1.
        let opts = ReadOptions {
            density: 2.0,
            ..ReadOptions::default()
        };
        let read = Morpher::read_svg(("a.svg", SQUARE), ("b.svg", CIRCLE), &opts).unwrap();
        let s = Drawing::from_str("a.svg", SQUARE, &opts).unwrap();
        let t = Drawing::from_str("b.svg", CIRCLE, &opts).unwrap();
        let by_hand = Morpher::new(s, t);
        let (at_two, at_one) = (
            vertices(&by_hand.clone().density(2.0)),
            vertices(&by_hand.clone().density(1.0)),
        );
        assert!(at_two > at_one, "{at_two} vs {at_one}");
        assert_eq!(vertices(&by_hand), at_two);
        assert_eq!(vertices(&read), at_two);
    }
}
