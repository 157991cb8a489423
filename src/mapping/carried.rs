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

use crate::geometry::{same_bits, Point};
use crate::grid::GridFrame;
use std::sync::Arc;

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
    /// Per feature: its vertices' attachments at t = 0 and at t = 1.
    features: Vec<[Arc<[Attachment]>; 2]>,
}

/// Attachments already made, kept from one carried model to the next (issue 16). Automatic
/// mode maps each part from either side, and again each time it gives up a hole, and every
/// such map attached the same feature curves to the same boundary anew: a model of `k`
/// features for each of the `2k` maps of the ladder. An attachment depends only on the
/// boundary and the feature vertex, so it is looked up by their bits and made once.
#[derive(Debug, Default)]
pub(crate) struct Attachments {
    /// Per boundary seen: its vertices and the feature curves attached to it.
    boundaries: Vec<AttachedTo>,
}

/// The feature curves attached to one boundary.
#[derive(Debug)]
struct AttachedTo {
    boundary: Vec<Point>,
    /// Per feature curve: its vertices and their attachments.
    features: Vec<(Vec<Point>, Arc<[Attachment]>)>,
}

impl Attachments {
    /// The attachments of every vertex of each of `features` to `boundary`: those made before
    /// for the same curves, the others made now.
    fn attach(&mut self, boundary: &[Point], features: &[&[Point]]) -> Vec<Arc<[Attachment]>> {
        let k = match self
            .boundaries
            .iter()
            .position(|b| same_bits(&b.boundary, boundary))
        {
            Some(k) => k,
            None => {
                self.boundaries.push(AttachedTo {
                    boundary: boundary.to_vec(),
                    features: Vec::new(),
                });
                self.boundaries.len() - 1
            }
        };
        let known = &mut self.boundaries[k].features;
        // The grid is built only when some feature is new.
        let mut near: Option<Option<Nearby<'_>>> = None;
        features
            .iter()
            .map(|f| {
                if let Some((_, a)) = known.iter().find(|(g, _)| same_bits(g, f)) {
                    return a.clone();
                }
                let grid = near.get_or_insert_with(|| Nearby::new(boundary));
                let a: Arc<[Attachment]> = f
                    .iter()
                    .map(|&p| attach(boundary, grid.as_ref(), p))
                    .collect();
                known.push((f.to_vec(), a.clone()));
                a
            })
            .collect()
    }
}

/// The boundary vertices that carry `p`, by a scan of the whole boundary: every vertex within
/// the radius (squared) `r2` that [`reach`] sets, as `(distance², index)` in that order (ties by
/// index), and `r2`. The reference [`Nearby`] must agree with bit for bit; used as it is where
/// no grid can be built (a boundary with a non-finite coordinate).
fn carriers_by_scan(boundary: &[Point], p: Point) -> (Vec<(f64, u32)>, f64) {
    // Only the nearest few set the radius and only those within it are kept, so the k nearest
    // are selected and the kept ones sorted, not the whole boundary.
    let mut by_distance: Vec<(f64, u32)> = boundary
        .iter()
        .enumerate()
        .map(|(i, b)| (b.distance_squared(p), i as u32))
        .collect();
    let k = MIN_CARRIERS.min(by_distance.len());
    let (nearest_k, kth, _) = by_distance.select_nth_unstable_by(k - 1, by_order);
    let nearest = nearest_k
        .iter()
        .min_by(|x, y| by_order(x, y))
        .unwrap_or(kth)
        .0;
    let r2 = reach(nearest, kth.0);
    by_distance.retain(|c| c.0 < r2);
    by_distance.sort_unstable_by(by_order);
    (by_distance, r2)
}

/// Distance first, then index: the order carriers are kept and summed in.
fn by_order(x: &(f64, u32), y: &(f64, u32)) -> std::cmp::Ordering {
    x.0.total_cmp(&y.0).then(x.1.cmp(&y.1))
}

/// Radius² of a feature vertex's carriers from the squared distances of its nearest and its
/// [`MIN_CARRIERS`]-th nearest boundary vertex: [`REACH`] times the distance, but wide enough
/// for `MIN_CARRIERS` vertices, and a little beyond the last one kept so that every carrier has
/// a positive weight.
fn reach(nearest: f64, kth: f64) -> f64 {
    (REACH * REACH * nearest).max(kth) * (1.0 + 1e-6) + f64::MIN_POSITIVE
}

