//! The barycenter-based shape model (BSM, §5): intermediate boundary and feature curves between
//! the source and the target, for the composite harmonic mapping.
//!
//! Each curve's shape is described by its intrinsic parameters \[9\] — edge lengths and turning
//! angles — interpolated linearly, `M_s^t = M_s^0 + t (M_s^1 − M_s^0)`. The spatial relation
//! between curves is described by the *barycenter mesh*: one node per curve at its barycenter
//! (vertex mean), every node connected to every other, interpolated with the disc-based
//! rigidity-preserving interpolation of §4.1 ([`crate::rigid::Interpolator`]). A curve at time `t`
//! is rebuilt from its interpolated lengths and angles, closed again (for closed curves) by the
//! smallest relative change of its edge lengths (after Sederberg et al. 1993), turned so that its
//! best-fit rotation relative to the source curve is `t` times the source-to-target rotation, and
//! moved so that its barycenter sits on the barycenter mesh's node at `t`.

use super::carried::{Attachments, Carried};
use crate::correspondence::CurvePair;
use crate::geometry::{bounding_box, centroid, Point};
use crate::mesh::Side;
use crate::rigid::Interpolator;
use crate::triangulation::side_of;
use crate::{Error, Result};
use std::f64::consts::{PI, TAU};

/// Intrinsic description of one curve at both ends of the morph.
#[derive(Debug, Clone)]
struct CurveModel {
    closed: bool,
    /// The curve at t = 0 and t = 1, exactly.
    from: Vec<Point>,
    to: Vec<Point>,
    /// `from` minus its barycenter (reference for the best-fit rotation).
    from_centred: Vec<Point>,
    /// Edge lengths at both ends (closed curves include the closing edge).
    len: [Vec<f64>; 2],
    /// Turning angles in (−π, π] at vertices 1..m−1 (between edge k−1 and edge k).
    turn: [Vec<f64>; 2],
    /// Direction of the first edge at t = 0.
    start_direction: f64,
    /// Best-fit rotation from `from` to `to`, on the branch consistent with the barycenter mesh.
    rotation: f64,
}

/// The barycenter-based shape model of a set of curve pairs (§5, Fig.9): gives the intermediate
/// curves at any `t ∈ [0, 1]`, exactly the source curves at 0 and the target curves at 1.
#[derive(Debug)]
pub struct ShapeModel {
    curves: Vec<CurveModel>,
    /// Barycenters at both ends.
    bary: [Vec<Point>; 2],
    /// Rigid interpolation of the barycenter mesh; `None` for a single curve or when the
    /// barycenter mesh is degenerate (barycenters then move linearly).
    interpolator: Option<Interpolator>,
    /// Straight-line vertex interpolation instead of the BSM (see [`ShapeModel::linear`]).
    linear: bool,
    /// Features carried by the boundary instead of placed by the barycenter mesh (see
    /// [`ShapeModel::carried`]).
    carried: Option<Carried>,
}

/// Angle of the rotation that best maps the point set `a` onto `b` (2D Procrustes, about their
/// centroids), in (−π, π].
fn best_fit_rotation(a: &[Point], b: &[Point]) -> f64 {
    crate::geometry::SimilarityFit::new(a, b).rotation()
}

/// Turns beyond this (150°) are close enough to a half turn that their direction is ambiguous.
const AMBIGUOUS_TURN: f64 = 5.0 * PI / 6.0;

/// `a + 2kπ` closest to `reference`; `a` itself when it is within π (so ties keep the smaller
/// turn).
fn branch_near(a: f64, reference: f64) -> f64 {
    if (a - reference).abs() <= PI {
        a
    } else {
        a + TAU * ((reference - a) / TAU).round()
    }
}

/// Signed angle from `a` to `b` in [−π, π], accurate for nearly parallel vectors (unlike an
/// arccosine).
fn turning_angle(a: Point, b: Point) -> f64 {
    a.perp_dot(b).atan2(a.dot(b))
}

fn rotate(p: Point, angle: f64) -> Point {
    Point::from_angle(angle).rotate(p)
}

