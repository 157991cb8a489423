//! Automatic mode's morphing paths ([`crate::morphing`]): from the matched shapes of two plain
//! drawings, one morphing path per pair of (source path, target path) with paired shapes, with
//! its aligned and carried holes and the shapes without a partner that ride in it.

use super::contours::{Contour, ContourKind};
use super::Matched;
use crate::artwork::{PointLocator, Scene};
use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;
use crate::morphing::{
    in_paint_order, paints_interpolate, paired_rings, plain_paths, same_paint, MorphingPath, Place,
    Rider, Ring,
};
use std::collections::BTreeMap;

/// One morphing path being gathered: the parts of one source path and one target path.
#[derive(Default)]
struct Gathered {
    curves: Vec<usize>,
    curve_holes: Vec<bool>,
    rings: Vec<Ring>,
    riders: Vec<Rider>,
    covers: (Vec<usize>, Vec<usize>),
    /// The parts drawn (indices into `Matched::plans`).
    parts: Vec<usize>,
}

impl Gathered {
    /// Whether this path draws only shapes without a partner (no paired part).
    fn alone(&self) -> bool {
        self.parts.is_empty()
    }
}

/// The morphing paths of automatic mode: one per pair (source path, target path) that has
/// paired shapes, with its holes, carried holes and the shapes without a partner that ride in
/// it (module docs).
pub(crate) fn morphing_paths(
    source_scene: &Scene,
    target_scene: &Scene,
    cs: &[Contour],
    ct: &[Contour],
    matched: &Matched,
    meshes: &CompatibleMeshes,
) -> Vec<MorphingPath> {
    let (ps, pt) = (plain_paths(source_scene), plain_paths(target_scene));
    let of_triangle = meshes
        .parts
        .as_ref()
        .map(|p| p.of_triangle.as_slice())
        .unwrap_or(&[]);
    // A locator over one part's triangles, on one side.
    let locate = |k: usize, source: bool, pts: &[Point]| -> Option<Place> {
        let m = &matched.parts[k].meshes;
        if m.triangles.is_empty() {
            return None;
        }
        let rest = if source {
            &meshes.source
        } else {
            &meshes.target
        };
        let l = PointLocator::of_triangles(rest, &meshes.triangles, |i| {
            of_triangle.get(i) == Some(&(k as u32))
        })
        .ok()?;
        Some(Place::Mesh(pts.iter().map(|&p| l.locate(p)).collect()))
    };
    // A rider on part k's outline, on one side.
    let rider_of = |k: usize, source: bool| -> Rider {
        let c = &meshes.curves[matched.curve_offset[k]];
        Rider::new(
            &c.vertices,
            if source {
                &meshes.source
            } else {
                &meshes.target
            },
        )
    };
    let mut groups: BTreeMap<(Option<usize>, Option<usize>), Gathered> = BTreeMap::new();
    for (k, plan) in matched.plans.iter().enumerate() {
        let (i, j) = (cs[plan.source].path, ct[plan.target].path);
        let (Some(Some(a)), Some(Some(b))) = (ps.get(i), pt.get(j)) else {
            continue;
        };
        if !paints_interpolate(a, b) {
            continue;
        }
        let part = &matched.parts[k];
        let g = groups.entry((Some(i), Some(j))).or_default();
        g.parts.push(k);
        let first = matched.curve_offset[k];
        g.curves.push(first);
        g.curve_holes.push(false);
        for &(_, c) in &part.features {
            g.curves.push(first + c);
            g.curve_holes.push(true);
        }
        // Places for rings of this part: its mesh, else a rider on its outline.
        let place = |g: &mut Gathered, source: bool, pts: &[Point]| -> Place {
            locate(k, source, pts).unwrap_or_else(|| {
                g.riders.push(rider_of(k, source));
                Place::Rider(g.riders.len() - 1, pts.to_vec())
            })
        };
        for &(h, hh) in &plan.holes {
            if part.features.iter().any(|f| f.0 == (h, hh)) {
                continue;
            }
            let (ra, rb) = paired_rings(&cs[h].points, &ct[hh].points);
            let source = place(g, true, &ra);
            let target = place(g, false, &rb);
            g.rings.push(Ring::Blended { source, target });
        }
        for (contours, outline, source) in [(cs, plan.source, true), (ct, plan.target, false)] {
            for (h, c) in contours.iter().enumerate() {
                let paired = plan
                    .holes
                    .iter()
                    .any(|p| if source { p.0 == h } else { p.1 == h });
                if c.parent != Some(outline) || paired {
                    continue;
                }
                let ring = place(g, source, &c.points);
                g.rings.push(Ring::Sized {
                    ring,
                    centre: None,
                    closing: source,
                    hole: true,
                    closed: true,
                });
            }
        }
    }
    // Shapes without a partner: into their own path's morphing path, else into the host's
    // when the paint is the same.
    for lone in &matched.lone {
        let contours = if lone.source { cs } else { ct };
        let item = contours[lone.contour].path;
        let own = groups
            .keys()
            .copied()
            .filter(|&(i, j)| {
                if lone.source {
                    i == Some(item)
                } else {
                    j == Some(item)
                }
            })
            .min_by_key(|key| {
                // Prefer the group holding the host part.
                let holds = lone
                    .host
                    .is_some_and(|(k, _)| groups[key].parts.contains(&k));
                !holds
            });
        let paths = if lone.source { &ps } else { &pt };
        let Some(Some(mine)) = paths.get(item) else {
            continue;
        };
        let host_key = lone.host.and_then(|(k, _)| {
            let key = *groups.keys().find(|key| groups[key].parts.contains(&k))?;
            let theirs = paths
                .get((if lone.source { key.0 } else { key.1 })?)?
                .as_ref()?;
            same_paint(mine, theirs).then_some(key)
        });
        // Else on its own: the path shrinks away (grows) in its own paint.
        let alone = if lone.source {
            (Some(item), None)
        } else {
            (None, Some(item))
        };
        // A stroke without a partner always goes on its own, so that its width can shrink with
        // it.
        let stroke = contours[lone.contour].kind == ContourKind::Stroke;
        let key = if stroke {
            alone
        } else {
            own.or(host_key).unwrap_or(alone)
        };
        let joins = key != alone && own.is_none() && host_key.is_some();
        let g = groups.entry(key).or_default();
        if joins {
            if lone.source {
                g.covers.0.push(item);
            } else {
                g.covers.1.push(item);
            }
        }
        // The shape shrinks about the point it goes into, turning with its host but keeping
        // its own size: riding the host's scale would swell it over a host that grows.
        let (anchor, centre, rider) = match lone.host {
            Some((k, c)) => {
                g.riders.push(rider_of(k, lone.source));
                let r = g.riders.len() - 1;
                // The point it goes into rides the host exactly where the host has a mesh.
                let centre = locate(k, lone.source, &[c]).unwrap_or(Place::Rider(r, vec![c]));
                (c, centre, Some(r))
            }
            None => {
                let c = contours[lone.contour].centroid;
                (c, Place::Still(vec![c]), None)
            }
        };
        let place_of = |pts: &[Point]| Place::About {
            centre: Box::new(centre.clone()),
            rider,
            anchor,
            points: pts.to_vec(),
        };
        let centre = Some(centre.clone());
        let outline = &contours[lone.contour];
        g.rings.push(Ring::Sized {
            ring: place_of(&outline.points),
            centre: centre.clone(),
            closing: lone.source,
            hole: false,
            closed: outline.closed,
        });
        for &h in &lone.holes {
            g.rings.push(Ring::Sized {
                ring: place_of(&contours[h].points),
                centre: centre.clone(),
                closing: lone.source,
                hole: true,
                closed: true,
            });
        }
    }
    let out = groups
        .into_iter()
        .filter_map(|((i, j), g)| {
            let sized_stroke = g.alone().then_some(i.is_some());
            let a = i.and_then(|i| ps.get(i)?.as_ref());
            let b = j.and_then(|j| pt.get(j)?.as_ref());
            let (a, b) = match (a, b) {
                (Some(a), Some(b)) => (a, b),
                (Some(a), None) => (a, a),
                (None, Some(b)) => (b, b),
                (None, None) => return None,
            };
            Some(MorphingPath {
                source_item: i,
                target_item: j,
                curves: g.curves,
                curve_holes: g.curve_holes,
                source: a.clone(),
                target: b.clone(),
                source_root: source_scene.root_transform,
                target_root: target_scene.root_transform,
                rings: g.rings,
                riders: g.riders,
                covers: g.covers,
                sized_stroke,
            })
        })
        .collect();
    in_paint_order(out)
}