/// A uniform grid over one side's boundary vertices, so that a feature vertex's carriers are
/// found among the cells around it instead of by measuring the whole boundary (issue 16: the
/// carried model measured every boundary vertex for every feature vertex, a tenth of the
/// slowest corpus pair's CPU). It finds exactly the carriers of [`carriers_by_scan`], in the
/// same order and with the same distances, so every output keeps its bits.
#[derive(Debug)]
struct Nearby<'a> {
    points: &'a [Point],
    /// The grid over the points' box, about one cell per point.
    frame: GridFrame,
    /// Per cell (row-major), the start of its vertices in `items`; one more entry at the end.
    start: Vec<usize>,
    /// Vertex indices, ascending within each cell.
    items: Vec<u32>,
    /// Slack for rounding in the cell bounds, far below any distance that matters.
    slack: f64,
}

impl<'a> Nearby<'a> {
    /// The grid over `points`; `None` when there are none or one is not finite.
    fn new(points: &'a [Point]) -> Option<Self> {
        if points.iter().any(|q| !q.is_finite()) {
            return None;
        }
        let (lo, hi) = crate::geometry::bounding_box(points.iter().copied())?;
        let frame = GridFrame::covering(lo, hi, points.len());
        let cells = points.iter().enumerate().map(|(i, &q)| {
            let (ix, iy) = frame.cell_of(q);
            ((iy * frame.nx + ix) as u32, i as u32)
        });
        let (start, items) = crate::mesh::compressed_rows(frame.nx * frame.ny, cells);
        let scale = lo.abs().max(frame.far.abs()).max_element().max(frame.cell);
        Some(Nearby {
            points,
            frame,
            start,
            items,
            slack: 1e-9 * scale,
        })
    }

    /// Calls `visit` with `(distance², index)` of every vertex in cells `x0..=x1` × `y0..=y1`.
    fn scan(
        &self,
        p: Point,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
        mut visit: impl FnMut(f64, u32),
    ) {
        for iy in y0..=y1 {
            let row = iy * self.frame.nx;
            let (s, e) = (self.start[row + x0], self.start[row + x1 + 1]);
            for &i in &self.items[s..e] {
                visit(self.points[i as usize].distance_squared(p), i);
            }
        }
    }

    /// [`carriers_by_scan`]'s answer for `p` (a finite point), from the cells around it.
    fn carriers(&self, p: Point) -> (Vec<(f64, u32)>, f64) {
        let k = MIN_CARRIERS.min(self.points.len());
        // The k smallest squared distances, ascending, from rings of cells around p's cell
        // until every cell not yet seen lies farther than the k-th.
        let mut best = [f64::INFINITY; MIN_CARRIERS];
        let keep = |best: &mut [f64; MIN_CARRIERS], d2: f64| {
            if d2 < best[k - 1] {
                let mut j = k - 1;
                while j > 0 && best[j - 1] > d2 {
                    best[j] = best[j - 1];
                    j -= 1;
                }
                best[j] = d2;
            }
        };
        let (cx, cy) = self.frame.cell_of(p);
        for r in 0.. {
            let ((x0, x1), (y0, y1)) = self.frame.ring_square((cx, cy), r);
            for (xs, ys) in self.frame.ring_strips((cx, cy), r) {
                self.scan(p, xs, ys, |d2, _| keep(&mut best, d2));
            }
            // Every vertex not yet seen lies in a cell beyond the square.
            let beyond = self.frame.beyond(p, (x0, x1), (y0, y1));
            if beyond == f64::INFINITY {
                break;
            }
            let bound = beyond - self.slack;
            if bound > 0.0 && best[k - 1] < bound * bound {
                break;
            }
        }
        let r2 = reach(best[0], best[k - 1]);
        // Every vertex within the radius, from the cells its disc meets (one more cell each
        // way for rounding in the cell assignment).
        let radius = r2.sqrt() + self.slack;
        let (o, c) = (self.frame.origin, self.frame.cell);
        let span = |v: f64, o: f64, n: usize| {
            let a = ((v - radius - o) / c).floor() - 1.0;
            let b = ((v + radius - o) / c).floor() + 1.0;
            (a.max(0.0) as usize).min(n - 1)..=(b.max(0.0) as usize).min(n - 1)
        };
        let (xs, ys) = (span(p.x, o.x, self.frame.nx), span(p.y, o.y, self.frame.ny));
        // Room for a typical vertex's carriers, so the list is not grown push by push.
        let mut kept = Vec::with_capacity(8 * MIN_CARRIERS);
        self.scan(
            p,
            (*xs.start(), *xs.end()),
            (*ys.start(), *ys.end()),
            |d2, i| {
                if d2 < r2 {
                    kept.push((d2, i));
                }
            },
        );
        // `by_order` on integer keys: a squared distance is never negative, −0 or NaN (the
        // points are finite), and there the bits of an `f64` order as the numbers do.
        kept.sort_unstable_by_key(|&(d2, i)| (d2.to_bits(), i));
        (kept, r2)
    }
}

