//! Reading a drawing: the artwork and the control geometry of one SVG file (DESIGN.md §1).
//!
//! usvg parses and normalizes the SVG (transforms resolved, shapes turned into paths) for the
//! artwork; quick-xml reads the raw ids and the `controls` guide group that usvg drops, so that
//! control curves are found by id wherever they are. Curves are flattened with lyon at a tolerance
//! relative to the drawing's size ([`crate::tolerance`]).

use crate::geometry::Point;
use crate::mesh::CurveKind;

/// A boundary or feature curve read from a drawing, flattened to a polyline in the root's user
/// space.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlCurve {
    /// The element id as written in the file (`boundary`, `feature-eye`, …).
    pub id: String,
    /// The matching key: `boundary` for the boundary, `NAME` for `feature-NAME`.
    pub name: String,
    /// Boundary or feature.
    pub kind: CurveKind,
    /// Whether the curve is closed (its last point connects back to the first; the first point is
    /// not repeated at the end).
    pub closed: bool,
    /// Flattened points, consecutive duplicates removed.
    pub points: Vec<Point>,
}

/// A pinned correspondence point (`anchor-NAME`).
#[derive(Debug, Clone, PartialEq)]
pub struct Anchor {
    /// The element id as written in the file.
    pub id: String,
    /// The matching key `NAME`.
    pub name: String,
    /// Position in the root's user space.
    pub point: Point,
}

/// A skeleton polyline (`skeleton` or `skeleton-NAME`): its vertices are joints, its segments
/// bones (§4.2).
#[derive(Debug, Clone, PartialEq)]
pub struct SkeletonChain {
    /// The element id as written in the file.
    pub id: String,
    /// Joint positions in the root's user space.
    pub points: Vec<Point>,
}

/// The control geometry of one drawing: what steers the morph.
#[derive(Debug, Clone, PartialEq)]
pub struct Controls {
    /// The outline of the shape: `boundary`, or the viewBox rectangle in image-morph mode.
    pub boundary: ControlCurve,
    /// Whether the boundary is the viewBox rectangle because the file has no `boundary` element.
    pub boundary_from_view_box: bool,
    /// Feature curves, sorted by name.
    pub features: Vec<ControlCurve>,
    /// Anchors, sorted by name.
    pub anchors: Vec<Anchor>,
    /// Skeleton chains in document order.
    pub skeleton: Vec<SkeletonChain>,
}

/// Id conventions for control geometry (renamed by `--boundary-id`, `--feature-prefix`,
/// `--skeleton-id`).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub struct ControlIds {
    /// Id of the boundary element. Default: `boundary`.
    pub boundary: String,
    /// Prefix of feature curve ids. Default: `feature-`.
    pub feature_prefix: String,
    /// Prefix of anchor ids. Default: `anchor-`.
    pub anchor_prefix: String,
    /// Id (and, followed by `-`, prefix) of skeleton elements. Default: `skeleton`.
    pub skeleton: String,
    /// Id of the group whose children are guides (never rendered). Default: `controls`.
    pub guides_group: String,
}

impl Default for ControlIds {
    fn default() -> Self {
        ControlIds {
            boundary: "boundary".into(),
            feature_prefix: "feature-".into(),
            anchor_prefix: "anchor-".into(),
            skeleton: "skeleton".into(),
            guides_group: "controls".into(),
        }
    }
}
