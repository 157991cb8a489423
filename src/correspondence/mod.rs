//! Vertex correspondence between a source curve and its target twin (§3, after [15]).
//!
//! Salient points (curvature extrema at a scale) are detected on both curves and associated by an
//! order-preserving dynamic-programming match (cyclic for closed curves); anchors override the
//! association. Between consecutive associated salient points, vertices are distributed by
//! normalized arc length so that both curves get the same vertex count, every original flattened
//! vertex of each curve is kept (so no shape detail is lost), and no edge is longer than the
//! density allows.

use crate::geometry::Point;
use crate::mesh::CurveKind;

/// A source curve and its target twin with equal vertex counts: `source[i]` corresponds to
/// `target[i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvePair {
    /// The element id (`boundary`, `feature-eye`, …), as in the source file.
    pub id: String,
    /// Boundary or feature.
    pub kind: CurveKind,
    /// Whether the curve is closed (last vertex connects to the first, not repeated).
    pub closed: bool,
    /// Source vertices (closed curves counter-clockwise).
    pub source: Vec<Point>,
    /// Target vertices, same count, corresponding one to one.
    pub target: Vec<Point>,
    /// Indices (into both vertex lists) of the associated salient points and anchors.
    pub salient: Vec<usize>,
}
