//! Binding the triangulation to the skeleton (§4.2.2): harmonic weights per joint, each vertex
//! bound to the bone `(k1, k2)` with the largest `λ_k1 + λ_k2`.
//!
//! The weight `λ_k` of joint k is the harmonic function on the source mesh (cotangent Laplacian,
//! the approach of [36]) that is 1 at the joint's vertex and 0 at every other joint's vertex;
//! it is smooth and falls off with the distance along the shape, so it is the joint's
//! influence. Computed once on the source mesh: every intermediate skeleton is derived from the
//! reference skeleton, so the binding never changes.
//!
//! Where two bones meet, the paper's hard binding puts vertices of one bone next to vertices of
//! the other, and eq. (2) must absorb the whole difference of the two bones' transformations
//! across one ring of triangles; with a limb swung by 35° that folds triangles at the seam. So a
//! vertex takes the bones' transformations *blended* by a softmax of `λ_k1 + λ_k2` with a
//! small temperature ([`SOFTNESS`]): well inside a limb it follows its bone exactly as in the
//! paper, and across a seam the transformation turns over a few rings.
//!
//! Regional control (Fig.14(a)): a skeleton may cover only part of the shape. A bone reaches as
//! far as 1.5 times its half-width (the largest distance from the bone to the nearest boundary
//! point); beyond that its influence fades to nothing over another half of that reach, and
//! vertices outside every reach keep their plain rigid interpolation transformations.

use super::Skeleton;
use crate::error::{Error, Result};
use crate::geometry::{point_segment_distance, Point};
use crate::mapping::harmonic::Harmonic;

/// Reach of a bone in multiples of the bone's half-width (distance to the boundary).
const REACH: f64 = 1.5;

/// Softmax temperature of the blend between bones, in units of `λ_k1 + λ_k2` (which lies in
/// [0, 2]): bones scoring 0.1 less than the best weigh e⁻¹ as much.
pub(crate) const SOFTNESS: f64 = 0.1;

