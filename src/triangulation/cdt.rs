//! The spade part of the triangulation: constrained Delaunay triangulation of validated curves,
//! Delaunay refinement that never splits a constraint, and the faces inside the boundary.
//!
//! spade's own `exclude_outer_faces` decides inside/outside by the parity of crossed constraint
//! edges, which would call the inside of a closed feature curve "outside". Instead the faces are
//! classified here by a flood fill that starts on the left of the (counter-clockwise) boundary and
//! never crosses a boundary edge; feature edges are crossed freely.

use crate::geometry::{orient2d, Point};
use crate::tolerance::Tolerances;
use spade::handles::FixedVertexHandle;
use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, PositionInTriangulation,
    RefinementParameters, Triangulation as _,
};
use std::collections::BTreeSet;

/// Why the CDT could not be built.
#[derive(Debug)]
pub(crate) enum CdtError {
    /// A constraint edge of this curve crosses (or runs through a vertex of) another curve.
    Crossing(usize),
    /// A vertex of this curve has a coordinate spade cannot represent.
    Coordinate(usize),
    /// A broken invariant.
    Other(String),
}

type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;

/// Builds the refined CDT of `curves` (the first one is the boundary) and returns the vertices —
/// the curve vertices first, in curve order — and the counter-clockwise triangles inside the
/// boundary.
pub(super) fn build(
    curves: &[(&[Point], bool)],
    tol: &Tolerances,
) -> Result<(Vec<Point>, Vec<[u32; 3]>), CdtError> {
    let mut cdt = Cdt::new();
    let mut starts = Vec::with_capacity(curves.len());
    let mut count = 0usize;
    for (c, &(pts, _)) in curves.iter().enumerate() {
        starts.push(count);
        for p in pts {
            let h = cdt
                .insert(Point2::new(p.x, p.y))
                .map_err(|_| CdtError::Coordinate(c))?;
            if h.index() != count {
                return Err(CdtError::Other(format!(
                    "curve {c}: vertex merged with another"
                )));
            }
            count += 1;
        }
    }
    let handle = |c: usize, k: usize| FixedVertexHandle::from_index(starts[c] + k);
    let mut boundary_edges = BTreeSet::new();
    let mut curve_edges = Vec::new();
    for (c, &(pts, closed)) in curves.iter().enumerate() {
        let n = pts.len();
        let m = if closed { n } else { n - 1 };
        for k in 0..m {
            let (a, b) = (handle(c, k), handle(c, (k + 1) % n));
            if !cdt.can_add_constraint(a, b) {
                return Err(CdtError::Crossing(c));
            }
            // More than one new edge means the segment ran through another vertex.
            if cdt.try_add_constraint(a, b).len() != 1 {
                return Err(CdtError::Crossing(c));
            }
            if c == 0 {
                boundary_edges.insert((a.index(), b.index()));
            }
            curve_edges.push((a, b));
        }
    }

    // Refinement: a generous cap on Steiner points, proportional to the area to fill.
    let (lo, hi) = crate::geometry::bounding_box(curves.iter().flat_map(|c| c.0.iter().copied()))
        .ok_or_else(|| CdtError::Other("no vertices".into()))?;
    let box_area = (hi - lo).x * (hi - lo).y;
    let cap = (8.0 * box_area / tol.max_area.max(f64::MIN_POSITIVE)).min(4e6) as usize + 10 * count;
    // Faces below a billionth of the largest area are left alone: outside the boundary, nearly
    // collinear hull vertices form slivers without a finite circumcenter, which spade's
    // refinement cannot locate.
    let params = RefinementParameters::<f64>::new()
        .keep_constraint_edges()
        .with_angle_limit(AngleLimit::from_deg(super::MIN_ANGLE_DEG))
        .with_max_allowed_area(tol.max_area)
        .with_min_required_area(tol.max_area * 1e-9)
        .with_max_additional_vertices(cap);
    // spade documents no panics for `refine`, but a failed point location panics inside it; keep
    // that from reaching the caller.
    let result =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| cdt.refine(params.clone())))
            .map_err(|_| CdtError::Other("spade's Delaunay refinement failed".into()))?;
    if !result.refinement_complete {
        log::warn!("triangulation: refinement stopped at {cap} additional vertices");
    }

    // A chord — an edge joining two curve vertices that is not a curve edge — pins the
    // triangles on it to the curves: their shape at every t is fixed by the curves alone, and
    // where the curves bend across the chord (a star's narrow tip becoming part of a smooth
    // outline) they must fold, whatever the mapping. Splitting every chord at its midpoint gives
    // each triangle a free corner; the refinement then restores the angles.
    for _ in 0..4 {
        if split_chords(&mut cdt, count) == 0 {
            break;
        }
        let again =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| cdt.refine(params.clone())))
                .map_err(|_| CdtError::Other("spade's Delaunay refinement failed".into()))?;
        if !again.refinement_complete {
            log::warn!("triangulation: refinement stopped at {cap} additional vertices");
        }
    }

    // Refinement must not have split a curve edge: every curve vertex keeps its twin.
    if curve_edges
        .iter()
        .any(|&(a, b)| cdt.get_edge_from_neighbors(a, b).is_none())
    {
        return Err(CdtError::Other("refinement split a curve edge".into()));
    }

    let inside = inside_faces(&cdt, &boundary_edges)?;

    // Keep the inside faces; curve vertices keep their indices, used Steiner points follow.
    let mut faces: Vec<[usize; 3]> = Vec::new();
    for f in cdt.fixed_inner_faces() {
        if inside[f.index()] {
            faces.push(cdt.face(f).vertices().map(|v| v.fix().index()));
        }
    }
    let mut remap = vec![u32::MAX; cdt.num_vertices()];
    let mut used = vec![false; cdt.num_vertices()];
    for f in &faces {
        for &v in f {
            used[v] = true;
        }
    }
    if let Some(v) = (0..count).find(|&v| !used[v]) {
        return Err(CdtError::Other(format!(
            "curve vertex {v} is outside the kept faces"
        )));
    }
    let mut points = Vec::with_capacity(cdt.num_vertices());
    for v in cdt.fixed_vertices() {
        if used[v.index()] {
            remap[v.index()] = points.len() as u32;
            let p = cdt.vertex(v).position();
            points.push(Point::new(p.x, p.y));
        }
    }
    let mut triangles = Vec::with_capacity(faces.len());
    for f in faces {
        let mut t = f.map(|v| remap[v]);
        let o = orient2d(
            points[t[0] as usize],
            points[t[1] as usize],
            points[t[2] as usize],
        );
        if o == 0.0 {
            return Err(CdtError::Other("degenerate triangle in the CDT".into()));
        }
        if o < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    Ok((points, triangles))
}

