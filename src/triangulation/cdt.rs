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
pub(super) enum CdtError {
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
fn inside_faces(
    cdt: &Cdt,
    boundary_edges: &BTreeSet<(usize, usize)>,
) -> Result<Vec<bool>, CdtError> {
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
