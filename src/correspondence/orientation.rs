//! Orientation of curve pairs (§3): closed curves run counter-clockwise, and an open target curve
//! runs the way that matches its source best.
//!
//! "Matches best" is measured by a best-fit similarity (Procrustes) between equal-count
//! arc-length resamplings of the two curves: the relative residual of the least-squares
//! rotation + uniform scale + translation that carries one point list onto the other. The same
//! measure picks the start of a closed target curve when no salient point can be associated
//! (circle ↔ ellipse).

use super::measure::Polyline;
use crate::geometry::{polygon_area, Point, SimilarityFit};

/// Number of arc-length samples used to compare two curves' shapes.
pub(crate) const SHAPE_SAMPLES: usize = 64;

/// Relative residual of the best similarity (rotation, uniform scale, translation) carrying `a`
/// onto `b`: `0` for similar point lists, `1` when the best fit is to collapse `a` to `b`'s
/// centroid. Equal lengths assumed.
pub(crate) fn similarity_residual(a: &[Point], b: &[Point]) -> f64 {
    let f = SimilarityFit::new(a, b);
    relative(
        f.to_spread - (f.dot * f.dot + f.cross * f.cross) / f.from_spread.max(f64::MIN_POSITIVE),
        f.to_spread,
    )
}

/// Relative residual of the best fit of `a` onto `b` by uniform scale and translation only (no
/// rotation): the tie-breaker that prefers correspondences needing the least turning.
pub(crate) fn unrotated_residual(a: &[Point], b: &[Point]) -> f64 {
    let f = SimilarityFit::new(a, b);
    let dot = f.dot.max(0.0);
    relative(
        f.to_spread - dot * dot / f.from_spread.max(f64::MIN_POSITIVE),
        f.to_spread,
    )
}

fn relative(residual: f64, scale: f64) -> f64 {
    if scale > 0.0 {
        (residual / scale).max(0.0)
    } else {
        0.0
    }
}

/// The closed curve made counter-clockwise (positive shoelace area in user coordinates), keeping
/// its first vertex.
pub(crate) fn counter_clockwise(curve: Polyline) -> Polyline {
    if polygon_area(curve.points()) < 0.0 {
        curve.reversed()
    } else {
        curve
    }
}

/// Whether the open target curve should be reversed to match the source: it is reversed when
/// its reversed resampling has a strictly smaller [`similarity_residual`] against the source's
/// than its as-drawn one. Ties (straight lines, curves with a half-turn symmetry) keep the
/// direction as drawn.
pub(crate) fn open_target_reversed(src: &Polyline, tgt: &Polyline) -> bool {
    let a = src.resample(SHAPE_SAMPLES, 0.0);
    let b = tgt.resample(SHAPE_SAMPLES, 0.0);
    let drawn = similarity_residual(&a, &b);
    let rev: Vec<Point> = b.iter().rev().copied().collect();
    let reversed = similarity_residual(&a, &rev);
    reversed < drawn - 1e-9
}

/// How much worse (in relative residual) a start of a closed feature may fit than the best one
/// and still be chosen for turning with the boundary ([`best_closed_start`]).
pub(crate) const TURN_SLACK: f64 = 0.03;

/// The best-fit rotation angle (radians, in (−π, π]) carrying the centred point list `a` onto `b`.
pub(crate) fn best_fit_rotation(a: &[Point], b: &[Point]) -> f64 {
    SimilarityFit::new(a, b).rotation()
}

/// Where the least-squares similarity (rotation, uniform scale, translation) carrying `a` onto
/// `b` takes `p`, and the RMS distance of `b` from its centroid (the scale to measure misfits
/// in). Equal lengths assumed; a degenerate `a` maps everything to `b`'s centroid.
pub(crate) fn similarity_apply(a: &[Point], b: &[Point], p: Point) -> (Point, f64) {
    let f = SimilarityFit::new(a, b);
    let spread = (f.to_spread / b.len().max(1) as f64).sqrt();
    if f.from_spread <= 0.0 {
        return (f.to_centroid, spread);
    }
    let (c, s) = (f.dot / f.from_spread, f.cross / f.from_spread);
    let d = p - f.from_centroid;
    (
        f.to_centroid + Point::new(c * d.x - s * d.y, s * d.x + c * d.y),
        spread,
    )
}

