//! One tolerance vocabulary, relative to the drawing's size.
//!
//! Every geometric tolerance in crmorph is a fraction of the drawing's size, called its
//! **diagonal**: the diameter of the boundary's defining points about their centroid — exactly the
//! diagonal for a rectangle, and for the viewBox rectangle in image-morph mode. Unlike a
//! bounding-box diagonal it does not change when the drawing rotates, so a drawing and a rotated,
//! scaled copy of it are flattened, triangulated and morphed alike, up to that similarity.
//!
//! | name | fraction of the diagonal | used for |
//! |---|---|---|
//! | [`Tolerances::flatten`] | `1e-3` (× `1/density`) | lyon flattening of curves to polylines |
//! | [`Tolerances::snap`] | `1e-9` | merging coincident points, "lands on its twin" checks |
//! | [`Tolerances::max_edge`] | `1/40` (× `1/density`) | the longest curve edge after correspondence |
//! | [`Tolerances::max_area`] | `(1/40)²` (× `1/density²`) | the largest triangle of the refined triangulation |

/// Smallest diagonal for which tolerances still make sense (a drawing smaller than this is
/// rejected as degenerate).
pub const MIN_DIAGONAL: f64 = 1e-6;
/// Largest coordinate magnitude accepted; beyond this, relative tolerances run out of f64
/// precision.
pub const MAX_COORDINATE: f64 = 1e12;

/// Tolerances derived from a drawing's size and the user's density setting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// The drawing's size (see the module docs), in user units.
    pub diagonal: f64,
    /// Maximum distance between a curve and its flattened polyline.
    pub flatten: f64,
    /// Distance under which two points are the same point.
    pub snap: f64,
    /// Longest edge allowed on a boundary or feature curve after correspondence.
    pub max_edge: f64,
    /// Largest triangle area allowed by Delaunay refinement.
    pub max_area: f64,
    /// The vertex density multiplier these were made for (1 when the one asked for was not a
    /// positive number): a drawing remembers the density it was read with, so that what is
    /// built from it can default to the same.
    pub density: f64,
}

impl Tolerances {
    /// Tolerances for a drawing with bounding-box `diagonal`; `density` (default 1.0) scales the
    /// number of vertices per unit length: 2.0 halves the edge lengths.
    pub fn new(diagonal: f64, density: f64) -> Self {
        let density = if density.is_finite() && density > 0.0 {
            density
        } else {
            1.0
        };
        let max_edge = diagonal / (40.0 * density);
        Tolerances {
            diagonal,
            flatten: diagonal * 1e-3 / density,
            snap: diagonal * 1e-9,
            max_edge,
            max_area: max_edge * max_edge,
            density,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerances_scale_with_the_drawing() {
        let a = Tolerances::new(100.0, 1.0);
        let b = Tolerances::new(100_000.0, 1.0);
        assert!((b.flatten / a.flatten - 1000.0).abs() < 1e-9);
        assert!((b.max_area / a.max_area - 1e6).abs() < 1e-3);
        let dense = Tolerances::new(100.0, 2.0);
        assert!((a.max_edge / dense.max_edge - 2.0).abs() < 1e-12);
        assert_eq!(Tolerances::new(100.0, f64::NAN), a);
    }
}
