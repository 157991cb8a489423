//! The paint of a path that morphs as one shape (issue #6: "colours in a perceptual space such as
//! Oklab; gradients interpolate their stops").
//!
//! Solid colours mix in Oklab. Gradients interpolate in two parts:
//! - stops: both stop lists are resampled at the union of their offsets (each gradient's colour
//!   at an offset is what a renderer paints there: sRGB interpolation between its stops, a hard
//!   edge where two stops share an offset), then the colours mix in Oklab and the opacities
//!   linearly;
//! - geometry: each side's gradient rides with the morph — it is mapped by the affine map that
//!   best carries its own path's outline (the feature curves at rest) to the outline at t
//!   (least squares) — and the two mapped geometries blend linearly in a form where blending is
//!   meaningful: a linear gradient as its start and end points in user space (any affine image
//!   of a linear gradient is one), a radial gradient as the affine frame of its unit circle.
//!
//! A solid colour facing a gradient is that gradient's geometry with every stop that colour.
//! Gradients of different kinds (linear and radial) do not interpolate: such paths cross-fade.

use crate::artwork::{Gradient, GradientKind, GradientStop, Paint, Rgba, Spread};
use crate::color::mix;
use crate::geometry::{Point, SimilarityFit};
use kurbo::Affine;
use std::sync::Arc;

/// Whether two paints interpolate: two colours, a colour and a gradient, or two gradients of
/// the same kind, each gradient with at least one stop.
pub(super) fn compatible(a: &Paint, b: &Paint) -> bool {
    let stops = |p: &Paint| match p {
        Paint::Color(_) => true,
        Paint::Gradient(g) => !g.stops.is_empty(),
    };
    let same_kind = match (a, b) {
        (Paint::Gradient(x), Paint::Gradient(y)) => matches!(
            (x.kind, y.kind),
            (GradientKind::Linear { .. }, GradientKind::Linear { .. })
                | (GradientKind::Radial { .. }, GradientKind::Radial { .. })
        ),
        _ => true,
    };
    stops(a) && stops(b) && same_kind
}

/// The paint a fraction `t` of the way from `a` to `b`. `a_map` carries `a`'s gradient user
/// space (the source scene's root user space) into the frame, `b_map` likewise for `b`.
pub(super) fn mix_paint(a: &Paint, b: &Paint, t: f64, a_map: Affine, b_map: Affine) -> Paint {
    let (ga, gb) = match (a, b) {
        (Paint::Color(x), Paint::Color(y)) => return Paint::Color(mix(*x, *y, t)),
        (Paint::Color(x), Paint::Gradient(y)) => {
            let g = Geometry::of(y, b_map);
            ((g, solid(*x)), (g, y.stops.clone()))
        }
        (Paint::Gradient(x), Paint::Color(y)) => {
            let g = Geometry::of(x, a_map);
            ((g, x.stops.clone()), (g, solid(*y)))
        }
        (Paint::Gradient(x), Paint::Gradient(y)) => (
            (Geometry::of(x, a_map), x.stops.clone()),
            (Geometry::of(y, b_map), y.stops.clone()),
        ),
    };
    let spread = match a {
        Paint::Gradient(x) => x.spread,
        Paint::Color(_) => match b {
            Paint::Gradient(y) => y.spread,
            Paint::Color(_) => Spread::Pad,
        },
    };
    let (kind, transform) = ga.0.lerp(gb.0, t).kind();
    Paint::Gradient(Arc::new(Gradient {
        kind,
        transform,
        spread,
        stops: mix_stops(&ga.1, &gb.1, t),
    }))
}

/// Stops painting `c` everywhere.
fn solid(c: Rgba) -> Vec<GradientStop> {
    [0.0, 1.0]
        .map(|offset| GradientStop {
            offset,
            color: c,
            opacity: 1.0,
        })
        .to_vec()
}

/// A gradient's geometry in the frame's user space, in a form that blends linearly.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Geometry {
    /// Start and end points in user space (no gradient transform).
    Linear { start: Point, end: Point },
    /// The frame mapping the unit end circle (centre 0, radius `radius`: 1, or 0 for a
    /// degenerate gradient) to user space, with the focal circle in that frame.
    Radial {
        frame: Affine,
        radius: f64,
        focal: Point,
        focal_radius: f64,
    },
}