/// [`unrotated_residual`] after turning `a` by `turn` (none when `None`): how far matching `a` to
/// `b` is from needing exactly that turn. The tie-breaker between symmetric correspondences.
pub(crate) fn turn_residual(a: &[Point], b: &[Point], turn: Option<f64>) -> f64 {
    match turn {
        None => unrotated_residual(a, b),
        Some(th) => {
            let (s, c) = th.sin_cos();
            let turned: Vec<Point> = a
                .iter()
                .map(|p| Point::new(c * p.x - s * p.y, s * p.x + c * p.y))
                .collect();
            unrotated_residual(&turned, b)
        }
    }
}

/// The target vertex at which a closed target curve should start so that it matches the source
/// started at its vertex 0 best.
///
/// Without a preferred `turn` (the boundary): the smallest [`similarity_residual`] between
/// equal-count resamplings; among starts within 0.1% of the best (a symmetric pair such as
/// circle ↔ ellipse), the one needing the least turning ([`unrotated_residual`]), then the
/// lowest index.
///
/// With a preferred `turn` (features, given the boundary's turn): among the starts whose residual
/// is within [`TURN_SLACK`] of the best, the one whose best-fit rotation is nearest `turn`. A
/// smooth closed feature (a spot, an eye) fits its twin almost equally well at many starts;
/// turning it with its surroundings matters more for the morph than the last bit of shape fit,
/// because a feature spinning against its surroundings forces every mapping to fold.
pub(crate) fn best_closed_start(src: &Polyline, tgt: &Polyline, turn: Option<f64>) -> usize {
    let a = src.resample(SHAPE_SAMPLES, 0.0);
    let scored: Vec<(usize, f64, Vec<Point>)> = (0..tgt.len())
        .map(|j| {
            let b = tgt.resample(SHAPE_SAMPLES, tgt.s(j));
            (j, similarity_residual(&a, &b), b)
        })
        .collect();
    let best = scored.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
    if let Some(turn) = turn {
        let mut choice = (0usize, f64::INFINITY);
        for (j, r, b) in &scored {
            if *r <= best + TURN_SLACK {
                let d = best_fit_rotation(&a, b) - turn;
                let d = d.sin().atan2(d.cos()).abs();
                if d < choice.1 - 1e-12 {
                    choice = (*j, d);
                }
            }
        }
        return choice.0;
    }
    let limit = best * 1.001 + 1e-12;
    let mut choice = (usize::MAX, f64::INFINITY);
    for (j, r, b) in &scored {
        if *r <= limit {
            let u = turn_residual(&a, b, turn);
            if u < choice.1 {
                choice = (*j, u);
            }
        }
    }
    if choice.0 == usize::MAX {
        0
    } else {
        choice.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn similarity_residual_ignores_rotation_scale_and_translation() {
        let a = [p(0., 0.), p(1., 0.), p(1., 2.)];
        let b: Vec<Point> = a
            .iter()
            .map(|q| p(-q.y * 3.0 + 5.0, q.x * 3.0 - 1.0))
            .collect();
        assert!(similarity_residual(&a, &b) < 1e-12);
        assert!(unrotated_residual(&a, &b) > 0.1);
        let mirrored: Vec<Point> = a.iter().map(|q| p(-q.x, q.y)).collect();
        assert!(similarity_residual(&a, &mirrored) > 0.01);
    }

    #[test]
    fn closed_curves_become_counter_clockwise() {
        let cw = Polyline::new(vec![p(0., 0.), p(0., 1.), p(1., 1.), p(1., 0.)], true);
        let ccw = counter_clockwise(cw);
        assert!(polygon_area(ccw.points()) > 0.0);
        assert_eq!(ccw.points()[0], p(0., 0.));
    }

    #[test]
    fn a_hook_drawn_backwards_is_reversed() {
        let hook = vec![p(0., 0.), p(0., 4.), p(1., 5.), p(2., 4.)];
        let src = Polyline::new(hook.clone(), false);
        let same = Polyline::new(hook.iter().map(|q| *q * 2.0).collect(), false);
        let back = Polyline::new(hook.iter().rev().copied().collect(), false);
        assert!(!open_target_reversed(&src, &same));
        assert!(open_target_reversed(&src, &back));
    }
}
