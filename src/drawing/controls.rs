//! Finding control geometry by id in the raw element tree (DESIGN.md §1) and validating it.

use kurbo::{Affine, BezPath};

use super::flatten::{flatten, Subpath};
use super::shapes::{is_shape, length, outline, transform};
use super::xml::Element;
use super::{Anchor, ControlCurve, ControlIds, Controls, SkeletonChain};
use crate::error::{Error, Result};
use crate::geometry::{polygon_area, polyline_self_intersection, segments_intersect, Point};
use crate::input::{Limit, Limits};
use crate::mesh::CurveKind;
use crate::tolerance::{Tolerances, MAX_COORDINATE, MIN_DIAGONAL};

/// What a control element is, by its id.
#[derive(Debug, Clone, PartialEq)]
enum Role {
    Boundary,
    Feature(String),
    Anchor(String),
    Skeleton,
}

/// A control element found in the tree, with its geometry in root user space.
#[derive(Debug, Clone)]
struct Found {
    id: String,
    role: Role,
    path: BezPath,
    element: String,
}

/// Elements whose subtrees are never rendered directly and hold no control geometry.
fn is_container_of_definitions(name: &str) -> bool {
    matches!(
        name,
        "defs"
            | "clipPath"
            | "mask"
            | "pattern"
            | "symbol"
            | "marker"
            | "linearGradient"
            | "radialGradient"
            | "filter"
            | "style"
            | "script"
            | "metadata"
            | "title"
            | "desc"
    )
}

fn role(id: &str, ids: &ControlIds) -> Option<Role> {
    if id == ids.boundary {
        Some(Role::Boundary)
    } else if let Some(n) = id
        .strip_prefix(&ids.feature_prefix)
        .filter(|n| !n.is_empty())
    {
        Some(Role::Feature(n.to_string()))
    } else if let Some(n) = id
        .strip_prefix(&ids.anchor_prefix)
        .filter(|n| !n.is_empty())
    {
        Some(Role::Anchor(n.to_string()))
    } else if id == ids.skeleton
        || id
            .strip_prefix(&ids.skeleton)
            .is_some_and(|r| r.starts_with('-') && r.len() > 1)
    {
        Some(Role::Skeleton)
    } else {
        None
    }
}

