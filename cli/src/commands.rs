//! Typed commands between clap and the library: each command is a plain struct, validated by
//! clap, run here.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use clap::{Args, ValueEnum};
use crmorph::artwork::Rgba;
use crmorph::drawing::{ControlIds, Drawing, ReadOptions};
use crmorph::export::{Easing, Export, Morph, Motion, Playback, Timeline};
use crmorph::morpher::{Morpher, Prepared, Side, View};
use crmorph::render::{encode_png, Padding};
use crmorph::rigid::Method;
use crmorph::skeleton::{pose_svg, Skeleton, SkeletonControl};

pub(crate) use crmorph::morpher::Shapes;

use crate::output::{refuse_overwriting_inputs, write_atomic, write_streamed, Format, FramesDir};
use crate::progress::Progress;

/// Which drawing is triangulated and mapped onto the other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub(crate) enum From {
    /// Triangulate the source, map it onto the target (default).
    #[default]
    Source,
    /// Triangulate the target, map it onto the source (paper Fig.12).
    Target,
}

/// Interpolation method (`--method`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub(crate) enum MethodArg {
    /// Disc-based rigidity-preserving interpolation with consistent rotations (§4.1; default).
    #[default]
    Disc,
    /// Triangle-based as-rigid-as-possible interpolation (Alexa et al. 2000), for comparison.
    Triangle,
    /// Linear vertex interpolation, for comparison.
    Linear,
}

impl MethodArg {
    fn method(self) -> Method {
        match self {
            MethodArg::Disc => Method::Disc,
            MethodArg::Triangle => Method::Triangle,
            MethodArg::Linear => Method::Linear,
        }
    }
}

/// Inputs and control conventions shared by every command.
#[derive(Debug, Clone, Args)]
pub(crate) struct Inputs {
    /// The source drawing: SVG (.svgz too) or an image (PNG, JPEG, GIF, WebP).
    pub(crate) source: PathBuf,
    /// The target drawing: SVG (.svgz too) or an image (PNG, JPEG, GIF, WebP).
    pub(crate) target: PathBuf,
    /// Output file; its extension picks the format.
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    /// Control geometry for two image inputs (PNG, JPEG, GIF, WebP): SVGs drawn in each
    /// image's pixel coordinates, whose feature curves, anchors, skeleton and optional boundary
    /// (replacing the traced one) steer the morph.
    #[arg(long, num_args = 2, value_names = ["SRC.svg", "TGT.svg"])]
    pub(crate) controls: Option<Vec<PathBuf>>,
    #[command(flatten)]
    pub(crate) reading: Reading,
}

/// How both drawings are read and triangulated: the control conventions, the vertex density,
/// which side is triangulated, and the input policy. Apart from [`Inputs`] so that `crmorph
/// batch`, which has no SRC, TGT and `-o` of its own, takes the same options for every pair.
#[derive(Debug, Clone, Args)]
pub(crate) struct Reading {
    /// Id of the boundary element.
    #[arg(long, default_value = "boundary")]
    pub(crate) boundary_id: String,
    /// Id prefix of feature curves.
    #[arg(long, default_value = "feature-")]
    pub(crate) feature_prefix: String,
    /// Id (and prefix) of skeleton polylines.
    #[arg(long, default_value = "skeleton")]
    pub(crate) skeleton_id: String,
    /// Vertex density multiplier: 2 gives twice as many vertices per unit length.
    #[arg(long, default_value_t = 1.0, value_parser = positive_f64, allow_hyphen_values = true)]
    pub(crate) density: f64,
    /// Which drawing to triangulate and map onto the other.
    #[arg(long, value_enum, default_value_t = From::Source)]
    pub(crate) from: From,
    #[command(flatten)]
    pub(crate) safety: crate::policy::Safety,
}

fn positive_f64(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
    if v.is_finite() && v > 0.0 && v <= 100.0 {
        Ok(v)
    } else {
        Err(format!("'{s}' must be a number in (0, 100]"))
    }
}

