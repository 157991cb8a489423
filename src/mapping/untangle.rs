//! Local untangling of a harmonic step that folds a few triangles (§5).
//!
//! The harmonic map is flip-free only for convex domains; the composite mapping's domains are
//! not convex, and a curve edge that moves fast relative to its surroundings can leave a free
//! vertex of an adjacent triangle on its wrong side. Halving the step does not help once the
//! triangle is thin. Instead, the free vertices of the folded (or numerically flat) triangles are
//! moved, one at a time, to the point that maximizes the smallest signed area of their incident
//! triangles — the classic optimization-based untangling of Freitag and Plassmann, whose local
//! problem is a linear program in three unknowns (the position and the smallest area), solved
//! exactly here by its vertices. Vertices that cannot be freed by moving alone pull their
//! neighbours into the next sweep. Curve vertices never move, so the step's curve positions stay
//! exact; whether the result is accepted is still decided by the caller's exact test.
//!
//! The same stars serve a last quality pass over the mapped mesh ([`Untangler::improve`]):
//! triangles that the steps left much thinner than they were before the mapping get their free
//! vertices moved where the worst relative quality of their star is best, which keeps the rigid
//! interpolation of §4.1 from folding them in between.

use crate::geometry::Point;
use crate::mesh::sort_unique;

/// Per vertex, the incident triangles as the counter-clockwise opposite edge `(a, b)` (the
/// triangle is `(v, a, b)`), and the mesh's vertex neighbours.
#[derive(Debug, Clone)]
pub(crate) struct Untangler {
    /// Vertex `v`'s entries of `stars` and `incident` are `star_start[v]..star_start[v + 1]`
    /// (compressed rows: the untangler is set up once per composite map, and a list per vertex
    /// was a tenth of that map's set-up, issue 16).
    star_start: Vec<usize>,
    stars: Vec<[u32; 2]>,
    /// The indices of the triangles (same order as `stars`).
    incident: Vec<u32>,
    /// Vertex `v`'s neighbours, ascending, are `rings[ring_start[v]..ring_start[v + 1]]`.
    ring_start: Vec<usize>,
    rings: Vec<u32>,
    fixed: Vec<bool>,
}

/// Sweeps over the tangled region before giving up.
const SWEEPS: usize = 12;
/// How many times faster than its best sweep so far an untangling would have to go on to be
/// let run: one whose tangled triangles could not be freed in the sweeps left even at that
/// pace gives up early.
const PACE: usize = 10;