/// Attaches `p` to the boundary: its carriers (from `near` when there is a grid, else by a
/// scan) and its side's half of the best fit.
fn attach(boundary: &[Point], near: Option<&Nearby<'_>>, p: Point) -> Attachment {
    let (by_distance, r2) = match near {
        Some(g) if p.is_finite() => g.carriers(p),
        _ => carriers_by_scan(boundary, p),
    };
    let floor = 1e-12 * r2;
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
    /// `(source, target)`, taking from `made` the attachments it holds and keeping there the
    /// ones made now. `None` if the boundary has no vertices or the two sides differ in length.
    pub(crate) fn new(
        boundary: (&[Point], &[Point]),
        features: &[(&[Point], &[Point])],
        made: &mut Attachments,
    ) -> Option<Self> {
        let (b0, b1) = boundary;
        if b0.is_empty() || b1.len() != b0.len() {
            return None;
        }
        let f0: Vec<&[Point]> = features.iter().map(|f| f.0).collect();
        let f1: Vec<&[Point]> = features.iter().map(|f| f.1).collect();
        let features = made
            .attach(b0, &f0)
            .into_iter()
            .zip(made.attach(b1, &f1))
            .map(|(a0, a1)| [a0, a1])
            .collect();
        Some(Carried { features })
    }

    /// The features at `t`, given the intermediate boundary `boundary_t` (same vertex count),
    /// into `out[f]`.
    pub(crate) fn features_at(&self, t: f64, boundary_t: &[Point], out: &mut [Vec<Point>]) {
        for (o, [f0, f1]) in out.iter_mut().zip(&self.features) {
            o.clear();
            o.extend(f0.iter().zip(f1.iter()).map(|(a0, a1)| {
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
            prop_assert_eq!(bits(&attach(&b, None, q).carriers), bits(&attach_by_full_sort(&b, q)));
        }
    }

    /// `Nearby`'s carriers against the scan's, bit for bit: distances, indices, order and radius.
    fn assert_grid_matches_scan(b: &[Point], q: Point) -> Result<(), TestCaseError> {
        let bits = |(c, r2): (Vec<(f64, u32)>, f64)| {
            (
                c.iter().map(|&(d, i)| (d.to_bits(), i)).collect::<Vec<_>>(),
                r2.to_bits(),
            )
        };
        let grid = Nearby::new(b).expect("finite, non-empty boundary");
        prop_assert_eq!(bits(grid.carriers(q)), bits(carriers_by_scan(b, q)));
        Ok(())
    }

    proptest! {
        /// On a coarse lattice (equal distances everywhere, repeated vertices, queries on a
        /// vertex, outside the boundary's box, far away), stretched to thin boxes, and with
        /// fewer vertices than MIN_CARRIERS.
        #[test]
        fn the_grid_finds_the_carriers_of_the_scan_on_a_lattice(
            boundary in proptest::collection::vec((-8i32..9, -8i32..9), 1..120),
            p in (-40i32..41, -40i32..41),
            stretch in prop_oneof![Just(1.0f64), Just(1e-3), Just(250.0)],
        ) {
            let b: Vec<Point> = boundary.iter().map(|&(x, y)| Point::new(x as f64, y as f64 * stretch)).collect();
            assert_grid_matches_scan(&b, Point::new(p.0 as f64 * 0.25, p.1 as f64 * 0.25 * stretch))?;
        }

        /// Random points, clustered or spread, in a box far from the origin (so the cell
        /// bounds round), queried anywhere around them.
        #[test]
        fn the_grid_finds_the_carriers_of_the_scan_anywhere(
            boundary in proptest::collection::vec((0.0f64..1.0, 0.0f64..1.0), 1..300),
            cluster in proptest::bool::ANY,
            offset in prop_oneof![Just(0.0f64), Just(1e6), Just(-3.7e3)],
            size in prop_oneof![Just(1.0f64), Just(1e-6), Just(4e4)],
            p in (-0.5f64..1.5, -0.5f64..1.5),
        ) {
            let place = |x: f64| offset + size * x;
            let b: Vec<Point> = boundary
                .iter()
                .map(|&(x, y)| if cluster { Point::new(place(x * x * x), place(y * y * y)) } else { Point::new(place(x), place(y)) })
                .collect();
            assert_grid_matches_scan(&b, Point::new(place(p.0), place(p.1)))?;
        }
    }

    /// A circle of `n` vertices of radius `r` about `c`.
    fn circle(n: usize, r: f64, c: Point) -> Vec<Point> {
        (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                c + Point::new(r * a.cos(), r * a.sin())
            })
            .collect()
    }

    /// The features at a few times, as bits.
    fn features_bits(c: &Carried, boundary_t: &[Point], n: usize) -> Vec<Vec<(u64, u64)>> {
        let mut out = vec![Vec::new(); n];
        let mut bits = Vec::new();
        for t in [0.0, 0.3, 0.7, 1.0] {
            c.features_at(t, boundary_t, &mut out);
            bits.extend(
                out.iter()
                    .map(|f| f.iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect()),
            );
        }
        bits
    }

    #[test]
    fn attachments_kept_from_earlier_models_are_reused_and_carry_alike() {
        let (b0, b1) = (
            circle(40, 10.0, Point::ZERO),
            circle(40, 12.0, Point::new(3.0, -1.0)),
        );
        let (h0, h1) = (
            circle(9, 2.0, Point::new(3.0, 1.0)),
            circle(9, 3.0, Point::new(5.0, 0.0)),
        );
        let (k0, k1) = (
            circle(7, 1.5, Point::new(-4.0, -2.0)),
            circle(7, 1.0, Point::new(-2.0, -4.0)),
        );
        let both = [(&h0[..], &h1[..]), (&k0[..], &k1[..])];
        let fresh = Carried::new((&b0, &b1), &both, &mut Attachments::default()).unwrap();
        let made = &mut Attachments::default();
        // A model with one hole, then the other way round (the other side triangulated), then
        // both holes: the last takes the first hole's attachments from the first two.
        let one = Carried::new((&b0, &b1), &both[..1], made).unwrap();
        let reversed = Carried::new((&b1, &b0), &[(&h1[..], &h0[..])], made).unwrap();
        let reused = Carried::new((&b0, &b1), &both, made).unwrap();
        assert!(Arc::ptr_eq(&one.features[0][0], &reused.features[0][0]));
        assert!(Arc::ptr_eq(
            &reversed.features[0][0],
            &reused.features[0][1]
        ));
        assert!(Arc::ptr_eq(&one.features[0][0], &reversed.features[0][1]));
        assert_eq!(made.boundaries.len(), 2);
        // Reused or made anew, the features move to the same bits.
        let mid = circle(40, 11.0, Point::new(1.0, 0.5));
        assert_eq!(
            features_bits(&reused, &mid, 2),
            features_bits(&fresh, &mid, 2)
        );
        // A boundary that differs in one bit is another boundary.
        let mut moved = b0.clone();
        moved[3].x = f64::from_bits(moved[3].x.to_bits() + 1);
        let other = Carried::new((&moved, &b1), &both[..1], made).unwrap();
        assert!(!Arc::ptr_eq(&other.features[0][0], &one.features[0][0]));
        assert_eq!(made.boundaries.len(), 3);
    }

    #[test]
    fn a_boundary_with_a_non_finite_vertex_has_no_grid_and_is_scanned() {
        let b = [
            Point::new(0.0, 0.0),
            Point::new(f64::NAN, 1.0),
            Point::new(2.0, 0.0),
        ];
        assert!(Nearby::new(&b).is_none());
        assert!(Nearby::new(&[]).is_none());
        let a = attach(&b, None, Point::new(1.0, 0.5));
        assert_eq!(a.carriers.len(), 2);
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
            let a = attach(&b, None, Point::new(p.0, p.1));
            let bits = |q: Point| (q.x.to_bits(), q.y.to_bits());
            prop_assert_eq!(bits(carry(&a, &to)), bits(carry_both_sides(&a, &b, &to)));
            prop_assert_eq!(bits(carry(&a, &b)), bits(carry_both_sides(&a, &b, &b)));
        }
    }
}
