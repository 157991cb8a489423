//! The frame of a uniform grid over a bounding box: how big a cell is, which cell a point falls
//! in, and how far the cells beyond a searched square of cells lie. Point location in a mesh
//! ([`crate::artwork::PointLocator`]) and the carried features' nearest boundary vertices
//! (`mapping::carried`) search rings of cells outward and stop when everything unseen is
//! farther than the best found; both use this frame, each with its own cell contents
//! (`mesh::compressed_rows`).

use crate::geometry::Point;

/// Largest number of cells along one side.
const MAX_CELLS: usize = 1024;

/// A uniform grid's cells over `[origin, far]`: `nx × ny` square cells of side `cell`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GridFrame {
    /// The lower corner of the grid.
    pub(crate) origin: Point,
    /// The grid's far corner: the box's largest coordinates, or the last cells' far sides if
    /// they reach further.
    pub(crate) far: Point,
    /// The side of a cell.
    pub(crate) cell: f64,
    /// Cells across and up.
    pub(crate) nx: usize,
    pub(crate) ny: usize,
}

impl GridFrame {
    /// About one cell per item over the box `[lo, hi]` (finite), at most [`MAX_CELLS`] cells
    /// along a side.
    pub(crate) fn covering(lo: Point, hi: Point, items: usize) -> Self {
        let ext = (hi - lo).max(Point::splat(f64::MIN_POSITIVE));
        let cell = (ext.x * ext.y / items.max(1) as f64)
            .sqrt()
            .max(ext.max_element() / MAX_CELLS as f64);
        let nx = ((ext.x / cell).ceil() as usize).clamp(1, MAX_CELLS);
        let ny = ((ext.y / cell).ceil() as usize).clamp(1, MAX_CELLS);
        GridFrame {
            origin: lo,
            far: hi.max(lo + Point::new(nx as f64, ny as f64) * cell),
            cell,
            nx,
            ny,
        }
    }

    /// The cell containing `p`, clamped to the grid (cell 0 along an axis where `p` is not
    /// finite).
    pub(crate) fn cell_of(&self, p: Point) -> (usize, usize) {
        let q = (p - self.origin) / self.cell;
        let cx = if q.x.is_finite() {
            q.x.floor().max(0.0) as usize
        } else {
            0
        };
        let cy = if q.y.is_finite() {
            q.y.floor().max(0.0) as usize
        } else {
            0
        };
        (cx.min(self.nx - 1), cy.min(self.ny - 1))
    }

    /// The square of cells within `r` rings of cell `(cx, cy)`, clipped to the grid:
    /// `((x0, x1), (y0, y1))`, inclusive.
    pub(crate) fn ring_square(
        &self,
        (cx, cy): (usize, usize),
        r: usize,
    ) -> ((usize, usize), (usize, usize)) {
        (
            (cx.saturating_sub(r), (cx + r).min(self.nx - 1)),
            (cy.saturating_sub(r), (cy + r).min(self.ny - 1)),
        )
    }

    /// The cells at Chebyshev distance exactly `r` from cell `(cx, cy)`, clipped to the grid,
    /// as up to four rectangles `((x0, x1), (y0, y1))` (inclusive): the ring's bottom and top
    /// rows, then its side columns between them. A ring search visits `O(r)` cells at ring
    /// `r` this way, where a scan of the square would pass over `O(r²)` inner ones.
    pub(crate) fn ring_strips(
        &self,
        (cx, cy): (usize, usize),
        r: usize,
    ) -> impl Iterator<Item = ((usize, usize), (usize, usize))> {
        let ((x0, x1), _) = self.ring_square((cx, cy), r);
        let (nx, ny) = (self.nx, self.ny);
        // The rows strictly between the ring's bottom and top (for r > 0).
        let inner = (
            (cy + 1).saturating_sub(r),
            (cy + r).saturating_sub(1).min(ny - 1),
        );
        [
            (cy >= r).then_some(((x0, x1), (cy - r, cy - r))),
            (r > 0 && cy + r < ny).then_some(((x0, x1), (cy + r, cy + r))),
            (r > 0 && cx >= r).then(|| ((cx - r, cx - r), inner)),
            (r > 0 && cx + r < nx).then(|| ((cx + r, cx + r), inner)),
        ]
        .into_iter()
        .flatten()
    }

    /// The squared distance from `p` to the cells `x0..=x1 × y0..=y1` (0 inside them): a
    /// search compares it with a squared bound, without a square root per cell. Whatever a
    /// cell lists because its box overlaps the cell may reach beyond it, but the part of it
    /// inside the cell is at least this far from `p` (up to the rounding of the cells' sides).
    pub(crate) fn cells_distance_squared(
        &self,
        p: Point,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
    ) -> f64 {
        box_distance_squared(p, self.corner(x0, y0), self.corner(x1 + 1, y1 + 1))
    }

