//! The shape pairs' compatible meshes made into one pair of meshes with [`Parts`]: every
//! shape's mesh with its vertices renumbered, then the still frame — a rectangle around both
//! drawings, the same in both meshes — that artwork outside every shape is bound to, so that
//! it stays where it is.

use super::part::PartMesh;
use crate::correspondence::CurvePair;
use crate::geometry::Point;
use crate::mesh::{CompatibleMeshes, CurveKind, MeshCurve, Parts};

/// Where each shape pair went in the union.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Placed {
    /// First curve of each part.
    pub(crate) curve_offset: Vec<usize>,
}

/// Joins `parts` and a still frame spanning `frame` (min and max corners) into one pair of
/// meshes, with the curve pairs of every mesh curve (ids prefixed `part-K/`).
pub(crate) fn union(
    parts: &[PartMesh],
    frame: (Point, Point),
) -> (CompatibleMeshes, Vec<CurvePair>, Placed) {
    let mut m = CompatibleMeshes::default();
    let mut pairs = Vec::new();
    let mut of_triangle = Vec::new();
    let mut chains = Vec::new();
    let mut placed = Placed {
        curve_offset: Vec::new(),
    };
    for (k, p) in parts.iter().enumerate() {
        let o = m.source.len() as u32;
        placed.curve_offset.push(m.curves.len());
        m.source.extend_from_slice(&p.meshes.source);
        m.target.extend_from_slice(&p.meshes.target);
        for t in &p.meshes.triangles {
            m.triangles.push(t.map(|v| v + o));
            of_triangle.push(k as u32);
        }
        for (c, pair) in p.meshes.curves.iter().zip(&p.pairs) {
            if p.meshes.triangles.is_empty() {
                chains.push(m.curves.len());
            }
            m.curves.push(MeshCurve {
                name: format!("part-{k}/{}", c.name),
                kind: c.kind,
                closed: c.closed,
                vertices: c.vertices.iter().map(|v| v + o).collect(),
            });
            pairs.push(CurvePair {
                id: format!("part-{k}/{}", pair.id),
                ..pair.clone()
            });
        }
    }
    // The still frame, last, so that shapes win where both contain a point.
    let (lo, hi) = frame;
    let o = m.source.len() as u32;
    let corners = [lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)];
    m.source.extend_from_slice(&corners);
    m.target.extend_from_slice(&corners);
    let still = parts.len() as u32;
    // Counter-clockwise in y-down user space is what `orient2d > 0` means here: pick the
    // winding that makes both triangles positive.
    let (a, b, c, d) = (o, o + 1, o + 2, o + 3);
    let tris = if crate::geometry::orient2d(corners[0], corners[1], corners[2]) > 0.0 {
        [[a, b, c], [a, c, d]]
    } else {
        [[a, c, b], [a, d, c]]
    };
    for t in tris {
        m.triangles.push(t);
        of_triangle.push(still);
    }
    m.curves.push(MeshCurve {
        name: "still-frame".into(),
        kind: CurveKind::Boundary,
        closed: true,
        vertices: vec![a, b, c, d],
    });
    pairs.push(CurvePair {
        id: "still-frame".into(),
        kind: CurveKind::Boundary,
        closed: true,
        source: corners.to_vec(),
        target: corners.to_vec(),
        salient: vec![0],
    });
    m.parts = Some(Parts {
        of_triangle,
        count: still + 1,
        still: Some(still),
        chains,
        repair: parts
            .iter()
            .enumerate()
            .filter(|(_, p)| p.repair)
            .map(|(k, _)| k as u32)
            .collect(),
    });
    (m, pairs, placed)
}