fn unit_f64(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("'{s}' is not a number"))?;
    if (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("'{s}' must be in [0, 1]"))
    }
}

/// `crmorph inspect`: the compatible triangulations.
#[derive(Debug, Clone, Args)]
pub(crate) struct InspectArgs {
    #[command(flatten)]
    pub(crate) inputs: Inputs,
    /// Width of a .png picture in pixels (default: the picture's own width).
    #[arg(
        long,
        value_parser = clap::value_parser!(u32).range(16..=16384),
        allow_hyphen_values = true
    )]
    pub(crate) width: Option<u32>,
}

/// `crmorph frame`: one frame of the morph.
#[derive(Debug, Clone, Args)]
pub(crate) struct FrameArgs {
    #[command(flatten)]
    pub(crate) inputs: Inputs,
    /// Time of the frame, from 0 (source) to 1 (target).
    #[arg(long, value_parser = unit_f64, allow_hyphen_values = true)]
    pub(crate) at: f64,
    /// Interpolation method.
    #[arg(long, value_enum, default_value_t = MethodArg::Disc)]
    pub(crate) method: MethodArg,
    #[command(flatten)]
    pub(crate) look: Look,
    #[command(flatten)]
    pub(crate) steering: Steering,
}

/// `crmorph skeleton`: the derived skeleton at T drawn over that frame, to edit into a pose.
#[derive(Debug, Clone, Args)]
pub(crate) struct SkeletonArgs {
    #[command(flatten)]
    pub(crate) inputs: Inputs,
    /// Time of the frame, strictly between 0 (source) and 1 (target).
    #[arg(long, value_parser = unit_f64, allow_hyphen_values = true)]
    pub(crate) at: f64,
    #[command(flatten)]
    pub(crate) look: Look,
    /// Poses already made: the frame and skeleton then show their effect.
    #[command(flatten)]
    pub(crate) steering: Steering,
}

/// Skeleton control (§4.2).
#[derive(Debug, Clone, Args, Default)]
pub(crate) struct Steering {
    /// A control pose: T=POSE.svg, a pose file (from `crmorph skeleton`, edited) for the frame at
    /// time T. Repeatable. Needs a skeleton in the source drawing and the disc method.
    #[arg(long = "pose", value_name = "T=POSE.svg", value_parser = parse_pose)]
    pub(crate) poses: Vec<(f64, PathBuf)>,
}

fn parse_pose(s: &str) -> std::result::Result<(f64, PathBuf), String> {
    let (t, file) = s
        .split_once('=')
        .ok_or_else(|| format!("'{s}' is not T=POSE.svg, e.g. 0.5=pose.svg"))?;
    let t: f64 = t
        .trim()
        .parse()
        .map_err(|_| format!("'{t}' in '{s}' is not a time"))?;
    if !(t > 0.0 && t < 1.0) {
        return Err(format!(
            "'{s}': a pose's time must be strictly between 0 (the source) and 1 (the target)"
        ));
    }
    if file.is_empty() {
        return Err(format!("'{s}' names no pose file"));
    }
    Ok((t, PathBuf::from(file)))
}

/// How rendered output looks: size and background.
#[derive(Debug, Clone, Args)]
pub(crate) struct Look {
    /// Output size in pixels, e.g. 512x512 (default: the drawing's own size). SVG output keeps
    /// the drawing's coordinates and gets this width and height.
    #[arg(long, value_parser = parse_size)]
    pub(crate) size: Option<(u32, u32)>,
    /// Background colour under the artwork, any SVG colour (default: transparent; white for
    /// GIF, which has no partial transparency).
    #[arg(long, value_parser = parse_colour)]
    pub(crate) background: Option<Rgba>,
    /// What frames show: `fit` grows the source drawing's view to hold every frame of the
    /// morph, so nothing is cut off (a morph that stays inside keeps the view exactly);
    /// `source` keeps the source's viewBox, cutting what leaves it.
    #[arg(long, value_enum, default_value_t = ViewArg::Fit)]
    pub(crate) view: ViewArg,
    /// Room around the view on every side: user units (`10`) or a percentage of its larger
    /// side (`5%`).
    #[arg(long, default_value = "0", value_parser = parse_padding, allow_hyphen_values = true)]
    pub(crate) padding: Padding,
}

