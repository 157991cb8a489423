//! Fold repair: a post-solve pass that straightens the few triangles a frame of eq. (1) inverts
//! (a deviation from the paper, which has no such pass; issue #7 item 2 and issue #9 item 4).
//!
//! The disc interpolation of two valid compatible meshes can still fold a triangle in between,
//! where neighbouring local transformations disagree a lot (slivers of an overlaid
//! triangulation, a mesh pushed through a narrow neck). Those folds are local: a handful of
//! triangles out of thousands. So after the solve, each free vertex (not on a curve, whose
//! position the frame must keep) of an inverted triangle is moved within its star — to the
//! mean of its neighbours, or part of the way there — when that leaves fewer inverted
//! triangles around it, then tries the same again, a few passes at most.
//!
//! Why this keeps the ends exact: the meshes at t = 0 and t = 1 fold nothing, so the pass does
//! nothing there. Why it is deterministic: vertices are visited in a fixed order. What it
//! cannot do: straighten a triangle whose three vertices are all on curves (the outline
//! itself folding); such frames stay as they are, and callers count them.

use crate::geometry::{orient2d, Point};

/// Passes over the inverted triangles per frame.
const PASSES: usize = 24;

/// What the repair needs of a mesh, precomputed once.
#[derive(Debug, Clone)]
pub(crate) struct FoldRepair {
    /// The triangles checked (a subset of the mesh's, e.g. the parts that can fold).
    triangles: Vec<[u32; 3]>,
    /// Per vertex: whether it may move (not on a curve).
    free: Vec<bool>,
    /// Per vertex: the checked triangles around it (indices into `triangles`).
    star: Vec<Vec<u32>>,
    /// Per vertex: its neighbours in the checked triangles.
    ring: Vec<Vec<u32>>,
    /// Per vertex: the weights of its neighbours (in `ring` order) when a patch around a fold
    /// is re-embedded: mean-value weights of the rest shape, positive, so that a patch with a
    /// convex rim re-embeds without a fold (Floater's theorem), and similarity-invariant, so
    /// that it keeps the rest shape where the rim allows.
    weights: Vec<Vec<f64>>,
    /// Per vertex: the sum of its `weights`, added in `ring` order (what every sweep of a
    /// re-embedding divides by).
    weight_sums: Vec<f64>,
    /// Whether curve vertices may move as a last resort (an interpolation's frames; not a
    /// mesh whose held vertices are its correspondence).
    curves_may_move: bool,
}

use crate::mesh::is_positive as positive;

impl FoldRepair {
    /// The repair of `triangles` over `n` points, of which those flagged in `fixed` move only
    /// with `curves_may_move`, when nothing else straightens a fold. With `rest` (a valid
    /// embedding, e.g. the source mesh) patches re-embed with its mean-value weights; without
    /// it, with uniform weights.
    pub(crate) fn new(
        triangles: &[[u32; 3]],
        n: usize,
        fixed: &[bool],
        rest: Option<&[Point]>,
        curves_may_move: bool,
    ) -> Self {
        let star = crate::mesh::stars(triangles, n);
        let ring = crate::mesh::one_rings(triangles, n);
        let weights: Vec<Vec<f64>> = (0..n)
            .map(|v| match rest {
                Some(r) if r.len() == n => mean_value_weights(v, &ring[v], &star[v], triangles, r),
                _ => vec![1.0; ring[v].len()],
            })
            .collect();
        let weight_sums = weights
            .iter()
            .map(|w| w.iter().fold(0.0, |total, &k| total + k))
            .collect();
        FoldRepair {
            triangles: triangles.to_vec(),
            free: (0..n)
                .map(|v| !fixed.get(v).copied().unwrap_or(false))
                .collect(),
            star,
            ring,
            weights,
            weight_sums,
            curves_may_move,
        }
    }

    /// Straightens the inverted triangles of frame `out` where free vertices can (module docs);
    /// returns how many stay inverted.
    ///
    /// Each pass moves the free corners of the inverted triangles into the kernel of their
    /// stars. A corner whose kernel is empty (its neighbours fold around it) cannot be placed,
    /// so the next pass also moves its free neighbours, which reopens its kernel; the region
    /// grows by one ring per pass, and only around the folds.
    pub(crate) fn apply(&self, out: &mut [Point]) -> usize {
        self.apply_with(out, self.curves_may_move)
    }

