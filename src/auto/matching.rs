//! Matching source contours to target contours: an optimal assignment (Hungarian method) on a
//! documented cost, outlines and strokes first, then holes within matched outlines.
//!
//! The cost of pairing contour a with contour b, for contours of the same kind:
//!
//! ```text
//! cost = |c_a − c_b| / D                      position: centroids, D = the larger drawing diagonal
//!      + 0.5 · |ln(s_a / s_b)|                size: s = √area (closed) or length (open)
//!      + 0.5 · |e_a − e_b|                    shape: elongation (small / large second moment)
//! ```
//!
//! Contours of different kinds (outline, hole, stroke), or open with closed, never pair. A pair
//! costing more than [`LEAVE`] is not made: those contours stay artwork only (warped and
//! blended), so two unrelated shapes are not forced into one. Holes pair only with holes whose
//! outlines were paired, so a counter stays in its letter.

use super::contours::{Contour, ContourKind};
use pathfinding::prelude::{kuhn_munkres_min, Matrix};

/// Cost above which two contours are left unpaired.
pub const LEAVE: f64 = 1.0;

/// Costs are integers of this many units per 1.0 for the assignment solver.
const SCALE: f64 = 1e6;

/// The cost of pairing `a` with `b` (see the module docs); `None` when they cannot pair.
pub fn cost(a: &Contour, b: &Contour, diagonal: f64) -> Option<f64> {
    if a.kind != b.kind || a.closed != b.closed {
        return None;
    }
    let size = |c: &Contour| {
        if c.closed && c.area > 0.0 {
            c.area.sqrt()
        } else {
            c.length
        }
    };
    let (sa, sb) = (size(a), size(b));
    if !(sa > 0.0 && sb > 0.0 && diagonal > 0.0) {
        return None;
    }
    Some(
        a.centroid.distance(b.centroid) / diagonal
            + 0.5 * (sa / sb).ln().abs()
            + 0.5 * (a.elongation - b.elongation).abs(),
    )
}

/// Pairs of indices `(source, target)` matched, sorted by source index.
pub fn match_contours(
    source: &[Contour],
    target: &[Contour],
    diagonal: f64,
) -> Vec<(usize, usize)> {
    matched(source, target, diagonal, LEAVE)
}

/// Like [`match_contours`], but outlines and strokes pair as many as they can: of n source and
/// m target outlines, min(n, m) pairs are made, the cheapest assignment of them (holes still
/// stay unpaired above [`LEAVE`]). Automatic mode morphs every shape it can into another
/// rather than fading it; the shapes left over grow or shrink.
pub fn match_shapes(source: &[Contour], target: &[Contour], diagonal: f64) -> Vec<(usize, usize)> {
    matched(source, target, diagonal, OUTLINE_LEAVE)
}

/// Cost of leaving an outline or stroke unpaired in [`match_shapes`]: above any real pair's.
const OUTLINE_LEAVE: f64 = 1e3;

fn matched(
    source: &[Contour],
    target: &[Contour],
    diagonal: f64,
    leave: f64,
) -> Vec<(usize, usize)> {
    let tops = |c: &[Contour]| -> Vec<usize> {
        (0..c.len())
            .filter(|&i| c[i].kind != ContourKind::Hole)
            .collect()
    };
    let mut pairs = assign(
        source,
        target,
        &tops(source),
        &tops(target),
        diagonal,
        leave,
    );
    // Holes, within each pair of matched outlines.
    let outer: Vec<(usize, usize)> = pairs.clone();
    for (a, b) in outer {
        let holes = |c: &[Contour], parent: usize| -> Vec<usize> {
            (0..c.len())
                .filter(|&i| c[i].kind == ContourKind::Hole && c[i].parent == Some(parent))
                .collect()
        };
        pairs.extend(assign(
            source,
            target,
            &holes(source, a),
            &holes(target, b),
            diagonal,
            LEAVE,
        ));
    }
    pairs.sort_unstable();
    pairs
}

/// Optimal assignment between the listed contours, each free to stay unmatched at cost
/// `leave`.
fn assign(
    source: &[Contour],
    target: &[Contour],
    rows: &[usize],
    cols: &[usize],
    diagonal: f64,
    leave: f64,
) -> Vec<(usize, usize)> {
    let (r, c) = (rows.len(), cols.len());
    if r == 0 || c == 0 {
        return Vec::new();
    }
    // Square (r + c): real pairs, "leave unmatched" on the padding.
    let n = r + c;
    let leave = (leave * SCALE) as i64;
    let never = 4 * leave;
    let mut m = Matrix::new(n, n, 0i64);
    for i in 0..n {
        for j in 0..n {
            m[(i, j)] = match (i < r, j < c) {
                (true, true) => cost(&source[rows[i]], &target[cols[j]], diagonal)
                    .map_or(never, |x| (x * SCALE).round().min(never as f64) as i64),
                (true, false) | (false, true) => leave,
                (false, false) => 0,
            };
        }
    }
    let (_, assignment) = kuhn_munkres_min(&m);
    let mut out = Vec::new();
    for (i, &j) in assignment.iter().enumerate().take(r) {
        if j < c && m[(i, j)] < leave {
            out.push((rows[i], cols[j]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn blob(x: f64, y: f64, r: f64, kind: ContourKind, parent: Option<usize>) -> Contour {
        Contour {
            points: vec![Point::new(x, y); 3],
            closed: true,
            kind,
            parent,
            path: 0,
            area: std::f64::consts::PI * r * r,
            length: std::f64::consts::TAU * r,
            centroid: Point::new(x, y),
            elongation: 1.0,
        }
    }

    #[test]
    fn nearby_similar_contours_pair_and_strangers_do_not() {
        use ContourKind::*;
        let a = vec![
            blob(10.0, 10.0, 5.0, Outline, None),
            blob(80.0, 80.0, 10.0, Outline, None),
            blob(80.0, 80.0, 3.0, Hole, Some(1)),
        ];
        let b = vec![
            blob(82.0, 79.0, 11.0, Outline, None),
            blob(12.0, 9.0, 5.5, Outline, None),
            blob(50.0, 10.0, 0.5, Outline, None), // a speck far away: left alone
        ];
        let m = match_contours(&a, &b, 141.0);
        assert_eq!(m, vec![(0, 1), (1, 0)], "the hole has no partner in b");
        let mut b2 = b.clone();
        b2.push(blob(81.0, 80.0, 2.5, Hole, Some(0)));
        let m = match_contours(&a, &b2, 141.0);
        assert_eq!(m, vec![(0, 1), (1, 0), (2, 3)]);
        // Kinds never mix.
        assert!(cost(&a[0], &blob(10.0, 10.0, 5.0, Hole, Some(1)), 141.0).is_none());
    }

    #[test]
    fn the_assignment_is_optimal_not_greedy() {
        use ContourKind::*;
        // Greedy nearest-first would pair a0 with b0 (distance 1) and leave a1 far from b1.
        let a = vec![
            blob(50.0, 50.0, 10.0, Outline, None),
            blob(40.0, 50.0, 10.0, Outline, None),
        ];
        let b = vec![
            blob(49.0, 50.0, 10.0, Outline, None),
            blob(62.0, 50.0, 10.0, Outline, None),
        ];
        let m = match_contours(&a, &b, 100.0);
        assert_eq!(m, vec![(0, 1), (1, 0)]);
    }
}