/// `--view`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ViewArg {
    /// The source's view grown to hold the whole morph.
    Fit,
    /// Exactly the source's viewBox.
    Source,
}

fn parse_padding(s: &str) -> std::result::Result<Padding, String> {
    let (num, percent) = match s.strip_suffix('%') {
        Some(n) => (n, true),
        None => (s, false),
    };
    let v: f64 = num
        .trim()
        .parse()
        .map_err(|_| "must be a number of user units or a percentage, e.g. 10 or 5%".to_string())?;
    if !(v.is_finite() && v >= 0.0) || (percent && v > 1000.0) {
        return Err("must be at least 0 (and at most 1000%)".into());
    }
    Ok(if percent {
        Padding::Percent(v)
    } else {
        Padding::Units(v)
    })
}

/// Timing of an animation.
#[derive(Debug, Clone, Args)]
pub(crate) struct Timing {
    /// Number of frames, the first at t = 0 and the last at t = 1.
    #[arg(
        long,
        default_value_t = 60,
        value_parser = clap::value_parser!(u32).range(2..=10000),
        allow_hyphen_values = true
    )]
    pub(crate) frames: u32,
    /// Seconds from the source to the target.
    #[arg(long, default_value_t = 2.0, value_parser = duration, allow_hyphen_values = true)]
    pub(crate) duration: f64,
    /// How the morph's progress follows time.
    #[arg(long, value_enum, default_value_t = EasingArg::Linear)]
    pub(crate) easing: EasingArg,
    /// Play forever, restarting from the source.
    #[arg(long = "loop", conflicts_with = "yoyo")]
    pub(crate) repeat: bool,
    /// Play forever, back and forth.
    #[arg(long)]
    pub(crate) yoyo: bool,
}

impl Timing {
    pub(crate) fn timeline(&self) -> Timeline {
        Timeline {
            frames: self.frames as usize,
            duration: self.duration,
            easing: match self.easing {
                EasingArg::Linear => Easing::Linear,
                EasingArg::EaseInOut => Easing::EaseInOut,
            },
            playback: if self.yoyo {
                Playback::Yoyo
            } else if self.repeat {
                Playback::Loop
            } else {
                Playback::Once
            },
        }
    }
}

/// `--easing`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum EasingArg {
    /// Constant speed.
    Linear,
    /// Slow at both ends.
    EaseInOut,
}

/// `--frame-format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub(crate) enum FrameFormat {
    /// Standalone SVG files.
    #[default]
    Svg,
    /// PNG images rendered at `--size`.
    Png,
}

fn duration(s: &str) -> std::result::Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("'{s}' is not a number of seconds"))?;
    if (0.01..=3600.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("'{s}' must be between 0.01 and 3600 seconds"))
    }
}

fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT, e.g. 512x512"))?;
    let px = |v: &str| match v.trim().parse::<u32>() {
        Ok(n) if (1..=16384).contains(&n) => Ok(n),
        _ => Err(format!(
            "'{s}': each side must be a whole number of pixels from 1 to 16384"
        )),
    };
    Ok((px(w)?, px(h)?))
}

fn parse_colour(s: &str) -> std::result::Result<Rgba, String> {
    let c: svgtypes::Color = s
        .parse()
        .map_err(|_| format!("'{s}' is not a colour (try #ffffff, white or rgb(255,255,255))"))?;
    Ok(Rgba {
        r: c.red,
        g: c.green,
        b: c.blue,
        a: c.alpha,
    })
}

