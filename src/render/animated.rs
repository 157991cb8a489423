//! The morph as one animated SVG file (SMIL), playable in Chromium, Firefox and Safari.
//!
//! Every keyframe is built as the same blended frame tree ([`super::svg_frame`] in
//! `Mode::Keyframe`); the trees are lined up element by element and every attribute that
//! differs between keyframes becomes an animation of that element:
//! - path data: one `<animate attributeName="d">` whose keyframes share one segment structure
//!   (browsers snap instead of interpolating otherwise), polylines fitted with cubics that hold a
//!   quarter pixel in *every* keyframe (`render::fit`);
//! - numbers (stroke widths, dashes, the opacities of the two sides of a cross-dissolve):
//!   `<animate>` with the numbers;
//! - transforms (images, gradients, shaped pens): decomposed as
//!   `translate · rotate · skewX · scale`, one `<animateTransform>` each (the first replaces,
//!   the rest add), the rotation unwrapped so it never jumps by a turn;
//! - anything else that changes: a discrete `<animate>`.
//!
//! Keyframes that linear interpolation between the kept neighbours already reproduces within
//! the tolerance (a quarter pixel for geometry, 1/1000 for scale-free numbers) are dropped, per
//! animation. The static attribute values are those of the first frame (t = 0) with the source
//! drawing's own geometry, so a viewer without SMIL (librsvg, thumbnailers) shows the source.
//!
//! Timing: the values run through [`Timeline::sequence`] (and back to the start for yoyo) at
//! uniform `keyTimes` over one [`Timeline::period`]; played once, the animation freezes on the
//! target. Paused at `τ·duration`, it shows the frame at `t = ease(τ)` (exactly at keyframes,
//! linearly between them).

use super::fit::fit_paths;
use super::svg_frame::{frame_tree, Layer, Mode};
use super::timeline::{Playback, Timeline};
use super::tree::{fixed, path_data, sig, Node, NumFormat, Value};
use super::FrameOptions;
use crate::artwork::Scene;
use crate::error::{Error, Result};
use kurbo::{Affine, BezPath, PathEl};
use rayon::prelude::*;

/// Tolerance for scale-free numbers (opacities, blend weights, matrix coefficients).
const UNIT_TOLERANCE: f64 = 1e-3;

/// The animated SVG of a morph. `keyframes[i]` are the warped source and target at frame `i` of
/// `timeline` (at `t = timeline.morph_times()[i]`), each from
/// [`crate::artwork::ArtworkPair::warped_at`] so that all keyframes have the same structure.
pub fn animated_svg(
    keyframes: &[(Scene, Scene)],
    timeline: &Timeline,
    opts: &FrameOptions,
) -> Result<String> {
    let layers: Vec<Vec<Layer>> = keyframes
        .iter()
        .map(|(s, t)| vec![Layer::Blend(s, t)])
        .collect();
    animated_svg_layers(&layers, timeline, opts, None)
}

/// [`animated_svg`] of frames made of layers (see [`super::svg_frame::frame_svg_layers`]):
/// `keyframes[i]` are keyframe `i`'s layers, bottom first. Every keyframe must have the same
/// layers with the same structure (warped with [`crate::artwork::ArtworkPair::warped_at`]).
/// `base`, when given, is the first keyframe with the source drawing's own geometry (same
/// structure, exact paths): the static attribute values come from it, so that a viewer
/// without SMIL shows the source drawing itself, not its warped copy.
pub fn animated_svg_layers(
    keyframes: &[Vec<Layer>],
    timeline: &Timeline,
    opts: &FrameOptions,
    base: Option<&[Layer]>,
) -> Result<String> {
    let timeline = timeline.sanitized();
    if keyframes.len() != timeline.frames {
        return Err(Error::internal(format!(
            "{} keyframes for a timeline of {} frames",
            keyframes.len(),
            timeline.frames
        )));
    }
    let ts = timeline.morph_times();
    let trees = |frames: &[usize]| -> Result<Vec<Node>> {
        Ok(frames
            .par_iter()
            .map(|&i| frame_tree(&keyframes[i], ts[i], opts, Mode::Keyframe))
            .collect())
    };
    let base = base.map(|layers| frame_tree(layers, 0.0, opts, Mode::Keyframe));
    let mut out = Vec::new();
    write_animated_svg(&timeline, opts, trees, base, &mut out)?;
    String::from_utf8(out).map_err(|_| Error::internal("the SVG is not UTF-8"))
}

