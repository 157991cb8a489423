//! Features carried by the boundary around them: an alternative placement of the feature curves
//! of the shape model (§5) for shapes that bend.
//!
//! The barycenter-based shape model moves every curve as one body whose position comes from
//! the barycenter mesh. When the shape bends — a U becoming an S — a feature in an arm has to
//! swing with that arm, which the barycenter mesh (a few nodes, all connected) cannot express,
//! and the intermediate features leave the band of the boundary they lie in. Here each feature
//! vertex is instead attached to the boundary vertices nearest to it: every such vertex carries
//! a local frame (its position, the direction of its outgoing edge, the local scale of the
//! edges), the feature vertex's offset in that frame is kept, and the frames' predictions are
//! averaged with inverse-square-distance weights. Doing so once from the source side and once
//! from the target side and blending the two by `t` gives exactly the source features at 0 and
//! the target features at 1. Each edge's turn is unwrapped consistently with the boundary's
//! total turn, so arms that turn beyond a half turn carry their features the same way round.

use crate::geometry::Point;
use std::f64::consts::TAU;

/// Boundary vertices whose frames carry one feature vertex.
const CARRIERS: usize = 12;
/// Half-width (edges) of the window over which a frame's scale is measured.
const SCALE_WINDOW: usize = 2;

/// One side's attachment of a feature vertex: its position and the weighted carrier vertices.
#[derive(Debug, Clone)]
struct Attachment {
    point: Point,
    carriers: Vec<(u32, f64)>,
}

/// Feature vertices attached to the boundary at both ends of the morph.
#[derive(Debug, Clone)]
pub(crate) struct Carried {
    /// Boundary at t = 0 and t = 1.
    boundary: [Vec<Point>; 2],
    /// Unwrapped total turn of each boundary edge from t = 0 to t = 1.
    total_turn: Vec<f64>,
    /// Per feature, per vertex: attachments at t = 0 and t = 1.
    features: Vec<Vec<[Attachment; 2]>>,
}

/// `a + 2kπ` closest to `reference`.
fn branch_near(a: f64, reference: f64) -> f64 {
    a + TAU * ((reference - a) / TAU).round()
}

fn direction(p: &[Point], k: usize) -> Point {
    p[(k + 1) % p.len()] - p[k]
}

fn angle_between(a: Point, b: Point) -> f64 {
    a.perp_dot(b).atan2(a.dot(b))
}

fn attach(boundary: &[Point], p: Point) -> Attachment {
    let mut idx: Vec<(f64, u32)> = boundary
        .iter()
        .enumerate()
        .map(|(i, b)| (b.distance_squared(p), i as u32))
        .collect();
    // The nearest CARRIERS vertices, weighted 1/d² − 1/r² with r the distance of the next one,
    // so that the weights change continuously along a feature as its carriers change.
    let k = (CARRIERS + 1).min(idx.len());
    idx.select_nth_unstable_by(k - 1, |x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    idx.truncate(k);
    idx.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let floor = 1e-12 * idx[k - 1].0.max(f64::MIN_POSITIVE);
    let cut = if k > CARRIERS {
        1.0 / idx[k - 1].0.max(floor)
    } else {
        0.0
    };
    idx.truncate(CARRIERS.min(idx.len()));
    if idx[0].0 <= floor {
        // On a boundary vertex: carried by it alone.
        idx.truncate(1);
    }
    let mut carriers: Vec<(u32, f64)> = idx
        .iter()
        .map(|&(d2, i)| (i, (1.0 / d2.max(floor) - cut).max(0.0)))
        .collect();
    if carriers.iter().all(|c| c.1 <= 0.0) {
        carriers.iter_mut().for_each(|c| c.1 = 1.0);
    }
    let sum: f64 = carriers.iter().map(|c| c.1).sum();
    for c in &mut carriers {
        c.1 /= sum;
    }
    Attachment { point: p, carriers }
}

impl Carried {
    /// Attaches the features (`features[f] = (source, target)` vertex lists) to the boundary
    /// `(source, target)`, whose source-to-target turn is `rotation` (the shape model's
    /// consistent choice of branch). `None` if the boundary has fewer than three vertices or a
    /// zero-length edge.
    pub(crate) fn new(
        boundary: (&[Point], &[Point]),
        rotation: f64,
        features: &[(&[Point], &[Point])],
    ) -> Option<Self> {
        let (b0, b1) = boundary;
        let n = b0.len();
        if n < 3 || b1.len() != n {
            return None;
        }
        if (0..n).any(|k| direction(b0, k) == Point::ZERO || direction(b1, k) == Point::ZERO) {
            return None;
        }
        // Edge 0's turn on the branch nearest the boundary's turn, the others following the
        // change of the turning angles along the curve.
        let mut total_turn = Vec::with_capacity(n);
        let mut turn = branch_near(angle_between(direction(b0, 0), direction(b1, 0)), rotation);
        total_turn.push(turn);
        for k in 1..n {
            let d0 = angle_between(direction(b0, k - 1), direction(b0, k));
            let d1 = angle_between(direction(b1, k - 1), direction(b1, k));
            turn += d1 - d0;
            total_turn.push(branch_near(
                angle_between(direction(b0, k), direction(b1, k)),
                turn,
            ));
            turn = total_turn[k];
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
        Some(Carried {
            boundary: [b0.to_vec(), b1.to_vec()],
            total_turn,
            features,
        })
    }

    /// The features at `t`, given the intermediate boundary `boundary_t` (same vertex count),
    /// into `out[f]`.
    pub(crate) fn features_at(&self, t: f64, boundary_t: &[Point], out: &mut [Vec<Point>]) {
        let n = boundary_t.len();
        // Per side and boundary vertex: the frame's turn and scale from that side to t.
        let frames: Vec<Vec<(Point, f64)>> = (0..2)
            .map(|side| {
                let b = &self.boundary[side];
                let lengths = |p: &[Point], k: usize| -> f64 {
                    (0..=2 * SCALE_WINDOW)
                        .map(|d| direction(p, (k + n + d - SCALE_WINDOW) % n).length())
                        .sum()
                };
                (0..n)
                    .map(|k| {
                        // Predicted turn from this side to t, then the actual one on its branch.
                        let expected = if side == 0 {
                            t * self.total_turn[k]
                        } else {
                            -(1.0 - t) * self.total_turn[k]
                        };
                        // The chord over the window: steadier than one edge.
                        let chord = |p: &[Point]| {
                            p[(k + SCALE_WINDOW + 1) % n] - p[(k + n - SCALE_WINDOW) % n]
                        };
                        let actual =
                            branch_near(angle_between(chord(b), chord(boundary_t)), expected);
                        let scale = lengths(boundary_t, k) / lengths(b, k);
                        (Point::from_angle(actual), scale)
                    })
                    .collect()
            })
            .collect();
        for (o, f) in out.iter_mut().zip(&self.features) {
            o.clear();
            o.extend(f.iter().map(|ends| {
                let mut blended = Point::ZERO;
                for (side, a) in ends.iter().enumerate() {
                    let b = &self.boundary[side];
                    let mut p = Point::ZERO;
                    for &(i, w) in &a.carriers {
                        let i = i as usize;
                        let (rot, scale) = frames[side][i];
                        p += (boundary_t[i] + rot.rotate(a.point - b[i]) * scale) * w;
                    }
                    blended += p * if side == 0 { 1.0 - t } else { t };
                }
                blended
            }));
        }
    }
}
