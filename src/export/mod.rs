//! Exporting a morph as an animation: the shared [`Timeline`] (frame times, easing, playback),
//! and the encoders that turn rendered frames into files users play (the end of DESIGN.md §2:
//! frames → GIF · APNG · HTML preview; the animated SVG writer lives in [`crate::render`]).

pub mod morph;
pub mod timeline;

pub use morph::Morph;
pub use timeline::{Easing, Playback, Timeline};