/// `crmorph morph`: the whole morph.
#[derive(Debug, Clone, Args)]
pub(crate) struct MorphArgs {
    #[command(flatten)]
    pub(crate) inputs: Inputs,
    /// Interpolation method.
    #[arg(long, value_enum, default_value_t = MethodArg::Disc)]
    pub(crate) method: MethodArg,
    #[command(flatten)]
    pub(crate) timing: Timing,
    #[command(flatten)]
    pub(crate) look: Look,
    #[command(flatten)]
    pub(crate) steering: Steering,
    /// Also write every frame into this folder (created if missing) as `frame_000.svg`, … .
    #[arg(long)]
    pub(crate) frames_dir: Option<PathBuf>,
    /// Format of the files in --frames-dir.
    #[arg(long, value_enum, default_value_t = FrameFormat::Svg, requires = "frames_dir")]
    pub(crate) frame_format: FrameFormat,
}

/// A usage problem found after parsing (exit status 2).
#[derive(Debug)]
pub(crate) struct Usage(pub String);

impl std::fmt::Display for Usage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for Usage {}

fn output_format(out: &Path, allowed: &[Format], command: &str) -> Result<Format> {
    let names = allowed
        .iter()
        .map(|f| f.extension().to_string())
        .collect::<Vec<_>>()
        .join(", ");
    match Format::of(out) {
        Some(f) if allowed.contains(&f) => Ok(f),
        Some(f) => {
            // Animations (a GIF, the preview page, Lottie) come from `crmorph morph`.
            let animation = matches!(
                f,
                Format::Gif | Format::Html | Format::Lottie | Format::DotLottie
            );
            let hint = if animation && command != "morph" {
                format!(
                    "; {} is an animation: write it with crmorph morph",
                    f.extension()
                )
            } else {
                String::new()
            };
            Err(Usage(format!(
                "{}: crmorph {command} writes {names}, not {}{hint}",
                out.display(),
                f.extension()
            ))
            .into())
        }
        None => Err(Usage(format!(
            "{}: unknown output extension; crmorph {command} writes {names}",
            out.display()
        ))
        .into()),
    }
}

fn read_options(inputs: &Inputs) -> ReadOptions {
    let inputs = &inputs.reading;
    let mut ids = ControlIds::default();
    ids.boundary = inputs.boundary_id.clone();
    ids.feature_prefix = inputs.feature_prefix.clone();
    ids.skeleton = inputs.skeleton_id.clone();
    let mut opts = ReadOptions::default();
    opts.ids = ids;
    opts.density = inputs.density;
    opts.policy = inputs.safety.policy();
    opts
}

fn read_both(inputs: &Inputs) -> Result<(Drawing, Drawing)> {
    let opts = read_options(inputs);
    if let Some(controls) = &inputs.controls {
        if let [sc, tc] = controls.as_slice() {
            let s = read_image_with_controls(&inputs.source, sc, inputs, &opts)?;
            let t = read_image_with_controls(&inputs.target, tc, inputs, &opts)?;
            return Ok((s, t));
        }
    }
    let s = Drawing::open(&inputs.source, &opts)?;
    let t = Drawing::open(&inputs.target, &opts)?;
    Ok((s, t))
}

/// The drawing of the image at `image` with the control geometry of `controls` merged in
/// (`--controls`); a usage error when `image` is not a raster image.
fn read_image_with_controls(
    image: &Path,
    controls: &Path,
    inputs: &Inputs,
    opts: &ReadOptions,
) -> Result<Drawing> {
    let name = crmorph::error::printable_path(image);
    let controls_name = crmorph::error::printable_path(controls);
    let text = crmorph::input::read_image_with_controls(
        (image, &name),
        (controls, &controls_name),
        &inputs.reading.boundary_id,
        &opts.policy.limits,
    )?;
    let Some(text) = text else {
        return Err(Usage(format!(
            "--controls: {name} is not an image (PNG, JPEG, GIF or WebP); an SVG drawing \
             carries its control geometry itself"
        ))
        .into());
    };
    Ok(Drawing::from_str(&name, &text, opts)?)
}

