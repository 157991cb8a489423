//! Improving compatible meshes without breaking them: edge flips, edge splits and vertex
//! smoothing that keep every triangle positively oriented in both meshes (exact predicate)
//! and never move or add a curve vertex.
//!
//! The overlaid triangulation of [`super::overlay`] is valid but full of slivers where chords
//! cross at small angles. The disc interpolation is insensitive to triangle quality (the
//! paper's Fig. 13), but long thin triangles still make coarse discs and long edges that bend
//! badly, so the mesh is improved in passes:
//!
//! 1. *flips*: an interior edge is turned to the other diagonal of its quadrilateral when that
//!    is valid in both meshes and raises the smaller angle of the two triangles in the worse of
//!    the two meshes;
//! 2. *splits*: interior edges longer than the tolerance's longest edge (in either mesh) are
//!    cut at their midpoints in both meshes — each half of a triangle keeps its orientation;
//! 3. *smoothing*: each free vertex moves, in each mesh on its own, towards the mean of its
//!    neighbours, as far as its star stays valid (the move is halved until it is).

use crate::geometry::Point;
use crate::mesh::CompatibleMeshes;
use crate::tolerance::Tolerances;

/// Most vertices the splits may bring the mesh to, as a multiple of its curve vertices.
const SPLIT_BUDGET: usize = 12;

/// Smoothing passes per round.
const SMOOTHING_PASSES: usize = 6;

/// Improves `m` in place (module docs); vertices `0..fixed` (the curves') never move.
pub(crate) fn improve(m: &mut CompatibleMeshes, fixed: usize, tol: &Tolerances) {
    for round in 0..3 {
        flip_all(m);
        smooth(m, fixed);
        flip_all(m);
        if round < 2 && split_long(m, fixed, tol.max_edge) == 0 {
            smooth(m, fixed);
            flip_all(m);
            break;
        }
    }
    smooth(m, fixed);
}

/// The sine of the smallest angle of triangle `abc`, 0 when degenerate: twice its area over the
/// product of the two sides at its most acute corner, whose angle is at most 60°, where the
/// sine grows with the angle (no trigonometry in the inner loop of the flips).
fn min_angle(a: Point, b: Point, c: Point) -> f64 {
    let twice = (b - a).perp_dot(c - a).abs();
    let (ab, bc, ca) = (a.distance(b), b.distance(c), c.distance(a));
    // The smallest angle is opposite the shortest side, between the two longer ones.
    let d = if ab <= bc && ab <= ca {
        bc * ca
    } else if bc <= ca {
        ab * ca
    } else {
        ab * bc
    };
    if d > 0.0 {
        twice / d
    } else {
        0.0
    }
}

use crate::mesh::is_positive as positive;