/// Edge lengths and turning angles of a polyline; `None` if an edge has zero length.
fn intrinsic(points: &[Point], closed: bool) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = points.len();
    let m = if closed { n } else { n - 1 };
    let edges: Vec<Point> = (0..m).map(|k| points[(k + 1) % n] - points[k]).collect();
    let len: Vec<f64> = edges.iter().map(|e| e.length()).collect();
    if len.iter().any(|&l| l <= 0.0 || !l.is_finite()) {
        return None;
    }
    let turn = (1..m)
        .map(|k| turning_angle(edges[k - 1], edges[k]))
        .collect();
    Some((len, turn))
}

impl CurveModel {
    fn new(id: &str, closed: bool, from: &[Point], to: &[Point]) -> Result<Self> {
        let degenerate = || Error::at(crate::error::Drawings::Pair, id, "has a zero-length edge");
        if from.len() != to.len() || from.len() < 2 {
            return Err(Error::internal(format!(
                "shape model: curve '{id}' has mismatched vertex lists"
            )));
        }
        let (l0, t0) = intrinsic(from, closed).ok_or_else(degenerate)?;
        let (l1, t1) = intrinsic(to, closed).ok_or_else(degenerate)?;
        let (c0, c1) = (centroid(from), centroid(to));
        let from_centred: Vec<Point> = from.iter().map(|p| *p - c0).collect();
        let to_centred: Vec<Point> = to.iter().map(|p| *p - c1).collect();
        let d = from[1] - from[0];
        Ok(CurveModel {
            closed,
            from: from.to_vec(),
            to: to.to_vec(),
            rotation: best_fit_rotation(&from_centred, &to_centred),
            from_centred,
            len: [l0, l1],
            turn: [t0, t1],
            start_direction: d.y.atan2(d.x),
        })
    }

    /// The curve at `t`, centred on the origin, in `out`.
    fn centred_at(&self, t: f64, out: &mut Vec<Point>) {
        let n = self.from.len();
        let m = self.len[0].len();
        let mut dirs: Vec<Point> = Vec::with_capacity(m);
        let mut lens: Vec<f64> = (0..m)
            .map(|k| (1.0 - t) * self.len[0][k] + t * self.len[1][k])
            .collect();
        let mut phi = self.start_direction;
        dirs.push(Point::from_angle(phi));
        for k in 1..m {
            phi += (1.0 - t) * self.turn[0][k - 1] + t * self.turn[1][k - 1];
            dirs.push(Point::from_angle(phi));
        }
        if self.closed {
            // Close the polygon: minimize Σ (δ_k / l_k)² subject to Σ (l_k + δ_k) u_k = 0.
            let gap: Point = lens.iter().zip(&dirs).map(|(l, u)| *u * *l).sum();
            let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
            for (l, u) in lens.iter().zip(&dirs) {
                let w = l * l;
                a += w * u.x * u.x;
                b += w * u.x * u.y;
                c += w * u.y * u.y;
            }
            let det = a * c - b * b;
            if det.abs() > 1e-300 {
                let mu = Point::new(c * gap.x - b * gap.y, a * gap.y - b * gap.x) / det;
                for (l, u) in lens.iter_mut().zip(&dirs) {
                    *l -= *l * *l * u.dot(mu);
                }
            }
        }
        out.clear();
        let mut p = Point::ZERO;
        out.push(p);
        for k in 0..n - 1 {
            p += dirs[k] * lens[k];
            out.push(p);
        }
        let c = centroid(out);
        for q in out.iter_mut() {
            *q -= c;
        }
    }
}