/// The library's front door for the two drawings of `inputs` (read here, with `--controls`
/// merged in), with the choices `inputs` makes: which side is triangulated, the density, the
/// skeleton id for messages.
fn morpher(inputs: &Inputs, progress: &Progress) -> Result<Morpher> {
    let mut read: Vec<&Path> = vec![&inputs.source, &inputs.target];
    read.extend(inputs.controls.iter().flatten().map(PathBuf::as_path));
    refuse_overwriting_inputs(&inputs.output, &read)?;
    progress.stage("reading drawings");
    let (s, t) = read_both(inputs)?;
    let side = match inputs.reading.from {
        From::Source => Side::Source,
        From::Target => Side::Target,
    };
    Ok(Morpher::new(s, t)
        .triangulate(side)
        .density(inputs.reading.density)
        .skeleton_id(&inputs.reading.skeleton_id))
}

/// The front door's progress reports on the CLI's progress display.
pub(crate) fn report(progress: &Progress) -> impl FnMut(crmorph::morpher::Progress) + '_ {
    |p| match p {
        crmorph::morpher::Progress::Stage(s) => progress.stage(s),
        crmorph::morpher::Progress::Note(n) => progress.note(n),
    }
}

/// The two drawings of `inputs` and their compatible triangulation
/// ([`Morpher::prepare`]), with the front door that made it.
fn compatible(inputs: &Inputs, progress: &Progress) -> Result<(Morpher, Prepared)> {
    let m = morpher(inputs, progress)?;
    let prepared = m.prepare(&mut report(progress))?;
    Ok((m, prepared))
}

/// Runs `inspect`.
pub(crate) fn inspect(a: &InspectArgs, progress: &Progress) -> Result<()> {
    let fmt = output_format(
        &a.inputs.output,
        &[Format::Svg, Format::Png, Format::Json],
        "inspect",
    )?;
    let (
        _,
        Prepared {
            source: s,
            compatible: c,
            ..
        },
    ) = compatible(&a.inputs, progress)?;
    // The reference skeleton, if the source has one, and where the target mesh carries it.
    let skeleton = if s.controls.skeleton.is_empty() {
        None
    } else {
        let sk = Skeleton::from_chains(&s.file, &s.controls.skeleton, c.tolerances.snap)?;
        let control = SkeletonControl::new(&c.meshes, sk.clone(), &[])
            .map_err(|e| e.in_file(a.inputs.source.display().to_string()))?;
        let target = control.derived(&c.meshes.target);
        let source = control.derived(&c.meshes.source);
        Some((sk.bones, source, target))
    };
    let picture = || {
        crmorph::inspect::inspect_svg_with_skeleton(
            &c,
            skeleton
                .as_ref()
                .map(|(b, s, t)| (b.as_slice(), s.as_slice(), t.as_slice())),
        )
    };
    let bytes = match fmt {
        Format::Json => crmorph::json::meshes_json(&c.meshes).into_bytes(),
        Format::Png => {
            progress.stage("rendering");
            let max_pixels = a.inputs.reading.safety.policy().limits.pixels;
            let file = a.inputs.source.display().to_string();
            crmorph::render::svg_png(&picture(), a.width, &file, max_pixels)?
        }
        _ => picture().into_bytes(),
    };
    write_atomic(&a.inputs.output, &bytes)
}

/// `m` with the method and the poses of `steering` (read here), or skeleton control always
/// (`crmorph skeleton`). Usage errors for poses the method cannot take and for two at one time.
fn steered(
    m: Morpher,
    inputs: &Inputs,
    method: MethodArg,
    steering: &Steering,
    always_skeleton: bool,
) -> Result<Morpher> {
    if !steering.poses.is_empty() && method != MethodArg::Disc {
        return Err(Usage("--pose steers the disc method only; leave out --method".into()).into());
    }
    let mut m = m.method(method.method()).always_skeleton(always_skeleton);
    for (k, (t, file)) in steering.poses.iter().enumerate() {
        if steering.poses[..k]
            .iter()
            .any(|(u, _)| (u - t).abs() < 1e-9)
        {
            return Err(Usage(format!("two poses at t = {t}")).into());
        }
        refuse_overwriting_inputs(&inputs.output, &[file])?;
        m = m.pose(*t, Drawing::open(file, &read_options(inputs))?);
    }
    Ok(m)
}

