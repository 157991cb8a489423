//! Warping bound artwork into the mesh of a frame (the end of §3: the source and target shapes
//! are transferred to the intermediate triangulations, then blended).
//!
//! Points move by their barycentric coordinates; everything that is not a point follows a local
//! affine map of the mesh — the map taking a rest triangle to its frame position:
//! - stroke widths and dashes scale by the median, over the path's points, of `sqrt |det A|`
//!   (the local area scale of the triangle under each point);
//! - gradient geometry follows the full affine map of the triangle under the path's bounding-box
//!   centre;
//! - images are placed by their texture grid (`super::texture`): each grid vertex moves like a
//!   point, and each cell triangle carries its part of the image affinely.

use super::bind::{BoundItem, BoundPath, BoundPathItem};
use super::{Binding, Clip, ClipShape, Gradient, Group, ImageGrid, Item, Paint, PathItem, Scene};
use crate::error::{Error, Result};
use crate::geometry::Point;
use kurbo::{Affine, BezPath};
use std::sync::Arc;

/// Whether the mesh `frame_vertices` is the mesh `rest`: every vertex within `1e-9` of the
/// diagonal of `rest` of its rest position. [`Binding::place`] gives the exact input scene for
/// such a frame (t = 0 for the source, t = 1 for the target).
pub(crate) fn at_rest(frame_vertices: &[Point], rest: &[Point]) -> bool {
    if frame_vertices.len() != rest.len() {
        return false;
    }
    let (lo, hi) =
        crate::geometry::bounding_box(rest.iter().copied()).unwrap_or((Point::ZERO, Point::ZERO));
    let eps = 1e-9 * (hi - lo).length();
    frame_vertices
        .iter()
        .zip(rest)
        .all(|(a, b)| a.distance(*b) <= eps)
}

impl Binding {
    /// The scene placed in the mesh whose vertex positions are `frame_vertices` (same order and
    /// count as the mesh the binding was made on). Paths come out as polylines. Warping with the
    /// rest vertices reproduces the flattened scene.
    pub fn warp(&self, frame_vertices: &[Point]) -> Result<Scene> {
        if frame_vertices.len() != self.rest.len() {
            return Err(Error::internal(format!(
                "frame has {} vertices, the bound mesh {}",
                frame_vertices.len(),
                self.rest.len()
            )));
        }
        let maps = TriangleMaps::new(&self.triangles, &self.rest, frame_vertices);
        let frame = Frame {
            triangles: &self.triangles,
            vertices: frame_vertices,
        };
        let mut next = 0usize;
        let root = self.warp_group(&self.scene.root, &maps, &frame, &mut next)?;
        Ok(Scene {
            root,
            ..self.scene_header()
        })
    }

    /// The scene for a frame whose mesh is `frame_vertices`: the exact input scene (curves
    /// intact, so the frame renders exactly as the input file) when every vertex is within
    /// `1e-9` of the mesh's diagonal of its rest position — frames t = 0 and t = 1 — and
    /// [`Binding::warp`] otherwise. Use [`Binding::warp`] where every frame needs the same path
    /// structure (animation keyframes).
    pub fn place(&self, frame_vertices: &[Point]) -> Result<Scene> {
        if at_rest(frame_vertices, &self.rest) {
            return Ok(self.scene_with_rest_grids());
        }
        self.warp(frame_vertices)
    }

    /// The input scene with every image's texture grid at rest, so that it has the structure
    /// of a warped frame (an animation's first keyframe) while its paths stay exact.
    fn scene_with_rest_grids(&self) -> Scene {
        let mut scene = self.scene.clone();
        let mut grids = self.items.iter().filter_map(|b| match b {
            BoundItem::Image(b) => Some((b.columns, b.rows)),
            _ => None,
        });
        fn walk(g: &mut Group, grids: &mut dyn Iterator<Item = (u32, u32)>) {
            for c in &mut g.children {
                match c {
                    Item::Group(sub) => walk(sub, grids),
                    Item::Image(img) => {
                        if let Some((columns, rows)) = grids.next() {
                            img.grid = Some(ImageGrid {
                                columns,
                                rows,
                                points: ImageGrid::rest_points(img, columns, rows),
                            });
                        }
                    }
                    Item::Path(_) => {}
                }
            }
        }
        walk(&mut scene.root, &mut grids);
        scene
    }

    fn scene_header(&self) -> Scene {
        Scene {
            file: self.scene.file.clone(),
            view_box: self.scene.view_box,
            size: self.scene.size,
            root_transform: self.scene.root_transform,
            root: Group {
                id: String::new(),
                opacity: 1.0,
                clip: None,
                children: Vec::new(),
            },
        }
    }