impl Untangler {
    /// Prepares the stars of `triangles` (counter-clockwise in the source) over `fixed.len()`
    /// vertices; `fixed` vertices never move.
    pub(crate) fn new(triangles: &[[u32; 3]], fixed: &[bool]) -> Self {
        let n = fixed.len();
        // Each vertex's corners (3 · triangle + corner) in triangle order, as a list per
        // vertex would hold them.
        let corners = triangles
            .iter()
            .enumerate()
            .flat_map(|(f, t)| (0..3).map(move |k| (t[k], (3 * f + k) as u32)));
        let (star_start, corners) = crate::mesh::compressed_rows(n, corners);
        let stars = corners
            .iter()
            .map(|&c| {
                let (t, k) = (&triangles[c as usize / 3], c as usize % 3);
                [t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        let incident = corners.iter().map(|&c| c / 3).collect();
        // The one-rings of `mesh::one_rings`: the sorted edges handed out to both ends in
        // turn, so each ring comes ascending.
        let edges = crate::mesh::edges(triangles);
        let (ring_start, rings) =
            crate::mesh::compressed_rows(n, edges.iter().flat_map(|&(a, b)| [(a, b), (b, a)]));
        Untangler {
            star_start,
            stars,
            incident,
            ring_start,
            rings,
            fixed: fixed.to_vec(),
        }
    }

    /// The triangles of `v` as their counter-clockwise opposite edges.
    fn star(&self, v: usize) -> &[[u32; 2]] {
        &self.stars[self.star_start[v]..self.star_start[v + 1]]
    }

    /// The indices of the triangles of `v`, in the order of [`Self::star`].
    fn incident(&self, v: usize) -> &[u32] {
        &self.incident[self.star_start[v]..self.star_start[v + 1]]
    }

    /// The neighbours of `v`, ascending.
    fn ring(&self, v: usize) -> &[u32] {
        &self.rings[self.ring_start[v]..self.ring_start[v + 1]]
    }

    /// Moves free vertices of the triangles for which `bad` holds until none does or the sweeps
    /// run out; returns whether none does. `triangles` are those the untangler was made for;
    /// those before `first_bad` are known not to be bad (the caller's test stopped there).
    /// A tangle that could not be cleared in the sweeps left even at [`PACE`] times its best
    /// sweep's pace is given up at once (issue 16: the untanglings that fail took most of the
    /// composite walks' time, all twelve sweeps each, over tangles that mostly grew; on two
    /// random 320-pair corpora this exit changed no rung, and one pair's mesh).
    pub(crate) fn untangle(
        &self,
        triangles: &[[u32; 3]],
        points: &mut [Point],
        bad: impl Fn(&[u32; 3], &[Point]) -> bool,
        first_bad: usize,
    ) -> bool {
        let mut active: Vec<u32> = Vec::new();
        let mut stuck: Vec<u32> = Vec::new();
        let mut scratch = Scratch::default();
        let mut marks = Vec::new();
        // The triangles for which `bad` holds, kept up to date: only a moved vertex's
        // triangles can change.
        let mut tangled: Vec<u32> = (first_bad.min(triangles.len()) as u32..triangles.len() as u32)
            .filter(|&f| bad(&triangles[f as usize], points))
            .collect();
        // The most triangles one sweep has freed so far (at least one).
        let mut best_pace = 1;
        for sweep in 1..=SWEEPS {
            let bad_before = tangled.len();
            active.clear();
            for &f in &tangled {
                let t = &triangles[f as usize];
                active.extend(t.iter().filter(|&&v| !self.fixed[v as usize]));
            }
            if active.is_empty() && tangled.is_empty() {
                return true;
            }
            // Vertices that could not be freed last sweep bring their free neighbours.
            for &v in &stuck {
                active.extend(
                    self.ring(v as usize)
                        .iter()
                        .filter(|&&w| !self.fixed[w as usize]),
                );
            }
            sort_unique(&mut active, &mut marks);
            if active.is_empty() {
                return false;
            }
            stuck.clear();
            for &v in &active {
                match self.best_position(v as usize, points, &mut scratch) {
                    Some((p, area)) => {
                        points[v as usize] = p;
                        if area <= 0.0 {
                            stuck.push(v);
                        }
                    }
                    None => stuck.push(v),
                }
            }
            for &v in &active {
                tangled.extend_from_slice(self.incident(v as usize));
            }
            sort_unique(&mut tangled, &mut marks);
            tangled.retain(|&f| bad(&triangles[f as usize], points));
            // A hopeless tangle: freeing PACE times more triangles per sweep than the best
            // sweep so far would still not clear it in the sweeps left.
            best_pace = best_pace.max(bad_before.saturating_sub(tangled.len()));
            if tangled.len() > PACE * best_pace * (SWEEPS - sweep) {
                return false;
            }
        }
        tangled.is_empty()
    }

    /// Improves the shapes of the triangles that the mapping distorted most: every free vertex
    /// of a triangle whose quality fell below [`DISTORTED`] times its quality in `rest` is moved
    /// — towards the centroid of its neighbours, towards the mean of the points where each of
    /// its triangles would regain its rest shape, or towards its max-min-area point, whichever
    /// raises the smallest relative quality of its star most — in a few sweeps. A move is taken
    /// only if it raises that smallest relative quality, so no triangle gets worse than the worst
    /// of its star was and none flips; an exact similarity of `rest` is left untouched.
    pub(crate) fn improve(&self, triangles: &[[u32; 3]], rest: &[Point], points: &mut [Point]) {
        let rest_quality: Vec<f64> = triangles.iter().map(|t| quality(t, rest)).collect();
        let incident = |v: usize| self.incident(v);
        let relative = |f: u32, pts: &[Point]| {
            let f = f as usize;
            quality(&triangles[f], pts) / rest_quality[f].max(f64::MIN_POSITIVE)
        };
        let star_min = |v: usize, pts: &[Point]| -> f64 {
            incident(v)
                .iter()
                .map(|&f| relative(f, pts))
                .fold(f64::INFINITY, f64::min)
        };
        // `star_min` when it is above `bound`, else `None`: a move is only taken when it
        // raises the smallest relative quality, so the first triangle at or below the best so
        // far settles it (the same minimum, in the same order, when it is above).
        let star_min_above = |v: usize, pts: &[Point], bound: f64| -> Option<f64> {
            let mut q = f64::INFINITY;
            for &f in incident(v) {
                let r = relative(f, pts);
                if r <= bound {
                    return None;
                }
                q = q.min(r);
            }
            (q > bound).then_some(q)
        };
        // Whether a vertex moved in the last sweep: a vertex none of whose star moved has
        // nothing new to gain.
        let mut changed = vec![true; self.fixed.len()];
        let mut now_changed = vec![false; self.fixed.len()];
        let mut scratch = Scratch::default();
        let mut marks = Vec::new();
        // Which triangles are distorted: only a moved vertex's triangles can change.
        let is_distorted =
            |f: usize, pts: &[Point]| quality(&triangles[f], pts) < DISTORTED * rest_quality[f];
        let mut distorted: Vec<bool> = (0..triangles.len())
            .map(|f| is_distorted(f, points))
            .collect();
        for sweep in 0..IMPROVE_SWEEPS {
            if sweep > 0 {
                for (v, _) in changed.iter().enumerate().filter(|(_, &c)| c) {
                    for &f in incident(v) {
                        distorted[f as usize] = is_distorted(f as usize, points);
                    }
                }
            }
            let mut active: Vec<u32> = Vec::new();
            for (t, _) in triangles.iter().zip(&distorted).filter(|(_, &d)| d) {
                active.extend(t.iter().filter(|&&v| !self.fixed[v as usize]));
            }
            sort_unique(&mut active, &mut marks);
            if active.is_empty() {
                return;
            }
            let mut moved = false;
            now_changed.fill(false);
            for &v in &active {
                let v = v as usize;
                if !changed[v] && !self.ring(v).iter().any(|&w| changed[w as usize]) {
                    continue;
                }
                let here = points[v];
                let mut best = (star_min(v, points), here);
                let ring = self.ring(v);
                let centroid = ring
                    .iter()
                    .fold(Point::ZERO, |a, &w| a + points[w as usize])
                    / ring.len().max(1) as f64;
                let lp = self.best_position(v, points, &mut scratch).map(|b| b.0);
                // Where each triangle of the star would put `v` to regain its rest shape (its
                // opposite edge kept), averaged.
                let mut shaped = Point::ZERO;
                for &[a, b] in self.star(v) {
                    let (a, b) = (a as usize, b as usize);
                    let (ra, rb, rv) = (rest[a], rest[b], rest[v]);
                    let (e, r) = (rb - ra, rv - ra);
                    let l2 = e.length_squared().max(f64::MIN_POSITIVE);
                    // r / e as a complex number, applied to the current edge.
                    let z = Point::new(r.dot(e), e.perp_dot(r)) / l2;
                    let d = points[b] - points[a];
                    shaped += points[a] + Point::new(z.x * d.x - z.y * d.y, z.x * d.y + z.y * d.x);
                }
                let shaped = shaped / self.star(v).len().max(1) as f64;
                for goal in [centroid, shaped].into_iter().chain(lp) {
                    for alpha in [1.0, 0.5, 0.25] {
                        points[v] = here + (goal - here) * alpha;
                        if let Some(q) = star_min_above(v, points, best.0) {
                            best = (q, points[v]);
                        }
                    }
                }
                if best.1 != here {
                    moved = true;
                    now_changed[v] = true;
                }
                points[v] = best.1;
            }
            std::mem::swap(&mut changed, &mut now_changed);
            if !moved {
                return;
            }
        }
    }

    /// The position of `v` maximizing the smallest doubled signed area of its triangles, and that
    /// area; `None` when the linear program has no bounded vertex (a degenerate star).
    ///
    /// The program is `max z` subject to `z ≤ cᵢ + gᵢ·x`, one constraint per triangle; its
    /// answer is the highest feasible vertex (three constraints tight), the first in the order
    /// `(i, j, l)` among equals, which [`enumerate`] finds by trying every vertex. Most
    /// vertices lie above the feasible region, so trying them costs a scan each; instead
    /// [`peak`] finds the answer among the few vertices that can be it, and the
    /// enumeration only runs where that is not enough (issue 16: this is the composite walk's
    /// hottest code). `scratch` is reused from call to call.
    fn best_position(
        &self,
        v: usize,
        points: &[Point],
        scratch: &mut Scratch,
    ) -> Option<(Point, f64)> {
        let Scratch { cons, among } = scratch;
        let (o, eps) = self.program(v, points, cons)?;
        let best = match peak(cons, among, eps) {
            Peak::Found(p, z) => Some((p, z)),
            Peak::Among => enumerate(cons, among, eps),
            Peak::Unknown => {
                among.clear();
                among.extend(0..cons.len());
                enumerate(cons, among, eps)
            }
        };
        best.map(|(p, z)| (o + p, z))
    }

    /// The constraints of [`Self::best_position`]'s program for `v` into `cons`, relative to
    /// the vertex's current position `o`; returns `o` and the feasibility tolerance, or `None`
    /// for a star with no extent.
    fn program(
        &self,
        v: usize,
        points: &[Point],
        cons: &mut Vec<Constraint>,
    ) -> Option<(Point, f64)> {
        // Doubled area of (v, a, b) = cross(a, b) + cross(v, a − b) = c + g·v, written relative
        // to the current position `o` for conditioning: c + g·o + g·(v − o).
        let o = points[v];
        cons.clear();
        let mut scale = 0.0f64;
        for &[a, b] in self.star(v) {
            let (a, b) = (points[a as usize], points[b as usize]);
            let d = a - b;
            let g = Point::new(d.y, -d.x);
            let c = a.perp_dot(b) + g.dot(o);
            scale = scale.max(g.length_squared().max(c.abs()));
            cons.push(Constraint::new(g, c));
        }
        if scale <= 0.0 || !scale.is_finite() {
            return None;
        }
        Some((o, 1e-12 * scale))
    }
}

/// Scratch space of [`Untangler::best_position`].
#[derive(Debug, Default)]
struct Scratch {
    /// The constraints of the star.
    cons: Vec<Constraint>,
    /// The constraints whose vertices can be the answer ([`peak`], [`enumerate`]).
    among: Vec<usize>,
}

/// The vertex of the rows `r0`, `r1`, `r2` (`pair` their last two's minors) by Cramer's rule:
/// its height `z` and the system's determinant, or `None` when the system is singular. Each
/// value is computed with the operations of the full 3 × 3 Cramer solve (the systems' third
/// column is all ones, and `x · 1 = x` exactly), so shared minors change no bit.
#[inline]
fn height(r0: &Constraint, pair: &Pair) -> Option<(f64, f64)> {
    let det = r0.a * pair.b - r0.b * pair.a + pair.ab;
    let norm = r0.largest.max(pair.largest);
    if det.abs() <= 1e-12 * norm * norm * norm || !det.is_finite() {
        return None;
    }
    let z = (r0.a * pair.bc - r0.b * pair.ac + r0.c * pair.ab) / det;
    (!z.is_nan()).then_some((z, det))
}

/// The position of the vertex of [`height`], relative to the star's vertex.
#[inline]
fn position(r0: &Constraint, r1: &Constraint, r2: &Constraint, pair: &Pair, det: f64) -> Point {
    Point::new(
        (r0.c * pair.b - r0.b * (r1.c - r2.c) + (r1.c * r2.b - r1.b * r2.c)) / det,
        (r0.a * (r1.c - r2.c) - r0.c * pair.a + pair.ac) / det,
    )
}

/// The optimum of the program, found among the vertices where the three tight constraints'
/// gradients surround the origin (`0` in the closed triangle of `gᵢ`, `gⱼ`, `gₗ`): only there
/// is `min(cᵢ + gᵢ·x, …)` of the three bounded above, by its vertex's height, so each such
/// height bounds the optimum from above, and one such vertex is the optimum (its tight
/// constraints' gradients surround the origin, or it would not be a maximum). The search is
/// the dual simplex method: from the first surrounding vertex, the most violated constraint
/// replaces the one of the three whose place keeps the origin surrounded, until the vertex is
/// feasible (a few pivots; it gives up after `2k + 8`).
///
/// The feasible vertex `p` found bounds where the enumeration's answer can be: it is
/// [`Peak::Found`] when it is provably that answer, bit for bit; else the constraints the
/// answer must be made of are listed in `among` ([`Peak::Among`], for [`enumerate`]), or
/// nothing is known ([`Peak::Unknown`]: no surrounding vertex, or no feasible one found).
///
/// The bound: the three tight constraints fall away from `p` at a rate of at least `α`, the
/// distance from the origin to the edges of their gradients' triangle, so a point within `eps`
/// of feasible and as high as `p` lies within `eps / α` of it; a vertex there has every one of
/// its constraints within `eps · (1 + G / α)` of tight at `p` (`G` the largest gradient). The
/// answer is feasible and at least as high as `p` (which is feasible), so its constraints are
/// among those that close to tight at `p` (twice that, for rounding); where no fourth one is,
/// the answer is `p` itself. Ties, repeated points and flat tops leave a few more.
fn peak(cons: &[Constraint], among: &mut Vec<usize>, eps: f64) -> Peak {
    let k = cons.len();
    let turn = |a: usize, b: usize| cons[a].g.perp_dot(cons[b].g);
    // gᵢ × gⱼ, gⱼ × gₗ and gₗ × gᵢ of one sign (or zero): the origin is in the triangle.
    let surrounds = |[i, j, l]: [usize; 3]| {
        let (x, y, z) = (turn(i, j), turn(j, l), turn(l, i));
        (x >= 0.0 && y >= 0.0 && z >= 0.0) || (x <= 0.0 && y <= 0.0 && z <= 0.0)
    };
    let first = (0..k).find_map(|i| {
        (i + 1..k).find_map(|j| (j + 1..k).map(|l| [i, j, l]).find(|&t| surrounds(t)))
    });
    let Some(mut tri) = first else {
        return Peak::Unknown;
    };
    // The vertex of the three (in ascending order, as the enumeration solves it).
    let mut found = None;
    for _ in 0..2 * k + 8 {
        tri.sort_unstable();
        let [i, j, l] = tri;
        let pair = Pair::new(&cons[j], &cons[l]);
        let Some((z, det)) = height(&cons[i], &pair) else {
            return Peak::Unknown;
        };
        let p = position(&cons[i], &cons[j], &cons[l], &pair, det);
        let holds = |q: &Constraint| z <= q.c + q.g.dot(p) + eps;
        if cons.iter().all(holds) {
            found = Some((p, z));
            break;
        }
        // The most violated constraint comes in.
        let Some(m) = (0..k).filter(|&m| !holds(&cons[m])).min_by(|&a, &b| {
            let slack = |m: usize| cons[m].c + cons[m].g.dot(p) - z;
            slack(a).total_cmp(&slack(b))
        }) else {
            return Peak::Unknown;
        };
        // A tight constraint cannot be violated but by rounding: no way on.
        if tri.contains(&m) {
            return Peak::Unknown;
        }
        let mut swapped = (0..3).map(|r| {
            let mut t = tri;
            t[r] = m;
            t
        });
        match swapped.find(|&t| surrounds(t)) {
            Some(t) => tri = t,
            None => return Peak::Unknown,
        }
    }
    let Some((p, z)) = found else {
        return Peak::Unknown;
    };
    let [i, j, l] = tri;
    // α: the distance from the origin to the nearest edge of the gradients' triangle; G / α
    // from squares, with one square root (it only sets a margin).
    let mut alpha2 = f64::INFINITY;
    for (a, b) in [(i, j), (j, l), (i, l)] {
        let t = turn(a, b);
        alpha2 = alpha2.min(t * t / (cons[a].g - cons[b].g).length_squared());
    }
    let steepest2 = cons
        .iter()
        .map(|q| q.g.length_squared())
        .fold(0.0f64, f64::max);
    let ratio = (steepest2 / alpha2).sqrt();
    if !(alpha2 > 0.0 && ratio.is_finite()) {
        return Peak::Unknown;
    }
    let near = 2.0 * eps * (1.0 + ratio);
    among.clear();
    for (m, q) in cons.iter().enumerate() {
        if m == i || m == j || m == l || q.c + q.g.dot(p) - z <= near {
            among.push(m);
        }
    }
    if among.len() == 3 {
        Peak::Found(p, z)
    } else {
        Peak::Among
    }
}

/// What [`peak`] found out about the program's answer.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Peak {
    /// The answer: its position and height.
    Found(Point, f64),
    /// The answer is a vertex of the constraints that `peak` listed (more than three).
    Among,
    /// Nothing: the answer may be any vertex.
    Unknown,
}

/// The highest feasible vertex of the program among the vertices of the constraints `among`
/// (ascending indices into `cons`; feasibility is always against all of `cons`), the first in
/// the order `(i, j, l)` among equals; `None` when none is feasible. The answer does not depend
/// on the order vertices are tried in, so the 2 × 2 minors of a pair of constraints `(j, l)`
/// are shared by every `i < j` (pairs are the outer loop), and a vertex's height is solved for
/// before its position, which is only needed when the height can win.
fn enumerate(cons: &[Constraint], among: &[usize], eps: f64) -> Option<(Point, f64)> {
    // The best vertex: its position, height and constraints.
    let mut best: Option<(Point, f64, [usize; 3])> = None;
    let k = among.len();
    let mut cut = 0;
    for j in 1..k {
        for l in j + 1..k {
            let (r1, r2) = (&cons[among[j]], &cons[among[l]]);
            let pair = Pair::new(r1, r2);
            for i in 0..j {
                let r0 = &cons[among[i]];
                let Some((z, det)) = height(r0, &pair) else {
                    continue;
                };
                let order = [among[i], among[j], among[l]];
                let loses = |b: &(Point, f64, [usize; 3])| z < b.1 || (z == b.1 && order > b.2);
                if best.as_ref().is_some_and(loses) {
                    continue;
                }
                let p = position(r0, r1, r2, &pair, det);
                let holds = |q: &Constraint| z <= q.c + q.g.dot(p) + eps;
                // The constraint that cut off the last vertex tried most often cuts off
                // this one too: tested first, it spares the scan.
                if !holds(&cons[cut]) {
                    continue;
                }
                match cons.iter().position(|q| !holds(q)) {
                    Some(c) => cut = c,
                    None => best = Some((p, z, order)),
                }
            }
        }
    }
    best.map(|(p, z, _)| (p, z))
}

/// One constraint `z ≤ c + g·x` of [`Untangler::best_position`]: its row `[a, b, 1 | c]` =
/// `[−g, 1 | c]` of the 3 × 3 systems and the row's largest coefficient (for the singularity
/// test).
#[derive(Debug)]
struct Constraint {
    g: Point,
    a: f64,
    b: f64,
    c: f64,
    largest: f64,
}

impl Constraint {
    fn new(g: Point, c: f64) -> Self {
        let (a, b) = (-g.x, -g.y);
        Constraint {
            g,
            a,
            b,
            c,
            largest: a.abs().max(b.abs()).max(1.0),
        }
    }
}

/// The 2 × 2 minors of the rows of two constraints, `[a₁, b₁, 1 | c₁]` and `[a₂, b₂, 1 | c₂]`,
/// that Cramer's rule expands every third row against.
#[derive(Debug)]
struct Pair {
    /// `b₁ − b₂`.
    b: f64,
    /// `a₁ − a₂`.
    a: f64,
    /// `a₁b₂ − b₁a₂`.
    ab: f64,
    /// `b₁c₂ − c₁b₂`.
    bc: f64,
    /// `a₁c₂ − c₁a₂`.
    ac: f64,
    /// The larger of the two rows' largest coefficients.
    largest: f64,
}

impl Pair {
    fn new(r1: &Constraint, r2: &Constraint) -> Self {
        Pair {
            b: r1.b - r2.b,
            a: r1.a - r2.a,
            ab: r1.a * r2.b - r1.b * r2.a,
            bc: r1.b * r2.c - r1.c * r2.b,
            ac: r1.a * r2.c - r1.c * r2.a,
            largest: r1.largest.max(r2.largest),
        }
    }
}

/// A triangle whose quality fell below this fraction of its quality before the mapping is
/// improved by [`Untangler::improve`].
const DISTORTED: f64 = 0.5;
/// Sweeps of [`Untangler::improve`].
const IMPROVE_SWEEPS: usize = 12;

/// Shape quality of a triangle: `4√3 · area / Σ edge²`, 1 for an equilateral triangle, 0 for a
/// degenerate one, negative when inverted.
fn quality(t: &[u32; 3], p: &[Point]) -> f64 {
    let [a, b, c] = t.map(|v| p[v as usize]);
    let twice_area = (b - a).perp_dot(c - a);
    let sum = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
    if sum > 0.0 {
        2.0 * 3f64.sqrt() * twice_area / sum
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::count_inverted;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    /// A square fan around a centre vertex 4, corners fixed.
    /// The local program solved as it was before issue 16: every vertex by a full 3 × 3
    /// Cramer solve, in the order `(i, j, l)`, the first of the highest feasible ones kept.
    fn best_position_reference(
        stars: &[[u32; 2]],
        o: Point,
        points: &[Point],
    ) -> Option<(Point, f64)> {
        let cons: Vec<(Point, f64)> = stars
            .iter()
            .map(|&[a, b]| {
                let (a, b) = (points[a as usize], points[b as usize]);
                let d = a - b;
                let g = Point::new(d.y, -d.x);
                (g, a.perp_dot(b) + g.dot(o))
            })
            .collect();
        let scale = cons
            .iter()
            .map(|(g, c)| g.length_squared().max(c.abs()))
            .fold(0.0f64, f64::max);
        if scale <= 0.0 || !scale.is_finite() {
            return None;
        }
        let eps = 1e-12 * scale;
        let solve3 = |m: &[[f64; 4]; 3]| -> Option<(f64, f64, f64)> {
            let det3 = |c0: usize, c1: usize, c2: usize| {
                m[0][c0] * (m[1][c1] * m[2][c2] - m[1][c2] * m[2][c1])
                    - m[0][c1] * (m[1][c0] * m[2][c2] - m[1][c2] * m[2][c0])
                    + m[0][c2] * (m[1][c0] * m[2][c1] - m[1][c1] * m[2][c0])
            };
            let d = det3(0, 1, 2);
            let norm = m
                .iter()
                .flat_map(|r| r[..3].iter())
                .fold(0.0f64, |a, &x| a.max(x.abs()));
            if d.abs() <= 1e-12 * norm * norm * norm || !d.is_finite() {
                return None;
            }
            Some((det3(3, 1, 2) / d, det3(0, 3, 2) / d, det3(0, 1, 3) / d))
        };
        let mut best: Option<(Point, f64)> = None;
        let k = cons.len();
        for i in 0..k {
            for j in i + 1..k {
                for l in j + 1..k {
                    let m = [cons[i], cons[j], cons[l]].map(|(g, c)| [-g.x, -g.y, 1.0, c]);
                    let Some((x, y, z)) = solve3(&m) else {
                        continue;
                    };
                    let p = Point::new(x, y);
                    if best.is_none_or(|b| z > b.1)
                        && cons.iter().all(|&(g, c)| z <= c + g.dot(p) + eps)
                    {
                        best = Some((p, z));
                    }
                }
            }
        }
        best.map(|(p, z)| (o + p, z))
    }

    proptest::proptest! {
        /// The program's answer is bit for bit the full Cramer enumeration's, on stars of 3 to
        /// 11 triangles whose points sit on a coarse grid (so ties, repeated points and
        /// singular systems are common) or anywhere.
        #[test]
        fn best_position_is_the_full_enumerations(
            ring in proptest::collection::vec((-4i32..5, -4i32..5), 3..12),
            centre in (-4i32..5, -4i32..5),
            jitter in proptest::collection::vec(-1.0f64..1.0, 24),
            coarse in proptest::bool::ANY,
        ) {
            let k = ring.len();
            let mut pts = vec![Point::new(f64::from(centre.0), f64::from(centre.1))];
            for (m, &(x, y)) in ring.iter().enumerate() {
                let (dx, dy) = if coarse { (0.0, 0.0) } else { (jitter[2 * m], jitter[2 * m + 1]) };
                pts.push(Point::new(f64::from(x) + dx, f64::from(y) + dy));
            }
            let tris: Vec<[u32; 3]> = (0..k as u32).map(|m| [0, 1 + m, 1 + (m + 1) % k as u32]).collect();
            let mut fixed = vec![true; k + 1];
            fixed[0] = false;
            let u = Untangler::new(&tris, &fixed);
            let bits = |r: Option<(Point, f64)>| r.map(|(p, z)| (p.x.to_bits(), p.y.to_bits(), z.to_bits()));
            proptest::prop_assert_eq!(
                bits(u.best_position(0, &pts, &mut Scratch::default())),
                bits(best_position_reference(u.star(0), pts[0], &pts))
            );
        }
    }

    /// Stars on a 9 × 9 grid (ties and flat tops everywhere) get the enumeration's answer bit
    /// for bit, and most stars of a jittered grid get it from [`peak`] alone, without the
    /// enumeration (so the shortcut is taken where it should be).
    #[test]
    fn the_peak_answers_most_stars_and_the_enumeration_the_rest() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let (mut cases, mut by_peak) = (0, 0);
        for jittered in [false, true] {
            for _ in 0..2000 {
                let k = 3 + (next() % 9) as usize;
                let mut point = || {
                    let m = (next() % 81) as i32;
                    let jitter = |r: u64| {
                        if jittered {
                            (r % 1000) as f64 / 2000.0
                        } else {
                            0.0
                        }
                    };
                    Point::new(
                        f64::from(m % 9 - 4) + jitter(next()),
                        f64::from(m / 9 - 4) + jitter(next()),
                    )
                };
                let pts: Vec<Point> = (0..=k).map(|_| point()).collect();
                let tris: Vec<[u32; 3]> = (0..k as u32)
                    .map(|m| [0, 1 + m, 1 + (m + 1) % k as u32])
                    .collect();
                let mut fixed = vec![true; k + 1];
                fixed[0] = false;
                let u = Untangler::new(&tris, &fixed);
                let mut scratch = Scratch::default();
                let got = u.best_position(0, &pts, &mut scratch);
                let want = best_position_reference(u.star(0), pts[0], &pts);
                let bits = |r: Option<(Point, f64)>| {
                    r.map(|(p, z)| (p.x.to_bits(), p.y.to_bits(), z.to_bits()))
                };
                assert_eq!(bits(got), bits(want), "{pts:?}");
                if jittered && want.is_some() {
                    let Scratch { cons, among } = &mut scratch;
                    let (_, eps) = u.program(0, &pts, cons).unwrap();
                    cases += 1;
                    by_peak += usize::from(matches!(peak(cons, among, eps), Peak::Found(..)));
                }
            }
        }
        assert!(
            by_peak * 10 >= cases * 9,
            "{by_peak} of {cases} by the peak"
        );
    }

    proptest::proptest! {
        /// The compressed stars, triangle indices and rings hold, vertex by vertex and in
        /// order, what a list per vertex and `mesh::one_rings` hold, on triangle soups with
        /// repeated and isolated vertices.
        #[test]
        fn compressed_stars_and_rings_are_the_lists_per_vertex(
            soup in proptest::collection::vec((0u32..25, 0u32..25, 0u32..25), 0..50),
        ) {
            let triangles: Vec<[u32; 3]> = soup.iter().map(|&(a, b, c)| [a, b, c]).collect();
            let n = 25;
            let u = Untangler::new(&triangles, &vec![false; n]);
            let mut stars = vec![Vec::new(); n];
            let mut incident = vec![Vec::new(); n];
            for (f, t) in triangles.iter().enumerate() {
                for k in 0..3 {
                    stars[t[k] as usize].push([t[(k + 1) % 3], t[(k + 2) % 3]]);
                    incident[t[k] as usize].push(f as u32);
                }
            }
            let rings = crate::mesh::one_rings(&triangles, n);
            for v in 0..n {
                proptest::prop_assert_eq!(u.star(v), stars[v].as_slice());
                proptest::prop_assert_eq!(u.incident(v), incident[v].as_slice());
                proptest::prop_assert_eq!(u.ring(v), rings[v].as_slice());
            }
        }
    }

    fn fan() -> (Vec<[u32; 3]>, Vec<bool>) {
        let tris = vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
        (tris, vec![true, true, true, true, false])
    }

    fn folded(t: &[u32; 3], pts: &[Point]) -> bool {
        crate::geometry::orient2d(pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]) <= 0.0
    }

    #[test]
    fn a_vertex_pushed_outside_its_star_comes_back_to_the_centre() {
        let (tris, fixed) = fan();
        let mut pts = vec![p(0., 0.), p(2., 0.), p(2., 2.), p(0., 2.), p(3., 1.)];
        assert!(count_inverted(&tris, &pts) > 0);
        let u = Untangler::new(&tris, &fixed);
        let start = pts.clone();
        assert!(u.untangle(&tris, &mut pts, folded, 0));
        assert_eq!(count_inverted(&tris, &pts), 0);
        // Max-min area of a square's fan: the centre.
        assert!(pts[4].distance(p(1., 1.)) < 1e-9);
        // Told where the first folded triangle is, it moves the vertex to the same bits.
        let first = tris.iter().position(|t| folded(t, &start)).unwrap();
        assert!(first > 0);
        let mut again = start;
        assert!(u.untangle(&tris, &mut again, folded, first));
        assert_eq!(
            again[4].to_array().map(f64::to_bits),
            pts[4].to_array().map(f64::to_bits)
        );
    }

    #[test]
    fn fixed_vertices_never_move_and_impossible_stars_are_reported() {
        let (tris, fixed) = fan();
        // A bow-tie ring: no position of vertex 4 makes all four triangles positive.
        let mut pts = vec![p(0., 0.), p(2., 0.), p(0., 2.), p(2., 2.), p(1., 1.)];
        let before = pts.clone();
        let u = Untangler::new(&tris, &fixed);
        assert!(!u.untangle(&tris, &mut pts, folded, 0));
        assert_eq!(&pts[..4], &before[..4]);
    }

    /// Many stars that no move can free (bow-tie rings) are given up after the first sweep,
    /// which frees none of them: at ten times that pace the rest would not clear in the
    /// sweeps left. The same number of stars that one sweep frees are untangled as before.
    #[test]
    fn a_hopeless_tangle_is_given_up_early() {
        let (fan_tris, fan_fixed) = fan();
        let copies = 200u32;
        let (mut tris, mut fixed) = (Vec::new(), Vec::new());
        let mut hopeless = Vec::new();
        let mut freeable = Vec::new();
        for k in 0..copies {
            tris.extend(fan_tris.iter().map(|t| t.map(|v| v + 5 * k)));
            fixed.extend_from_slice(&fan_fixed);
            let o = p(4.0 * f64::from(k), 0.0);
            hopeless.extend([p(0., 0.), p(2., 0.), p(0., 2.), p(2., 2.), p(1., 1.)].map(|q| q + o));
            freeable.extend([p(0., 0.), p(2., 0.), p(2., 2.), p(0., 2.), p(3., 1.)].map(|q| q + o));
        }
        let u = Untangler::new(&tris, &fixed);
        let tests = std::cell::Cell::new(0usize);
        let counted = |t: &[u32; 3], pts: &[Point]| {
            tests.set(tests.get() + 1);
            folded(t, pts)
        };
        assert!(!u.untangle(&tris, &mut hopeless, counted, 0));
        // The first test of every triangle, then one sweep's (each star's four triangles):
        // twelve sweeps would test them twelve times.
        assert_eq!(tests.get(), 2 * tris.len());
        assert!(u.untangle(&tris, &mut freeable, folded, 0));
        assert_eq!(count_inverted(&tris, &freeable), 0);
    }

    #[test]
    fn improving_restores_a_squashed_star_and_leaves_similarities_alone() {
        let (tris, fixed) = fan();
        let rest = vec![p(0., 0.), p(2., 0.), p(2., 2.), p(0., 2.), p(1., 1.)];
        let u = Untangler::new(&tris, &fixed);
        // A similarity of the rest mesh: nothing moves.
        let sim: Vec<Point> = rest
            .iter()
            .map(|&q| p(-q.y, q.x) * 3.0 + p(5., 1.))
            .collect();
        let mut same = sim.clone();
        u.improve(&tris, &rest, &mut same);
        assert_eq!(same, sim);
        // The centre pushed next to a side: valid but thin; it comes back.
        let mut squashed = rest.clone();
        squashed[4] = p(1.0, 0.01);
        let worst = |v: &[Point]| {
            tris.iter()
                .map(|t| quality(t, v))
                .fold(f64::INFINITY, f64::min)
        };
        let before = worst(&squashed);
        u.improve(&tris, &rest, &mut squashed);
        assert!(worst(&squashed) > 2.0 * before, "{squashed:?}");
        assert_eq!(count_inverted(&tris, &squashed), 0);
        assert_eq!(&squashed[..4], &rest[..4]);
    }

    #[test]
    fn a_chain_of_free_vertices_is_untangled_through_its_neighbours() {
        // A 4×4 grid of squares, each split in two; the interior vertices are free and two of
        // them are thrown across each other.
        let n = 5usize;
        let id = |i: usize, j: usize| (j * n + i) as u32;
        let mut tris = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let mut pts: Vec<Point> = (0..n * n)
            .map(|k| p((k % n) as f64, (k / n) as f64))
            .collect();
        let fixed: Vec<bool> = (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                i == 0 || j == 0 || i == n - 1 || j == n - 1
            })
            .collect();
        pts[id(1, 1) as usize] = p(3.2, 2.9);
        pts[id(3, 2) as usize] = p(0.8, 1.1);
        assert!(count_inverted(&tris, &pts) > 0);
        let u = Untangler::new(&tris, &fixed);
        assert!(u.untangle(&tris, &mut pts, folded, 0));
        assert_eq!(count_inverted(&tris, &pts), 0);
    }
}