    /// The lower left corner of cell `(x, y)` (the upper right of cell `(x − 1, y − 1)`).
    fn corner(&self, x: usize, y: usize) -> Point {
        self.origin + Point::new(x as f64, y as f64) * self.cell
    }

    /// The distance from `p` to the nearest cell outside the square `x0..=x1 × y0..=y1`: the
    /// nearest of the four strips of the grid beyond the square's sides (the grid's own edges
    /// have none), infinite when the square covers the grid. Whatever lies in a cell outside
    /// the square is at least this far from `p`.
    pub(crate) fn beyond(
        &self,
        p: Point,
        (x0, x1): (usize, usize),
        (y0, y1): (usize, usize),
    ) -> f64 {
        let (o, far) = (self.origin, self.far);
        let (lo, hi) = (self.corner(x0, y0), self.corner(x1 + 1, y1 + 1));
        let (left, right, low, high) = (lo.x, hi.x, lo.y, hi.y);
        let mut beyond = f64::INFINITY;
        if x0 > 0 {
            beyond = beyond.min(box_distance(p, o, Point::new(left, far.y)));
        }
        if x1 + 1 < self.nx {
            beyond = beyond.min(box_distance(p, Point::new(right, o.y), far));
        }
        if y0 > 0 {
            beyond = beyond.min(box_distance(p, o, Point::new(far.x, low)));
        }
        if y1 + 1 < self.ny {
            beyond = beyond.min(box_distance(p, Point::new(o.x, high), far));
        }
        beyond
    }
}

/// The squared distance from `p` to the box with corners `lo` and `hi` (0 inside it): for
/// searches that compare it with a squared bound.
pub(crate) fn box_distance_squared(p: Point, lo: Point, hi: Point) -> f64 {
    (lo - p).max(p - hi).max(Point::ZERO).length_squared()
}

/// The distance from `p` to the box with corners `lo` and `hi` (0 inside it).
pub(crate) fn box_distance(p: Point, lo: Point, hi: Point) -> f64 {
    let dx = (lo.x - p.x).max(p.x - hi.x).max(0.0);
    let dy = (lo.y - p.y).max(p.y - hi.y).max(0.0);
    dx.hypot(dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rings' strips cover every cell of the grid once, ring `r` the cells at Chebyshev
    /// distance `r` from the centre, wherever the centre is (corners and edges clip the rings).
    #[test]
    fn ring_strips_cover_each_cell_once_in_its_ring() {
        let frame = GridFrame::covering(Point::ZERO, Point::new(7.0, 4.0), 28);
        let (nx, ny) = (frame.nx, frame.ny);
        assert!(nx > 3 && ny > 2, "{nx} × {ny}");
        for (cx, cy) in [(0, 0), (nx - 1, ny - 1), (2, 1), (nx - 1, 0), (1, ny - 1)] {
            let mut seen = vec![0; nx * ny];
            for r in 0..nx.max(ny) {
                for ((x0, x1), (y0, y1)) in frame.ring_strips((cx, cy), r) {
                    for y in y0..=y1 {
                        for x in x0..=x1 {
                            assert_eq!(x.abs_diff(cx).max(y.abs_diff(cy)), r, "({x}, {y})");
                            seen[y * nx + x] += 1;
                        }
                    }
                }
            }
            assert!(
                seen.iter().all(|&k| k == 1),
                "centre ({cx}, {cy}): {seen:?}"
            );
        }
    }

    /// The distance to a block of cells is the distance to its box, and no more than to any of
    /// its cells.
    #[test]
    fn cells_distance_is_the_distance_to_the_block() {
        let frame = GridFrame::covering(Point::ZERO, Point::new(8.0, 8.0), 64);
        let c = frame.cell;
        let p = Point::new(-1.0, 0.5 * c);
        let cells_distance = |xs, ys| frame.cells_distance_squared(p, xs, ys).sqrt();
        assert!((cells_distance((0, 0), (0, 3)) - 1.0).abs() < 1e-12);
        assert!((cells_distance((2, 5), (0, 0)) - (1.0 + 2.0 * c)).abs() < 1e-12);
        // Beyond a corner: the distance to the corner.
        let corner = (1.0 + 2.0 * c).hypot(2.5 * c);
        assert!((cells_distance((2, 5), (3, 4)) - corner).abs() < 1e-12);
        assert_eq!(
            frame.cells_distance_squared(Point::new(0.5 * c, 0.5 * c), (0, 1), (0, 1)),
            0.0
        );
        for x in 2..=5 {
            assert!(cells_distance((2, 5), (1, 3)) <= cells_distance((x, x), (2, 2)));
        }
    }
}