    fn warp_group(
        &self,
        g: &Group,
        maps: &TriangleMaps,
        frame: &Frame,
        next: &mut usize,
    ) -> Result<Group> {
        let clip = match &g.clip {
            None => None,
            Some(c) => match self.items.get(*next) {
                Some(BoundItem::Clip(bound)) if bound.len() == c.shapes.len() => {
                    *next += 1;
                    let shapes = c
                        .shapes
                        .iter()
                        .zip(bound)
                        .map(|(s, b)| ClipShape {
                            path: polylines(b, frame),
                            even_odd: s.even_odd,
                        })
                        .collect();
                    Some(Clip { shapes })
                }
                _ => return Err(out_of_step()),
            },
        };
        let mut children = Vec::with_capacity(g.children.len());
        for c in &g.children {
            match (c, self.items.get(*next)) {
                (Item::Group(sub), _) => {
                    children.push(Item::Group(self.warp_group(sub, maps, frame, next)?));
                }
                (Item::Path(p), Some(BoundItem::Path(b))) => {
                    *next += 1;
                    children.extend(warp_path(p, b, maps, frame).into_iter().map(Item::Path));
                }
                (Item::Image(img), Some(BoundItem::Image(b))) => {
                    *next += 1;
                    let mut img = img.clone();
                    img.grid = Some(ImageGrid {
                        columns: b.columns,
                        rows: b.rows,
                        points: b
                            .locations
                            .iter()
                            .map(|l| l.place(frame.triangles, frame.vertices))
                            .collect(),
                    });
                    children.push(Item::Image(img));
                }
                _ => return Err(out_of_step()),
            }
        }
        Ok(Group {
            id: g.id.clone(),
            opacity: g.opacity,
            clip,
            children,
        })
    }
}

fn out_of_step() -> Error {
    Error::internal("artwork binding out of step with its scene")
}

/// A bound path's points placed in the frame, as polylines with the original subpaths.
fn polylines(b: &BoundPath, frame: &Frame) -> BezPath {
    let mut path = BezPath::new();
    for s in &b.subpaths {
        let mut pts = b.locations[s.start..s.start + s.len]
            .iter()
            .map(|l| super::to_kurbo(l.place(frame.triangles, frame.vertices)));
        let Some(first) = pts.next() else {
            continue;
        };
        path.move_to(first);
        for q in pts {
            path.line_to(q);
        }
        if s.closed {
            path.close_path();
        }
    }
    path
}

/// The mesh of the frame being warped into.
struct Frame<'a> {
    triangles: &'a [[u32; 3]],
    vertices: &'a [Point],
}

/// The affine map of every triangle from its rest position to the frame.
struct TriangleMaps {
    maps: Vec<Affine>,
}

impl TriangleMaps {
    fn new(triangles: &[[u32; 3]], rest: &[Point], frame: &[Point]) -> Self {
        let maps = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| rest[v as usize]);
                let [a2, b2, c2] = t.map(|v| frame[v as usize]);
                let m0 = Affine::new([b.x - a.x, b.y - a.y, c.x - a.x, c.y - a.y, a.x, a.y]);
                let m1 = Affine::new([
                    b2.x - a2.x,
                    b2.y - a2.y,
                    c2.x - a2.x,
                    c2.y - a2.y,
                    a2.x,
                    a2.y,
                ]);
                if m0.determinant() == 0.0 {
                    // Never used: degenerate triangles are not located into.
                    Affine::IDENTITY
                } else {
                    m1 * m0.inverse()
                }
            })
            .collect();
        TriangleMaps { maps }
    }

    fn affine(&self, triangle: u32) -> Affine {
        self.maps[triangle as usize]
    }

    fn scale(&self, triangle: u32) -> f64 {
        self.maps[triangle as usize].determinant().abs().sqrt()
    }
}

/// A bound path item placed in the frame: one path, or for a cut dashed stroke a fill-only
/// path and a stroke-only path of the dashes, in the item's paint order.
fn warp_path(p: &PathItem, b: &BoundPathItem, maps: &TriangleMaps, frame: &Frame) -> Vec<PathItem> {
    let o = &b.outline;
    let warp_paint = |paint: &Paint| match paint {
        Paint::Color(c) => Paint::Color(*c),
        Paint::Gradient(g) => Paint::Gradient(Arc::new(Gradient {
            transform: maps.affine(o.anchor.triangle) * g.transform,
            ..(**g).clone()
        })),
    };
    let fill = p.fill.as_ref().map(|f| super::Fill {
        paint: warp_paint(&f.paint),
        ..f.clone()
    });
    let stroke = p.stroke.as_ref().map(|s| {
        // A round pen scales by the median local scale under the path; a shaped pen's frame
        // follows the local affine map at the path's anchor.
        let (k, pen) = match s.frame {
            None => (median_scale(o, maps), None),
            Some(f) => (1.0, Some(maps.affine(o.anchor.triangle) * f)),
        };
        let cut = b.dashes.is_some();
        super::Stroke {
            paint: warp_paint(&s.paint),
            width: s.width * k,
            dashes: if cut {
                Vec::new()
            } else {
                s.dashes.iter().map(|d| d * k).collect()
            },
            dash_offset: if cut { 0.0 } else { s.dash_offset * k },
            frame: pen,
            ..s.clone()
        }
    });
    // Barycentric placement is the triangle's affine map applied to the rest point, also for
    // points outside the mesh (their weights extend the map).
    let outline = polylines(o, frame);
    let Some(dashes) = &b.dashes else {
        return vec![PathItem {
            id: p.id.clone(),
            path: outline,
            fill,
            stroke,
            stroke_first: p.stroke_first,
        }];
    };
    let mut out = Vec::with_capacity(2);
    if fill.is_some() {
        out.push(PathItem {
            id: p.id.clone(),
            path: outline,
            fill,
            stroke: None,
            stroke_first: false,
        });
    }
    let dashed = PathItem {
        id: p.id.clone(),
        path: polylines(dashes, frame),
        fill: None,
        stroke,
        stroke_first: false,
    };
    if p.stroke_first {
        out.insert(0, dashed);
    } else {
        out.push(dashed);
    }
    out
}

