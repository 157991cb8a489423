//! Features carried by the boundary around them: an alternative placement of the feature curves
//! of the shape model (§5) for shapes that bend.
//!
//! The barycenter-based shape model moves every curve as one body whose position comes from
//! the barycenter mesh. When the shape bends — a U becoming an S — a feature in an arm has to
//! swing with that arm, which the barycenter mesh (a few nodes, all connected) cannot express,
//! and the intermediate features leave the band of the boundary they lie in. Here each feature
//! vertex is instead attached to the boundary around it: the boundary vertices within twice its
//! distance to the boundary (at least [`MIN_CARRIERS`] of them), weighted `1/d² − 1/R²` so that
//! the weights fade out smoothly at that radius `R`. At time `t` the vertex moves by the
//! weighted best-fit similarity (Procrustes) that carries those boundary vertices to their
//! intermediate positions. The neighbourhood is a region of the plane, not a vertex count, so
//! the result does not depend on how densely the curves are sampled. Doing so once from the
//! source side and once from the target side and blending the two by `t` gives exactly the
//! source features at 0 and the target features at 1.

use crate::geometry::Point;

/// Fewest boundary vertices carrying one feature vertex.
const MIN_CARRIERS: usize = 4;
/// Carriers lie within this multiple of the feature vertex's distance to the boundary.
const REACH: f64 = 2.0;

/// One side's attachment of a feature vertex: its position, the weighted carrier vertices and
/// what [`carry`] needs of their positions on this side, which do not change with `t`.
#[derive(Debug, Clone)]
struct Attachment {
    point: Point,
    /// The carriers: boundary vertex, weight.
    carriers: Vec<(u32, f64)>,
    /// Per carrier, its offset from the weighted centroid `centre`.
    offsets: Vec<Point>,
    /// The sum of the weights.
    weight: f64,
    /// The carriers' weighted centroid.
    centre: Point,
    /// The weighted sum of the offsets' squared lengths.
    spread: f64,
}

/// Feature vertices attached to the boundary at both ends of the morph.
#[derive(Debug, Clone)]
pub(crate) struct Carried {
    /// Per feature, per vertex: attachments at t = 0 and t = 1.
    features: Vec<Vec<[Attachment; 2]>>,
}

fn attach(boundary: &[Point], p: Point) -> Attachment {
    // Boundary vertices in order of distance (ties by index). Only the nearest few set the
    // radius and only those within it are kept, so the k nearest are selected and the kept
    // ones sorted, not the whole boundary (for every feature vertex).
    let order = |x: &(f64, u32), y: &(f64, u32)| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1));
    let mut by_distance: Vec<(f64, u32)> = boundary
        .iter()
        .enumerate()
        .map(|(i, b)| (b.distance_squared(p), i as u32))
        .collect();
    let k = MIN_CARRIERS.min(by_distance.len());
    let (nearest_k, kth, _) = by_distance.select_nth_unstable_by(k - 1, order);
    let nearest = nearest_k.iter().min_by(|x, y| order(x, y)).unwrap_or(kth).0;
    // Radius²: REACH times the distance, but wide enough for MIN_CARRIERS vertices, and a
    // little beyond the last one kept so that every carrier has a positive weight.
    let r2 = (REACH * REACH * nearest).max(kth.0) * (1.0 + 1e-6) + f64::MIN_POSITIVE;
    let floor = 1e-12 * r2;
    by_distance.retain(|c| c.0 < r2);
    by_distance.sort_unstable_by(order);
    let carriers: Vec<(u32, f64)> = by_distance
        .iter()
        .map(|&(d2, i)| (i, 1.0 / d2.max(floor) - 1.0 / r2))
        .collect();
    // The side's own half of the best fit, summed in the carriers' order as [`carry`] did
    // every step before (so every step keeps its bits).
    let (mut weight, mut centre) = (0.0, Point::ZERO);
    for &(i, wi) in &carriers {
        weight += wi;
        centre += boundary[i as usize] * wi;
    }
    let centre = centre / weight;
    let offsets: Vec<Point> = carriers
        .iter()
        .map(|&(i, _)| boundary[i as usize] - centre)
        .collect();
    let spread = carriers
        .iter()
        .zip(&offsets)
        .fold(0.0, |total, (&(_, wi), x)| total + wi * x.length_squared());
    Attachment {
        point: p,
        carriers,
        offsets,
        weight,
        centre,
        spread,
    }
}

/// Where the weighted best-fit similarity carrying the carriers from the side they were
/// attached on to `to` takes the attached point.
fn carry(a: &Attachment, to: &[Point]) -> Point {
    if a.weight <= 0.0 {
        return a.point;
    }
    let mut ct = Point::ZERO;
    for &(i, wi) in &a.carriers {
        ct += to[i as usize] * wi;
    }
    let ct = ct / a.weight;
    // Complex least squares: (dot + i·cross) / Σ|x|² is scale times rotation.
    let (mut dot, mut cross) = (0.0, 0.0);
    for (&(i, wi), &x) in a.carriers.iter().zip(&a.offsets) {
        let y = to[i as usize] - ct;
        dot += wi * x.dot(y);
        cross += wi * x.perp_dot(y);
    }
    let d = a.point - a.centre;
    if a.spread <= 0.0 {
        return ct + d;
    }
    let (c, s) = (dot / a.spread, cross / a.spread);
    ct + Point::new(c * d.x - s * d.y, s * d.x + c * d.y)
}

