//! Constrained Delaunay triangulation of the source shape (§5) with spade.
//!
//! The paper triangulates the source with Triangle \[37\], taking the boundary and every interior
//! feature curve as constraints. Here: the curves are validated first ([`triangulate`] refuses
//! self-intersecting or crossing curves with an error naming them), then spade builds the CDT,
//! Delaunay refinement improves its angles without ever splitting a curve edge (so every curve
//! vertex corresponds one to one with its target twin), and the faces inside the boundary are
//! kept — including those inside closed feature curves.

mod cdt;
pub(crate) mod validate;

use crate::correspondence::CurvePair;
use crate::error::ProblemKind;
use crate::geometry::{point_in_polygon, polygon_area, Point};
use crate::mesh::{CurveKind, MeshCurve, Side};
use crate::tolerance::Tolerances;
use crate::{Error, Result};

/// A triangulation of one side (source or target) of a set of curve pairs.
///
/// Curve vertices come first, curve after curve in the order of the [`CurvePair`]s, so
/// `curves[c].vertices[k]` is vertex `k` of curve pair `c`; the Steiner points added by refinement
/// follow.
#[derive(Debug, Clone, PartialEq)]
pub struct Triangulation {
    /// Vertex positions (in the drawing that was triangulated).
    pub points: Vec<Point>,
    /// Triangles, counter-clockwise (positive [`crate::geometry::orient2d`]).
    pub triangles: Vec<[u32; 3]>,
    /// The boundary and feature curves as vertex chains, in the order of the curve pairs.
    pub curves: Vec<MeshCurve>,
    /// The side that was triangulated (`--from target`, §6.1 / Fig.12).
    pub triangulated: Side,
}

/// Minimum angle that Delaunay refinement aims for, in degrees (Triangle's `-q` quality switch
/// in the paper's pipeline; spade refines to this where constraint angles allow).
pub const MIN_ANGLE_DEG: f64 = 25.0;

/// Triangulates side `triangulated` of `pairs` (the paper: the source): validates the
/// curves, builds the constrained Delaunay triangulation with every curve edge as a constraint,
/// refines it to [`MIN_ANGLE_DEG`] and [`Tolerances::max_area`] without splitting constraints,
/// and keeps the faces inside the boundary.
///
/// Errors name the offending curve: a boundary that is not simple or not counter-clockwise, a
/// feature outside the boundary, curves that cross or touch each other or themselves, or vertices
/// closer than [`Tolerances::snap`].
pub fn triangulate(
    pairs: &[CurvePair],
    tol: &Tolerances,
    triangulated: Side,
) -> Result<Triangulation> {
    let file = triangulated.drawing();
    let side = |p| side_of(p, triangulated);
    validate_curves(pairs, tol, triangulated)?;
    let curves: Vec<(&[Point], bool)> = pairs.iter().map(|p| (side(p), p.closed)).collect();
    let twins: Vec<Point> = pairs
        .iter()
        .flat_map(|p| side_of(p, triangulated.other()).iter().copied())
        .collect();
    let (points, triangles) = cdt::build(&curves, &twins, tol).map_err(|e| match e {
        cdt::CdtError::Crossing(c) => Error::at(
            file,
            pairs[c].id.clone(),
            "crosses another curve (constraint edge could not be added)",
        )
        .of_kind(ProblemKind::Crossing),
        cdt::CdtError::Other(msg) => Error::internal(msg),
        cdt::CdtError::Coordinate(c) => {
            Error::at(file, pairs[c].id.clone(), "has a coordinate out of range")
        }
    })?;
    let mut next = 0u32;
    let mesh_curves = pairs
        .iter()
        .map(|p| {
            let n = side(p).len() as u32;
            let c = MeshCurve {
                name: p.id.clone(),
                kind: p.kind,
                closed: p.closed,
                vertices: (next..next + n).collect(),
            };
            next += n;
            c
        })
        .collect();
    Ok(Triangulation {
        points,
        triangles,
        curves: mesh_curves,
        triangulated,
    })
}

/// Checks the curves of one side: one closed, simple, counter-clockwise boundary first; features
/// inside it; no crossings, touchings or coincident vertices.
pub(crate) fn validate_curves(pairs: &[CurvePair], tol: &Tolerances, checked: Side) -> Result<()> {
    let file = checked.drawing();
    let side = |p| side_of(p, checked);
    let Some(boundary) = pairs.first().filter(|p| p.kind == CurveKind::Boundary) else {
        return Err(Error::input(file, "no boundary curve"));
    };
    if let Some(p) = pairs[1..].iter().find(|p| p.kind == CurveKind::Boundary) {
        return Err(Error::at(file, p.id.clone(), "a second boundary curve"));
    }
    for p in pairs {
        let pts = side(p);
        if p.source.len() != p.target.len() {
            return Err(Error::internal(format!(
                "curve pair '{}' has unequal vertex counts",
                p.id
            )));
        }
        if pts.iter().any(|q| !q.is_finite()) {
            return Err(Error::at(file, p.id.clone(), "has a non-finite coordinate"));
        }
        if pts.len() < if p.closed { 3 } else { 2 } {
            return Err(Error::at(file, p.id.clone(), "has too few vertices"));
        }
    }
    let bpts = side(boundary);
    if !boundary.closed || polygon_area(bpts) <= 0.0 {
        return Err(Error::at(
            file,
            boundary.id.clone(),
            "is not a closed counter-clockwise polygon",
        ));
    }
    let curves: Vec<(&[Point], bool)> = pairs.iter().map(|p| (side(p), p.closed)).collect();
    if let Some(((c1, k1), (c2, k2))) = validate::first_coincidence(&curves, tol.snap) {
        let what = if c1 == c2 {
            format!("vertices {k1} and {k2} coincide")
        } else {
            format!(
                "vertex {k1} coincides with vertex {k2} of '{}'",
                pairs[c2].id
            )
        };
        return Err(Error::at(file, pairs[c1].id.clone(), what));
    }
    if let Some(((c1, k1), (c2, _))) = validate::first_crossing(&curves) {
        let (a, b) = (&pairs[c1], &pairs[c2]);
        let err = if c1 == c2 {
            Error::at(
                file,
                a.id.clone(),
                format!("intersects itself (at edge {k1})"),
            )
        } else if a.kind == CurveKind::Boundary {
            Error::at(file, b.id.clone(), "crosses the boundary")
                .concerning([a.id.clone()])
                .of_kind(ProblemKind::Crossing)
        } else {
            Error::at(file, b.id.clone(), format!("crosses {}", a.id))
                .concerning([a.id.clone()])
                .of_kind(ProblemKind::Crossing)
        };
        return Err(err);
    }
    if let Some(p) = pairs[1..]
        .iter()
        .find(|p| !point_in_polygon(side(p)[0], bpts))
    {
        return Err(Error::at(file, p.id.clone(), "lies outside the boundary"));
    }
    Ok(())
}

/// The vertices of one side of a curve pair.
pub(crate) fn side_of(p: &CurvePair, side: Side) -> &[Point] {
    match side {
        Side::Source => &p.source,
        Side::Target => &p.target,
    }
}

#[cfg(test)]
pub(crate) mod tests;