impl ShapeModel {
    /// Builds the model from the source side to the target side of `pairs` (target to source
    /// when `triangulated` is the target). Errors on curves with zero-length edges.
    pub fn new(pairs: &[CurvePair], triangulated: Side) -> Result<Self> {
        let mut curves = pairs
            .iter()
            .map(|p| {
                CurveModel::new(
                    &p.id,
                    p.closed,
                    side_of(p, triangulated),
                    side_of(p, triangulated.other()),
                )
            })
            .collect::<Result<Vec<_>>>()?;
        let b0: Vec<Point> = curves.iter().map(|c| centroid(&c.from)).collect();
        let b1: Vec<Point> = curves.iter().map(|c| centroid(&c.to)).collect();
        let scale = bounding_box(
            curves
                .iter()
                .flat_map(|c| c.from.iter().chain(&c.to).copied()),
        )
        .map(|(lo, hi)| lo.distance(hi))
        .unwrap_or(0.0);
        let interpolator = barycenter_mesh(&b0, &b1, 1e-9 * scale);
        // Each curve turns by its best-fit rotation, on a 2kπ branch chosen so that all curves
        // turn the same way round. The boundary keeps its principal turn unless that is close to
        // a half turn, where the direction is ambiguous and the barycenter mesh's consistent
        // rotation (§4.1.1) decides; features take the branch nearest the boundary's turn. (The
        // barycenter mesh alone is no guide when its nodes are nearly collinear on one side, as
        // in U → S, where it would spin the boundary by 290° instead of turning it by −70°.)
        if let Some(first) = curves.first_mut() {
            if first.rotation.abs() > AMBIGUOUS_TURN {
                if let Some(ip) = &interpolator {
                    first.rotation = branch_near(first.rotation, ip.rotation_at(0));
                }
            }
        }
        if let Some(reference) = curves.first().map(|c| c.rotation) {
            for c in curves.iter_mut().skip(1) {
                c.rotation = branch_near(c.rotation, reference);
            }
        }
        Ok(ShapeModel {
            curves,
            bary: [b0, b1],
            interpolator,
            linear: false,
            carried: None,
        })
    }

    /// The straight-line alternative to the BSM (Fig.9(b), left): every curve vertex moves
    /// linearly. It distorts rotating curves, but keeps curves that translate or shear together
    /// in place relative to each other, so the composite mapping falls back to it when the BSM
    /// path folds the mesh.
    pub fn linear(pairs: &[CurvePair], triangulated: Side) -> Result<Self> {
        Ok(ShapeModel::new(pairs, triangulated)?.into_linear())
    }

    /// This model's curves followed along straight lines ([`ShapeModel::linear`]), without
    /// building the model again (the composite mapping turns to it when its other paths fail).
    pub(crate) fn into_linear(mut self) -> Self {
        self.interpolator = None;
        self.carried = None;
        self.linear = true;
        self
    }

    /// The BSM's boundary with the features carried by it: each feature vertex keeps its
    /// offset in the local frames of the boundary vertices nearest to it (`carried.rs`), instead
    /// of its curve moving as one body placed by the barycenter mesh. A feature in an arm that
    /// swings (a U becoming an S) swings with it. The composite mapping tries it when the BSM
    /// path folds the mesh. Falls back to the plain BSM when the boundary has a zero-length edge.
    pub fn carried(pairs: &[CurvePair], triangulated: Side) -> Result<Self> {
        Ok(ShapeModel::new(pairs, triangulated)?.with_carried(&mut Attachments::default()))
    }

    /// This BSM with its features carried by the boundary ([`ShapeModel::carried`]), taking
    /// the attachments of feature vertices to the boundary from `made` where it holds them and
    /// keeping there the ones made now (issue 16: the models of one part's maps share them).
    pub(crate) fn with_carried(mut self, made: &mut Attachments) -> Self {
        if let Some((b, fs)) = self.curves.split_first() {
            let features: Vec<(&[Point], &[Point])> = fs
                .iter()
                .map(|c| (c.from.as_slice(), c.to.as_slice()))
                .collect();
            self.carried = Carried::new((&b.from, &b.to), &features, made);
        }
        self
    }

    /// Number of curves.
    pub fn len(&self) -> usize {
        self.curves.len()
    }

    /// Whether the model has no curves.
    pub fn is_empty(&self) -> bool {
        self.curves.is_empty()
    }