/// Per vertex of the source mesh, the bones (indices into `skeleton.bones`) whose
/// transformations it takes and their weights; the weights sum to at most 1, the rest being the
/// identity (outside the skeleton's region). `boundary` is the source boundary's points.
pub(crate) fn bind(
    skeleton: &Skeleton,
    source: &[Point],
    triangles: &[[u32; 3]],
    boundary: &[Point],
) -> Result<Vec<Vec<(u32, f64)>>> {
    let n = source.len();
    if skeleton.bones.is_empty() || n == 0 {
        return Ok(vec![Vec::new(); n]);
    }
    let weights = joint_weights(skeleton, source, triangles)?;
    let reach: Vec<f64> = skeleton
        .bones
        .iter()
        .map(|&[a, b]| {
            let (p, q) = (skeleton.joints[a as usize], skeleton.joints[b as usize]);
            let half_width = (0..=8)
                .map(|s| {
                    let x = p + (q - p) * (s as f64 / 8.0);
                    boundary
                        .iter()
                        .map(|c| c.distance(x))
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max);
            REACH * half_width
        })
        .collect();
    Ok((0..n)
        .map(|v| {
            let score: Vec<f64> = skeleton
                .bones
                .iter()
                .map(|&[k1, k2]| weights[k1 as usize][v] + weights[k2 as usize][v])
                .collect();
            let best = score.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let soft: Vec<f64> = score
                .iter()
                .map(|s| ((s - best) / SOFTNESS).exp())
                .collect();
            let total: f64 = soft.iter().sum();
            let mut out: Vec<(u32, f64)> = soft
                .iter()
                .enumerate()
                .filter_map(|(b, w)| {
                    let [a, c] = skeleton.bones[b];
                    let d = point_segment_distance(
                        source[v],
                        skeleton.joints[a as usize],
                        skeleton.joints[c as usize],
                    )
                    .0;
                    // Full influence within reach, fading to none at 1.5 × reach.
                    let x = ((d - reach[b]) / (0.5 * reach[b]).max(1e-300)).clamp(0.0, 1.0);
                    let fade = 1.0 - x * x * (3.0 - 2.0 * x);
                    let w = w / total * fade;
                    (w > 1e-3).then_some((b as u32, w))
                })
                .collect();
            out.sort_by_key(|e| e.0);
            out
        })
        .collect())
}

/// Harmonic weight of every joint at every vertex, `w[k][v]`.
pub(crate) fn joint_weights(
    skeleton: &Skeleton,
    source: &[Point],
    triangles: &[[u32; 3]],
) -> Result<Vec<Vec<f64>>> {
    let n = source.len();
    let handles = handle_vertices(skeleton, source)?;
    // Vertices of mesh parts that hold no handle are fixed at 0 (no influence), so every free
    // vertex is connected to a fixed one and the Laplacian is definite.
    let mut fixed = vec![false; n];
    for &h in &handles {
        fixed[h as usize] = true;
    }
    let reached = reachable(triangles, n, &handles);
    for v in 0..n {
        if !reached[v] {
            fixed[v] = true;
        }
    }
    let mut harmonic = Harmonic::new(triangles, n, &fixed)?;
    let k = handles.len();
    let mut w = vec![vec![0.0; n]; k];
    // Two joints per solve: one in x, one in y.
    for pair in (0..k).collect::<Vec<_>>().chunks(2) {
        let mut out = vec![Point::ZERO; n];
        for (slot, &j) in pair.iter().enumerate() {
            let h = handles[j] as usize;
            if slot == 0 {
                out[h].x = 1.0;
            } else {
                out[h].y = 1.0;
            }
        }
        harmonic
            .solve(source, &mut out)
            .map_err(|e| Error::internal(format!("skeleton weights: {e}")))?;
        for v in 0..n {
            w[pair[0]][v] = out[v].x;
            if let Some(&j) = pair.get(1) {
                w[j][v] = out[v].y;
            }
        }
    }
    Ok(w)
}

/// The mesh vertex standing for each joint: the nearest vertex not taken by another joint.
fn handle_vertices(skeleton: &Skeleton, source: &[Point]) -> Result<Vec<u32>> {
    if skeleton.joints.len() > source.len() {
        return Err(Error::input(
            crate::error::Drawings::Source,
            "the skeleton has more joints than the mesh has vertices; use a higher --density",
        ));
    }
    let mut taken = vec![false; source.len()];
    let mut out = Vec::with_capacity(skeleton.joints.len());
    for &j in &skeleton.joints {
        let v = (0..source.len())
            .filter(|&v| !taken[v])
            .min_by(|&a, &b| source[a].distance(j).total_cmp(&source[b].distance(j)))
            .ok_or_else(|| Error::internal("no vertex left for a joint"))?;
        taken[v] = true;
        out.push(v as u32);
    }
    Ok(out)
}

/// Which vertices are connected (through triangle edges) to one of `seeds`.
fn reachable(triangles: &[[u32; 3]], n: usize, seeds: &[u32]) -> Vec<bool> {
    let rings = crate::mesh::one_rings(triangles, n);
    let mut seen = vec![false; n];
    let mut stack: Vec<u32> = seeds.to_vec();
    for &s in seeds {
        seen[s as usize] = true;
    }
    while let Some(v) = stack.pop() {
        for &u in &rings[v as usize] {
            if !seen[u as usize] {
                seen[u as usize] = true;
                stack.push(u);
            }
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `w × h` grid of unit squares, two triangles each.
    fn grid(w: usize, h: usize) -> (Vec<Point>, Vec<[u32; 3]>) {
        let pts = (0..=h)
            .flat_map(|j| (0..=w).map(move |i| Point::new(i as f64, j as f64)))
            .collect();
        let mut tris = Vec::new();
        for j in 0..h {
            for i in 0..w {
                let v = |i: usize, j: usize| (j * (w + 1) + i) as u32;
                tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        (pts, tris)
    }

    /// The points of a `w × h` grid on its outer edge.
    fn rim(pts: &[Point], w: f64, h: f64) -> Vec<Point> {
        pts.iter()
            .copied()
            .filter(|p| p.x == 0.0 || p.x == w || p.y == 0.0 || p.y == h)
            .collect()
    }

    #[test]
    fn weights_are_one_at_their_joint_and_fall_off() {
        let (pts, tris) = grid(20, 4);
        let s = crate::skeleton::reference::one_chain(&[
            Point::new(1.0, 2.0),
            Point::new(10.0, 2.0),
            Point::new(19.0, 2.0),
        ]);
        let w = joint_weights(&s, &pts, &tris).unwrap();
        let at = |x: usize, y: usize| y * 21 + x;
        assert!((w[0][at(1, 2)] - 1.0).abs() < 1e-12);
        assert!(w[0][at(10, 2)].abs() < 1e-12);
        assert!(w[0][at(3, 2)] > w[0][at(6, 2)] && w[0][at(6, 2)] > w[0][at(9, 2)]);
        // A partition of unity between the joints.
        for v in [at(4, 0), at(12, 3), at(15, 1)] {
            let sum: f64 = w.iter().map(|wk| wk[v]).sum();
            assert!((sum - 1.0).abs() < 1e-9, "{sum}");
        }
        // Bound to the nearer bone.
        let boundary = rim(&pts, 20.0, 4.0);
        let b = bind(&s, &pts, &tris, &boundary).unwrap();
        let main = |v: usize| b[v].iter().max_by(|x, y| x.1.total_cmp(&y.1)).unwrap().0;
        assert_eq!(main(at(4, 1)), 0);
        assert_eq!(main(at(16, 3)), 1);
        // Well inside a bone's part a vertex follows that bone alone; at the joint between the
        // two bones it blends them.
        assert!(b[at(3, 2)].len() == 1 && (b[at(3, 2)][0].1 - 1.0).abs() < 1e-3);
        assert_eq!(b[at(10, 2)].len(), 2);
        for w in &b {
            let sum: f64 = w.iter().map(|e| e.1).sum();
            assert!(sum <= 1.0 + 1e-12);
        }
    }

    #[test]
    fn a_regional_skeleton_leaves_the_rest_unbound() {
        let (pts, tris) = grid(30, 4);
        let s = crate::skeleton::reference::one_chain(&[
            Point::new(1.0, 2.0),
            Point::new(5.0, 2.0),
            Point::new(9.0, 2.0),
        ]);
        let boundary = rim(&pts, 30.0, 4.0);
        let b = bind(&s, &pts, &tris, &boundary).unwrap();
        let at = |x: usize, y: usize| y * 31 + x;
        let total = |v: usize| b[v].iter().map(|e| e.1).sum::<f64>();
        assert!(total(at(4, 2)) > 0.99 && total(at(8, 0)) > 0.99);
        assert!(b[at(25, 2)].is_empty() && b[at(29, 4)].is_empty());
    }
}