impl Carried {
    /// Attaches the features (`features[f] = (source, target)` vertex lists) to the boundary
    /// `(source, target)`. `None` if the boundary has no vertices or the two sides differ in
    /// length.
    pub(crate) fn new(
        boundary: (&[Point], &[Point]),
        features: &[(&[Point], &[Point])],
    ) -> Option<Self> {
        let (b0, b1) = boundary;
        if b0.is_empty() || b1.len() != b0.len() {
            return None;
        }
        let features = features
            .iter()
            .map(|(f0, f1)| {
                f0.iter()
                    .zip(f1.iter())
                    .map(|(&p, &q)| [attach(b0, p), attach(b1, q)])
                    .collect()
            })
            .collect();
        Some(Carried { features })
    }

    /// The features at `t`, given the intermediate boundary `boundary_t` (same vertex count),
    /// into `out[f]`.
    pub(crate) fn features_at(&self, t: f64, boundary_t: &[Point], out: &mut [Vec<Point>]) {
        for (o, f) in out.iter_mut().zip(&self.features) {
            o.clear();
            o.extend(f.iter().map(|[a0, a1]| {
                let p0 = carry(a0, boundary_t);
                let p1 = carry(a1, boundary_t);
                p0 * (1.0 - t) + p1 * t
            }));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The attachment as first written: the whole boundary sorted by distance.
    fn attach_by_full_sort(boundary: &[Point], p: Point) -> Vec<(u32, f64)> {
        let mut by_distance: Vec<(f64, u32)> = boundary
            .iter()
            .enumerate()
            .map(|(i, b)| (b.distance_squared(p), i as u32))
            .collect();
        by_distance.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let nearest = by_distance[0].0;
        let k = MIN_CARRIERS.min(by_distance.len());
        let r2 =
            (REACH * REACH * nearest).max(by_distance[k - 1].0) * (1.0 + 1e-6) + f64::MIN_POSITIVE;
        let floor = 1e-12 * r2;
        by_distance
            .iter()
            .take_while(|c| c.0 < r2)
            .map(|&(d2, i)| (i, 1.0 / d2.max(floor) - 1.0 / r2))
            .collect()
    }

    proptest! {
        /// Selecting the nearest few and sorting only the kept carriers gives the carriers and
        /// weights, bit for bit and in order, of sorting the whole boundary: on a coarse grid,
        /// so that equal distances (ties broken by index), repeated vertices, a point on the
        /// boundary and boundaries shorter than MIN_CARRIERS all occur.
        #[test]
        fn selecting_the_nearest_gives_the_carriers_of_a_full_sort(
            boundary in proptest::collection::vec((-5i32..6, -5i32..6), 1..40),
            p in (-6i32..7, -6i32..7),
        ) {
            let b: Vec<Point> = boundary.iter().map(|&(x, y)| Point::new(x as f64, y as f64)).collect();
            let q = Point::new(p.0 as f64 * 0.5, p.1 as f64);
            let bits = |c: &[(u32, f64)]| c.iter().map(|&(i, w)| (i, w.to_bits())).collect::<Vec<_>>();
            prop_assert_eq!(bits(&attach(&b, q).carriers), bits(&attach_by_full_sort(&b, q)));
        }
    }

    /// The best fit as first written: both sides' sums every time.
    fn carry_both_sides(a: &Attachment, from: &[Point], to: &[Point]) -> Point {
        let (mut w, mut cf, mut ct) = (0.0, Point::ZERO, Point::ZERO);
        for &(i, wi) in &a.carriers {
            w += wi;
            cf += from[i as usize] * wi;
            ct += to[i as usize] * wi;
        }
        if w <= 0.0 {
            return a.point;
        }
        let (cf, ct) = (cf / w, ct / w);
        let (mut xx, mut dot, mut cross) = (0.0, 0.0, 0.0);
        for &(i, wi) in &a.carriers {
            let (x, y) = (from[i as usize] - cf, to[i as usize] - ct);
            xx += wi * x.length_squared();
            dot += wi * x.dot(y);
            cross += wi * x.perp_dot(y);
        }
        let d = a.point - cf;
        if xx <= 0.0 {
            return ct + d;
        }
        let (c, s) = (dot / xx, cross / xx);
        ct + Point::new(c * d.x - s * d.y, s * d.x + c * d.y)
    }

    proptest! {
        /// Carrying with the attached side's sums made once gives the bits of summing both
        /// sides every time: random boundaries, moved anywhere (collapsed to a point too).
        #[test]
        fn carrying_keeps_the_bits_of_summing_both_sides(
            boundary in proptest::collection::vec((-50.0f64..50.0, -50.0f64..50.0), 1..30),
            moved in proptest::collection::vec((-50.0f64..50.0, -50.0f64..50.0), 30),
            p in (-60.0f64..60.0, -60.0f64..60.0),
            collapse in proptest::bool::ANY,
        ) {
            let b: Vec<Point> = boundary.iter().map(|&(x, y)| Point::new(x, y)).collect();
            let to: Vec<Point> = moved[..b.len()]
                .iter()
                .map(|&(x, y)| if collapse { Point::new(1.5, -2.0) } else { Point::new(x, y) })
                .collect();
            let a = attach(&b, Point::new(p.0, p.1));
            let bits = |q: Point| (q.x.to_bits(), q.y.to_bits());
            prop_assert_eq!(bits(carry(&a, &to)), bits(carry_both_sides(&a, &b, &to)));
            prop_assert_eq!(bits(carry(&a, &b)), bits(carry_both_sides(&a, &b, &b)));
        }
    }
}