impl Geometry {
    /// `g`'s geometry mapped by `map` (after its own transform).
    fn of(g: &Gradient, map: Affine) -> Geometry {
        let m = map * g.transform;
        let p = |q: Point| {
            let r = m * kurbo::Point::new(q.x, q.y);
            Point::new(r.x, r.y)
        };
        match g.kind {
            GradientKind::Linear { start, end } => {
                // The gradient's parameter s(y) = (M⁻¹y − start)·d / |d|² is affine in y with
                // gradient L⁻ᵀd / |d|² (L: M's linear part), so the same gradient in user space
                // runs from M·start along that vector to where s = 1.
                let d = end - start;
                let [a, b, c, dd, _, _] = m.as_coeffs();
                let det = a * dd - b * c;
                let len2 = d.length_squared();
                let grad = Point::new(dd * d.x - b * d.y, -c * d.x + a * d.y) / (det * len2);
                let g2 = grad.length_squared();
                let start = p(start);
                let end = if g2.is_finite() && g2 > 0.0 {
                    start + grad / g2
                } else {
                    p(end)
                };
                Geometry::Linear { start, end }
            }
            GradientKind::Radial {
                center,
                radius,
                focal,
                focal_radius,
            } => {
                let r = if radius > 0.0 { radius } else { 1.0 };
                Geometry::Radial {
                    frame: m * Affine::translate((center.x, center.y)) * Affine::scale(r),
                    radius: if radius > 0.0 { 1.0 } else { 0.0 },
                    focal: (focal - center) / r,
                    focal_radius: focal_radius / r,
                }
            }
        }
    }

    /// The linear blend of two geometries of the same kind (`self` where kinds differ).
    fn lerp(self, other: Geometry, t: f64) -> Geometry {
        let l = |a: f64, b: f64| a + (b - a) * t;
        let lp = |a: Point, b: Point| a + (b - a) * t;
        match (self, other) {
            (Geometry::Linear { start, end }, Geometry::Linear { start: s2, end: e2 }) => {
                Geometry::Linear {
                    start: lp(start, s2),
                    end: lp(end, e2),
                }
            }
            (
                Geometry::Radial {
                    frame,
                    radius,
                    focal,
                    focal_radius,
                },
                Geometry::Radial {
                    frame: f2,
                    radius: r2,
                    focal: fo2,
                    focal_radius: fr2,
                },
            ) => {
                let (x, y) = (frame.as_coeffs(), f2.as_coeffs());
                Geometry::Radial {
                    frame: Affine::new(std::array::from_fn(|i| l(x[i], y[i]))),
                    radius: l(radius, r2),
                    focal: lp(focal, fo2),
                    focal_radius: l(focal_radius, fr2),
                }
            }
            _ => self,
        }
    }

    /// The gradient kind and transform drawing this geometry.
    fn kind(self) -> (GradientKind, Affine) {
        match self {
            Geometry::Linear { start, end } => {
                (GradientKind::Linear { start, end }, Affine::IDENTITY)
            }
            Geometry::Radial {
                frame,
                radius,
                focal,
                focal_radius,
            } => (
                GradientKind::Radial {
                    center: Point::ZERO,
                    radius,
                    focal,
                    focal_radius,
                },
                frame,
            ),
        }
    }
}

/// Offsets closer than this are one offset.
const SAME_OFFSET: f64 = 1e-9;

/// The stops of the blend of two gradients: both resampled at the union of their offsets (two
/// stops where either has a hard edge), colours mixed in Oklab, opacities linearly.
fn mix_stops(a: &[GradientStop], b: &[GradientStop], t: f64) -> Vec<GradientStop> {
    let mut offsets: Vec<f64> = a.iter().chain(b).map(|s| s.offset).collect();
    offsets.sort_by(f64::total_cmp);
    offsets.dedup_by(|x, y| (*x - *y).abs() <= SAME_OFFSET);
    let mut out = Vec::with_capacity(offsets.len());
    for u in offsets {
        let (al, ar) = (sample(a, u, false), sample(a, u, true));
        let (bl, br) = (sample(b, u, false), sample(b, u, true));
        let stop = |p: (Rgba, f64), q: (Rgba, f64)| GradientStop {
            offset: u,
            color: mix(p.0, q.0, t),
            opacity: p.1 + (q.1 - p.1) * t,
        };
        out.push(stop(al, bl));
        if al != ar || bl != br {
            out.push(stop(ar, br));
        }
    }
    out
}

