//! The area rule: each connected part of a disc-interpolated mesh is scaled uniformly so that its
//! area follows the similarity curve between its end areas (a deviation from the paper, §4.1).
//!
//! Eq. (1) interpolates every edge's length on its own, `1 − t + t·s_ij`. A region stretched
//! unevenly — ×2 one way and ×½ the other — then has area `1.5 × 0.75 = 1.125` at t = ½ where
//! both end areas are 1: the shape swells through the morph (the leaf → butterfly fixture by
//! 12.8 %). After the solve, each part is therefore scaled about its centroid by
//! `√(A*(t) / A(t))`, where `A(t)` is its area in the frame and
//! `A*(t) = ((1 − t)·√A₀ + t·√A₁)²` is the area a similarity between the ends would give it
//! (the scale of a similarity moves linearly in t, as eq. (1) moves it).
//!
//! Why uniform and per part: a uniform scaling keeps every triangle's orientation and shape, so
//! the frame folds exactly where the paper's frame folds (nowhere, on valid meshes); a
//! per-vertex factor field was tried first and folded thin triangles wherever the factors
//! varied. For a similarity the factor is 1, so frames stay exact similarities with the scale
//! linear in t; at t = 0 and t = 1 the frame already has its end area, so the ends stay exact.

use crate::geometry::Point;

/// Per-part end areas of a triangle mesh, for scaling frames (module docs).
///
/// A region's area is the shoelace sum over its border: the directed triangle edges whose
/// reverse is not in the region (interior edges cancel in pairs). So a frame costs a pass over
/// the border edges, not over every triangle.
#[derive(Debug, Clone)]
pub(crate) struct AreaRule {
    /// Border edges `(a, b)` of the measured triangles, each with the part (connected component)
    /// it belongs to.
    border: Vec<(u32, u32, u32)>,
    /// `√A₀` and `√A₁` of every part; 0 for a part without area (no rule applied).
    root_source: Vec<f64>,
    root_target: Vec<f64>,
}

/// Signed area of triangle `tri` in `points`.
#[cfg(test)]
fn signed_area(points: &[Point], tri: [u32; 3]) -> f64 {
    let [a, b, c] = tri.map(|v| points[v as usize]);
    0.5 * (b - a).perp_dot(c - a)
}

/// The directed edges of `triangles` (indices below `n`) whose reverse is not among them (each
/// kept once per occurrence), sorted. Each vertex's outgoing edges are one short row, so the
/// reverse of `(a, b)` is looked up in `b`'s few; only the border found is sorted, not every
/// row.
fn border_edges(triangles: &[[u32; 3]], n: usize) -> Vec<(u32, u32)> {
    let (start, to) = crate::mesh::compressed_rows(
        n,
        triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]),
    );
    let row = |v: usize| &to[start[v]..start[v + 1]];
    let mut border = Vec::new();
    for a in 0..n {
        for &b in row(a) {
            if !row(b as usize).contains(&(a as u32)) {
                border.push((a as u32, b));
            }
        }
    }
    border.sort_unstable();
    border
}

/// Twice the signed area enclosed by the border edges of every part, into `areas`.
fn border_areas(border: &[(u32, u32, u32)], points: &[Point], areas: &mut [f64]) {
    areas.fill(0.0);
    for &(a, b, c) in border {
        areas[c as usize] += points[a as usize].perp_dot(points[b as usize]);
    }
}

/// Scales every point of `out` about its part's centroid by its part's factor (`factors[c]`,
/// 1 leaves the part alone). A lone part, the common case, takes one factor and centroid for
/// every point, which wide instructions run two points at a time; the operations and so the
/// bits are those of the general loop.
#[inline(always)]
fn scale_parts(factors: &[f64], comp: &[u32], centroids: &[Point], out: &mut [Point]) {
    if let ([f], [o]) = (factors, centroids) {
        let (f, o) = (*f, *o);
        if f != 1.0 {
            for p in out.iter_mut() {
                *p = o + (*p - o) * f;
            }
        }
        return;
    }
    for (p, &c) in out.iter_mut().zip(comp) {
        let (f, o) = (factors[c as usize], centroids[c as usize]);
        if f != 1.0 {
            *p = o + (*p - o) * f;
        }
    }
}

impl AreaRule {
    /// The rule measuring the area of `triangles` (all of a mesh's, or a region of them) and of
    /// the polygons whose directed edges are `cycles` (closed outlines without a mesh) over
    /// parts `comp[v]` (`count` parts) of a mesh with ends `source` and `target`; a part with no
    /// measured triangle is left alone. Triangles must be valid indices.
    pub(crate) fn new(
        triangles: &[[u32; 3]],
        cycles: &[(u32, u32)],
        comp: &[u32],
        count: usize,
        source: &[Point],
        target: &[Point],
    ) -> Self {
        let border: Vec<(u32, u32, u32)> = border_edges(triangles, comp.len())
            .into_iter()
            .chain(cycles.iter().copied())
            .map(|(a, b)| (a, b, comp[a as usize]))
            .collect();
        let mut a0 = vec![0.0; count];
        let mut a1 = vec![0.0; count];
        border_areas(&border, source, &mut a0);
        border_areas(&border, target, &mut a1);
        // (Twice the) areas of one sign at both ends: the rule needs a positive size at each
        // end; the factor of 2 cancels in the ratio `apply` takes.
        let (mut root_source, mut root_target) = (vec![0.0; count], vec![0.0; count]);
        for c in 0..count {
            let same_sign = a0[c] * a1[c] > 0.0;
            if same_sign && a0[c].is_finite() && a1[c].is_finite() {
                root_source[c] = a0[c].abs().sqrt();
                root_target[c] = a1[c].abs().sqrt();
            }
        }
        AreaRule {
            border,
            root_source,
            root_target,
        }
    }

