//! # crmorph — controllable rigid morphing of SVG drawings
//!
//! crmorph implements CR-Morph (`shared/paper/cr-morph.txt`): it morphs one SVG drawing into
//! another rigidly, with interior features kept aligned, with motion that a skeleton can steer.
//!
//! ## The pipeline
//!
//! ```text
//! SVG ─usvg/quick-xml─▶ Drawing { artwork, controls }                      drawing
//! controls ─lyon flatten─▶ polylines ─correspondence─▶ curve pairs (§3)   correspondence
//! curve pairs ─spade CDT of the source─▶ source mesh                       triangulation
//!   ─composite harmonic mapping through BSM intermediates (§5)─▶ target    mapping
//! meshes ─disc-based rigid interpolation (§4.1, eq.1)─▶ vertices at any t  rigid
//! ```
//!
//! 1. [`drawing`] reads a file: the control geometry found by id (boundary, `feature-NAME`,
//!    `anchor-NAME`, skeleton), flattened at a tolerance relative to the drawing's size
//!    ([`tolerance`]).
//! 2. [`correspondence`] gives each source curve and its target twin the same number of
//!    corresponding vertices, aligning salient points.
//! 3. [`triangulation`] builds a constrained Delaunay triangulation of the source with every curve
//!    as a constraint, refined for quality without splitting the curves.
//! 4. [`mapping`] carries it to the target through a sequence of intermediate curves from the
//!    barycenter-based shape model, one harmonic map per step, with no triangle flipped.
//! 5. [`rigid`] interpolates the two meshes: local disc-to-disc rotations and scales, made
//!    globally consistent, assembled by one factored least-squares solve per frame.
//!
//! [`compatible`] runs stages 1–4 for a pair of drawings; [`mesh`] holds the result and its
//! [`mesh::sanity_check`]; [`quality`] measures frames.
//!
//! ## Morphing two SVGs
//!
//! [`Morpher`] is the front door: two drawings and every choice about their morph, built into
//! an [`export::Morph`] that writes every output (animated SVG, frames, GIF, APNG, HTML, JSON,
//! Lottie). Two plain SVG strings, no markup, into an animated SVG:
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
//! assert!(svg.starts_with("<svg") && svg.contains("<animate"));
//! # Ok::<(), crmorph::Error>(())
//! ```
//!
//! A frame at t, whatever it is written as, is [`frame::Frame`] ([`export::Morph::frame_at`]);
//! input errors name the file, the element and the problem, with a [`ProblemKind`].

pub mod artwork;
pub mod auto;
pub mod base64;
pub mod budget;
pub mod color;
pub mod compatible;
pub mod correspondence;
pub mod drawing;
pub mod error;
pub mod export;
pub mod frame;
pub mod geometry;
mod grid;
pub mod input;
pub mod inspect;
pub mod json;
pub mod mapping;
pub mod mesh;
pub mod morpher;
pub mod morphing;
mod number;
mod parallel;
pub mod quality;
pub mod render;
pub mod rigid;
pub mod skeleton;
pub mod tolerance;
pub mod triangulation;

pub use error::{Drawings, Error, InputError, ProblemKind, Result};
pub use geometry::Point;
pub use mesh::{CompatibleMeshes, CurveKind, MeshCurve, Side};
pub use morpher::Morpher;
