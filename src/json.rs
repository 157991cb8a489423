//! The JSON documents of DESIGN.md §3, for tooling and tests: the compatible meshes
//! (`inspect -o m.json`) and one frame (`frame -o f.json`).
//!
//! Output is deterministic: the same input gives the same bytes (`serde_json` writes each f64 as
//! its shortest round-trip decimal).

use serde::Serialize;

use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;

#[derive(Serialize)]
struct Curve<'a> {
    name: &'a str,
    closed: bool,
    vertices: &'a [u32],
}

fn xy(points: &[Point]) -> Vec<[f64; 2]> {
    points.iter().map(|p| [p.x, p.y]).collect()
}

fn curves(m: &CompatibleMeshes) -> Vec<Curve<'_>> {
    m.curves
        .iter()
        .map(|c| Curve {
            name: &c.name,
            closed: c.closed,
            vertices: &c.vertices,
        })
        .collect()
}

#[derive(Serialize)]
struct Meshes<'a> {
    triangles: &'a [[u32; 3]],
    source: Vec<[f64; 2]>,
    target: Vec<[f64; 2]>,
    curves: Vec<Curve<'a>>,
}

#[derive(Serialize)]
struct Frame<'a> {
    triangles: &'a [[u32; 3]],
    t: f64,
    vertices: Vec<[f64; 2]>,
    curves: Vec<Curve<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    skeleton: Option<SkeletonDoc<'a>>,
}

#[derive(Serialize)]
struct SkeletonDoc<'a> {
    joints: Vec<[f64; 2]>,
    bones: &'a [[u32; 2]],
}

/// The compatible meshes as JSON: shared `triangles`, `source` and `target` vertices in the
/// same order, and the `curves` as vertex chains.
pub fn meshes_json(m: &CompatibleMeshes) -> String {
    let doc = Meshes {
        triangles: &m.triangles,
        source: xy(&m.source),
        target: xy(&m.target),
        curves: curves(m),
    };
    serde_json::to_string(&doc).expect("plain data serializes")
}

/// One frame as JSON: the mesh at `t` (`vertices`), with the shared `triangles` and `curves`.
pub fn frame_json(m: &CompatibleMeshes, t: f64, vertices: &[Point]) -> String {
    frame_json_with_skeleton(m, t, vertices, None)
}

/// [`frame_json`] with the frame's `skeleton`: its `bones` and the `joints` where the frame's
/// mesh carries the reference joints (§4.2; DESIGN.md §3).
pub fn frame_json_with_skeleton(
    m: &CompatibleMeshes,
    t: f64,
    vertices: &[Point],
    skeleton: Option<(&[[u32; 2]], &[Point])>,
) -> String {
    let doc = Frame {
        triangles: &m.triangles,
        t,
        vertices: xy(vertices),
        curves: curves(m),
        skeleton: skeleton.map(|(bones, joints)| SkeletonDoc {
            joints: xy(joints),
            bones,
        }),
    };
    serde_json::to_string(&doc).expect("plain data serializes")
}

/// Every frame of a sequence as JSON: `{"frames": [frame, …]}`, each frame as in
/// [`frame_json`], `frames[k]` being the mesh at `ts[k]`.
pub fn frames_json(m: &CompatibleMeshes, ts: &[f64], frames: &[Vec<Point>]) -> String {
    let docs: Vec<String> = ts
        .iter()
        .zip(frames)
        .map(|(t, v)| frame_json(m, *t, v))
        .collect();
    format!("{{\"frames\":[{}]}}", docs.join(","))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{CurveKind, MeshCurve};

    #[test]
    fn documents_have_the_design_fields() {
        let m = CompatibleMeshes {
            triangles: vec![[0, 1, 2]],
            source: vec![Point::new(0., 0.), Point::new(1., 0.), Point::new(0., 1.)],
            target: vec![Point::new(0., 0.), Point::new(2., 0.), Point::new(0., 2.)],
            curves: vec![MeshCurve {
                name: "boundary".into(),
                kind: CurveKind::Boundary,
                closed: true,
                vertices: vec![0, 1, 2],
            }],
            parts: None,
        };
        let v: serde_json::Value = serde_json::from_str(&meshes_json(&m)).unwrap();
        assert_eq!(v["triangles"][0], serde_json::json!([0, 1, 2]));
        assert_eq!(v["target"][1], serde_json::json!([2.0, 0.0]));
        assert_eq!(v["curves"][0]["name"], "boundary");
        assert_eq!(v["curves"][0]["closed"], true);
        let f: serde_json::Value = serde_json::from_str(&frame_json(&m, 0.5, &m.source)).unwrap();
        assert_eq!(f["t"], 0.5);
        assert_eq!(f["vertices"].as_array().unwrap().len(), 3);
        assert_eq!(meshes_json(&m), meshes_json(&m.clone()));
    }
}
