//! Composite harmonic mapping of the source triangulation onto the target (§5).
//!
//! A single harmonic (barycentric) map from the source curves to the target curves may fold
//! triangles when the shapes differ a lot (Fig.8). Following the composite barycentric mapping
//! of \[41\], the triangulation is carried through a sequence of intermediate curves that are close
//! to each other, one harmonic map per step ([`harmonic`]); the intermediate curves come from the
//! barycenter-based shape model ([`shape_model`], Fig.9), and the steps are refined adaptively
//! until none flips a triangle ([`composite`], Fig.10).

mod carried;
pub mod composite;
pub mod harmonic;
pub mod overlay;
mod relax;
mod remesh;
pub mod samples;
pub mod shape_model;
mod untangle;

pub(crate) use carried::Attachments;
pub(crate) use composite::{check_curves, composite_map_reusing, CurveCheck};
pub use composite::{composite_map, Intermediates, MappingOptions, MappingStats};
pub use harmonic::Harmonic;
pub(crate) use relax::relax_towards;
pub use shape_model::ShapeModel;