/// The median local scale under a path's points (1 for a path without points).
fn median_scale(b: &BoundPath, maps: &TriangleMaps) -> f64 {
    let mut s: Vec<f64> = b.locations.iter().map(|l| maps.scale(l.triangle)).collect();
    if s.is_empty() {
        return maps.scale(b.anchor.triangle);
    }
    let mid = s.len() / 2;
    let (_, m, _) = s.select_nth_unstable_by(mid, f64::total_cmp);
    *m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::artwork::bind_tests::grid;

    const ART: &str = r##"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30">
      <circle cx="20" cy="15" r="9" fill="#abc" stroke="#123" stroke-width="2"/>
      <path d="M-3 2 C 10 -5 30 40 43 28" fill="none" stroke="red" stroke-dasharray="2 1"/>
    </svg>"##;

    fn bound() -> (Binding, Vec<Point>) {
        let scene = Scene::from_svg("w.svg", ART, "controls").unwrap();
        let (pts, tris) = grid(4, 3, 40.0, 30.0);
        (Binding::new(&scene, &pts, &tris, 0.01).unwrap(), pts)
    }

    #[test]
    fn warping_with_the_rest_mesh_is_the_identity() {
        let (b, rest) = bound();
        let w = b.warp(&rest).unwrap();
        let (wi, si) = (w.items(), b.scene().items());
        assert_eq!(wi.len(), si.len());
        for (a, s) in wi.iter().zip(&si) {
            let (Item::Path(a), Item::Path(s)) = (a, s) else {
                panic!("paths only")
            };
            if s.stroke.as_ref().is_some_and(|s| !s.dashes.is_empty()) {
                continue; // cut into dashes: see the dash test
            }
            // Every warped point is a flattened point of the exact curve, within tolerance.
            let mut flat = Vec::new();
            kurbo::flatten(&s.path, 0.01, |el| {
                if let Some(p) = el.end_point() {
                    flat.push(p)
                }
            });
            let pts: Vec<kurbo::Point> = a
                .path
                .elements()
                .iter()
                .filter_map(|e| e.end_point())
                .collect();
            assert_eq!(pts.len(), flat.len());
            for (p, q) in pts.iter().zip(&flat) {
                assert!(p.distance(*q) < 1e-9);
            }
            let (sa, ss) = (a.stroke.as_ref().unwrap(), s.stroke.as_ref().unwrap());
            assert!((sa.width - ss.width).abs() < 1e-12);
            assert_eq!(a.fill, s.fill);
        }
        // place() hands back the exact scene at rest, polylines elsewhere.
        let exact = b.place(&rest).unwrap();
        assert_eq!(exact.root, b.scene().root);
        let moved: Vec<Point> = rest.iter().map(|p| *p * 1.5).collect();
        assert_ne!(b.place(&moved).unwrap().root, b.scene().root);
    }

    #[test]
    fn wrong_vertex_count_is_an_error() {
        let (b, rest) = bound();
        assert!(b.warp(&rest[1..]).is_err());
        assert!(b.place(&rest[1..]).is_err());
    }

    #[test]
    fn dashes_are_cut_on_the_exact_curve_and_carried() {
        let (b, rest) = bound();
        let w = b.warp(&rest).unwrap();
        // The dashed path became a stroke-only path of dashes with no dash array.
        let Item::Path(p) = &w.root.children[1] else {
            panic!("{}", w.root.children.len())
        };
        assert!(p.fill.is_none());
        let s = p.stroke.as_ref().unwrap();
        assert!(s.dashes.is_empty());
        let subpaths = crate::artwork::subpath_count(&p.path);
        // Each dash is 2 long on a period of 3: the curve's length / 3, give or take one.
        let Item::Path(orig) = &b.scene().root.children[1] else {
            panic!()
        };
        let len: f64 = orig
            .path
            .segments()
            .map(|s| kurbo::ParamCurveArclen::arclen(&s, 1e-6))
            .sum();
        assert!(
            (subpaths as f64 - len / 3.0).abs() <= 1.0,
            "{subpaths} {len}"
        );
        // Scaling the mesh scales the dashes with it (they do not slide or re-cut).
        let big: Vec<Point> = rest.iter().map(|p| *p * 2.0).collect();
        let wb = b.warp(&big).unwrap();
        let Item::Path(pb) = &wb.root.children[1] else {
            panic!()
        };
        assert_eq!(pb.path.elements().len(), p.path.elements().len());
        assert!((pb.stroke.as_ref().unwrap().width - 2.0).abs() < 1e-9);
    }
}