/// Which faces are inside the boundary whose (counter-clockwise) edges are `boundary_edges`:
/// a flood fill from the faces left of them that never crosses a boundary edge (feature edges
/// are crossed freely).
fn inside_faces(cdt: &Cdt, boundary_edges: &BTreeSet<(usize, usize)>) -> Result<Vec<bool>, CdtError> {
    let mut inside = vec![false; cdt.num_all_faces()];
    let mut stack = Vec::new();
    for &(a, b) in boundary_edges {
        let e = cdt
            .get_edge_from_neighbors(
                FixedVertexHandle::from_index(a),
                FixedVertexHandle::from_index(b),
            )
            .ok_or_else(|| CdtError::Other("a boundary edge was split".into()))?;
        if let Some(f) = e.face().as_inner() {
            if !inside[f.fix().index()] {
                inside[f.fix().index()] = true;
                stack.push(f.fix());
            }
        }
    }
    while let Some(f) = stack.pop() {
        for e in cdt.face(f).adjacent_edges() {
            let (a, b) = (e.from().fix().index(), e.to().fix().index());
            if boundary_edges.contains(&(a, b)) || boundary_edges.contains(&(b, a)) {
                continue;
            }
            if let Some(g) = e.rev().face().as_inner() {
                if !inside[g.fix().index()] {
                    inside[g.fix().index()] = true;
                    stack.push(g.fix());
                }
            }
        }
    }

    Ok(inside)
}