    /// Scales every part of frame `out` at `t` about its centroid `centroids[c]` (module docs).
    /// `areas` is scratch with one entry per part. Does not allocate.
    pub(crate) fn apply(
        &self,
        t: f64,
        comp: &[u32],
        centroids: &[Point],
        out: &mut [Point],
        areas: &mut [f64],
    ) {
        border_areas(&self.border, out, areas);
        for (c, a) in areas.iter_mut().enumerate() {
            let (r0, r1) = (self.root_source[c], self.root_target[c]);
            let want = (1.0 - t) * r0 + t * r1;
            // The frame's area has the ends' sign unless the frame folded the part as a whole.
            let now = if r0 > 0.0 { a.abs() } else { 0.0 };
            *a = if now > 0.0 && want > 0.0 {
                want / now.sqrt()
            } else {
                1.0
            };
        }
        super::simd::vectorized(
            #[inline(always)]
            || scale_parts(areas, comp, centroids, out),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(s: f64, o: Point) -> Vec<Point> {
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .map(|&(x, y)| o + Point::new(x, y) * s)
            .collect()
    }

    #[test]
    fn each_part_is_scaled_to_the_similarity_area_about_its_centroid() {
        let tris = [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
        let comp = [0, 0, 0, 0, 1, 1, 1, 1];
        let src: Vec<Point> =
            [square(1.0, Point::ZERO), square(1.0, Point::new(5.0, 0.0))].concat();
        let tgt: Vec<Point> =
            [square(3.0, Point::ZERO), square(1.0, Point::new(5.0, 0.0))].concat();
        let rule = AreaRule::new(&tris, &[], &comp, 2, &src, &tgt);
        // A frame at t = ½ where part 0 is 1.5 × 3 (area 4.5, a swell over the similarity's
        // 2 × 2) and part 1 is unchanged (area 1, as wanted).
        let mut frame: Vec<Point> = [
            vec![
                Point::new(0.0, 0.0),
                Point::new(1.5, 0.0),
                Point::new(1.5, 3.0),
                Point::new(0.0, 3.0),
            ],
            square(1.0, Point::new(5.0, 0.0)),
        ]
        .concat();
        let before = frame.clone();
        let centroids = [Point::new(0.75, 1.5), Point::new(5.5, 0.5)];
        let mut areas = [0.0; 2];
        rule.apply(0.5, &comp, &centroids, &mut frame, &mut areas);
        let area = |p: &[Point]| signed_area(p, [0, 1, 2]) + signed_area(p, [0, 2, 3]);
        assert!((area(&frame[..4]) - 4.0).abs() < 1e-12);
        // Uniform about the centroid: the shape is kept.
        let f = (4.0f64 / 4.5).sqrt();
        for (a, b) in frame[..4].iter().zip(&before[..4]) {
            assert!(a.distance(centroids[0] + (*b - centroids[0]) * f) < 1e-12);
        }
        assert_eq!(&frame[4..], &before[4..]);
    }

    #[test]
    fn the_border_sum_is_the_sum_of_the_triangles() {
        // A 3 × 2 grid of squares, one of them left out (a hole in the region).
        let pts: Vec<Point> = (0..3)
            .flat_map(|j| {
                (0..4).map(move |i| Point::new(i as f64 * 1.5, j as f64 + 0.1 * i as f64))
            })
            .collect();
        let mut tris = Vec::new();
        for j in 0..2u32 {
            for i in 0..3u32 {
                if (i, j) == (1, 0) {
                    continue;
                }
                let v = |i: u32, j: u32| j * 4 + i;
                tris.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                tris.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        let border: Vec<(u32, u32, u32)> = border_edges(&tris, pts.len())
            .into_iter()
            .map(|(a, b)| (a, b, 0))
            .collect();
        let mut twice = [0.0];
        border_areas(&border, &pts, &mut twice);
        let sum: f64 = tris.iter().map(|&t| signed_area(&pts, t)).sum();
        assert!(
            (0.5 * twice[0] - sum).abs() < 1e-12,
            "{} vs {sum}",
            0.5 * twice[0]
        );
    }

    proptest::proptest! {
        /// The border is every directed edge whose reverse no triangle has, once per
        /// occurrence, sorted: what a scan of the whole edge list finds.
        #[test]
        fn border_edges_are_the_edges_without_a_reverse(
            tris in proptest::collection::vec(proptest::array::uniform3(0u32..12), 0..40),
        ) {
            let all: Vec<(u32, u32)> = tris
                .iter()
                .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                .collect();
            let mut expected: Vec<(u32, u32)> = all
                .iter()
                .copied()
                .filter(|&(a, b)| !all.contains(&(b, a)))
                .collect();
            expected.sort_unstable();
            proptest::prop_assert_eq!(border_edges(&tris, 12), expected);
        }
    }

    #[test]
    fn parts_without_area_are_left_alone() {
        let pts = vec![Point::ZERO, Point::new(1.0, 0.0), Point::new(2.0, 0.0)];
        let rule = AreaRule::new(&[[0, 1, 2]], &[], &[0, 0, 0], 1, &pts, &pts);
        let mut frame = pts.clone();
        rule.apply(
            0.5,
            &[0, 0, 0],
            &[Point::new(1.0, 0.0)],
            &mut frame,
            &mut [0.0],
        );
        assert_eq!(frame, pts);
    }
}
