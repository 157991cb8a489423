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
/// boundary. `twins`: the curve vertices' positions in the other drawing, in the same order
/// (they decide which chords must be split, [`split_chords`]).
pub(super) fn build(
    curves: &[(&[Point], bool)],
    twins: &[Point],
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
    if twins.len() != count {
        return Err(CdtError::Other(
            "curve vertices and their twins differ in number".into(),
        ));
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
    // each triangle a free corner (where that makes only slivers, only the chords of triangles
    // that would fold are split, `split_chords`); the refinement then restores the angles.
    for _ in 0..4 {
        if split_chords(&mut cdt, count, twins, &boundary_edges)? == 0 {
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
    Ok(merge_twin_steiner_points(
        points, triangles, count, tol.snap,
    ))
}

/// Merges each Steiner point (index `curve_vertices` and up) that lies within `snap` of a
/// neighbour into that neighbour, dropping the triangles that shrink to an edge and any vertex
/// left unused.
///
/// spade's refinement inserts the circumcentre of each bad triangle; the two triangles of four
/// points on one circle (a band between concentric arcs) share theirs, up to rounding, and both
/// get inserted: two vertices a rounding error apart, joined by an edge to which the disc
/// interpolation cannot give a rotation. A merge is kept only if every triangle it touches stays
/// counter-clockwise (exact test); moving a vertex by `snap` can only flip a sliver that thin.
fn merge_twin_steiner_points(
    mut points: Vec<Point>,
    mut triangles: Vec<[u32; 3]>,
    curve_vertices: usize,
    snap: f64,
) -> (Vec<Point>, Vec<[u32; 3]>) {
    let mut into: Vec<u32> = (0..points.len() as u32).collect();
    let mut merged = false;
    for k in 0..triangles.len() {
        for e in 0..3 {
            let (u, v) = (triangles[k][e], triangles[k][(e + 1) % 3]);
            let (u, v) = (into[u as usize], into[v as usize]);
            // The later-numbered of the two goes (never a curve vertex: they come first).
            let (keep, gone) = (u.min(v), u.max(v));
            if keep == gone
                || (gone as usize) < curve_vertices
                || points[keep as usize].distance(points[gone as usize]) > snap
            {
                continue;
            }
            let at = |w: u32| {
                if into[w as usize] == gone {
                    keep
                } else {
                    into[w as usize]
                }
            };
            let valid = triangles.iter().all(|t| {
                let m = t.map(at);
                m[0] == m[1] || m[1] == m[2] || m[2] == m[0] || {
                    let [a, b, c] = m.map(|w| points[w as usize]);
                    orient2d(a, b, c) > 0.0
                }
            });
            if valid {
                for w in into.iter_mut().filter(|w| **w == gone) {
                    *w = keep;
                }
                merged = true;
            }
        }
    }
    if !merged {
        return (points, triangles);
    }
    triangles = triangles
        .into_iter()
        .map(|t| t.map(|w| into[w as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    let mut renumber = vec![u32::MAX; points.len()];
    let mut kept = Vec::with_capacity(points.len());
    for (w, p) in points.drain(..).enumerate() {
        if into[w] == w as u32 {
            renumber[w] = kept.len() as u32;
            kept.push(p);
        }
    }
    for t in &mut triangles {
        *t = t.map(|w| renumber[w as usize]);
    }
    (kept, triangles)
}

/// Which faces are inside the boundary whose (counter-clockwise) edges are `boundary_edges`:
/// a flood fill from the faces left of them that never crosses a boundary edge (feature edges
/// are crossed freely). The boundary's edges are flagged by handle first, so the fill tests a
/// flag per edge rather than searching the set twice.
fn inside_faces(
    cdt: &Cdt,
    boundary_edges: &BTreeSet<(usize, usize)>,
) -> Result<Vec<bool>, CdtError> {
    let mut inside = vec![false; cdt.num_all_faces()];
    let mut on_boundary = vec![false; cdt.num_undirected_edges()];
    let mut stack = Vec::new();
    for &(a, b) in boundary_edges {
        let e = cdt
            .get_edge_from_neighbors(
                FixedVertexHandle::from_index(a),
                FixedVertexHandle::from_index(b),
            )
            .ok_or_else(|| CdtError::Other("a boundary edge was split".into()))?;
        on_boundary[e.as_undirected().fix().index()] = true;
        if let Some(f) = e.face().as_inner() {
            if !inside[f.fix().index()] {
                inside[f.fix().index()] = true;
                stack.push(f.fix());
            }
        }
    }
    while let Some(f) = stack.pop() {
        for e in cdt.face(f).adjacent_edges() {
            if on_boundary[e.as_undirected().fix().index()] {
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

/// Inserts a free vertex at every chord (an edge between two curve vertices, the first
/// `curve_vertices` of the triangulation, that is not a constraint); returns how many.
///
/// The vertex goes at the chord's midpoint, which splits it. A midpoint closer than a fifth of
/// the chord's half-length to another vertex or edge of the triangle it lands in would only
/// make a sliver, and is skipped — unless the chord borders an *ear*, a triangle of three curve
/// vertices, that is inverted or a sliver in the other drawing (`twins`: every curve vertex's
/// twin; [`crate::geometry::inverted_or_sliver`], the test the mapping applies). No mapping can unfold such an ear, since all its corners are held on the curves, so
/// it must go whatever the slivers: the vertex is put a fifth of the half-length off the chord
/// on the side away from the ear, where the Delaunay flip replaces the chord by an edge from
/// the ear's apex (the apex lies inside the circle through the chord and the new vertex), or on
/// the midpoint when that side has no room. A star's tip that becomes a straight run of a
/// smooth outline makes such an ear.
fn split_chords(
    cdt: &mut Cdt,
    curve_vertices: usize,
    twins: &[Point],
    boundary_edges: &BTreeSet<(usize, usize)>,
) -> Result<usize, CdtError> {
    let on_curve = |v: FixedVertexHandle| v.index() < curve_vertices;
    let xy = |p: Point2<f64>| Point::new(p.x, p.y);
    let chords: Vec<[FixedVertexHandle; 2]> = cdt
        .undirected_edges()
        .filter(|e| {
            let [a, b] = e.vertices();
            on_curve(a.fix()) && on_curve(b.fix()) && !cdt.is_constraint_edge(e.fix())
        })
        .map(|e| e.vertices().map(|v| v.fix()))
        .collect();
    // Midpoints first, each checked against the vertices inserted before it.
    let mut inserted = 0;
    let mut unclear = Vec::new();
    for [a, b] in chords {
        let (pa, pb) = (xy(cdt.vertex(a).position()), xy(cdt.vertex(b).position()));
        let (m, half) = ((pa + pb) * 0.5, 0.5 * pa.distance(pb));
        if !clear_of_others(cdt, m, half, (pa, pb)) {
            unclear.push(([a, b], pa, pb, m, half));
        } else if insert_free(cdt, m) {
            inserted += 1;
        }
    }
    // Then the ears pinned flat or inverted in the other drawing, on the chords still there:
    // the new vertex goes on the side of the chord away from the ear.
    let inside = inside_faces(cdt, boundary_edges)?;
    let mut spots: Vec<Point> = Vec::new();
    for ([a, b], pa, pb, m, half) in unclear {
        let Some(e) = cdt.get_edge_from_neighbors(a, b) else {
            continue;
        };
        for (f, other) in [(e.face(), e.rev().face()), (e.rev().face(), e.face())] {
            let (Some(f), Some(other)) = (f.as_inner(), other.as_inner()) else {
                continue;
            };
            let v = f.vertices().map(|v| v.fix());
            let pinned = v.iter().all(|&v| on_curve(v)) && {
                let [p, q, r] = v.map(|v| twins[v.index()]);
                crate::geometry::inverted_or_sliver(p, q, r)
            };
            if !inside[f.fix().index()] || !pinned {
                continue;
            }
            let Some(apex) = v.iter().find(|&&v| v != a && v != b) else {
                continue;
            };
            let apex = xy(cdt.vertex(*apex).position());
            let n = (pb - pa).perp() / (2.0 * half);
            let away = if n.dot(apex - m) > 0.0 { -n } else { n };
            let off = m + away * (0.2 * half);
            // Clear of the far triangle's corners, else the midpoint, clear of the apex.
            let room = |p: Point| {
                other
                    .vertices()
                    .iter()
                    .chain(&f.vertices())
                    .all(|v| xy(v.position()).distance(p) >= 0.05 * half)
            };
            let in_other = matches!(cdt.locate(Point2::new(off.x, off.y)),
                PositionInTriangulation::OnFace(g) if g == other.fix());
            if in_other && room(off) {
                spots.push(off);
            } else if room(m) {
                spots.push(m);
            }
        }
    }
    for p in spots {
        if insert_free(cdt, p) {
            inserted += 1;
        }
    }
    Ok(inserted)
}

/// Inserts a vertex at `p` unless that is on a vertex (a spot found twice is inserted once) or
/// on a curve edge (the correspondence needs it whole); returns whether it did.
fn insert_free(cdt: &mut Cdt, p: Point) -> bool {
    let at = Point2::new(p.x, p.y);
    let free = match cdt.locate(at) {
        PositionInTriangulation::OnFace(_) => true,
        PositionInTriangulation::OnEdge(e) => !cdt.is_constraint_edge(e.as_undirected()),
        _ => false,
    };
    free && cdt.insert(at).is_ok()
}

/// Whether a new vertex at `p` stays at least a fifth of `half` away from the vertices and
/// edges of the triangle it lands in (else it would only make a sliver), and off every curve
/// edge (the correspondence needs them whole). `chord`: the endpoints of the edge `p` is the
/// midpoint of, which the vertex is meant to split (so its distance to that edge is not
/// counted).
fn clear_of_others(cdt: &Cdt, p: Point, half: f64, chord: (Point, Point)) -> bool {
    let at = Point2::new(p.x, p.y);
    let on_chord = |q: Point| q == chord.0 || q == chord.1;
    match cdt.locate(at) {
        PositionInTriangulation::OnFace(f) => {
            let c = cdt
                .face(f)
                .vertices()
                .map(|v| v.position())
                .map(|q| Point::new(q.x, q.y));
            (0..3).all(|k| {
                let (d, _) = crate::geometry::point_segment_distance(p, c[k], c[(k + 1) % 3]);
                d >= 0.2 * half || (on_chord(c[k]) && on_chord(c[(k + 1) % 3]))
            }) && c.iter().all(|q| q.distance(p) >= 0.2 * half)
        }
        // On a curve edge the insertion would split it.
        PositionInTriangulation::OnEdge(e) if cdt.is_constraint_edge(e.as_undirected()) => false,
        PositionInTriangulation::OnEdge(e) => {
            let [a, b] = cdt.directed_edge(e).vertices().map(|v| v.position());
            Point::new(a.x, a.y).distance(p) >= 0.2 * half
                && Point::new(b.x, b.y).distance(p) >= 0.2 * half
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn a_steiner_point_a_rounding_error_from_another_is_merged() {
        // A square fanned around two centres 1e-12 apart (indices 4 and 5).
        let e = 1e-12;
        let points = vec![
            p(0., 0.),
            p(1., 0.),
            p(1., 1.),
            p(0., 1.),
            p(0.5, 0.5),
            p(0.5 + e, 0.5),
        ];
        let triangles = vec![
            [0, 1, 5],
            [1, 2, 5],
            [2, 4, 5],
            [2, 3, 4],
            [3, 0, 4],
            [0, 5, 4],
        ];
        let (pts, tris) = merge_twin_steiner_points(points.clone(), triangles.clone(), 4, 1e-9);
        assert_eq!(pts, points[..5]);
        assert_eq!(tris.len(), 4);
        assert!(tris.iter().all(|t| orient2d(
            pts[t[0] as usize],
            pts[t[1] as usize],
            pts[t[2] as usize]
        ) > 0.0));
        // Farther apart than `snap`, or a curve vertex: left alone.
        let (pts, tris) = merge_twin_steiner_points(points.clone(), triangles.clone(), 4, 1e-13);
        assert_eq!((pts.len(), tris.len()), (6, 6));
        let (pts, _) = merge_twin_steiner_points(points, triangles, 6, 1e-9);
        assert_eq!(pts.len(), 6);
    }

    #[test]
    fn an_ear_pinned_flat_in_the_other_drawing_is_split() {
        // A spike whose tip ear (tip and its two neighbours, as in a star rounded by an
        // optimiser) is cut off by a chord whose midpoint lies close to one side, so the
        // sliver rule alone would keep it; in the other drawing the three are collinear.
        let tip = p(0., 0.);
        let (l, r) = (p(-0.42, 1.0).normalize(), p(0.42, 1.0).normalize());
        let mut outline = vec![tip];
        outline.extend([3.6, 7.2, 10.8, 14.4].map(|d| tip + r * d));
        outline.push(p(0., 16.));
        outline.extend([14.4, 10.8, 7.2, 3.6, 0.5].map(|d| tip + l * d));
        let n = outline.len();
        let mut twins = outline.clone();
        // The tip onto the segment between its neighbours.
        twins[0] = (twins[1] + twins[n - 1]) * 0.5;
        let tol = Tolerances::new(20.0, 1.0);
        let (points, triangles) = build(&[(&outline, true)], &twins, &tol).unwrap();
        for t in &triangles {
            if t.iter().all(|&v| (v as usize) < n) {
                assert!(
                    !crate::geometry::inverted_or_sliver(
                        twins[t[0] as usize],
                        twins[t[1] as usize],
                        twins[t[2] as usize]
                    ),
                    "triangle {t:?} of curve vertices only is flat in the other drawing"
                );
            }
        }
        assert!(triangles.iter().all(|t| orient2d(
            points[t[0] as usize],
            points[t[1] as usize],
            points[t[2] as usize]
        ) > 0.0));
    }
}
