//! A compatible triangulation that always exists for two simple outlines with a matched vertex
//! correspondence (issue #7, item 2): the rung under the composite harmonic mapping of §5.
//!
//! 1. Each outline is triangulated on its own (the refined constrained Delaunay triangulation
//!    of [`crate::triangulation`], coarse inside: every crossing below becomes a vertex), with
//!    the outline's corresponded vertices as its boundary.
//! 2. Both meshes are embedded in one disc: boundary vertex k goes to the same point of the
//!    unit circle in both (at the mean of its two normalized arc lengths) and the interior
//!    vertices where a convex-combination map puts them — the cotangent weights of the
//!    Delaunay mesh, clamped to stay positive — which is one-to-one onto a convex boundary by
//!    Tutte's theorem (Floater, 2003). Each mesh's embedding is thus a valid triangulation of
//!    the same convex polygon.
//! 3. The two embedded triangulations are overlaid (Aronov, Seidel and Souvaine, 1993;
//!    Surazhsky and Gotsman, 2004): a constrained Delaunay triangulation of the disc with the
//!    edges of both as constraints, every crossing of a source edge with a target edge a new
//!    vertex. Each of its triangles lies inside one source triangle and one target triangle.
//! 4. Every vertex is carried back to each outline through the triangle of that side's mesh it
//!    lies in (barycentric coordinates). Inside one triangle the map from the disc to an
//!    outline is affine, so every overlay triangle keeps its orientation in both: the meshes
//!    are compatible by construction, with every boundary vertex on its twin. The composite of
//!    the two embeddings is a smooth one-to-one map between the shapes, so the interpolation
//!    has a sensible interior to move.
//!
//! Floating point can still leave a sliver inverted where edges cross at a tiny angle; those
//! vertices are moved within their stars, and the `remesh` module then improves the mesh (splits,
//! flips and smoothing that keep it valid in both meshes).

use crate::artwork::PointLocator;
use crate::correspondence::CurvePair;
use crate::geometry::{orient2d, polygon_area, Point};
use crate::mesh::{count_inverted, CompatibleMeshes, CurveKind, MeshCurve, Side};
use crate::tolerance::Tolerances;
use crate::triangulation::{triangulate, Triangulation};
use crate::{Error, Result};
use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation as _};

/// How much longer the edges of the two meshes overlaid are than the tolerance's.
const COARSENESS: f64 = 4.0;

/// Most vertices of the overlay, as a multiple of the two meshes' vertex counts: beyond, the
/// outlines' embeddings cross each other nearly everywhere, the overlay is large and slow to
/// interpolate, and its slivers fold; the outline then morphs on its own instead.
const VERTEX_BUDGET: usize = 3;

/// Most grid cells per edge that [`crossings`] lists the edges of a mesh in before it gives the
/// count up: a bound on its memory.
const LISTING_BUDGET: usize = 64;