/// The animated SVG of keyframe trees made on demand, written to `out`: `trees(frames)` are
/// the trees ([`frame_tree`] in `Mode::Keyframe`) of those frames of `timeline`, in order,
/// asked for a chunk at a time, so that no frame's scenes outlive their chunk. What is kept of
/// every keyframe until the end is its attribute values packed (path coordinates as plain
/// numbers: about 16 bytes a vertex); the merge needs every keyframe of an element at once
/// (curves are fitted through all of them). `base` as in [`animated_svg_layers`].
pub(crate) fn write_animated_svg<W: std::io::Write>(
    timeline: &Timeline,
    opts: &FrameOptions,
    trees: impl Fn(&[usize]) -> Result<Vec<Node>>,
    base: Option<Node>,
    out: W,
) -> Result<()> {
    let timeline = timeline.sanitized();
    let frames: Vec<usize> = (0..timeline.frames).collect();
    let mut first: Option<Node> = None;
    let mut packed: Vec<Vec<Slot>> = Vec::with_capacity(frames.len());
    for chunk in frames.chunks(super::stream::chunk_len(0)) {
        let made = trees(chunk)?;
        if made.len() != chunk.len() {
            return Err(Error::internal(format!(
                "{} keyframe trees for {} frames",
                made.len(),
                chunk.len()
            )));
        }
        for tree in made {
            let first = first.get_or_insert_with(|| tree.clone());
            let mut slots = Vec::new();
            pack(&tree, first, &mut slots)?;
            slots.shrink_to_fit();
            packed.push(slots);
        }
    }
    let Some(first) = first else {
        return Err(Error::internal("no keyframes"));
    };
    let mut order = timeline.sequence();
    if timeline.playback == Playback::Yoyo {
        order.push(0);
    }
    let ctx = Context {
        tol: opts.flatten_tolerance(),
        timing: timing(&timeline),
        key_decimals: (order.len() as f64).log10().ceil() as usize + 2,
        parallel: crate::parallel::worth(order.len().saturating_mul(slot_points(&packed[0]))),
        order,
    };
    // A base of another structure (it should not happen) is ignored, not an error.
    let base = base.filter(|b| same_shape(b, &first));
    merge(&first, 0, &packed, base.as_ref(), &ctx)?.write_svg(out)
}

/// One attribute value of one keyframe as kept until the merge: path data as plain numbers
/// (a `kurbo::PathEl` takes 56 bytes whatever its kind; a line's end point here takes 16),
/// everything else as it is.
enum Slot {
    /// [`Value::Path`], packed.
    Path {
        /// 0 move, 1 line, 2 quadratic, 3 cubic, 4 close.
        verbs: Box<[u8]>,
        /// The points' coordinates, x then y, in order.
        coords: Box<[f64]>,
        decimals: usize,
        fit: Option<f64>,
    },
    /// Any other value.
    Other(Value),
}

impl Slot {
    fn new(v: &Value) -> Slot {
        match v {
            Value::Path {
                path,
                decimals,
                fit,
            } => {
                let mut verbs = Vec::with_capacity(path.elements().len());
                let mut coords = Vec::new();
                for el in path.elements() {
                    let (verb, pts): (u8, &[kurbo::Point]) = match el {
                        PathEl::MoveTo(a) => (0, std::slice::from_ref(a)),
                        PathEl::LineTo(a) => (1, std::slice::from_ref(a)),
                        PathEl::QuadTo(a, b) => (2, &[*a, *b]),
                        PathEl::CurveTo(a, b, c) => (3, &[*a, *b, *c]),
                        PathEl::ClosePath => (4, &[]),
                    };
                    verbs.push(verb);
                    for p in pts {
                        coords.extend([p.x, p.y]);
                    }
                }
                Slot::Path {
                    verbs: verbs.into(),
                    coords: coords.into(),
                    decimals: *decimals,
                    fit: *fit,
                }
            }
            other => Slot::Other(other.clone()),
        }
    }

