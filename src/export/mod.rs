//! Exporting a morph as an animation: the shared [`Timeline`] (frame times, easing, playback),
//! [`Morph`] (built once, any frame or animation after), and the encoders that turn rendered
//! frames into files users play (the end of DESIGN.md §2: frames → GIF · APNG · HTML preview;
//! the animated SVG writer lives in [`crate::render`]).

pub mod apng;
pub mod gif;
pub mod html;
pub mod lottie;
pub mod morph;

pub use apng::encode_apng;
pub use gif::{encode_gif, gif_fidelity, Fidelity};
pub use html::{preview_html, PreviewMesh};
pub use lottie::Lottie;
pub use morph::{Export, Morph, Motion};
// The timeline is part of what a frame is (its time), so it lives below the exporters, in
// `render`; it is re-exported here, where exporters' users look for it.
pub use crate::render::timeline;
pub use crate::render::timeline::{Easing, Playback, Timeline};