/// Compatible triangulations of the two sides of the closed outline pair `outline` (module
/// docs): vertices `0..n` are the outline's, in order. Errors when a side is not a simple
/// polygon, or when rounding left a triangle the repair cannot straighten.
pub fn compatible_outlines(outline: &CurvePair, tol: &Tolerances) -> Result<CompatibleMeshes> {
    let (p, q) = (&outline.source, &outline.target);
    let n = p.len();
    if !outline.closed || n < 3 || q.len() != n {
        return Err(Error::internal("overlay: not a closed outline pair"));
    }
    if polygon_area(p) <= 0.0 || polygon_area(q) <= 0.0 {
        return Err(Error::input(
            crate::error::Drawings::Pair,
            format!("{}: an outline is not counter-clockwise", outline.id),
        ));
    }
    let pairs = [outline.clone()];
    // Coarse interiors: every crossing of the two meshes becomes a vertex, so each is
    // triangulated with triangles COARSENESS times the usual size; the overlay's own refinement
    // (`remesh`) brings the mesh back to the tolerance's edge length.
    let coarse = Tolerances::new(tol.diagonal * COARSENESS, 1.0);
    let coarse = Tolerances {
        snap: tol.snap,
        flatten: tol.flatten,
        ..coarse
    };
    let a = triangulate(&pairs, &coarse, Side::Source)?;
    let b = triangulate(&pairs, &coarse, Side::Target)?;
    let circle = disc_points(p, q);
    let da = embed(&a, &circle)?;
    let db = embed(&b, &circle)?;
    let budget = VERTEX_BUDGET * (a.points.len() + b.points.len());
    let over_budget = || {
        Error::input(
            crate::error::Drawings::Pair,
            format!(
                "{}: the overlay would have more than {budget} vertices",
                outline.id
            ),
        )
    };
    let (ea, eb) = (
        crate::mesh::edges(&a.triangles),
        crate::mesh::edges(&b.triangles),
    );
    // Every proper crossing of a source edge with a target edge is a vertex of the overlay, so
    // counting them (far cheaper than making them) tells most overlays over the budget before
    // one is made. The margin keeps a crossing that rounds onto an existing vertex (no new
    // vertex) from deciding; `overlay` still stops at the budget itself.
    let room = budget.saturating_sub(a.points.len() + b.points.len() - n) + budget / 64;
    if crossings(&da, &ea, &db, &eb, room) > room {
        return Err(over_budget());
    }
    let Some((disc, owner_a, owner_b, triangles)) = overlay(n, (&da, &ea), (&db, &eb), budget)?
    else {
        return Err(over_budget());
    };
    let carry = |d: &[Point], mesh: &Triangulation, owner: &[Option<u32>]| -> Result<Vec<Point>> {
        let locator = PointLocator::new(d, &mesh.triangles)?;
        Ok(disc
            .iter()
            .zip(owner)
            .map(|(&x, o)| match o {
                Some(k) => mesh.points[*k as usize],
                None => locator.locate(x).place(&mesh.triangles, &mesh.points),
            })
            .collect())
    };
    let source = carry(&da, &a, &owner_a)?;
    let target = carry(&db, &b, &owner_b)?;
    let mut m = CompatibleMeshes {
        triangles,
        source,
        target,
        curves: vec![MeshCurve {
            name: outline.id.clone(),
            kind: CurveKind::Boundary,
            closed: true,
            vertices: (0..n as u32).collect(),
        }],
        parts: None,
    };
    super::remesh::untangle(&mut m, n);
    let folded = count_inverted(&m.triangles, &m.source) + count_inverted(&m.triangles, &m.target);
    if folded > 0 {
        return Err(Error::input(
            crate::error::Drawings::Pair,
            format!(
                "{}: {folded} triangles of the overlaid triangulation are degenerate",
                outline.id
            ),
        ));
    }
    super::remesh::improve(&mut m, n, tol);
    Ok(m)
}

/// The disc embedding of a triangulation whose first `circle.len()` vertices are its boundary:
/// those on `circle`, the others by a convex-combination map (module docs).
fn embed(mesh: &Triangulation, circle: &[Point]) -> Result<Vec<Point>> {
    let n = circle.len();
    let mut fixed = vec![false; mesh.points.len()];
    fixed[..n].fill(true);
    let mut h = super::harmonic::Harmonic::new(&mesh.triangles, mesh.points.len(), &fixed)?;
    let mut out = mesh.points.clone();
    out[..n].copy_from_slice(circle);
    h.solve_convex(&mesh.points, &mut out)?;
    Ok(out)
}

/// Boundary vertex k on the unit circle at the mean of its normalized arc lengths along the two
/// outlines (counter-clockwise, like the outlines).
fn disc_points(p: &[Point], q: &[Point]) -> Vec<Point> {
    let arcs = |r: &[Point]| -> Vec<f64> {
        let n = r.len();
        let mut s = Vec::with_capacity(n);
        let mut acc = 0.0;
        for k in 0..n {
            s.push(acc);
            acc += r[k].distance(r[(k + 1) % n]);
        }
        s.iter().map(|x| x / acc.max(f64::MIN_POSITIVE)).collect()
    };
    let (a, b) = (arcs(p), arcs(q));
    a.iter()
        .zip(&b)
        .map(|(x, y)| {
            let th = std::f64::consts::TAU * 0.5 * (x + y);
            Point::new(th.cos(), th.sin())
        })
        .collect()
}