    /// The value again, exactly.
    fn value(&self) -> Value {
        match self {
            Slot::Path {
                verbs,
                coords,
                decimals,
                fit,
            } => {
                let mut path = BezPath::new();
                let mut c = coords
                    .chunks_exact(2)
                    .map(|p| kurbo::Point::new(p[0], p[1]));
                let mut next = || c.next().unwrap_or_default();
                for v in verbs.iter() {
                    match v {
                        0 => path.move_to(next()),
                        1 => path.line_to(next()),
                        2 => {
                            let a = next();
                            path.quad_to(a, next());
                        }
                        3 => {
                            let (a, b) = (next(), next());
                            path.curve_to(a, b, next());
                        }
                        _ => path.close_path(),
                    }
                }
                Value::Path {
                    path,
                    decimals: *decimals,
                    fit: *fit,
                }
            }
            Slot::Other(v) => v.clone(),
        }
    }
}

/// Appends `tree`'s attribute values in document order (each element's, then its children's)
/// to `out`, checking that it has `first`'s structure.
fn pack(tree: &Node, first: &Node, out: &mut Vec<Slot>) -> Result<()> {
    let same = tree.name == first.name
        && tree.children.len() == first.children.len()
        && tree.attrs.len() == first.attrs.len()
        && tree.attrs.iter().zip(&first.attrs).all(|(a, b)| a.0 == b.0);
    if !same {
        return Err(Error::internal(format!(
            "keyframes differ in structure at <{}>",
            first.name
        )));
    }
    out.extend(tree.attrs.iter().map(|(_, v)| Slot::new(v)));
    for (c, f) in tree.children.iter().zip(&first.children) {
        pack(c, f, out)?;
    }
    Ok(())
}

/// Attribute values in a subtree (the slots [`pack`] makes of it).
/// The points of one keyframe's packed values (a path's points, one for any other value): the
/// merge's work per keyframe.
fn slot_points(slots: &[Slot]) -> usize {
    slots
        .iter()
        .map(|s| match s {
            Slot::Path { coords, .. } => coords.len() / 2,
            Slot::Other(_) => 1,
        })
        .sum()
}

fn slot_count(node: &Node) -> usize {
    node.attrs.len() + node.children.iter().map(slot_count).sum::<usize>()
}

/// Whether two trees have the same elements with the same attribute names, in order.
fn same_shape(a: &Node, b: &Node) -> bool {
    a.name == b.name
        && a.attrs.len() == b.attrs.len()
        && a.attrs.iter().zip(&b.attrs).all(|(x, y)| x.0 == y.0)
        && a.children.len() == b.children.len()
        && a.children
            .iter()
            .zip(&b.children)
            .all(|(x, y)| same_shape(x, y))
}

