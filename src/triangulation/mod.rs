//! Constrained Delaunay triangulation of the source shape (§5) with spade.