fn quality(m: &CompatibleMeshes, t: [u32; 3]) -> f64 {
    let q = |p: &[Point]| min_angle(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
    q(&m.source).min(q(&m.target))
}

/// Flips interior edges while a flip improves the pair's worse angle; returns the count.
fn flip_all(m: &mut CompatibleMeshes) -> usize {
    let mut total = 0;
    let curve_edge: std::collections::HashSet<(u32, u32)> = m
        .curves
        .iter()
        .flat_map(|c| {
            let n = c.vertices.len();
            let links = if c.closed { n } else { n.saturating_sub(1) };
            (0..links).map(move |k| {
                let (a, b) = (c.vertices[k], c.vertices[(k + 1) % n]);
                (a.min(b), a.max(b))
            })
        })
        .collect();
    for _ in 0..8 {
        let mut flipped = 0;
        // Directed edge → (triangle, index of the edge's first corner).
        let mut owner: std::collections::HashMap<(u32, u32), usize> = Default::default();
        for (f, t) in m.triangles.iter().enumerate() {
            for k in 0..3 {
                owner.insert((t[k], t[(k + 1) % 3]), f);
            }
        }
        let mut touched = vec![false; m.triangles.len()];
        for f in 0..m.triangles.len() {
            if touched[f] {
                continue;
            }
            for k in 0..3 {
                let t1 = m.triangles[f];
                let (u, v, a) = (t1[k], t1[(k + 1) % 3], t1[(k + 2) % 3]);
                if curve_edge.contains(&(u.min(v), u.max(v))) {
                    continue;
                }
                let Some(&g) = owner.get(&(v, u)) else {
                    continue;
                };
                if touched[g] || g == f {
                    continue;
                }
                let t2 = m.triangles[g];
                let Some(b) = t2.iter().copied().find(|&x| x != u && x != v) else {
                    continue;
                };
                let (n1, n2) = ([u, b, a], [b, v, a]);
                if !(positive(&m.source, n1)
                    && positive(&m.source, n2)
                    && positive(&m.target, n1)
                    && positive(&m.target, n2))
                {
                    continue;
                }
                let before = quality(m, t1).min(quality(m, t2));
                let after = quality(m, n1).min(quality(m, n2));
                if after > before * 1.01 + 1e-12 {
                    m.triangles[f] = n1;
                    m.triangles[g] = n2;
                    touched[f] = true;
                    touched[g] = true;
                    flipped += 1;
                    break;
                }
            }
        }
        total += flipped;
        if flipped == 0 {
            break;
        }
    }
    total
}

/// Splits interior edges longer than `max_edge` in either mesh at their midpoints (both
/// meshes), within the vertex budget; returns how many.
fn split_long(m: &mut CompatibleMeshes, fixed: usize, max_edge: f64) -> usize {
    let budget = SPLIT_BUDGET * fixed.max(8);
    let on_curve: std::collections::HashSet<(u32, u32)> = m
        .curves
        .iter()
        .flat_map(|c| {
            let n = c.vertices.len();
            (0..n).map(move |k| {
                let (a, b) = (c.vertices[k], c.vertices[(k + 1) % n]);
                (a.min(b), a.max(b))
            })
        })
        .collect();
    let long = |m: &CompatibleMeshes, a: u32, b: u32| {
        let (a, b) = (a as usize, b as usize);
        (m.source[a].distance(m.source[b]) / max_edge)
            .max(m.target[a].distance(m.target[b]) / max_edge)
    };
    let mut edges: Vec<(f64, u32, u32)> = crate::mesh::edges(&m.triangles)
        .into_iter()
        .filter(|e| !on_curve.contains(e))
        .map(|(a, b)| (long(m, a, b), a, b))
        .filter(|e| e.0 > 1.0)
        .collect();
    edges.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    let mut done = 0;
    let mut split: std::collections::HashSet<u32> = Default::default();
    for (_, a, b) in edges {
        if m.source.len() >= budget {
            break;
        }
        // One split per triangle per pass: skip edges whose triangles changed already.
        if split.contains(&a) || split.contains(&b) {
            continue;
        }
        let faces: Vec<usize> = m
            .triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.contains(&a) && t.contains(&b))
            .map(|(f, _)| f)
            .collect();
        if faces.len() != 2 {
            continue;
        }
        let mid = m.source.len() as u32;
        let (ms, mt) = (
            (m.source[a as usize] + m.source[b as usize]) * 0.5,
            (m.target[a as usize] + m.target[b as usize]) * 0.5,
        );
        let mut replaced = Vec::new();
        for &f in &faces {
            let t = m.triangles[f];
            let k = (0..3)
                .find(|&k| {
                    let (x, y) = (t[k], t[(k + 1) % 3]);
                    (x == a && y == b) || (x == b && y == a)
                })
                .unwrap_or(0);
            let (x, y, z) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            replaced.push((f, [x, mid, z], [mid, y, z]));
        }
        m.source.push(ms);
        m.target.push(mt);
        let ok = replaced.iter().all(|(_, t1, t2)| {
            positive(&m.source, *t1)
                && positive(&m.source, *t2)
                && positive(&m.target, *t1)
                && positive(&m.target, *t2)
        });
        if !ok {
            m.source.pop();
            m.target.pop();
            continue;
        }
        for (f, t1, t2) in replaced {
            m.triangles[f] = t1;
            m.triangles.push(t2);
        }
        split.insert(a);
        split.insert(b);
        done += 1;
    }
    done
}

/// Straightens triangles that rounding left inverted or flat in either mesh: the fold repair
/// of the disc interpolation (`rigid::repair`) on each mesh, vertices `0..fixed` held.
pub(crate) fn untangle(m: &mut CompatibleMeshes, fixed: usize) {
    let n = m.source.len();
    let held: Vec<bool> = (0..n).map(|v| v < fixed).collect();
    let repair = crate::rigid::repair::FoldRepair::new(&m.triangles, n, &held, None, false);
    repair.apply(&mut m.source);
    repair.apply(&mut m.target);
}

/// Moves every free vertex (index ≥ `fixed`) towards the mean of its neighbours, in each mesh
/// on its own, as far as its star stays valid.
fn smooth(m: &mut CompatibleMeshes, fixed: usize) {
    let n = m.source.len();
    let star = crate::mesh::stars(&m.triangles, n);
    let rings = crate::mesh::one_rings(&m.triangles, n);
    let triangles = m.triangles.clone();
    for points in [&mut m.source, &mut m.target] {
        for _ in 0..SMOOTHING_PASSES {
            for v in fixed..n {
                if rings[v].is_empty() {
                    continue;
                }
                let mean = rings[v].iter().map(|&w| points[w as usize]).sum::<Point>()
                    / rings[v].len() as f64;
                let old = points[v];
                let mut step = 1.0;
                for _ in 0..4 {
                    points[v] = old + (mean - old) * step;
                    if star[v]
                        .iter()
                        .all(|&f| positive(points, triangles[f as usize]))
                    {
                        break;
                    }
                    step *= 0.5;
                    points[v] = old;
                }
            }
        }
    }
}