/// Reads both drawings and makes their morph through the front door with the motion of
/// `method` and `steering` and the look of `look`. With `raster`, the frame size (the
/// drawing's own or `--size`, and again after `--view fit` grew it) is checked against
/// `--max-pixels` before any work at that size. Returns the morph and how its artwork moves.
fn build_morph(
    inputs: &Inputs,
    method: MethodArg,
    look: &Look,
    steering: &Steering,
    always_skeleton: bool,
    raster: bool,
    progress: &Progress,
) -> Result<(Morph, Shapes)> {
    let m = steered(
        morpher(inputs, progress)?,
        inputs,
        method,
        steering,
        always_skeleton,
    )?;
    let view = match look.view {
        ViewArg::Fit => View::Fit,
        ViewArg::Source => View::Source,
    };
    let m = m
        .size(look.size)
        .background(look.background)
        .view(view)
        .padding(look.padding)
        .raster(raster);
    Ok(m.build_with(&mut report(progress))?)
}

/// Runs `frame`.
pub(crate) fn frame(a: &FrameArgs, progress: &Progress) -> Result<()> {
    let fmt = output_format(
        &a.inputs.output,
        &[Format::Json, Format::Svg, Format::Png],
        "frame",
    )?;
    let bytes = if fmt == Format::Json {
        let (m, prepared) = compatible(&a.inputs, progress)?;
        progress.stage("interpolation");
        // With a skeleton in the source, the frame carries it (always through skeleton
        // control, which without poses is the plain disc interpolation).
        let has_skeleton =
            !prepared.source.controls.skeleton.is_empty() && a.method == MethodArg::Disc;
        let m = steered(m, &a.inputs, a.method, &a.steering, has_skeleton)?;
        let mv = m.motion(&prepared)?;
        let c = &prepared.compatible;
        let v = mv.at_vec(a.at);
        let skeleton = match &mv {
            Motion::Skeleton(control) => {
                Some((control.skeleton().bones.clone(), control.derived(&v)))
            }
            Motion::Plain(_) => None,
        };
        crmorph::json::frame_json_with_skeleton(
            &c.meshes,
            a.at,
            &v,
            skeleton.as_ref().map(|(b, j)| (b.as_slice(), j.as_slice())),
        )
        .into_bytes()
    } else {
        let raster = fmt == Format::Png;
        let (morph, _) = build_morph(
            &a.inputs,
            a.method,
            &a.look,
            &a.steering,
            false,
            raster,
            progress,
        )?;
        progress.stage("rendering");
        match fmt {
            Format::Svg => morph.svg_at(a.at)?.into_bytes(),
            _ => encode_png(&morph.pixmap_at(a.at)?)?,
        }
    };
    write_atomic(&a.inputs.output, &bytes)
}

/// Runs `morph`.
pub(crate) fn morph(a: &MorphArgs, progress: &Progress) -> Result<()> {
    morph_pair(a, progress).map(|_| ())
}

/// A finished `morph` of one pair, for `crmorph batch`'s report: the morph itself (to measure
/// its frames), how its artwork moves, and where the time went.
pub(crate) struct Morphed {
    /// The morph whose output was written.
    pub(crate) morph: Morph,
    /// The frames it was written with.
    pub(crate) timeline: Timeline,
    /// How its artwork moves.
    pub(crate) shapes: Shapes,
    /// Reading, triangulating, interpolating and binding the artwork.
    pub(crate) setup: std::time::Duration,
    /// Rendering the frames and writing the output(s).
    pub(crate) render: std::time::Duration,
}

