//! Both drawings' artwork bound to the compatible meshes: what every frame is made from (the
//! end of §3: source and target shapes transferred to the in-between triangulation, then
//! blended).

use super::{Binding, Scene};
use crate::error::Result;
use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;

/// The source artwork bound to the source mesh and the target artwork to the target mesh, ready
/// to be placed in the mesh of any frame.
#[derive(Debug, Clone)]
pub struct ArtworkPair {
    /// The source drawing's artwork, bound to `meshes.source`.
    pub source: Binding,
    /// The target drawing's artwork, bound to `meshes.target`.
    pub target: Binding,
}

impl ArtworkPair {
    /// Binds both scenes to their meshes, flattening curves at `tolerance` user units (use
    /// [`crate::render::FrameOptions::flatten_tolerance`] for a quarter pixel at the output
    /// size).
    pub fn new(
        source: &Scene,
        target: &Scene,
        meshes: &CompatibleMeshes,
        tolerance: f64,
    ) -> Result<Self> {
        Ok(ArtworkPair {
            source: Binding::with_parts(
                source,
                &meshes.source,
                &meshes.triangles,
                meshes.parts.as_ref(),
                tolerance,
            )
            .map_err(|e| e.in_file(&source.file))?,
            target: Binding::with_parts(
                target,
                &meshes.target,
                &meshes.triangles,
                meshes.parts.as_ref(),
                tolerance,
            )
            .map_err(|e| e.in_file(&target.file))?,
        })
    }

    /// The warped source and target for the frame whose mesh is `vertices` (the interpolator's
    /// output at t), with [`Binding::place`]: the exact input scene on the side whose rest mesh
    /// the frame is (t = 0 for the source, t = 1 for the target).
    pub fn at(&self, vertices: &[Point]) -> Result<(Scene, Scene)> {
        Ok((self.source.place(vertices)?, self.target.place(vertices)?))
    }

    /// Like [`ArtworkPair::at`] but always as warped polylines ([`Binding::warp`]), so that every
    /// frame has the same path structure (for animation keyframes).
    pub fn warped_at(&self, vertices: &[Point]) -> Result<(Scene, Scene)> {
        Ok((self.source.warp(vertices)?, self.target.warp(vertices)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::artwork::bind_tests::grid;

    #[test]
    fn binds_each_side_to_its_own_mesh() {
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30">
          <circle cx="10" cy="10" r="5" fill="#123"/></svg>"##;
        let scene = Scene::from_svg("a.svg", svg, "controls").unwrap();
        let (pts, triangles) = grid(4, 3, 40.0, 30.0);
        let meshes = CompatibleMeshes {
            triangles,
            target: pts.iter().map(|p| *p * 2.0).collect(),
            source: pts,
            curves: Vec::new(),
            parts: None,
        };
        let pair = ArtworkPair::new(&scene, &scene, &meshes, 0.01).unwrap();
        // At the source mesh: the source is exact, the target is shrunk by half.
        let (s, t) = pair.at(&meshes.source).unwrap();
        assert_eq!(s.root, scene.root);
        let bb = kurbo::Shape::bounding_box(&match &t.root.children[0] {
            crate::artwork::Item::Path(p) => p.path.clone(),
            _ => panic!(),
        });
        assert!(
            (bb.x0 - 2.5).abs() < 1e-9 && (bb.x1 - 7.5).abs() < 1e-9,
            "{bb:?}"
        );
        let (ws, _) = pair.warped_at(&meshes.source).unwrap();
        assert_ne!(ws.root, scene.root, "warped_at always gives polylines");
        assert!(pair.at(&meshes.source[1..]).is_err());
    }
}
