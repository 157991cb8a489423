//! Where a hole with no partner closes (or opens): its seed, a small circle inside the other
//! drawing's matched outline (issue #6, item 2).
//!
//! A hole of the source outline `A` whose matched target outline `B` has no hole for it shrinks
//! to a spot in `B` (and the reverse opens one). The composite mapping keeps every curve's
//! containment (a curve inside another stays inside it, the paper's Fig.16 limitation), so the
//! spot must lie in `B`'s *filled* region: inside `B` and outside `B`'s own holes. A glyph's
//! centre often is not — the middle of a "c" is its open mouth — so the seed goes to the filled
//! point nearest to where `B` carries the hole's centre, among the points at least half as deep
//! in the fill as the deepest one (the middle of the stroke rather than its edge, so that the
//! closing hole never grazes the outline).

use super::contours::Contour;
use crate::geometry::{point_in_polygon, point_segment_distance, Point};

/// Candidate points per side of the outline's bounding box.
const GRID: usize = 64;

/// The seed circle's centre and largest radius for a hole whose centre `B` carries to `want`:
/// `outline` is `B`, `holes` its holes. `None` when `B` has no filled interior (a degenerate
/// outline).
pub(crate) fn seed_place(
    outline: &Contour,
    holes: &[&Contour],
    want: Point,
) -> Option<(Point, f64)> {
    let edges = || {
        std::iter::once(outline)
            .chain(holes.iter().copied())
            .flat_map(|c| {
                let n = c.points.len();
                (0..n).map(move |i| (c.points[i], c.points[(i + 1) % n]))
            })
    };
    let depth = |p: Point| {
        edges()
            .map(|(a, b)| point_segment_distance(p, a, b).0)
            .fold(f64::INFINITY, f64::min)
    };
    let filled = |p: Point| {
        point_in_polygon(p, &outline.points)
            && !holes.iter().any(|h| point_in_polygon(p, &h.points))
    };
    let (lo, hi) = crate::geometry::bounding_box(outline.points.iter().copied())?;
    let mut candidates = Vec::new();
    for j in 0..GRID {
        for i in 0..GRID {
            let p = Point::new(
                lo.x + (hi.x - lo.x) * (i as f64 + 0.5) / GRID as f64,
                lo.y + (hi.y - lo.y) * (j as f64 + 0.5) / GRID as f64,
            );
            if filled(p) {
                candidates.push((p, depth(p)));
            }
        }
    }
    if filled(want) {
        candidates.push((want, depth(want)));
    }
    let deepest = candidates.iter().map(|c| c.1).fold(0.0, f64::max);
    if deepest <= 0.0 {
        return None;
    }
    candidates
        .into_iter()
        .filter(|c| c.1 >= 0.5 * deepest)
        .min_by(|a, b| {
            a.0.distance_squared(want)
                .total_cmp(&b.0.distance_squared(want))
                .then(b.1.total_cmp(&a.1))
        })
        .map(|(p, d)| (p, 0.5 * d))
}

/// A small circle (counter-clockwise in SVG coordinates like the outlines it stands for).
pub(crate) fn seed_circle(centre: Point, radius: f64, n: usize) -> Vec<Point> {
    (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            centre + Point::new(a.cos(), a.sin()) * radius
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::auto::contours::ContourKind;

    fn contour(points: Vec<Point>, parent: Option<usize>) -> Contour {
        Contour {
            area: crate::geometry::polygon_area(&points).abs(),
            centroid: crate::geometry::centroid(&points),
            length: crate::geometry::polyline_length(&points, true),
            points,
            closed: true,
            kind: if parent.is_some() {
                ContourKind::Hole
            } else {
                ContourKind::Outline
            },
            parent,
            path: 0,
            elongation: 1.0,
        }
    }

    /// A "C": an annulus sector open to the right (outer radius 10, inner 6).
    fn c_shape() -> Contour {
        let mut pts = Vec::new();
        let n = 40;
        for k in 0..=n {
            let a = 0.6 + (std::f64::consts::TAU - 1.2) * k as f64 / n as f64;
            pts.push(Point::new(10.0 * a.cos(), 10.0 * a.sin()));
        }
        for k in (0..=n).rev() {
            let a = 0.6 + (std::f64::consts::TAU - 1.2) * k as f64 / n as f64;
            pts.push(Point::new(6.0 * a.cos(), 6.0 * a.sin()));
        }
        contour(pts, None)
    }

    #[test]
    fn a_seed_aimed_at_the_mouth_of_a_c_lands_in_its_stroke() {
        let c = c_shape();
        // The centre of the C is open: the seed goes to the nearest point at least half as deep
        // in the stroke (4 wide) as its middle, i.e. at radius 7 below the centre.
        let (p, r) = seed_place(&c, &[], Point::new(0.0, -1.0)).unwrap();
        assert!(point_in_polygon(p, &c.points));
        assert!((p.length() - 7.0).abs() < 0.35 && p.y < -6.5, "{p}");
        assert!((0.49..=1.0).contains(&r), "{r}");
        // Aimed inside the stroke, it stays where it is aimed.
        let want = Point::new(-8.0, 0.1);
        let (p, _) = seed_place(&c, &[], want).unwrap();
        assert_eq!(p, want);
    }

    #[test]
    fn a_seed_avoids_the_outlines_own_holes() {
        let square = |h: f64| {
            vec![
                Point::new(-h, -h),
                Point::new(h, -h),
                Point::new(h, h),
                Point::new(-h, h),
            ]
        };
        let outer = contour(square(10.0), None);
        let hole = contour(square(6.0), Some(0));
        let (p, r) = seed_place(&outer, &[&hole], Point::ZERO).unwrap();
        assert!(!point_in_polygon(p, &hole.points) && point_in_polygon(p, &outer.points));
        assert!(r > 0.4, "{r}");
    }
}
