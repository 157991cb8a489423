//! Rendering frames: the warped source and target artwork blended at t (end of §3), as a
//! standalone SVG ([`frame_svg`]) or as pixels ([`frame_pixmap`], [`frame_png`]), in the view
//! of [`FrameOptions`] ([`view`] grows it to hold the whole morph).
//!
//! Both outputs show the same thing: the two warped renderings cross-dissolved
//! ([`dissolve`]), composited over an optional background; at t = 0 and t = 1 exactly one
//! drawing. The raster path renders each side with resvg (through the same SVG writer, parsed back
//! with usvg, so the two outputs cannot drift apart) and composites pixels; the SVG path writes
//! two groups with plain opacity (see [`svg_frame`]).

pub mod animated;
mod fit;
mod font;
mod raster;
pub(crate) mod stream;
pub mod svg_frame;
mod texture;
pub mod timeline;
mod tree;
pub mod view;

pub(crate) use animated::write_animated_svg;
pub use animated::{animated_svg, animated_svg_layers};
pub(crate) use fit::fit_paths;
pub(crate) use raster::view_transform;
pub use raster::{
    encode_png, frame_pixmap, frame_pixmap_layers, frame_png, render_scene, straight_rgba, svg_png,
};
pub use svg_frame::{frame_svg, frame_svg_layers, layers_of, scene_svg, Layer};
pub(crate) use svg_frame::{frame_tree, Mode};
pub use timeline::{Easing, Playback, Timeline};
pub(crate) use tree::Node;
pub use view::Padding;

/// Re-exported from the frame model, where it belongs: every exporter weighs blended layers by it.
pub use crate::frame::dissolve;

use crate::artwork::{Rgba, Scene};
use crate::geometry::Point;

/// What a frame is rendered into: the part of user space shown, the output size, the background.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameOptions {
    /// The user-space rectangle shown, `(min, max)`: normally the source drawing's viewBox.
    pub view_box: (Point, Point),
    /// Output size in pixels (width, height). Default: the drawing's own size.
    pub size: (u32, u32),
    /// Colour under the artwork. Default: none (transparent).
    pub background: Option<Rgba>,
    /// Most pixels a raster frame of these options may have
    /// ([`crate::input::Limits::pixels`]): every pixmap is checked against it before it is
    /// allocated, so that a drawing with `width="100000"` is a prompt error, not a 40 GB
    /// allocation that aborts. Default: the default limit.
    pub max_pixels: u64,
}

impl FrameOptions {
    /// The drawing's own viewBox and size (rounded up to whole pixels, at least 1), no
    /// background.
    pub fn for_scene(scene: &Scene) -> Self {
        let px = |x: f64| {
            if x.is_finite() {
                x.ceil().clamp(1.0, u32::MAX as f64) as u32
            } else {
                1
            }
        };
        FrameOptions {
            view_box: scene.view_box,
            size: (px(scene.size.0), px(scene.size.1)),
            background: None,
            max_pixels: crate::input::Limits::default().pixels,
        }
    }

    /// Pixels in one raster frame of this size.
    pub fn pixels(&self) -> u64 {
        self.size.0 as u64 * self.size.1 as u64
    }

    /// Checks that a raster frame of this size is within [`FrameOptions::max_pixels`] (and
    /// not empty): the input error for `file` (the drawing whose size it is) naming
    /// `--max-pixels` otherwise. Called before any pixmap is allocated.
    pub fn check_pixels(&self, file: &str) -> crate::Result<()> {
        check_raster_size(file, self.size, self.max_pixels)
    }

    /// Output pixels per user unit (the finer axis): the scale flattening tolerances refer to.
    pub fn scale(&self) -> f64 {
        let d = self.view_box.1 - self.view_box.0;
        (self.size.0 as f64 / d.x).max(self.size.1 as f64 / d.y)
    }

    /// The flattening tolerance, in user units, for a quarter-pixel error at this output size.
    pub fn flatten_tolerance(&self) -> f64 {
        crate::artwork::flatten_tolerance(self.view_box, (self.size.0 as f64, self.size.1 as f64))
    }
}

/// Checks that a `size.0 × size.1` raster is neither empty nor over `max_pixels` (see
/// [`FrameOptions::check_pixels`]).
pub(crate) fn check_raster_size(
    file: &str,
    size: (u32, u32),
    max_pixels: u64,
) -> crate::Result<()> {
    let (w, h) = size;
    if w == 0 || h == 0 {
        return Err(crate::Error::input(
            file,
            format!("cannot render a {w}×{h} image: the size must be positive"),
        ));
    }
    let limits = crate::input::Limits {
        pixels: max_pixels,
        ..crate::input::Limits::default()
    };
    if w as u64 * h as u64 > max_pixels {
        return Err(crate::input::Limit::Pixels.exceeded(
            file,
            &format!("a frame of {w} × {h} px"),
            &limits,
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
