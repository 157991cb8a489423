//! Skeleton control of the motion dynamics (§4.2): a reference skeleton on the source, control
//! poses edited at any in-between frame, and the two-phase propagation that makes the whole
//! sequence meet them.
//!
//! - [`Skeleton`]: joints and bones from the source's `skeleton` / `skeleton-NAME` polylines
//!   (DESIGN.md §1), joined into trees; it may cover only part of the shape (Fig.14(a)).
//! - Derived skeletons: every joint's barycentric coordinates in the source mesh carry it
//!   through every in-between mesh ([`SkeletonControl::derived`]).
//! - Phase 1 ([`PoseTrack`], §4.2.1): the desired skeleton through time, interpolated in
//!   intrinsic parameters through the keys.
//! - Phase 2 ([`SkeletonControl`], §4.2.2): bone transformations spread over the discs of the
//!   vertices bound to each bone, then eq. (2) with the joints as positional constraints.
//! - [`pose_svg`]: a frame with its derived skeleton drawn on it, for a user to edit into a
//!   control pose.

mod binding;
mod control;
mod kinematics;
mod pose_file;
mod reference;

pub use control::{ControlWorkspace, Pose, SkeletonControl};
pub use kinematics::PoseTrack;
pub use pose_file::pose_svg;
pub use reference::Skeleton;