    /// [`FoldRepair::apply`], moving curve vertices as a last resort only with
    /// `curves_may_move`, whatever the repair was set up with.
    pub(crate) fn apply_with(&self, out: &mut [Point], curves_may_move: bool) -> usize {
        let mut bad: Vec<u32> = (0..self.triangles.len() as u32)
            .filter(|&f| !positive(out, self.triangles[f as usize]))
            .collect();
        if bad.is_empty() {
            return 0;
        }
        self.passes(out, &mut bad, false);
        if !bad.is_empty() {
            // Corners locked by their folded neighbours: re-embed a patch around each fold.
            self.reembed(out, &mut bad, false);
        }
        if !bad.is_empty() && curves_may_move {
            // The curves themselves fold here (a curve vertex is on the wrong side of its
            // neighbours' sides): curve vertices may move too, as little as they can.
            self.passes(out, &mut bad, true);
            if !bad.is_empty() {
                self.reembed(out, &mut bad, true);
            }
        }
        bad.len()
    }

    /// Re-embeds a patch around the triangles in `bad` (which it updates): the vertices within
    /// a few rings of them that may move (free ones, and with `curves` curve vertices too) and
    /// whose whole star lies in the patch are placed at the weighted mean of their neighbours
    /// (Gauss–Seidel sweeps), the patch's rim held. The patch grows one ring at a time until
    /// its triangles are all positive, up to [`PATCH_RINGS`] rings; a patch that does not
    /// straighten is put back as it was.
    fn reembed(&self, out: &mut [Point], bad: &mut Vec<u32>, curves: bool) {
        let may_move = |v: usize| curves || self.free[v];
        let n = self.free.len();
        let mut in_patch = vec![false; n];
        let mut patch: Vec<u32> = Vec::new();
        let add = |v: u32, in_patch: &mut Vec<bool>, patch: &mut Vec<u32>| {
            if !in_patch[v as usize] {
                in_patch[v as usize] = true;
                patch.push(v);
            }
        };
        for &f in bad.iter() {
            for v in self.triangles[f as usize] {
                add(v, &mut in_patch, &mut patch);
            }
        }
        for _ in 0..PATCH_RINGS {
            let rim: Vec<u32> = patch.clone();
            for v in rim {
                for &w in &self.ring[v as usize] {
                    add(w, &mut in_patch, &mut patch);
                }
            }
            // Movable: its star's triangles are all in the patch.
            let movable: Vec<usize> = patch
                .iter()
                .map(|&v| v as usize)
                .filter(|&v| may_move(v) && self.ring[v].iter().all(|&w| in_patch[w as usize]))
                .filter(|&v| {
                    self.star[v].iter().all(|&g| {
                        self.triangles[g as usize]
                            .iter()
                            .all(|&w| in_patch[w as usize])
                    })
                })
                .collect();
            if movable.is_empty() {
                continue;
            }
            let saved: Vec<Point> = movable.iter().map(|&v| out[v]).collect();
            let scale = movable
                .iter()
                .flat_map(|&v| self.ring[v].iter().map(move |&w| (v, w as usize)))
                .map(|(v, w)| out[v].distance(out[w]))
                .fold(0.0, f64::max);
            // The movable vertices' neighbours beside their weights in one array, read by
            // every sweep (up to a hundred on a stubborn fold) instead of two lists apiece.
            let mut terms: Vec<(u32, f64)> = Vec::new();
            let mut sweep: Vec<(usize, f64, usize)> = Vec::with_capacity(movable.len());
            for &v in &movable {
                if self.weight_sums[v] > 0.0 {
                    terms.extend(
                        self.ring[v]
                            .iter()
                            .copied()
                            .zip(self.weights[v].iter().copied()),
                    );
                    sweep.push((v, self.weight_sums[v], terms.len()));
                }
            }
            for _ in 0..SWEEPS {
                // The largest squared move: its root is the largest move (the root is
                // monotonic and correctly rounded), taken once per sweep, not once per vertex.
                let mut shift2 = 0.0f64;
                let mut from = 0;
                for &(v, total, to) in &sweep {
                    let mut sum = Point::ZERO;
                    for &(w, k) in &terms[from..to] {
                        sum += out[w as usize] * k;
                    }
                    from = to;
                    let p = sum / total;
                    shift2 = shift2.max((p - out[v]).length_squared());
                    out[v] = p;
                }
                if shift2.sqrt() <= 1e-9 * scale {
                    break;
                }
            }
            let patch_ok = movable.iter().all(|&v| {
                self.star[v]
                    .iter()
                    .all(|&g| positive(out, self.triangles[g as usize]))
            });
            let moved: Vec<u32> = movable.iter().map(|&v| v as u32).collect();
            self.refresh(out, bad, &moved);
            if patch_ok && bad.is_empty() {
                return;
            }
            if !patch_ok {
                for (&v, &p) in movable.iter().zip(&saved) {
                    out[v] = p;
                }
                self.refresh(out, bad, &moved);
            }
        }
    }