/// What every animation of a file shares.
struct Context {
    /// Geometry tolerance in user units.
    tol: f64,
    /// `dur`, `repeatCount`/`fill` attributes.
    timing: Vec<(&'static str, Value)>,
    /// Decimals of `keyTimes`.
    key_decimals: usize,
    /// The keyframes in playback order (indices of frames).
    order: Vec<usize>,
    /// Whether elements' children are merged on rayon's threads: when the whole merge is worth
    /// it ([`crate::parallel`]).
    parallel: bool,
}

fn timing(tl: &Timeline) -> Vec<(&'static str, Value)> {
    let mut a = vec![
        ("begin", "0s".into()),
        ("dur", format!("{}s", sig(tl.period())).into()),
    ];
    if tl.repeats() {
        a.push(("repeatCount", "indefinite".into()));
    } else {
        a.push(("fill", "freeze".into()));
    }
    a
}

/// One element (`node`, as in the first keyframe, its values from slot `at` of every
/// keyframe in `packed`) merged across the keyframes of the playback order into one element
/// with animations.
fn merge(
    node: &Node,
    at: usize,
    packed: &[Vec<Slot>],
    base: Option<&Node>,
    ctx: &Context,
) -> Result<Node> {
    let mut out = Node::new(&node.name, Vec::new());
    let mut animations = Vec::new();
    for (ai, (key, _)) in node.attrs.iter().enumerate() {
        // The values in playback order, unpacked for this attribute alone.
        let values: Vec<Value> = ctx
            .order
            .iter()
            .map(|&k| packed[k][at + ai].value())
            .collect();
        let (stat, anims) = attribute(key, values, ctx);
        // The static value from the base where it has one of the same kind.
        let stat = match (base.map(|b| &b.attrs[ai].1), &stat) {
            (Some(Value::Path { path, decimals, .. }), Value::Text(_)) => {
                Value::Text(path_data(path, *decimals))
            }
            (Some(v), _) if std::mem::discriminant(v) == std::mem::discriminant(&stat) => v.clone(),
            _ => stat,
        };
        out.attrs.push((key, stat));
        animations.extend(anims);
    }
    let mut starts = Vec::with_capacity(node.children.len());
    let mut next = at + node.attrs.len();
    for c in &node.children {
        starts.push(next);
        next += slot_count(c);
    }
    let child = |ci: usize| {
        merge(
            &node.children[ci],
            starts[ci],
            packed,
            base.map(|b| &b.children[ci]),
            ctx,
        )
    };
    let children: Vec<Node> = if ctx.parallel {
        (0..node.children.len())
            .into_par_iter()
            .map(child)
            .collect::<Result<_>>()?
    } else {
        (0..node.children.len()).map(child).collect::<Result<_>>()?
    };
    out.children = children;
    out.children.extend(animations);
    Ok(out)
}

/// The static value of one attribute and the animations it needs.
///
/// `values` are the attribute's values in the keyframes of the playback order (the first is
/// the static one); they are consumed, so that an outline's keyframes are held once while their
/// curves are fitted (the paths of every keyframe of one element are the largest thing the
/// merge holds).
fn attribute(key: &'static str, values: Vec<Value>, ctx: &Context) -> (Value, Vec<Node>) {
    let v0 = values[0].clone();
    match &v0 {
        Value::Path { decimals, fit, .. } => {
            let paths: Vec<BezPath> = values
                .into_iter()
                .map(|v| match v {
                    Value::Path { path, .. } => path,
                    _ => BezPath::new(),
                })
                .collect();
            let tol = fit.unwrap_or(ctx.tol);
            let paths = fitted(paths, *fit);
            let stat = Value::Text(path_data(&paths[0], *decimals));
            let nums: Vec<Vec<f64>> = paths.iter().map(coordinates).collect();
            // Unchanged (to the written precision) in every keyframe: no animation.
            let step = 0.5 * 10f64.powi(-(*decimals as i32));
            let still = nums
                .iter()
                .all(|n| n.iter().zip(&nums[0]).all(|(a, b)| (a - b).abs() < step));
            if still {
                return (stat, Vec::new());
            }
            let kept = keep(&nums, tol);
            // Keyframe values at 1/10 px: in motion, finer steps are invisible, and they are
            // most of the file.
            let text = |k: usize| path_data(&paths[k], decimals.saturating_sub(1));
            let anim = animate(key, &kept, text, ctx, false);
            (stat, vec![anim])
        }
        Value::Matrix(_) => {
            let ms: Vec<Affine> = values
                .iter()
                .map(|v| match v {
                    Value::Matrix(m) => *m,
                    _ => Affine::IDENTITY,
                })
                .collect();
            if ms.iter().all(|m| *m == ms[0]) {
                return (values[0].clone(), Vec::new());
            }
            (values[0].clone(), animate_transform(key, &ms, ctx))
        }
        _ => {
            let texts: Vec<String> = values.iter().map(|v| v.text()).collect();
            if texts.iter().all(|t| *t == texts[0]) {
                return (values[0].clone(), Vec::new());
            }
            // Numbers and colours interpolate; text, or numbers whose count changes, switch.
            let nums: Option<Vec<Vec<f64>>> = values.iter().map(numbers).collect();
            let anim = match nums {
                Some(nums) if nums.iter().all(|n| n.len() == nums[0].len()) => {
                    let kept = keep(&nums, tolerance(&v0, ctx));
                    animate(key, &kept, |k| texts[k].clone(), ctx, false)
                }
                _ => discrete(key, &texts, ctx),
            };
            (values[0].clone(), vec![anim])
        }
    }
}

/// `paths` with curves fitted within `fit` in every keyframe (unchanged without a tolerance);
/// the polylines are dropped as soon as the fit is made.
fn fitted(paths: Vec<BezPath>, fit: Option<f64>) -> Vec<BezPath> {
    match fit {
        Some(t) => fit_paths(&paths, t),
        None => paths,
    }
}

/// The numbers an attribute value interpolates, if it interpolates: numbers as they are, a
/// colour as its sRGB channels (browsers interpolate colours channel by channel in sRGB).
fn numbers(v: &Value) -> Option<Vec<f64>> {
    match v {
        Value::Nums(n, _) => Some(n.clone()),
        Value::Color(c) => Some(vec![c.r as f64, c.g as f64, c.b as f64]),
        _ => None,
    }
}

/// How far linear interpolation may miss a dropped keyframe of this kind of value: the
/// geometry tolerance for lengths, [`UNIT_TOLERANCE`] for scale-free numbers, one channel level
/// for colours.
fn tolerance(v: &Value, ctx: &Context) -> f64 {
    match v {
        Value::Nums(_, NumFormat::Fixed(_)) => ctx.tol,
        Value::Color(_) => 1.0,
        _ => UNIT_TOLERANCE,
    }
}

/// Every coordinate of a path, in order.
fn coordinates(p: &BezPath) -> Vec<f64> {
    let mut out = Vec::new();
    for el in p.elements() {
        let pts: &[kurbo::Point] = match el {
            PathEl::MoveTo(a) | PathEl::LineTo(a) => std::slice::from_ref(a),
            PathEl::QuadTo(a, b) => &[*a, *b],
            PathEl::CurveTo(a, b, c) => &[*a, *b, *c],
            PathEl::ClosePath => &[],
        };
        for q in pts {
            out.extend([q.x, q.y]);
        }
    }
    out
}

/// The keyframes to keep (indices, first and last always): greedily, each kept keyframe reaches
/// as far as linear interpolation to the next kept one reproduces every keyframe between them
/// within `tol` (per number). The keyframes are at uniform times.
fn keep(values: &[Vec<f64>], tol: f64) -> Vec<usize> {
    let n = values.len();
    let mut kept = vec![0];
    let mut a = 0;
    while a < n - 1 {
        let mut b = a + 1;
        while b + 1 < n && reproduces(values, a, b + 1, tol) {
            b += 1;
        }
        kept.push(b);
        a = b;
    }
    kept
}

/// Whether the lerp from keyframe `a` to `b` reproduces every keyframe strictly between.
fn reproduces(values: &[Vec<f64>], a: usize, b: usize, tol: f64) -> bool {
    let (va, vb) = (&values[a], &values[b]);
    (a + 1..b).all(|i| {
        let s = (i - a) as f64 / (b - a) as f64;
        values[i]
            .iter()
            .zip(va.iter().zip(vb))
            .all(|(x, (p, q))| (p + (q - p) * s - x).abs() <= tol)
    })
}

/// `keyTimes` of the kept keyframes out of `total`.
fn key_times(kept: &[usize], total: usize, ctx: &Context) -> String {
    kept.iter()
        .map(|&k| fixed(k as f64 / (total - 1) as f64, ctx.key_decimals))
        .collect::<Vec<_>>()
        .join(";")
}

/// An `<animate>` of `key` through the kept keyframes.
fn animate(
    key: &str,
    kept: &[usize],
    text: impl Fn(usize) -> String,
    ctx: &Context,
    discrete: bool,
) -> Node {
    let mut head: Vec<(&'static str, Value)> = vec![("attributeName", key.into())];
    if discrete {
        head.push(("calcMode", "discrete".into()));
    }
    animation("animate", head, kept, text, ctx)
}

/// An animation element: `head` attributes, then the kept keyframes' `values` and `keyTimes`,
/// then the file's timing.
fn animation(
    element: &str,
    mut head: Vec<(&'static str, Value)>,
    kept: &[usize],
    text: impl Fn(usize) -> String,
    ctx: &Context,
) -> Node {
    let total = *kept.last().unwrap_or(&0) + 1;
    head.push((
        "values",
        kept.iter()
            .map(|&k| text(k))
            .collect::<Vec<_>>()
            .join(";")
            .into(),
    ));
    head.push(("keyTimes", key_times(kept, total, ctx).into()));
    head.extend(ctx.timing.iter().cloned());
    Node::new(element, head)
}

/// A discrete `<animate>` switching at every change.
fn discrete(key: &str, texts: &[String], ctx: &Context) -> Node {
    let mut kept = vec![0];
    for k in 1..texts.len() {
        if texts[k] != texts[k - 1] || k == texts.len() - 1 {
            kept.push(k);
        }
    }
    animate(key, &kept, |k| texts[k].clone(), ctx, true)
}

/// `m` as `translate(e, f) · rotate(θ) · skewX(φ) · scale(sx, sy)`: `[e, f, θ°, φ°, sx, sy]`.
fn decompose(m: Affine) -> [f64; 6] {
    let [a, b, c, d, e, f] = m.as_coeffs();
    let sx = a.hypot(b);
    let theta = b.atan2(a);
    let (sin, cos) = theta.sin_cos();
    // The second column rotated back by −θ is (tan φ · sy, sy).
    let (c2, sy) = (cos * c + sin * d, -sin * c + cos * d);
    let skew = if sy != 0.0 { (c2 / sy).atan() } else { 0.0 };
    [e, f, theta.to_degrees(), skew.to_degrees(), sx, sy]
}

/// The four `<animateTransform>`s of a changing transform attribute.
fn animate_transform(key: &str, ms: &[Affine], ctx: &Context) -> Vec<Node> {
    let mut parts: Vec<[f64; 6]> = ms.iter().map(|m| decompose(*m)).collect();
    // Unwrap the rotation so consecutive keyframes never differ by half a turn or more.
    for k in 1..parts.len() {
        let prev = parts[k - 1][2];
        let mut a = parts[k][2];
        a -= 360.0 * ((a - prev) / 360.0).round();
        parts[k][2] = a;
    }
    // Translations to 1/100 of the tolerance, angles to 1/1000 degree, scales to 6 decimals.
    let move_decimals = (-(ctx.tol / 100.0).log10()).ceil().clamp(0.0, 12.0) as usize;
    let kinds: [(&str, [usize; 2], usize, f64, usize); 4] = [
        ("translate", [0, 1], 2, ctx.tol, move_decimals),
        ("rotate", [2, 2], 1, UNIT_TOLERANCE, 3),
        ("skewX", [3, 3], 1, UNIT_TOLERANCE, 3),
        ("scale", [4, 5], 2, UNIT_TOLERANCE, 6),
    ];
    let mut out = Vec::new();
    for (i, (kind, idx, dims, tol, decimals)) in kinds.iter().enumerate() {
        let nums: Vec<Vec<f64>> = parts
            .iter()
            .map(|p| idx[..*dims].iter().map(|&j| p[j]).collect())
            .collect();
        let kept = keep(&nums, *tol);
        let text = |k: usize| {
            nums[k]
                .iter()
                .map(|x| fixed(*x, *decimals))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let mut head: Vec<(&'static str, Value)> = vec![
            ("attributeName", key.to_string().into()),
            ("type", (*kind).into()),
        ];
        if i > 0 {
            head.push(("additive", "sum".into()));
        }
        out.push(animation("animateTransform", head, &kept, text, ctx));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decomposition_recomposes() {
        let m = Affine::translate((3.0, -2.0))
            * Affine::rotate(2.5)
            * Affine::skew(0.3, 0.0)
            * Affine::scale_non_uniform(1.5, -0.7);
        let [e, f, th, sk, sx, sy] = decompose(m);
        let r = Affine::translate((e, f))
            * Affine::rotate(th.to_radians())
            * Affine::skew(sk.to_radians().tan(), 0.0)
            * Affine::scale_non_uniform(sx, sy);
        for (a, b) in m.as_coeffs().iter().zip(r.as_coeffs()) {
            assert!((a - b).abs() < 1e-12, "{m:?} vs {r:?}");
        }
    }

    #[test]
    fn keyframes_on_a_line_are_dropped_and_turns_kept() {
        // Linear, then a kink at 5, then linear: keep 0, 5, 9.
        let v: Vec<Vec<f64>> = (0..10)
            .map(|i| {
                let x = i as f64;
                vec![if i <= 5 { x } else { 5.0 - (x - 5.0) * 2.0 }, 7.0]
            })
            .collect();
        assert_eq!(keep(&v, 1e-9), vec![0, 5, 9]);
        // Within tolerance a small wobble is dropped too.
        let w: Vec<Vec<f64>> = (0..5)
            .map(|i| vec![i as f64 + (i % 2) as f64 * 0.01])
            .collect();
        assert_eq!(keep(&w, 0.05), vec![0, 4]);
        assert_eq!(keep(&w, 0.001), vec![0, 1, 2, 3, 4]);
        assert_eq!(keep(&v[..2], 0.1), vec![0, 1]);
    }
}