/// A triangulation of the simple counter-clockwise polygon `points` with no Steiner point: the
/// constrained Delaunay triangulation of its corners with its edges as constraints, and also
/// every diagonal of `wanted` that lies inside it and crosses no edge kept so far (taken in
/// order). Returns the triangles (counter-clockwise, vertex indices of `points`) and the
/// diagonals of `wanted` that were kept.
///
/// Vertices on a straight run of the outline (within `1e-10` of the run's length from the line
/// through their corners — densified edges, vertices the correspondence inserted) are left out
/// of the Delaunay triangulation and fanned in afterwards, each triangle on the run split at
/// them: a run bulging inwards by a rounding error would otherwise give slivers of zero area
/// in floating point.
pub(crate) fn polygon(
    points: &[Point],
    wanted: &[(u32, u32)],
) -> Result<(Vec<[u32; 3]>, Vec<(u32, u32)>), CdtError> {
    let n = points.len();
    if n < 3 {
        return Err(CdtError::Other("polygon: fewer than 3 vertices".into()));
    }
    // Corners: the vertices that are not on a straight run between their neighbouring corners.
    let mut corner = vec![true; n];
    loop {
        let mut changed = false;
        let kept: Vec<usize> = (0..n).filter(|&k| corner[k]).collect();
        if kept.len() <= 3 {
            break;
        }
        for w in 0..kept.len() {
            let (a, k, b) = (
                kept[(w + kept.len() - 1) % kept.len()],
                kept[w],
                kept[(w + 1) % kept.len()],
            );
            if !corner[a] || !corner[b] {
                continue;
            }
            let span = points[b] - points[a];
            let off = span.perp_dot(points[k] - points[a]).abs();
            let along = (points[k] - points[a]).dot(span);
            if off <= 1e-10 * span.length_squared() && along > 0.0 && along < span.length_squared()
            {
                corner[k] = false;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let kept: Vec<usize> = (0..n).filter(|&k| corner[k]).collect();
    let index_of: Vec<Option<usize>> = {
        let mut v = vec![None; n];
        for (i, &k) in kept.iter().enumerate() {
            v[k] = Some(i);
        }
        v
    };
    let m = kept.len();
    let mut cdt = Cdt::new();
    for (i, &k) in kept.iter().enumerate() {
        let p = points[k];
        let h = cdt
            .insert(Point2::new(p.x, p.y))
            .map_err(|_| CdtError::Coordinate(0))?;
        if h.index() != i {
            return Err(CdtError::Other("polygon: vertex merged with another".into()));
        }
    }
    let mut boundary_edges = BTreeSet::new();
    for i in 0..m {
        let (a, b) = (
            FixedVertexHandle::from_index(i),
            FixedVertexHandle::from_index((i + 1) % m),
        );
        if !cdt.can_add_constraint(a, b) || cdt.try_add_constraint(a, b).len() != 1 {
            return Err(CdtError::Crossing(0));
        }
        boundary_edges.insert((i, (i + 1) % m));
    }
    let mut kept_wanted = Vec::new();
    for &(i, j) in wanted {
        let (a, b) = (i as usize, j as usize);
        let (Some(Some(ia)), Some(Some(ib))) = (index_of.get(a), index_of.get(b)) else {
            continue;
        };
        let (ia, ib) = (*ia, *ib);
        if ia == ib || (ia + 1) % m == ib || (ib + 1) % m == ia {
            continue;
        }
        let (ha, hb) = (FixedVertexHandle::from_index(ia), FixedVertexHandle::from_index(ib));
        let mid = (points[a] + points[b]) * 0.5;
        if cdt.exists_constraint(ha, hb)
            || !crate::geometry::point_in_polygon(mid, points)
            || !cdt.can_add_constraint(ha, hb)
        {
            continue;
        }
        if cdt.try_add_constraint(ha, hb).len() == 1 {
            kept_wanted.push((i, j));
        }
    }
    let inside = inside_faces(&cdt, &boundary_edges)?;
    let mut triangles = Vec::new();
    for f in cdt.fixed_inner_faces() {
        if !inside[f.index()] {
            continue;
        }
        let mut t = cdt.face(f).vertices().map(|v| kept[v.fix().index()] as u32);
        let o = orient2d(points[t[0] as usize], points[t[1] as usize], points[t[2] as usize]);
        if o == 0.0 {
            return Err(CdtError::Other("polygon: degenerate triangle".into()));
        }
        if o < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    // Fan the straight-run vertices in: a side (a, b) of the corner polygon that runs over
    // left-out vertices a+1 … b−1 splits its triangle at each of them.
    let mut again = true;
    while again {
        again = false;
        let mut next = Vec::with_capacity(triangles.len());
        for t in triangles {
            let mut split = None;
            for r in 0..3 {
                let (a, b) = (t[r] as usize, t[(r + 1) % 3] as usize);
                if (a + 1) % n != b && index_of[(a + 1) % n].is_none() {
                    let mut k = (a + 1) % n;
                    let mut ok = true;
                    while k != b {
                        if index_of[k].is_some() {
                            ok = false;
                            break;
                        }
                        k = (k + 1) % n;
                    }
                    if ok {
                        split = Some(r);
                        break;
                    }
                }
            }
            match split {
                None => next.push(t),
                Some(r) => {
                    again = true;
                    let (a, b, c) = (t[r], t[(r + 1) % 3], t[(r + 2) % 3]);
                    let k = ((a as usize + 1) % n) as u32;
                    next.push([a, k, c]);
                    next.push([k, b, c]);
                }
            }
        }
        triangles = next;
    }
    if triangles.len() + 2 != n {
        return Err(CdtError::Other(format!(
            "polygon: {} triangles for {n} vertices",
            triangles.len()
        )));
    }
    Ok((triangles, kept_wanted))
}

/// Inserts the midpoint of every chord (an edge between two curve vertices, the first
/// `curve_vertices` of the triangulation, that is not a constraint); returns how many. A midpoint
/// closer than a fifth of the chord's half-length to another vertex or edge of the triangle it
/// lands in would only make a sliver, and is skipped.
fn split_chords(cdt: &mut Cdt, curve_vertices: usize) -> usize {
    let chords: Vec<(Point, f64)> = cdt
        .undirected_edges()
        .filter(|e| {
            let [a, b] = e.vertices();
            a.fix().index() < curve_vertices
                && b.fix().index() < curve_vertices
                && !cdt.is_constraint_edge(e.fix())
        })
        .map(|e| {
            let [a, b] = e
                .vertices()
                .map(|v| v.position())
                .map(|p| Point::new(p.x, p.y));
            ((a + b) * 0.5, 0.5 * a.distance(b))
        })
        .collect();
    let mut inserted = 0;
    for (m, half) in chords {
        let at = Point2::new(m.x, m.y);
        let clear = match cdt.locate(at) {
            PositionInTriangulation::OnFace(f) => {
                let p = cdt
                    .face(f)
                    .vertices()
                    .map(|v| v.position())
                    .map(|q| Point::new(q.x, q.y));
                (0..3).all(|k| {
                    let (d, _) = crate::geometry::point_segment_distance(m, p[k], p[(k + 1) % 3]);
                    // the chord itself passes through m: it is one of the edges at distance 0
                    let is_chord = |q: Point| (q.distance(m) - half).abs() < 1e-6 * half;
                    d >= 0.2 * half || (is_chord(p[k]) && is_chord(p[(k + 1) % 3]))
                }) && p.iter().all(|q| q.distance(m) >= 0.2 * half)
            }
            // On a curve edge the insertion would split it (the correspondence needs it whole).
            PositionInTriangulation::OnEdge(e) if cdt.is_constraint_edge(e.as_undirected()) => {
                false
            }
            PositionInTriangulation::OnEdge(e) => {
                let [a, b] = cdt.directed_edge(e).vertices().map(|v| v.position());
                Point::new(a.x, a.y).distance(m) >= 0.2 * half
                    && Point::new(b.x, b.y).distance(m) >= 0.2 * half
            }
            _ => false,
        };
        if clear && cdt.insert(at).is_ok() {
            inserted += 1;
        }
    }
    inserted
}
