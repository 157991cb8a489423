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
        let (o, c, far) = (self.origin, self.cell, self.far);
        let (left, right) = (o.x + x0 as f64 * c, o.x + (x1 + 1) as f64 * c);
        let (low, high) = (o.y + y0 as f64 * c, o.y + (y1 + 1) as f64 * c);
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

/// The distance from `p` to the box with corners `lo` and `hi` (0 inside it).
pub(crate) fn box_distance(p: Point, lo: Point, hi: Point) -> f64 {
    let dx = (lo.x - p.x).max(p.x - hi.x).max(0.0);
    let dy = (lo.y - p.y).max(p.y - hi.y).max(0.0);
    dx.hypot(dy)
}