    /// Updates `bad`, the inverted triangles of `out` before the vertices `moved` moved, to
    /// those of `out` now: a move straightens its own star, but the fallback candidates and a
    /// patch can invert a triangle that was not in the list. Only triangles with a moved corner
    /// can have changed, so only they and the old list are checked, not the whole mesh.
    fn refresh(&self, out: &[Point], bad: &mut Vec<u32>, moved: &[u32]) {
        for &v in moved {
            bad.extend_from_slice(&self.star[v as usize]);
        }
        bad.sort_unstable();
        bad.dedup();
        bad.retain(|&f| !positive(out, self.triangles[f as usize]));
    }

    /// Up to [`PASSES`] passes over the corners of the triangles in `bad` (which it updates),
    /// moving the free vertices, and with `curves` the curve vertices too.
    fn passes(&self, out: &mut [Point], bad: &mut Vec<u32>, curves: bool) {
        let may_move = |v: u32| curves || self.free[v as usize];
        let mut reach: Vec<u32> = Vec::new();
        let mut scratch = Scratch::default();
        for _ in 0..PASSES {
            if bad.is_empty() {
                break;
            }
            let mut stuck: Vec<u32> = Vec::new();
            let mut todo: Vec<u32> = bad
                .iter()
                .flat_map(|&f| self.triangles[f as usize])
                .chain(reach.iter().copied())
                .filter(|&v| may_move(v))
                .collect();
            todo.sort_unstable();
            todo.dedup();
            let mut moved = false;
            for &v in &todo {
                let room = reach.binary_search(&v).is_ok();
                match self.relax(v as usize, out, room, &mut scratch) {
                    Relax::Moved => moved = true,
                    Relax::Stuck => stuck.push(v),
                    Relax::Kept => {}
                }
            }
            self.refresh(out, bad, &todo);
            // The neighbours of the corners that could not be placed, and of the corners
            // that may not move, make room in the next pass.
            let mut grow: Vec<u32> = stuck
                .iter()
                .chain(bad.iter().flat_map(|&f| self.triangles[f as usize].iter()))
                .flat_map(|&v| self.ring[v as usize].iter().copied())
                .filter(|&w| may_move(w))
                .collect();
            grow.extend(reach.iter().copied());
            grow.sort_unstable();
            grow.dedup();
            if !moved && grow == reach {
                break;
            }
            reach = grow;
        }
    }

    /// Moves free vertex `v` so that its star has no inverted triangle when its neighbours
    /// allow it, by as little as it can: to the point nearest its solved position from which
    /// every opposite side `a → b` is seen counter-clockwise with a height of at least a tenth
    /// of the side (then a fiftieth, then any positive height), so that the triangles it
    /// straightens are not slivers. A vertex asked to make room (`room`, its star positive)
    /// moves part of the way to its kernel's centroid instead, which opens its neighbours'
    /// kernels. When the kernel is empty, the best of a few local candidates (fewest inverted
    /// triangles, then the largest smallest area) is taken and `Stuck` returned.
    fn relax(&self, v: usize, out: &mut [Point], room: bool, scratch: &mut Scratch) -> Relax {
        if self.ring[v].is_empty() {
            return Relax::Kept;
        }
        let Scratch {
            sides,
            lines,
            poly,
            next,
        } = scratch;
        sides.clear();
        sides.extend(self.star[v].iter().map(|&g| {
            let t = self.triangles[g as usize];
            let k = t.iter().position(|&x| x as usize == v).unwrap_or(0);
            (out[t[(k + 1) % 3] as usize], out[t[(k + 2) % 3] as usize])
        }));
        let sides = &sides[..];
        let old = out[v];
        let inverted = |p: Point| {
            sides
                .iter()
                .filter(|&&(a, b)| orient2d(a, b, p) <= 0.0)
                .count()
        };
        let before = inverted(old);
        if before == 0 {
            if !room {
                return Relax::Kept;
            }
            if let Some(c) = kernel_centroid(sides, poly, next) {
                let p = toward_kernel(sides, old, c);
                if p != old && inverted(p) == 0 {
                    out[v] = p;
                    return Relax::Moved;
                }
            }
            return Relax::Kept;
        }
        for height in [0.1, 0.02, 1e-6] {
            if let Some(p) = nearest_seeing(sides, old, height, lines) {
                if inverted(p) == 0 {
                    out[v] = p;
                    return Relax::Moved;
                }
            }
        }
        // No kernel: the local candidates of the mean of the neighbours, part of the way
        // there, and a point just inside each opposite side.
        let score = |p: Point| -> (usize, f64) {
            let least = sides
                .iter()
                .map(|&(a, b)| (b - a).perp_dot(p - a))
                .fold(f64::INFINITY, f64::min);
            (inverted(p), least)
        };
        let mean = self.ring[v].iter().map(|&w| out[w as usize]).sum::<Point>()
            / self.ring[v].len() as f64;
        let candidates = [1.0, 0.5, 0.25, 0.75, 0.1]
            .iter()
            .map(|&s| old + (mean - old) * s)
            .chain(sides.iter().map(|&(a, b)| {
                let inward = Point::new(-(b - a).y, (b - a).x);
                (a + b) * 0.5 + inward * 0.3
            }));
        let better = |x: (usize, f64), y: (usize, f64)| x.0 < y.0 || (x.0 == y.0 && x.1 > y.1);
        let mut best = (score(old), old);
        for p in candidates {
            let s = score(p);
            if better(s, best.0) {
                best = (s, p);
            }
        }
        out[v] = best.1;
        Relax::Stuck
    }
}

