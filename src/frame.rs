//! What a frame of a morph is, independent of any output format: the frame model every exporter
//! reads.
//!
//! A [`Frame`] at `t` is a stack of [`FrameLayer`]s drawn from the mesh at `t` (§4.1), bottom first:
//! parts of the artwork that cross-dissolve (the warped source and target of the part, weighed by
//! [`dissolve`], end of §3), and paths that morph as one shape (automatic mode's matched paths,
//! [`crate::morphing`], with their paints already mixed), interleaved in the inputs' paint order.
//! The SVG and PNG frames, the animated SVG, GIF, APNG, the HTML preview and Lottie are all written
//! from frames ([`crate::export::Morph::frame_at`] and [`crate::export::Morph::keyframe_at`]);
//! when they are shown is the [`crate::render::Timeline`]'s business. The JSON output is the
//! mesh itself ([`crate::export::Morph::vertex_frames`]), not a drawing, so it needs no frame.

use crate::artwork::Scene;

/// One layer of a [`Frame`].
#[derive(Debug, Clone)]
pub enum FrameLayer {
    /// A part of the artwork cross-dissolved on its own: its warped source and target, drawn
    /// with the opacities [`Frame::weights`], the target over the source.
    Blend {
        /// The source side of the part, placed in the mesh at `t`.
        source: Scene,
        /// The target side of the part, placed in the mesh at `t`.
        target: Scene,
    },
    /// Artwork painted as it is over the layers below: paths that morph as one shape.
    Over(Scene),
}

impl FrameLayer {
    /// The scenes of the layer: both sides of a blend, or the one scene painted over.
    pub fn scenes(&self) -> impl Iterator<Item = &Scene> {
        let (a, b) = match self {
            FrameLayer::Blend { source, target } => (source, Some(target)),
            FrameLayer::Over(o) => (o, None),
        };
        std::iter::once(a).chain(b)
    }
}

/// A frame of a morph at `t`: the layers drawn from the mesh at `t`, bottom first.
#[derive(Debug, Clone)]
pub struct Frame {
    /// The morph's progress, in [0, 1] ([`crate::rigid::clamp_time`]).
    pub t: f64,
    /// The layers, bottom first.
    pub layers: Vec<FrameLayer>,
}

impl Frame {
    /// The opacities `(source, target)` of every [`FrameLayer::Blend`] of this frame.
    pub fn weights(&self) -> (f64, f64) {
        dissolve(self.t)
    }

    /// The file name that names this frame in error messages: the first layer's first scene's.
    pub fn file(&self) -> &str {
        self.layers
            .first()
            .and_then(|l| l.scenes().next())
            .map_or("<output>", |s| s.file.as_str())
    }
}

/// The opacities `(a, b)` of the source and the target side of a cross-dissolve at `t`:
/// `a = min(1, 2(1 − t))` under `b = min(1, 2t)`. The target fades in over the source in the
/// first half and the uncovered source fades out in the second; each is a plain group opacity,
/// which every renderer and player implements alike.
pub fn dissolve(t: f64) -> (f64, f64) {
    let t = crate::rigid::clamp_time(t);
    ((2.0 * (1.0 - t)).min(1.0), (2.0 * t).min(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dissolve_shows_one_side_at_each_end_and_both_in_the_middle() {
        assert_eq!(dissolve(0.0), (1.0, 0.0));
        assert_eq!(dissolve(1.0), (0.0, 1.0));
        assert_eq!(dissolve(0.5), (1.0, 1.0));
        assert_eq!(dissolve(0.25), (1.0, 0.5));
        assert_eq!(dissolve(f64::NAN), (1.0, 0.0), "NaN is t = 0");
        assert_eq!(dissolve(7.0), (0.0, 1.0), "held at the target past 1");
    }
}