/// The colour and opacity `stops` paint at `offset`, approached from below (`right` false) or
/// from above: the stop colours interpolated in sRGB as renderers do, the end stops' colours
/// beyond them. `stops` is non-empty, offsets ascending.
fn sample(stops: &[GradientStop], offset: f64, right: bool) -> (Rgba, f64) {
    let at = |s: &GradientStop| (s.color, s.opacity);
    let same: Vec<&GradientStop> = stops
        .iter()
        .filter(|s| (s.offset - offset).abs() <= SAME_OFFSET)
        .collect();
    if let (Some(first), Some(last)) = (same.first(), same.last()) {
        // Approached from below, a run of stops at one offset shows its first; from above,
        // its last (a hard edge).
        return at(if right { last } else { first });
    }
    let Some(k) = stops.iter().position(|s| s.offset > offset) else {
        return stops.last().map(at).unwrap_or((Rgba::TRANSPARENT, 0.0));
    };
    if k == 0 {
        return at(&stops[0]);
    }
    let (p, q) = (&stops[k - 1], &stops[k]);
    let f = (offset - p.offset) / (q.offset - p.offset);
    let ch = |x: u8, y: u8| (x as f64 + (y as f64 - x as f64) * f).round() as u8;
    (
        Rgba {
            r: ch(p.color.r, q.color.r),
            g: ch(p.color.g, q.color.g),
            b: ch(p.color.b, q.color.b),
            a: ch(p.color.a, q.color.a),
        },
        p.opacity + (q.opacity - p.opacity) * f,
    )
}