fn walk(
    el: &Element,
    ctm: Affine,
    ids: &ControlIds,
    file: &str,
    found: &mut Vec<Found>,
) -> Result<()> {
    for child in &el.children {
        if is_container_of_definitions(&child.name) {
            continue;
        }
        let local = transform(child).map_err(|m| locate(file, child, m))?;
        let m = ctm * local;
        match child.name.as_str() {
            "g" | "a" | "switch" => walk(child, m, ids, file, found)?,
            "svg" => {
                let x = length(child, "x", 0.0).map_err(|e| locate(file, child, e))?;
                let y = length(child, "y", 0.0).map_err(|e| locate(file, child, e))?;
                walk(child, m * Affine::translate((x, y)), ids, file, found)?
            }
            name if is_shape(name) => {
                if let Some(id) = child.id() {
                    if let Some(r) = role(id, ids) {
                        let p = outline(child).map_err(|e| locate(file, child, e))?;
                        found.push(Found {
                            id: id.to_string(),
                            role: r,
                            path: m * p,
                            element: child.name.clone(),
                        });
                    }
                }
            }
            _ => {
                if let Some(id) = child.id() {
                    if role(id, ids).is_some() {
                        return Err(Error::at(
                            file,
                            id,
                            format!("a <{}> cannot be control geometry", child.name),
                        )
                        .with_hint(
                            "use a path, rect, circle, ellipse, line, polyline or polygon",
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

fn locate(file: &str, el: &Element, problem: String) -> Error {
    match el.id() {
        Some(id) => Error::at(file, id, problem),
        None => Error::input(file, format!("<{}>: {problem}", el.name)),
    }
}

/// The root's viewBox as `(min, max)`, from `viewBox` or else `width`/`height`.
pub(crate) fn view_box(root: &Element, file: &str) -> Result<Option<(Point, Point)>> {
    if let Some(v) = root.attr("viewBox") {
        let n: Vec<f64> = v
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| s.parse::<f64>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| Error::input(file, format!("bad viewBox \"{v}\"")))?;
        if n.len() != 4 || n.iter().any(|x| !x.is_finite()) || n[2] <= 0.0 || n[3] <= 0.0 {
            return Err(Error::input(file, format!("bad viewBox \"{v}\"")));
        }
        return Ok(Some((
            Point::new(n[0], n[1]),
            Point::new(n[0] + n[2], n[1] + n[3]),
        )));
    }
    let w = length(root, "width", 0.0).map_err(|e| Error::input(file, e))?;
    let h = length(root, "height", 0.0).map_err(|e| Error::input(file, e))?;
    if w > 0.0 && h > 0.0 {
        Ok(Some((Point::ZERO, Point::new(w, h))))
    } else {
        Ok(None)
    }
}

fn check_coordinates(f: &Found, file: &str) -> Result<()> {
    for el in f.path.elements() {
        let pts: &[kurbo::Point] = match el {
            kurbo::PathEl::MoveTo(p) | kurbo::PathEl::LineTo(p) => std::slice::from_ref(p),
            kurbo::PathEl::QuadTo(a, b) => &[*a, *b][..],
            kurbo::PathEl::CurveTo(a, b, c) => &[*a, *b, *c][..],
            kurbo::PathEl::ClosePath => &[],
        };
        for p in pts {
            if !p.x.is_finite() || !p.y.is_finite() {
                return Err(Error::at(
                    file,
                    &f.id,
                    "has a coordinate that is not finite",
                ));
            }
            if p.x.abs() > MAX_COORDINATE || p.y.abs() > MAX_COORDINATE {
                return Err(Error::at(
                    file,
                    &f.id,
                    format!(
                        "has a coordinate ({:.3e}, {:.3e}) too large to morph accurately",
                        p.x, p.y
                    ),
                )
                .with_hint(format!("keep coordinates within ±{MAX_COORDINATE:e}")));
            }
        }
    }
    Ok(())
}

fn single_subpath(f: &Found, subs: Vec<Subpath>, file: &str) -> Result<Subpath> {
    let n = subs.len();
    let mut it = subs.into_iter();
    match (it.next(), n) {
        (Some(s), 1) => Ok(s),
        (None, _) => Err(Error::at(file, &f.id, "is empty")),
        (Some(_), n) => Err(Error::at(
            file,
            &f.id,
            format!("has {n} subpaths; a control curve must be one"),
        )
        .with_hint("split it into separate elements")),
    }
}

/// Whether every point lies within `tol` of the line through the first point and the point
/// farthest from it.
fn all_on_one_line(points: &[Point], tol: f64) -> bool {
    let Some(&a) = points.first() else {
        return true;
    };
    let b = points
        .iter()
        .copied()
        .max_by(|p, q| p.distance(a).total_cmp(&q.distance(a)))
        .unwrap_or(a);
    let len = a.distance(b);
    if len <= tol {
        return true;
    }
    let dir = (b - a) / len;
    points.iter().all(|p| dir.perp_dot(*p - a).abs() <= tol)
}

/// The drawing's size for relative tolerances: the diameter of the boundary's defining points
/// (end and control points) about their centroid. For a rectangle this is exactly its diagonal;
/// unlike a bounding-box diagonal it does not change when the drawing is rotated, so a rotated copy
/// is flattened exactly like the original (DESIGN.md §5 invariant 4 depends on it).
fn drawing_size(path: &BezPath) -> f64 {
    let mut pts = Vec::new();
    for el in path.elements() {
        match *el {
            kurbo::PathEl::MoveTo(p) | kurbo::PathEl::LineTo(p) => pts.push(p),
            kurbo::PathEl::QuadTo(a, b) => pts.extend([a, b]),
            kurbo::PathEl::CurveTo(a, b, c) => pts.extend([a, b, c]),
            kurbo::PathEl::ClosePath => {}
        }
    }
    let pts: Vec<Point> = pts.iter().map(|p| Point::new(p.x, p.y)).collect();
    let c = crate::geometry::centroid(&pts);
    2.0 * pts.iter().map(|p| p.distance(c)).fold(0.0, f64::max)
}

/// Refuses control curves that would flatten (at `tolerance`) to more vertices in all than
/// [`Limits::vertices`], before any is flattened: a curve far larger than the drawing, or a
/// `--density` that makes its tolerance tiny, would otherwise fill memory.
fn check_vertex_budget(found: &[Found], tolerance: f64, file: &str, limits: &Limits) -> Result<()> {
    let mut total = 0.0;
    for f in found.iter().filter(|f| !matches!(f.role, Role::Anchor(_))) {
        total += super::flatten::flattened_count(&f.path, tolerance);
        if total > limits.vertices as f64 {
            let what = format!(
                "control curves flattening to about {} vertices (at '{}')",
                crate::budget::count_text(total),
                crate::error::printable(&f.id)
            );
            return Err(Limit::Vertices.exceeded(file, &what, limits));
        }
    }
    Ok(())
}

/// What [`read_controls`] finds: the controls, their tolerances and the root's viewBox.
pub(crate) type ReadControls = (Controls, Tolerances, Option<(Point, Point)>);

/// Reads and validates the control geometry of a parsed document.
pub(crate) fn read_controls(
    root: &Element,
    file: &str,
    ids: &ControlIds,
    density: f64,
    limits: &Limits,
) -> Result<ReadControls> {
    let vb = view_box(root, file)?;
    let mut found = Vec::new();
    walk(root, Affine::IDENTITY, ids, file, &mut found)?;
    let mut seen = std::collections::BTreeSet::new();
    for f in &found {
        if !seen.insert(f.id.clone()) {
            return Err(Error::at(
                file,
                &f.id,
                "id is used by more than one element",
            ));
        }
        check_coordinates(f, file)?;
    }

    // Size of the drawing: the boundary's bounding box, else the viewBox.
    let boundary = found.iter().find(|f| f.role == Role::Boundary);
    let (lo, hi) = match (boundary, vb) {
        (Some(b), _) => {
            let r = kurbo::Shape::bounding_box(&b.path);
            (Point::new(r.x0, r.y0), Point::new(r.x1, r.y1))
        }
        (None, Some((lo, hi))) => {
            let big = [lo.x, lo.y, hi.x, hi.y]
                .iter()
                .any(|v| v.abs() > MAX_COORDINATE);
            if big {
                return Err(Error::input(
                    file,
                    format!(
                        "the viewBox (from ({:e}, {:e}) to ({:e}, {:e})) is too large to morph \
                         accurately",
                        lo.x, lo.y, hi.x, hi.y
                    ),
                )
                .with_hint(format!("keep coordinates within ±{MAX_COORDINATE:e}")));
            }
            (lo, hi)
        }
        (None, None) => {
            return Err(Error::input(
                file,
                format!(
                    "no '{}' element and no viewBox or width/height to stand in for it",
                    ids.boundary
                ),
            ))
        }
    };
    let diagonal = match boundary {
        Some(b) => drawing_size(&b.path),
        None => lo.distance(hi),
    };
    if diagonal.is_nan() || diagonal < MIN_DIAGONAL {
        return Err(match boundary {
            Some(b) => Error::at(file, &b.id, "is degenerate: it has no extent"),
            None => Error::input(file, "the viewBox is degenerate: it has no extent"),
        });
    }
    let tol = Tolerances::new(diagonal, density);
    check_vertex_budget(&found, tol.flatten, file, limits)?;

    let boundary_curve = match boundary {
        Some(b) => {
            let sp = single_subpath(b, flatten(&b.path, tol.flatten, tol.snap), file)?;
            if !sp.closed {
                return Err(Error::at(file, &b.id, "is not closed")
                    .with_hint("end the path with 'z' or use a closed shape"));
            }
            ControlCurve {
                id: b.id.clone(),
                name: b.id.clone(),
                kind: CurveKind::Boundary,
                closed: true,
                points: sp.points,
            }
        }
        None => ControlCurve {
            id: ids.boundary.clone(),
            name: ids.boundary.clone(),
            kind: CurveKind::Boundary,
            closed: true,
            points: vec![lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)],
        },
    };
    // Problems of the boundary, or of the viewBox standing in for it: only an element that
    // exists is blamed.
    let blame = |problem: String| match boundary {
        Some(b) => Error::at(file, &b.id, problem),
        None => Error::input(file, format!("the viewBox {problem}")),
    };
    if all_on_one_line(&boundary_curve.points, 1e-9 * diagonal) {
        return Err(blame(
            "is degenerate: it encloses no area (its points lie on one line)".into(),
        ));
    }
    if let Some((i, j)) = polyline_self_intersection(&boundary_curve.points, true) {
        let p = edge_crossing(&boundary_curve.points, i, j);
        return Err(blame(format!(
            "crosses itself (edges {i} and {j}, near ({:.3}, {:.3}))",
            p.x, p.y
        )));
    }

    let area = polygon_area(&boundary_curve.points);
    if boundary_curve.points.len() < 3 || area.abs() <= 1e-9 * diagonal * diagonal {
        return Err(blame("is degenerate: it encloses no area".into()));
    }
    let mut features = Vec::new();
    let mut anchors = Vec::new();
    let mut skeleton = Vec::new();
    for f in &found {
        match &f.role {
            Role::Boundary => {}
            Role::Feature(name) => {
                let sp = single_subpath(f, flatten(&f.path, tol.flatten, tol.snap), file)?;
                let distinct = sp.points.len();
                if distinct < 2 || (sp.closed && distinct < 3) {
                    return Err(Error::at(file, &f.id, "is degenerate: it has no length"));
                }
                features.push(ControlCurve {
                    id: f.id.clone(),
                    name: name.clone(),
                    kind: CurveKind::Feature,
                    closed: sp.closed,
                    points: sp.points,
                });
            }
            Role::Anchor(name) => {
                let point = match f.element.as_str() {
                    "circle" | "ellipse" | "rect" => {
                        let r = kurbo::Shape::bounding_box(&f.path);
                        Point::new((r.x0 + r.x1) / 2.0, (r.y0 + r.y1) / 2.0)
                    }
                    _ => match f.path.elements().first() {
                        Some(kurbo::PathEl::MoveTo(p)) => Point::new(p.x, p.y),
                        _ => return Err(Error::at(file, &f.id, "is empty")),
                    },
                };
                anchors.push(Anchor {
                    id: f.id.clone(),
                    name: name.clone(),
                    point,
                });
            }
            Role::Skeleton => {
                let subs = flatten(&f.path, tol.flatten, tol.snap);
                for sp in subs {
                    let mut pts: Vec<Point> = Vec::new();
                    for p in sp.nodes {
                        if pts.last().is_none_or(|q| q.distance(p) > tol.snap) {
                            pts.push(p);
                        }
                    }
                    if pts.len() < 2 {
                        return Err(Error::at(
                            file,
                            &f.id,
                            "has a chain with fewer than two joints",
                        ));
                    }
                    skeleton.push(SkeletonChain {
                        id: f.id.clone(),
                        points: pts,
                    });
                }
            }
        }
    }
    features.sort_by(|a, b| a.name.cmp(&b.name));
    anchors.sort_by(|a, b| a.name.cmp(&b.name));

    validate_layout(&boundary_curve, &features, file)?;

    let controls = Controls {
        boundary: boundary_curve,
        boundary_from_view_box: boundary.is_none(),
        features,
        anchors,
        skeleton,
        near_misses: super::near_miss::near_misses(root, ids),
    };
    Ok((controls, tol, vb))
}

/// Segments of one curve, bucketed on a uniform grid so that crossing tests stay near-linear.
struct SegmentGrid {
    origin: Point,
    cell: f64,
    cols: usize,
    rows: usize,
    cells: Vec<Vec<(usize, usize)>>, // (curve, edge)
}

impl SegmentGrid {
    fn new(lo: Point, hi: Point, segments: usize) -> Self {
        let size = (hi - lo).max(Point::splat(1e-300));
        let n = (segments as f64).sqrt().ceil().clamp(1.0, 512.0);
        let cell = size.x.max(size.y) / n;
        let cols = ((size.x / cell).ceil() as usize).clamp(1, 1024);
        let rows = ((size.y / cell).ceil() as usize).clamp(1, 1024);
        SegmentGrid {
            origin: lo,
            cell,
            cols,
            rows,
            cells: vec![Vec::new(); cols * rows],
        }
    }

    fn range(&self, a: Point, b: Point) -> (usize, usize, usize, usize) {
        let f = |v: f64, n: usize| ((v / self.cell).floor().max(0.0) as usize).min(n - 1);
        let lo = a.min(b) - self.origin;
        let hi = a.max(b) - self.origin;
        (
            f(lo.x, self.cols),
            f(hi.x, self.cols),
            f(lo.y, self.rows),
            f(hi.y, self.rows),
        )
    }

    fn insert(&mut self, a: Point, b: Point, key: (usize, usize)) {
        let (x0, x1, y0, y1) = self.range(a, b);
        for y in y0..=y1 {
            for x in x0..=x1 {
                self.cells[y * self.cols + x].push(key);
            }
        }
    }
}

/// Where edges `i` and `j` of a closed or open polyline cross.
fn edge_crossing(points: &[Point], i: usize, j: usize) -> Point {
    let n = points.len();
    crate::geometry::segment_crossing(
        points[i],
        points[(i + 1) % n],
        points[j],
        points[(j + 1) % n],
    )
}

fn edges_of(c: &ControlCurve) -> impl Iterator<Item = (usize, Point, Point)> + '_ {
    let n = c.points.len();
    let m = if c.closed { n } else { n - 1 };
    (0..m).map(move |i| (i, c.points[i], c.points[(i + 1) % n]))
}

/// Features must lie inside the boundary and must not cross the boundary, each other, or
/// themselves (§5 needs them as non-crossing constraints).
pub(crate) fn validate_layout(
    boundary: &ControlCurve,
    features: &[ControlCurve],
    file: &str,
) -> Result<()> {
    for f in features {
        if !crate::geometry::point_in_polygon(f.points[0], &boundary.points) {
            return Err(Error::at(
                file,
                &f.id,
                format!("lies outside the '{}'", boundary.id),
            ));
        }
        if let Some((i, j)) = polyline_self_intersection(&f.points, f.closed) {
            let p = edge_crossing(&f.points, i, j);
            return Err(Error::at(
                file,
                &f.id,
                format!("crosses itself near ({:.3}, {:.3})", p.x, p.y),
            ));
        }
    }
    let curves: Vec<&ControlCurve> = std::iter::once(boundary).chain(features.iter()).collect();
    let all = curves.iter().flat_map(|c| c.points.iter().copied());
    let Some((lo, hi)) = crate::geometry::bounding_box(all) else {
        return Ok(());
    };
    let total: usize = curves.iter().map(|c| c.points.len()).sum();
    let mut grid = SegmentGrid::new(lo, hi, total);
    for (ci, c) in curves.iter().enumerate() {
        for (ei, a, b) in edges_of(c) {
            grid.insert(a, b, (ci, ei));
        }
    }
    let mut pairs = std::collections::BTreeSet::new();
    for cell in &grid.cells {
        for (x, &(c1, e1)) in cell.iter().enumerate() {
            for &(c2, e2) in &cell[x + 1..] {
                if c1 != c2 {
                    pairs.insert(((c1, e1), (c2, e2)));
                }
            }
        }
    }
    for ((c1, e1), (c2, e2)) in pairs {
        let seg = |c: usize, e: usize| {
            let pts = &curves[c].points;
            (pts[e], pts[(e + 1) % pts.len()])
        };
        let (a, b) = seg(c1, e1);
        let (c, d) = seg(c2, e2);
        if segments_intersect(a, b, c, d) {
            let p = crate::geometry::segment_crossing(a, b, c, d);
            let (first, second) = (curves[c1.min(c2)], curves[c1.max(c2)]);
            let what = if first.kind == CurveKind::Boundary {
                "leaves"
            } else {
                "crosses"
            };
            return Err(Error::at(
                file,
                &second.id,
                format!("{what} '{}' near ({:.3}, {:.3})", first.id, p.x, p.y),
            )
            .with_hint("features must lie inside the boundary and must not touch each other")
            .concerning([first.id.clone()])
            .of_kind(crate::error::ProblemKind::Crossing));
        }
    }
    Ok(())
}