    /// The intermediate curves at `t` (clamped to [0, 1]) into `out`, one vertex list per curve
    /// in curve-pair order. At `t = 0` and `t = 1` these are exactly the end curves.
    pub fn curves_at(&self, t: f64, out: &mut Vec<Vec<Point>>) {
        let t = t.clamp(0.0, 1.0);
        out.resize(self.curves.len(), Vec::new());
        if t == 0.0 || t == 1.0 {
            for (o, c) in out.iter_mut().zip(&self.curves) {
                o.clone_from(if t == 0.0 { &c.from } else { &c.to });
            }
            return;
        }
        if self.linear {
            for (o, c) in out.iter_mut().zip(&self.curves) {
                o.clear();
                o.extend(c.from.iter().zip(&c.to).map(|(p, q)| p.lerp(*q, t)));
            }
            return;
        }
        let mut centres = vec![Point::ZERO; self.curves.len()];
        match &self.interpolator {
            Some(ip) => {
                let mut ws = ip.workspace();
                ip.at(t, &mut centres, &mut ws);
            }
            None => {
                for (c, (p, q)) in centres
                    .iter_mut()
                    .zip(self.bary[0].iter().zip(&self.bary[1]))
                {
                    *c = p.lerp(*q, t);
                }
            }
        }
        for ((o, c), centre) in out.iter_mut().zip(&self.curves).zip(&centres) {
            c.centred_at(t, o);
            let turn = t * c.rotation - best_fit_rotation(&c.from_centred, o);
            for q in o.iter_mut() {
                *q = *centre + rotate(*q, turn);
            }
        }
        if let (Some(carried), Some((boundary, features))) = (&self.carried, out.split_first_mut())
        {
            carried.features_at(t, boundary, features);
        }
    }
}

/// The rigid interpolator of the barycenter mesh: complete graph on the barycenters, leaving out
/// pairs that coincide (closer than `eps`) at either end, where no rotation is defined.
fn barycenter_mesh(b0: &[Point], b1: &[Point], eps: f64) -> Option<Interpolator> {
    let n = b0.len();
    if n < 2 {
        return None;
    }
    let discs: Vec<Vec<u32>> = (0..n)
        .map(|i| {
            (0..n)
                .filter(|&j| j != i && b0[i].distance(b0[j]) > eps && b1[i].distance(b1[j]) > eps)
                .map(|j| j as u32)
                .collect()
        })
        .collect();
    if discs.iter().any(|d| d.is_empty()) {
        log::debug!("shape model: coincident barycenters, barycenters move linearly");
        return None;
    }
    Interpolator::from_discs(b0, b1, &discs).ok()
}