/// Overlay vertices in the disc, which of them are vertices of the source mesh `a` (and of
/// the target mesh `b`) with their index there, and the overlay's triangles
/// (counter-clockwise).
type Overlaid = (
    Vec<Point>,
    Vec<Option<u32>>,
    Vec<Option<u32>>,
    Vec<[u32; 3]>,
);

/// How many times an edge of `ea` (vertex pairs, positions `pa`) crosses an edge of `eb`
/// (positions `pb`) properly ([`crate::geometry::segments_cross`]), counted until the count
/// passes `limit`; 0 (nothing known) when listing the edges would take more than
/// [`LISTING_BUDGET`] cells per edge.
///
/// The edges of `ea` are listed in the cells of a grid whose lines are at quantiles of the
/// vertices' coordinates, so that a disc embedding's crowded middle is split as finely as its
/// rim; each edge of `eb` is tested against the edges listed in the cells its box covers, each
/// once. An edge is listed in every cell of its box, so many long diagonal edges (chords of the
/// disc) could fill a listing far larger than the meshes: then the count is not made, and the
/// overlay's own stop at its budget decides.
fn crossings(
    pa: &[Point],
    ea: &[(u32, u32)],
    pb: &[Point],
    eb: &[(u32, u32)],
    limit: usize,
) -> usize {
    let side = ((ea.len() as f64).sqrt() as usize).clamp(1, 512);
    let cuts = |coordinate: fn(&Point) -> f64| -> Vec<f64> {
        let mut v: Vec<f64> = pa.iter().map(coordinate).collect();
        v.sort_unstable_by(f64::total_cmp);
        (1..side).map(|k| v[k * v.len() / side]).collect()
    };
    let (cx, cy) = (cuts(|p| p.x), cuts(|p| p.y));
    // The cells (columns, rows) that the box of segment `pq` covers.
    let span = |p: Point, q: Point| {
        let at = |cuts: &[f64], v: f64| cuts.partition_point(|&c| c < v);
        (
            at(&cx, p.x.min(q.x))..=at(&cx, p.x.max(q.x)),
            at(&cy, p.y.min(q.y))..=at(&cy, p.y.max(q.y)),
        )
    };
    let spans: Vec<_> = ea
        .iter()
        .map(|&(u, v)| span(pa[u as usize], pa[v as usize]))
        .collect();
    let listing: usize = spans
        .iter()
        .map(|(xs, ys)| xs.clone().count() * ys.clone().count())
        .sum();
    if listing > LISTING_BUDGET * ea.len() {
        return 0;
    }
    let mut entries: Vec<(u32, u32)> = Vec::with_capacity(listing);
    for (e, (xs, ys)) in spans.into_iter().enumerate() {
        for y in ys {
            entries.extend(xs.clone().map(|x| ((y * side + x) as u32, e as u32)));
        }
    }
    let (start, listed) = crate::mesh::compressed_rows(side * side, entries.into_iter());
    let mut tested = vec![u32::MAX; ea.len()];
    let mut count = 0;
    for (f, &(u, v)) in eb.iter().enumerate() {
        let (p, q) = (pb[u as usize], pb[v as usize]);
        let (xs, ys) = span(p, q);
        for y in ys {
            for x in xs.clone() {
                let cell = y * side + x;
                for &e in &listed[start[cell]..start[cell + 1]] {
                    if std::mem::replace(&mut tested[e as usize], f as u32) == f as u32 {
                        continue;
                    }
                    let (a, b) = ea[e as usize];
                    if crate::geometry::segments_cross(pa[a as usize], pa[b as usize], p, q) {
                        count += 1;
                        if count > limit {
                            return count;
                        }
                    }
                }
            }
        }
    }
    count
}