/// The affine map that best carries `from` onto `to` in the least-squares sense (pairs beyond
/// the shorter list ignored): the motion of a path's outline, which its gradient follows. Points
/// on a line leave the map across the line undetermined: then the best similarity, and for a
/// single point (or none) the translation.
pub(super) fn fitted_affine(from: &[Point], to: &[Point]) -> Affine {
    let n = from.len().min(to.len());
    if n == 0 {
        return Affine::IDENTITY;
    }
    let fit = SimilarityFit::new(&from[..n], &to[..n]);
    let (cp, cq) = (fit.from_centroid, fit.to_centroid);
    // Normal equations: L · Σ p pᵀ = Σ q pᵀ (centred).
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    let (mut qx, mut qy) = (Point::ZERO, Point::ZERO); // Σ q·p.x, Σ q·p.y
    for (&p, &q) in from[..n].iter().zip(&to[..n]) {
        let (p, q) = (p - cp, q - cq);
        sxx += p.x * p.x;
        sxy += p.x * p.y;
        syy += p.y * p.y;
        qx += q * p.x;
        qy += q * p.y;
    }
    let det = sxx * syy - sxy * sxy;
    let linear = if det > 1e-12 * (sxx + syy).powi(2) {
        // L = [qx qy] · [[sxx sxy] [sxy syy]]⁻¹, columns L·e_x and L·e_y.
        let col_x = (qx * syy - qy * sxy) / det;
        let col_y = (qy * sxx - qx * sxy) / det;
        Affine::new([col_x.x, col_x.y, col_y.x, col_y.y, 0.0, 0.0])
    } else if fit.from_spread > 0.0 {
        let s = fit.dot.hypot(fit.cross) / fit.from_spread;
        Affine::rotate(fit.rotation()) * Affine::scale(s)
    } else {
        Affine::IDENTITY
    };
    let c = linear * kurbo::Point::new(cp.x, cp.y);
    Affine::translate((cq.x - c.x, cq.y - c.y)) * linear
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn rgb(r: u8, g: u8, b: u8) -> Rgba {
        Rgba { r, g, b, a: 255 }
    }

    fn stop(offset: f64, color: Rgba, opacity: f64) -> GradientStop {
        GradientStop {
            offset,
            color,
            opacity,
        }
    }

    fn apply(m: Affine, p: Point) -> Point {
        let q = m * kurbo::Point::new(p.x, p.y);
        Point::new(q.x, q.y)
    }

    #[test]
    fn the_fitted_affine_recovers_an_affine_motion_and_degrades_gracefully() {
        let m = Affine::new([1.3, 0.4, -0.7, 0.9, 5.0, -2.0]);
        let from = [(0.0, 0.0), (3.0, 1.0), (1.0, 4.0), (-2.0, 2.0)].map(|(x, y)| Point::new(x, y));
        let to = from.map(|p| apply(m, p));
        let fit = fitted_affine(&from, &to);
        for (a, b) in fit.as_coeffs().iter().zip(m.as_coeffs()) {
            assert!((a - b).abs() < 1e-9, "{fit:?} vs {m:?}");
        }
        // Points on a line: the best similarity (here a quarter turn, doubled, moved).
        let line = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)].map(|(x, y)| Point::new(x, y));
        let sim = Affine::translate((1.0, 1.0))
            * Affine::rotate(std::f64::consts::FRAC_PI_2)
            * Affine::scale(2.0);
        let fit = fitted_affine(&line, &line.map(|p| apply(sim, p)));
        for (a, b) in fit.as_coeffs().iter().zip(sim.as_coeffs()) {
            assert!((a - b).abs() < 1e-9, "{fit:?} vs {sim:?}");
        }
        let one = fitted_affine(&[Point::new(1.0, 1.0)], &[Point::new(4.0, 5.0)]);
        assert_eq!(one, Affine::translate((3.0, 4.0)));
        assert_eq!(fitted_affine(&[], &[]), Affine::IDENTITY);
    }

    #[test]
    fn resampled_stops_paint_each_end_and_keep_hard_edges() {
        let a = [
            stop(0.0, rgb(255, 0, 0), 1.0),
            stop(0.5, rgb(0, 0, 255), 1.0),
            stop(0.5, rgb(0, 255, 0), 0.5),
            stop(1.0, rgb(0, 0, 0), 0.0),
        ];
        let b = [
            stop(0.2, rgb(10, 20, 30), 1.0),
            stop(0.8, rgb(200, 100, 0), 1.0),
        ];
        for (t, side) in [(0.0, &a[..]), (1.0, &b[..])] {
            let m = mix_stops(&a, &b, t);
            assert!(m.windows(2).all(|w| w[0].offset <= w[1].offset));
            for k in 0..=40 {
                let u = k as f64 / 40.0;
                for right in [false, true] {
                    let (p, q) = (sample(&m, u, right), sample(side, u, right));
                    let near = |x: u8, y: u8| x.abs_diff(y) <= 1;
                    assert!(
                        near(p.0.r, q.0.r) && near(p.0.g, q.0.g) && near(p.0.b, q.0.b),
                        "t = {t}, offset {u}: {p:?} vs {q:?}"
                    );
                    assert!((p.1 - q.1).abs() < 1e-9);
                }
            }
        }
        // The hard edge at 0.5 stays hard in between; the union has offsets 0, .2, .5, .8, 1.
        let m = mix_stops(&a, &b, 0.5);
        let offsets: Vec<f64> = m.iter().map(|s| s.offset).collect();
        assert_eq!(offsets, [0.0, 0.2, 0.5, 0.5, 0.8, 1.0]);
        // Colours mix in Oklab.
        assert_eq!(
            m[1].color,
            mix(sample(&a, 0.2, false).0, rgb(10, 20, 30), 0.5)
        );
    }

    #[test]
    fn colours_mix_in_oklab_and_a_colour_meets_a_gradient_on_its_geometry() {
        let (x, y) = (rgb(0, 200, 0), rgb(200, 0, 0));
        let id = Affine::IDENTITY;
        assert_eq!(
            mix_paint(&Paint::Color(x), &Paint::Color(y), 0.3, id, id),
            Paint::Color(mix(x, y, 0.3))
        );
        let g = Gradient {
            kind: GradientKind::Linear {
                start: Point::new(0.0, 0.0),
                end: Point::new(10.0, 0.0),
            },
            transform: Affine::IDENTITY,
            spread: Spread::Reflect,
            stops: vec![
                stop(0.0, rgb(0, 0, 0), 1.0),
                stop(1.0, rgb(255, 255, 255), 1.0),
            ],
        };
        let moved = Affine::translate((5.0, 0.0));
        let Paint::Gradient(m) = mix_paint(
            &Paint::Color(x),
            &Paint::Gradient(Arc::new(g)),
            0.0,
            id,
            moved,
        ) else {
            panic!("a gradient");
        };
        assert!(m.stops.iter().all(|s| s.color == x && s.opacity == 1.0));
        assert_eq!(m.spread, Spread::Reflect);
        let GradientKind::Linear { start, end } = m.kind else {
            panic!("linear");
        };
        assert!(start.distance(Point::new(5.0, 0.0)) < 1e-12);
        assert!(end.distance(Point::new(15.0, 0.0)) < 1e-12);
        // Linear and radial do not interpolate; empty gradients neither.
        let radial = Gradient {
            kind: GradientKind::Radial {
                center: Point::ZERO,
                radius: 1.0,
                focal: Point::ZERO,
                focal_radius: 0.0,
            },
            ..(*m).clone()
        };
        assert!(!compatible(
            &Paint::Gradient(m.clone()),
            &Paint::Gradient(Arc::new(radial.clone()))
        ));
        assert!(compatible(
            &Paint::Color(x),
            &Paint::Gradient(Arc::new(radial.clone()))
        ));
        let empty = Gradient {
            stops: Vec::new(),
            ..radial
        };
        assert!(!compatible(
            &Paint::Color(x),
            &Paint::Gradient(Arc::new(empty))
        ));
    }

    proptest! {
        /// A linear gradient under any invertible affine map, rewritten in user space, paints
        /// the same parameter everywhere.
        #[test]
        fn linear_gradients_keep_their_parameter_in_user_space(
            c in prop::array::uniform6(-3.0f64..3.0),
            s in prop::array::uniform2(-5.0f64..5.0),
            e in prop::array::uniform2(-5.0f64..5.0),
            y in prop::array::uniform2(-10.0f64..10.0),
        ) {
            let m = Affine::new(c);
            prop_assume!(m.determinant().abs() > 0.1);
            let (start, end) = (Point::new(s[0], s[1]), Point::new(e[0], e[1]));
            prop_assume!(start.distance(end) > 0.1);
            let g = Gradient {
                kind: GradientKind::Linear { start, end },
                transform: Affine::scale(0.5),
                spread: Spread::Pad,
                stops: Vec::new(),
            };
            let Geometry::Linear { start: s2, end: e2 } = Geometry::of(&g, m) else {
                panic!("linear");
            };
            let y = Point::new(y[0], y[1]);
            let local = apply((m * g.transform).inverse(), y);
            let want = (local - start).dot(end - start) / (end - start).length_squared();
            let got = (y - s2).dot(e2 - s2) / (e2 - s2).length_squared();
            prop_assert!((want - got).abs() < 1e-6 * (1.0 + want.abs()), "{want} vs {got}");
        }

        /// A radial gradient's unit frame maps the unit circle onto the mapped end circle and
        /// the normalized focal point onto the mapped focal point.
        #[test]
        fn radial_frames_carry_the_circles(
            c in prop::array::uniform6(-3.0f64..3.0),
            centre in prop::array::uniform2(-5.0f64..5.0),
            r in 0.1f64..4.0,
            angle in 0.0f64..6.3,
        ) {
            let m = Affine::new(c);
            let center = Point::new(centre[0], centre[1]);
            let focal = center + Point::new(0.3 * r, -0.2 * r);
            let g = Gradient {
                kind: GradientKind::Radial { center, radius: r, focal, focal_radius: 0.1 * r },
                transform: Affine::IDENTITY,
                spread: Spread::Pad,
                stops: Vec::new(),
            };
            let Geometry::Radial { frame, radius, focal: f2, focal_radius } = Geometry::of(&g, m)
            else {
                panic!("radial");
            };
            prop_assert_eq!(radius, 1.0);
            prop_assert!((focal_radius - 0.1).abs() < 1e-12);
            let (sin, cos) = angle.sin_cos();
            let on = apply(frame, Point::new(cos, sin));
            let want = apply(m, center + Point::new(cos, sin) * r);
            prop_assert!(on.distance(want) < 1e-9);
            prop_assert!(apply(frame, f2).distance(apply(m, focal)) < 1e-9);
        }
    }
}