/// The point nearest `from` that sees every directed side `a → b` on its left at a height of
/// at least `height · |b − a|`, or `None` when no point does. The feasible set is convex, so
/// the nearest point is `from` itself, its projection onto one side's line, or a corner where
/// two lines meet: all are tried, each checked against every side.
fn nearest_seeing(
    sides: &[(Point, Point)],
    from: Point,
    height: f64,
    lines: &mut Vec<(Point, f64)>,
) -> Option<Point> {
    // Side k as n·p ≥ c, n the inward normal.
    lines.clear();
    lines.extend(sides.iter().map(|&(a, b)| {
        let d = b - a;
        let n = Point::new(-d.y, d.x);
        (n, n.dot(a) + height * d.length_squared())
    }));
    let lines = &lines[..];
    let feasible = |p: Point| {
        p.is_finite()
            && lines
                .iter()
                .all(|&(n, c)| n.dot(p) >= c - 1e-12 * c.abs().max(n.length_squared()))
    };
    if feasible(from) {
        return Some(from);
    }
    let mut best: Option<(f64, Point)> = None;
    // Nearer than the best so far first: the feasibility test reads every line.
    let mut offer = |p: Point| {
        let d = p.distance_squared(from);
        if best.is_none_or(|(e, _)| d < e) && feasible(p) {
            best = Some((d, p));
        }
    };
    for &(n, c) in lines {
        let nn = n.length_squared();
        if nn > 0.0 {
            offer(from + n * ((c - n.dot(from)) / nn));
        }
    }
    for (i, &(n1, c1)) in lines.iter().enumerate() {
        for &(n2, c2) in &lines[i + 1..] {
            let det = n1.perp_dot(n2);
            if det != 0.0 {
                offer(Point::new(c1 * n2.y - c2 * n1.y, n1.x * c2 - n2.x * c1) / det);
            }
        }
    }
    best.map(|(_, p)| p)
}

/// Rings a re-embedded patch grows to around a fold.
const PATCH_RINGS: usize = 6;

/// Gauss–Seidel sweeps of a patch's re-embedding at most.
const SWEEPS: usize = 400;