/// The overlay of two disc embeddings, each given as its vertices' positions and its edges;
/// the first `n` vertices of both are the shared boundary (module docs). `None` as soon as it
/// has more than `budget` vertices: most of its cost is the crossings, each a new vertex, and
/// an overlay over the budget is given up whatever its final size, so the rest of them are not
/// worth making.
fn overlay(
    n: usize,
    (da, ea): (&[Point], &[(u32, u32)]),
    (db, eb): (&[Point], &[(u32, u32)]),
    budget: usize,
) -> Result<Option<Overlaid>> {
    type Cdt = ConstrainedDelaunayTriangulation<Point2<f64>>;
    let mut cdt = Cdt::new();
    let insert = |cdt: &mut Cdt, p: Point| {
        cdt.insert(Point2::new(p.x, p.y))
            .map_err(|_| Error::internal("overlay: a disc position spade cannot take"))
    };
    let mut ha: Vec<FixedVertexHandle> = Vec::with_capacity(da.len());
    for (k, &p) in da.iter().enumerate() {
        let h = insert(&mut cdt, p)?;
        if k < n && h.index() != k {
            return Err(Error::internal("overlay: boundary vertices merged"));
        }
        ha.push(h);
    }
    let mut hb: Vec<FixedVertexHandle> = ha[..n].to_vec();
    for &p in &db[n..] {
        hb.push(insert(&mut cdt, p)?);
    }
    for &(x, y) in ea {
        cdt.add_constraint(ha[x as usize], ha[y as usize]);
    }
    if cdt.num_vertices() > budget {
        return Ok(None);
    }
    for &(x, y) in eb {
        cdt.add_constraint_and_split(hb[x as usize], hb[y as usize], |p| p);
        if cdt.num_vertices() > budget {
            return Ok(None);
        }
    }
    let count = cdt.num_vertices();
    let mut owner_a = vec![None; count];
    let mut owner_b = vec![None; count];
    for (k, h) in ha.iter().enumerate() {
        owner_a[h.index()] = Some(k as u32);
    }
    for (k, h) in hb.iter().enumerate() {
        owner_b[h.index()] = Some(k as u32);
    }
    let disc: Vec<Point> = cdt
        .fixed_vertices()
        .map(|v| {
            let p = cdt.vertex(v).position();
            Point::new(p.x, p.y)
        })
        .collect();
    let mut triangles = Vec::with_capacity(cdt.num_inner_faces());
    for f in cdt.fixed_inner_faces() {
        let mut t = cdt.face(f).vertices().map(|v| v.fix().index() as u32);
        let o = orient2d(
            disc[t[0] as usize],
            disc[t[1] as usize],
            disc[t[2] as usize],
        );
        if o == 0.0 {
            continue;
        }
        if o < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    Ok(Some((disc, owner_a, owner_b, triangles)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::sanity_check;

    fn pair(source: Vec<Point>, target: Vec<Point>) -> CurvePair {
        CurvePair {
            id: "boundary".into(),
            kind: CurveKind::Boundary,
            closed: true,
            salient: vec![0],
            source,
            target,
        }
    }

    /// A comb and a spiral-ish star with the same vertex count: their own triangulations share
    /// few diagonals, so the overlay has crossings, and both meshes must still be valid.
    fn star(n: usize, k: f64, phase: f64, amp: f64) -> Vec<Point> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64 + phase;
                let r = 1.0 + amp * (k * a).sin();
                Point::new(r * a.cos(), r * a.sin())
            })
            .collect()
    }

    #[test]
    fn overlaid_outlines_are_compatible_and_unfolded() {
        let mut built = 0;
        for (k1, k2, n, amp) in [
            (3.0, 3.0, 60, 0.6),
            (4.0, 4.0, 40, 0.5),
            (3.0, 5.0, 60, 0.6),
            (2.0, 7.0, 84, 0.6),
        ] {
            let (s, t) = (star(n, k1, 0.0, amp), star(n, k2, 0.3, 0.3));
            let o = pair(s.clone(), t.clone());
            // Outlines too different for the vertex budget are an input error, not a panic.
            let m = match compatible_outlines(&o, &Tolerances::new(4.0, 1.0)) {
                Ok(m) => m,
                Err(e) => {
                    assert!(e.is_input(), "{e}");
                    continue;
                }
            };
            built += 1;
            let r = sanity_check(&m, Some(std::slice::from_ref(&t)), 1e-12);
            assert!(r.is_ok(), "{k1} {k2}: {r:?}");
            for (i, (a, b)) in s.iter().zip(&t).enumerate() {
                assert_eq!(m.source[i], *a);
                assert_eq!(m.target[i], *b);
            }
        }
        assert!(built >= 2, "only {built} overlays within the budget");
    }

    /// An embedded mesh: its vertices' positions in the disc, and its edges.
    type Embedding = (Vec<Point>, Vec<(u32, u32)>);

    /// The boundary's vertex count and the two embedded meshes of a star pair with crossings.
    fn embedded_stars() -> (usize, Embedding, Embedding) {
        let (s, t) = (star(60, 3.0, 0.0, 0.6), star(60, 5.0, 0.3, 0.3));
        let pairs = [pair(s.clone(), t.clone())];
        let tol = Tolerances::new(4.0, 1.0);
        let a = triangulate(&pairs, &tol, Side::Source).unwrap();
        let b = triangulate(&pairs, &tol, Side::Target).unwrap();
        let circle = disc_points(&s, &t);
        let (da, db) = (embed(&a, &circle).unwrap(), embed(&b, &circle).unwrap());
        let (ea, eb) = (
            crate::mesh::edges(&a.triangles),
            crate::mesh::edges(&b.triangles),
        );
        (60, (da, ea), (db, eb))
    }

    /// The overlay stops as soon as it passes its vertex budget, and gives up exactly the
    /// overlays that, made whole, would have more vertices than the budget.
    #[test]
    fn the_overlay_stops_once_over_its_budget_and_only_then() {
        let (n, (da, ea), (db, eb)) = embedded_stars();
        let (a, b) = ((&da[..], &ea[..]), (&db[..], &eb[..]));
        let whole = overlay(n, a, b, usize::MAX).unwrap().unwrap();
        let count = whole.0.len();
        let vertices = da.len() + db.len() - n;
        // Crossings make most of it: a budget anywhere below stops it early.
        assert!(count > vertices);
        let at = overlay(n, a, b, count).unwrap().unwrap();
        assert!(crate::geometry::same_bits(&at.0, &whole.0));
        assert_eq!(at.3, whole.3);
        for budget in [count - 1, vertices] {
            assert!(overlay(n, a, b, budget).unwrap().is_none());
        }
    }

    /// The crossings counted are every pair of edges that cross properly (a test of all
    /// pairs), each one a vertex the overlay adds; counting stops just past the limit.
    #[test]
    fn crossings_are_the_vertices_the_overlay_adds() {
        let (n, (da, ea), (db, eb)) = embedded_stars();
        let all = ea
            .iter()
            .flat_map(|&(u, v)| eb.iter().map(move |&(x, y)| (u, v, x, y)))
            .filter(|&(u, v, x, y)| {
                crate::geometry::segments_cross(
                    da[u as usize],
                    da[v as usize],
                    db[x as usize],
                    db[y as usize],
                )
            })
            .count();
        assert!(all > 100, "{all}");
        assert_eq!(crossings(&da, &ea, &db, &eb, usize::MAX), all);
        assert_eq!(crossings(&da, &ea, &db, &eb, 10), 11);
        // Long diagonal edges listed in too many cells: no count.
        let fan: Vec<(u32, u32)> = (1..ea.len() as u32).map(|k| (0, k % 60)).collect();
        let spread: Vec<Point> = (0..60)
            .map(|k| Point::new(k as f64, (k * 37 % 60) as f64))
            .collect();
        assert_eq!(crossings(&spread, &fan, &db, &eb, usize::MAX), 0);
        let whole = overlay(n, (&da, &ea), (&db, &eb), usize::MAX)
            .unwrap()
            .unwrap();
        assert_eq!(whole.0.len(), da.len() + db.len() - n + all);
    }
}
