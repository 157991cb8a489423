//! Arc-length measurement of a flattened curve: measure once, then sample by arc length, project
//! points, insert vertices and re-start closed curves.
//!
//! This is the polyline counterpart of lyon's `PathMeasurements`: a cumulative-length array is
//! built once, and every lookup is a binary search in it. All positions along a curve are arc
//! lengths `s` from its first vertex; a closed curve's `s` runs over `[0, length)` and wraps.

use crate::geometry::{point_segment_distance, Point};

/// A polyline with its cumulative arc lengths.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Polyline {
    points: Vec<Point>,
    closed: bool,
    /// `cum[i]` is the arc length at vertex `i`; a closed curve has one extra entry, the total
    /// length, for the closing edge.
    cum: Vec<f64>,
}

impl Polyline {
    /// Measures `points` (at least two, consecutive points distinct).
    pub(crate) fn new(points: Vec<Point>, closed: bool) -> Self {
        let n = points.len();
        let mut cum = Vec::with_capacity(n + 1);
        let mut acc = 0.0;
        cum.push(0.0);
        for w in points.windows(2) {
            acc += w[0].distance(w[1]);
            cum.push(acc);
        }
        if closed && n > 1 {
            acc += points[n - 1].distance(points[0]);
            cum.push(acc);
        }
        Polyline {
            points,
            closed,
            cum,
        }
    }

    /// The vertices.
    pub(crate) fn points(&self) -> &[Point] {
        &self.points
    }

    /// Number of vertices.
    pub(crate) fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the last vertex connects back to the first.
    pub(crate) fn closed(&self) -> bool {
        self.closed
    }

    /// Total arc length (including the closing edge of a closed curve).
    pub(crate) fn length(&self) -> f64 {
        self.cum.last().copied().unwrap_or(0.0)
    }

    /// Arc length at vertex `i`.
    pub(crate) fn s(&self, i: usize) -> f64 {
        self.cum[i]
    }

    fn edge_count(&self) -> usize {
        self.cum.len().saturating_sub(1)
    }

    /// Wraps (closed) or clamps (open) an arc length into the curve's range.
    pub(crate) fn normalize(&self, s: f64) -> f64 {
        let l = self.length();
        if self.closed {
            let w = s.rem_euclid(l);
            if w >= l {
                0.0
            } else {
                w
            }
        } else {
            s.clamp(0.0, l)
        }
    }