/// Morphs one pair as `crmorph morph` does (`a` holds the pair and every option) and writes
/// its output: the one path `morph` and `batch` share.
pub(crate) fn morph_pair(a: &MorphArgs, progress: &Progress) -> Result<Morphed> {
    let started = std::time::Instant::now();
    let fmt = output_format(
        &a.inputs.output,
        &[
            Format::Svg,
            Format::Gif,
            Format::Png,
            Format::Html,
            Format::Json,
            Format::Lottie,
            Format::DotLottie,
        ],
        "morph",
    )?;
    let timeline = a.timing.timeline();
    let mut frame_files = Vec::new();
    if let Some(dir) = &a.frames_dir {
        let n = timeline.frames;
        let digits = ((n - 1) as f64).log10().floor() as usize + 1;
        let ext = match a.frame_format {
            FrameFormat::Svg => "svg",
            FrameFormat::Png => "png",
        };
        for i in 0..n {
            let p = dir.join(format!("frame_{i:0width$}.{ext}", width = digits.max(3)));
            refuse_overwriting_inputs(&p, &[&a.inputs.source, &a.inputs.target])?;
            frame_files.push(p);
        }
    }
    let raster = matches!(fmt, Format::Gif | Format::Png)
        || (a.frames_dir.is_some() && a.frame_format == FrameFormat::Png);
    let (mut morph, shapes) = build_morph(
        &a.inputs,
        a.method,
        &a.look,
        &a.steering,
        false,
        raster,
        progress,
    )?;
    let setup = started.elapsed();
    progress.stage("rendering");
    // Frames done / total, over both outputs (the frames folder is made first).
    let main = match fmt {
        Format::Gif => Some(Export::Gif),
        Format::Png => Some(Export::Apng),
        Format::Svg | Format::Html | Format::Lottie | Format::DotLottie => {
            Some(Export::AnimatedSvg)
        }
        _ => None,
    };
    let dir_reports = match frame_files.is_empty() {
        true => 0,
        false => morph.reports(Export::Frames, &timeline),
    };
    let total = main.map_or(0, |e| morph.reports(e, &timeline)) + dir_reports;
    if total > 0 {
        progress.frames(total);
        let then = match fmt {
            Format::Gif | Format::Png => "encoding",
            _ => "assembling",
        };
        morph.on_frame(progress.frame_counter(total, then));
    }
    // The frames go into a staging folder first, one by one as they are made, and into
    // --frames-dir only once the main output is in place: a failure leaves neither partial
    // output nor frames behind.
    let staged = match &a.frames_dir {
        Some(dir) => {
            let mut staged = FramesDir::create(dir)?;
            let mut failed = None;
            let mut keep = |i: usize, bytes: &[u8]| {
                staged.add(&frame_files[i], bytes).map_err(|e| {
                    failed = Some(e);
                    crmorph::Error::internal("writing a frame failed")
                })
            };
            let made = match a.frame_format {
                FrameFormat::Svg => {
                    morph.for_each_svg_frame(&timeline, |i, svg| keep(i, svg.as_bytes()))
                }
                FrameFormat::Png => {
                    morph.for_each_pixmap_frame(&timeline, |i, px| keep(i, &encode_png(&px)?))
                }
            };
            if let Some(e) = failed {
                return Err(e);
            }
            made?;
            Some(staged)
        }
        None => None,
    };
    let out = &a.inputs.output;
    match fmt {
        Format::Json => write_streamed(out, |w| {
            w.cap(1 << 31, "use fewer frames");
            morph.write_frames_json(&timeline, w)
        })?,
        Format::Svg => write_streamed(out, |w| morph.write_animated_svg(&timeline, w))?,
        Format::Gif => write_streamed(out, |w| morph.write_gif(&timeline, w))?,
        Format::Png => write_streamed(out, |w| morph.write_apng(&timeline, w))?,
        Format::Lottie | Format::DotLottie => {
            let name = lottie_name(out);
            let lottie = morph.lottie(&timeline, &name)?;
            for n in &lottie.notes {
                progress.note(&format!("{}: {n}", out.display()));
            }
            if fmt == Format::Lottie {
                write_atomic(out, lottie.json.as_bytes())?;
            } else {
                write_atomic(out, &lottie.dotlottie(&name)?)?;
            }
        }
        _ => {
            let title = format!(
                "{} → {}",
                file_name(&a.inputs.source),
                file_name(&a.inputs.target)
            );
            write_atomic(out, morph.html(&timeline, &title)?.as_bytes())?;
        }
    }
    progress.frames_done();
    if let Some(s) = staged {
        s.commit()?;
    }
    Ok(Morphed {
        morph,
        timeline,
        shapes,
        setup,
        render: started.elapsed() - setup,
    })
}