/// Wraps an angle to (−π, π].
#[cfg(test)]
fn wrap(a: f64) -> f64 {
    let r = branch_near(a, 0.0);
    if r <= -PI {
        r + TAU
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::triangulation::tests::{circle, pair, subdivided};

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    fn scene() -> Vec<CurvePair> {
        let mut b = pair(
            "boundary",
            true,
            subdivided(&[p(0., 0.), p(10., 0.), p(10., 4.), p(0., 4.)], 6),
        );
        // target: a bent, stretched boundary with the same vertex count
        b.target = b
            .source
            .iter()
            .map(|q| p(q.x * 1.2, q.y + 0.05 * q.x * q.x))
            .collect();
        let mut eye = pair("feature-eye", true, circle(p(3., 2.), 1.0, 12));
        eye.target = circle(p(4., 4.), 0.5, 12)
            .iter()
            .map(|q| p(q.x * 1.5, q.y))
            .collect();
        let mut line = pair(
            "feature-line",
            false,
            vec![p(6., 1.), p(7., 2.), p(8., 2.5)],
        );
        line.target = vec![p(7., 3.), p(8., 2.), p(9., 3.)];
        vec![b, eye, line]
    }

    fn similar(pairs: &mut [CurvePair], angle: f64, s: f64, d: Point) {
        for pc in pairs {
            pc.target = pc
                .source
                .iter()
                .map(|q| d + s * rotate(*q, angle))
                .collect();
        }
    }

    #[test]
    fn reproduces_both_ends() {
        let pairs = scene();
        let m = ShapeModel::new(&pairs, Side::Source).unwrap();
        let mut out = Vec::new();
        m.curves_at(0.0, &mut out);
        assert!(pairs.iter().zip(&out).all(|(pc, o)| pc.source == *o));
        m.curves_at(1.0, &mut out);
        assert!(pairs.iter().zip(&out).all(|(pc, o)| pc.target == *o));
        // continuity at the ends
        for (t, side) in [(1e-9, Side::Source), (1.0 - 1e-9, Side::Target)] {
            m.curves_at(t, &mut out);
            for (pc, o) in pairs.iter().zip(&out) {
                let end = side_of(pc, side);
                let err = end
                    .iter()
                    .zip(o)
                    .map(|(a, b)| a.distance(*b))
                    .fold(0.0, f64::max);
                assert!(err < 1e-6, "{} off by {err} at t={t}", pc.id);
            }
        }
        // from the target side, the model runs backwards
        let back = ShapeModel::new(&pairs, Side::Target).unwrap();
        back.curves_at(0.0, &mut out);
        assert!(pairs.iter().zip(&out).all(|(pc, o)| pc.target == *o));
    }

    #[test]
    fn a_similarity_stays_a_similarity() {
        for deg in [30.0f64, 179.0, 181.0, 270.0] {
            let mut pairs = scene();
            let angle = deg.to_radians();
            similar(&mut pairs, angle, 1.7, p(5., -3.));
            let m = ShapeModel::new(&pairs, Side::Source).unwrap();
            let mut out = Vec::new();
            for t in [0.25, 0.5, 0.8] {
                m.curves_at(t, &mut out);
                // all curves together are one similarity of the source: fit it from two points
                let (a0, a1) = (pairs[0].source[0], pairs[0].source[3]);
                let (b0, b1) = (out[0][0], out[0][3]);
                let (da, db) = (a1 - a0, b1 - b0);
                let s = db.length() / da.length();
                let rot = turning_angle(da, db);
                for (pc, o) in pairs.iter().zip(&out) {
                    for (q, r) in pc.source.iter().zip(o) {
                        let expect = b0 + s * rotate(*q - a0, rot);
                        assert!(
                            expect.distance(*r) < 1e-9,
                            "deg {deg} t {t}: {} off by {}",
                            pc.id,
                            expect.distance(*r)
                        );
                    }
                }
                assert!((s - (1.0 - t + t * 1.7)).abs() < 1e-12);
                // the short way round: rotation t·angle with angle in (−π, π]
                assert!(
                    (wrap(rot - t * wrap(angle))).abs() < 1e-9,
                    "deg {deg} t {t} rot {rot}"
                );
            }
        }
    }

    #[test]
    fn a_half_turn_turns_every_curve_the_same_way() {
        let mut pairs = scene();
        similar(&mut pairs, PI, 1.0, p(0., 0.));
        let m = ShapeModel::new(&pairs, Side::Source).unwrap();
        let mut out = Vec::new();
        m.curves_at(0.5, &mut out);
        let turns: Vec<f64> = pairs
            .iter()
            .zip(&out)
            .map(|(pc, o)| {
                let (c0, c1) = (centroid(&pc.source), centroid(o));
                let a: Vec<Point> = pc.source.iter().map(|q| *q - c0).collect();
                let b: Vec<Point> = o.iter().map(|q| *q - c1).collect();
                best_fit_rotation(&a, &b)
            })
            .collect();
        for r in &turns {
            assert!((r.abs() - PI / 2.0).abs() < 1e-9, "{turns:?}");
            assert_eq!(r.signum(), turns[0].signum(), "{turns:?}");
        }
    }

    #[test]
    fn closed_curves_stay_closed_and_keep_their_length_budget() {
        let pairs = scene();
        let m = ShapeModel::new(&pairs, Side::Source).unwrap();
        let mut out = Vec::new();
        m.curves_at(0.5, &mut out);
        let eye = &out[1];
        let (l0, l1) = (
            crate::geometry::polyline_length(&pairs[1].source, true),
            crate::geometry::polyline_length(&pairs[1].target, true),
        );
        let l = crate::geometry::polyline_length(eye, true);
        assert!((l - 0.5 * (l0 + l1)).abs() < 0.05 * l, "{l} vs {l0} {l1}");
        assert!(crate::geometry::polygon_area(eye) > 0.0);
        assert!(crate::geometry::polyline_self_intersection(eye, true).is_none());
    }
}