    /// The point at arc length `s` (wrapped or clamped into range).
    pub(crate) fn point_at(&self, s: f64) -> Point {
        let s = self.normalize(s);
        let edges = self.edge_count();
        if edges == 0 {
            return self.points[0];
        }
        let e = self
            .cum
            .partition_point(|&c| c <= s)
            .saturating_sub(1)
            .min(edges - 1);
        let len = self.cum[e + 1] - self.cum[e];
        let t = if len > 0.0 {
            ((s - self.cum[e]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let a = self.points[e];
        let b = self.points[(e + 1) % self.points.len()];
        a + (b - a) * t
    }

    /// The nearest point of the curve to `p`: `(distance, arc length)`. Ties go to the first edge.
    pub(crate) fn project(&self, p: Point) -> (f64, f64) {
        let n = self.points.len();
        let mut best = (f64::INFINITY, 0.0);
        for e in 0..self.edge_count() {
            let (a, b) = (self.points[e], self.points[(e + 1) % n]);
            let (d, t) = point_segment_distance(p, a, b);
            if d < best.0 {
                best = (d, self.cum[e] + t * (self.cum[e + 1] - self.cum[e]));
            }
        }
        if n == 1 {
            best = (p.distance(self.points[0]), 0.0);
        }
        (best.0, self.normalize(best.1))
    }

    /// The index of a vertex within arc length `snap` of `s`, if there is one.
    pub(crate) fn vertex_near(&self, s: f64, snap: f64) -> Option<usize> {
        let s = self.normalize(s);
        let n = self.points.len();
        let k = self.cum.partition_point(|&c| c < s);
        let mut cands = [k.saturating_sub(1), k.min(self.cum.len() - 1)];
        cands.sort_unstable();
        cands
            .iter()
            .filter(|&&i| (self.cum[i] - s).abs() <= snap)
            .map(|&i| i % n)
            .next()
    }

    /// A copy with a vertex at each arc length of `at` (existing vertices within `snap` are
    /// reused), and the vertex index for each entry of `at`.
    pub(crate) fn with_vertices_at(&self, at: &[f64], snap: f64) -> (Polyline, Vec<usize>) {
        // New vertices, each with the arc length it sits at.
        let mut extra: Vec<(f64, usize)> = Vec::new();
        for (k, &s) in at.iter().enumerate() {
            if self.vertex_near(s, snap).is_none() {
                extra.push((self.normalize(s), k));
            }
        }
        extra.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        extra.dedup_by(|b, a| (b.0 - a.0).abs() <= snap);
        let mut points = Vec::with_capacity(self.points.len() + extra.len());
        let mut positions = Vec::with_capacity(self.points.len() + extra.len());
        let mut old_to_new = Vec::with_capacity(self.points.len());
        let mut next = 0;
        for (i, &p) in self.points.iter().enumerate() {
            while next < extra.len() && extra[next].0 < self.cum[i] {
                positions.push(extra[next].0);
                points.push(self.point_at(extra[next].0));
                next += 1;
            }
            old_to_new.push(points.len());
            positions.push(self.cum[i]);
            points.push(p);
        }
        for &(s, _) in &extra[next..] {
            positions.push(s);
            points.push(self.point_at(s));
        }
        let out = Polyline::new(points, self.closed);
        let index = at
            .iter()
            .map(|&s| match self.vertex_near(s, snap) {
                Some(i) => old_to_new[i],
                None => {
                    let s = self.normalize(s);
                    positions
                        .partition_point(|&c| c < s - snap)
                        .min(positions.len() - 1)
                }
            })
            .collect();
        (out, index)
    }

    /// A closed curve re-started at vertex `start` (same direction).
    pub(crate) fn rotated(&self, start: usize) -> Polyline {
        let mut pts = self.points.clone();
        let k = start % pts.len().max(1);
        pts.rotate_left(k);
        Polyline::new(pts, self.closed)
    }

    /// The curve traversed the other way. A closed curve keeps its first vertex.
    pub(crate) fn reversed(&self) -> Polyline {
        let mut pts = self.points.clone();
        if self.closed {
            pts[1..].reverse();
        } else {
            pts.reverse();
        }
        Polyline::new(pts, self.closed)
    }

    /// `count` points at equal arc-length steps: from end to end of an open curve, or once
    /// around a closed curve starting at arc length `offset`.
    pub(crate) fn resample(&self, count: usize, offset: f64) -> Vec<Point> {
        let l = self.length();
        if self.closed {
            (0..count)
                .map(|k| self.point_at(offset + l * k as f64 / count as f64))
                .collect()
        } else {
            let d = (count.max(2) - 1) as f64;
            (0..count)
                .map(|k| self.point_at(l * k as f64 / d))
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    fn square() -> Polyline {
        Polyline::new(vec![p(0., 0.), p(2., 0.), p(2., 2.), p(0., 2.)], true)
    }

    #[test]
    fn arc_length_lookup_wraps_on_closed_curves() {
        let sq = square();
        assert_eq!(sq.length(), 8.0);
        assert_eq!(sq.point_at(1.0), p(1., 0.));
        assert_eq!(sq.point_at(7.0), p(0., 1.));
        assert_eq!(sq.point_at(9.0), p(1., 0.));
        assert_eq!(sq.point_at(8.0), p(0., 0.));
        let open = Polyline::new(vec![p(0., 0.), p(2., 0.), p(2., 2.)], false);
        assert_eq!(open.point_at(5.0), p(2., 2.));
        assert_eq!(open.point_at(-1.0), p(0., 0.));
    }

    #[test]
    fn projection_and_vertex_insertion() {
        let sq = square();
        let (d, s) = sq.project(p(1.0, -0.5));
        assert!((d - 0.5).abs() < 1e-12 && (s - 1.0).abs() < 1e-12);
        let (q, idx) = sq.with_vertices_at(&[7.0, 1.0, 2.0], 1e-9);
        assert_eq!(q.len(), 6);
        assert_eq!(q.points()[idx[0]], p(0., 1.));
        assert_eq!(q.points()[idx[1]], p(1., 0.));
        assert_eq!(idx[2], 2);
        assert_eq!(q.points()[2], p(2., 0.));
        assert_eq!(q.length(), 8.0);
    }

    #[test]
    fn rotation_reversal_and_resampling() {
        let sq = square();
        assert_eq!(sq.rotated(2).points()[0], p(2., 2.));
        let r = sq.reversed();
        assert_eq!(r.points(), &[p(0., 0.), p(0., 2.), p(2., 2.), p(2., 0.)]);
        let pts = sq.resample(8, 1.0);
        assert_eq!(pts[0], p(1., 0.));
        assert_eq!(pts[7], p(0., 0.));
        let open = Polyline::new(vec![p(0., 0.), p(4., 0.)], false);
        assert_eq!(open.resample(3, 0.0), vec![p(0., 0.), p(2., 0.), p(4., 0.)]);
    }
}