/// The animation's name in a Lottie file: the output's file name without `.lottie(.json)`.
fn lottie_name(out: &Path) -> String {
    let name = file_name(out);
    let lower = name.to_ascii_lowercase();
    let cut = [".lottie.json", ".lottie"]
        .iter()
        .find(|e| lower.ends_with(*e))
        .map_or(name.len(), |e| name.len() - e.len());
    name[..cut].to_string()
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

/// Runs `skeleton`: the frame at T with its derived skeleton drawn on it.
pub(crate) fn skeleton(a: &SkeletonArgs, progress: &Progress) -> Result<()> {
    output_format(&a.inputs.output, &[Format::Svg], "skeleton")?;
    if !(a.at > 0.0 && a.at < 1.0) {
        return Err(Usage(format!(
            "--at {}: a pose is edited on an in-between frame, strictly between 0 and 1",
            a.at
        ))
        .into());
    }
    let (morph, _) = build_morph(
        &a.inputs,
        MethodArg::Disc,
        &a.look,
        &a.steering,
        true,
        false,
        progress,
    )?;
    let Motion::Skeleton(control) = morph.motion() else {
        bail!("internal error: skeleton control was not set up");
    };
    progress.stage("rendering");
    let mesh = morph.vertices_at(a.at);
    let joints = control.derived(&mesh);
    let frame = morph.svg_at(a.at)?;
    let (lo, hi) = morph.frame_options().view_box;
    let width = 0.006 * (hi - lo).length();
    let text = pose_svg(&frame, control.skeleton(), &joints, a.at, width);
    write_atomic(&a.inputs.output, text.as_bytes())
}

/// `crmorph init`: an image as an SVG drawing to draw controls on.
#[derive(Debug, Clone, Args)]
pub(crate) struct InitArgs {
    /// The image: PNG, JPEG, GIF or WebP.
    pub(crate) image: PathBuf,
    /// The SVG to write.
    #[arg(short, long)]
    pub(crate) output: PathBuf,
    #[command(flatten)]
    pub(crate) safety: crate::policy::Safety,
}

/// Runs `init`: writes the SVG that embeds the image, with its boundary (the image rectangle,
/// or the traced outline of its alpha) in a hidden `controls` group, ready for feature curves.
pub(crate) fn init(a: &InitArgs) -> Result<()> {
    output_format(&a.output, &[Format::Svg], "init")?;
    refuse_overwriting_inputs(&a.output, &[&a.image])?;
    let limits = a.safety.policy().limits;
    let name = crmorph::error::printable_path(&a.image);
    let bytes = crmorph::input::read_file(&a.image, &name, &limits)?;
    let Some(format) = crmorph::input::raster::sniff(&bytes) else {
        return Err(Usage(format!(
            "{name}: crmorph init reads an image (PNG, JPEG, GIF or WebP), not this file"
        ))
        .into());
    };
    let svg = crmorph::input::raster::image_svg(&name, &bytes, format, "boundary", &limits)?;
    write_atomic(&a.output, svg.as_bytes())
}