/// Mean-value weights of vertex `v`'s neighbours `ring` in the embedding `rest`:
/// `(tan(α/2) + tan(β/2)) / |r_w − r_v|` over the angles at `v` of the two triangles beside the
/// edge (one at the mesh's border), each `tan(θ/2) = |a × b| / (|a||b| + a · b)`. A degenerate
/// rest triangle adds nothing; a vertex left without weight takes uniform ones.
fn mean_value_weights(
    v: usize,
    ring: &[u32],
    star: &[u32],
    triangles: &[[u32; 3]],
    rest: &[Point],
) -> Vec<f64> {
    let mut w = vec![0.0; ring.len()];
    let o = rest[v];
    for &g in star {
        let t = triangles[g as usize];
        let Some(k) = t.iter().position(|&x| x as usize == v) else {
            continue;
        };
        let (b, c) = (t[(k + 1) % 3], t[(k + 2) % 3]);
        let (x, y) = (rest[b as usize] - o, rest[c as usize] - o);
        let half = x.perp_dot(y).abs() / (x.length() * y.length() + x.dot(y));
        if !half.is_finite() {
            continue;
        }
        for u in [b, c] {
            if let Some(i) = ring.iter().position(|&r| r == u) {
                let d = rest[u as usize].distance(o);
                if d > 0.0 {
                    w[i] += half / d;
                }
            }
        }
    }
    if w.iter().all(|&x| x > 0.0 && x.is_finite()) {
        w
    } else {
        vec![1.0; ring.len()]
    }
}

/// Buffers [`FoldRepair::relax`] reuses from one vertex to the next: the star's opposite
/// sides, their lines and the kernel's clipped polygon.
#[derive(Debug, Default)]
struct Scratch {
    sides: Vec<(Point, Point)>,
    lines: Vec<(Point, f64)>,
    poly: Vec<Point>,
    next: Vec<Point>,
}

/// What [`FoldRepair::relax`] did to a vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Relax {
    /// Its star was positive and it stayed.
    Kept,
    /// It moved into its star's kernel.
    Moved,
    /// Its star has no kernel: it moved to the best local candidate (or stayed).
    Stuck,
}

/// The centroid of the kernel of a star: the intersection of the open half-planes to the left
/// of each directed side `a → b`, clipped from a box around the sides; `None` when it is empty
/// or has no area. `poly` and `next` are scratch.
fn kernel_centroid(
    sides: &[(Point, Point)],
    poly: &mut Vec<Point>,
    next: &mut Vec<Point>,
) -> Option<Point> {
    let (mut lo, mut hi) = (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY));
    for &(a, b) in sides {
        lo = lo.min(a).min(b);
        hi = hi.max(a).max(b);
    }
    let pad = (hi - lo).max_element();
    if !(pad > 0.0 && pad.is_finite()) {
        return None;
    }
    let (lo, hi) = (lo - Point::splat(pad), hi + Point::splat(pad));
    poly.clear();
    poly.extend([lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)]);
    for &(a, b) in sides {
        let d = b - a;
        let side = |p: Point| d.perp_dot(p - a);
        next.clear();
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp > 0.0 {
                next.push(p);
            }
            if (sp > 0.0) != (sq > 0.0) && sp != sq {
                next.push(p + (q - p) * (sp / (sp - sq)));
            }
        }
        std::mem::swap(poly, next);
        if poly.len() < 3 {
            return None;
        }
    }
    let area = crate::geometry::polygon_area(poly);
    if area.is_nan() || area <= 0.0 {
        return None;
    }
    Some(crate::geometry::polygon_centroid(poly))
}

/// The point on the segment from `from` to `c` (a point of the kernel) nearest `from` at which
/// every side sees at least half the doubled area it sees `c` with.
fn toward_kernel(sides: &[(Point, Point)], from: Point, c: Point) -> Point {
    let f = |p: Point, (a, b): (Point, Point)| (b - a).perp_dot(p - a);
    let least = sides.iter().map(|&s| f(c, s)).fold(f64::INFINITY, f64::min);
    let want = 0.5 * least;
    let mut s = 0.0f64;
    for &side in sides {
        let (f0, f1) = (f(from, side), f(c, side));
        if f0 < want {
            s = s.max((want - f0) / (f1 - f0));
        }
    }
    if s <= 0.0 {
        from
    } else {
        from + (c - from) * s.min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan around a centre vertex pushed out of its star: the repair brings it back.
    #[test]
    fn a_pushed_out_vertex_returns_into_its_star() {
        let (pts, tris) = crate::mesh::hexagon_fan();
        let mut fixed = vec![true; 7];
        fixed[6] = false;
        let r = FoldRepair::new(&tris, 7, &fixed, None, false);
        let mut frame = pts.clone();
        frame[6] = Point::new(1.5, 0.2);
        assert!(crate::mesh::count_inverted(&tris, &frame) > 0);
        assert_eq!(r.apply(&mut frame), 0);
        assert_eq!(crate::mesh::count_inverted(&tris, &frame), 0);
        // A valid frame is left exactly as it is.
        let mut same = pts.clone();
        assert_eq!(r.apply(&mut same), 0);
        assert_eq!(same, pts);
    }
}
