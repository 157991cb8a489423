//! Globally consistent rotation (§4.1.1).
//!
//! Every local transformation's angle is first measured independently in (−π, π] (the small
//! rotation). For a shape that turns by 180° or more, neighbouring transformations can then
//! disagree by almost 2π and parts of the shape would spin the other way. The fix of §4.1.1: a
//! graph with a node per local transformation, an edge between neighbouring transformations with
//! cost `|α₁ − α₂|`, its minimum spanning tree, and a depth-first traversal from the
//! transformation of smallest `|α|` that shifts each child's angle by the smallest `±2kπ` making
//! `|α_parent − α_child| ≤ π`.
//!
//! [`consistent_angles`] is that algorithm on any node/link graph; the callers choose the graph.
//! The disc method uses a reduced graph, one node per undirected disc edge (see
//! [`crate::rigid::disc`]); [`full_disc_graph`] builds the paper's literal graph so tests can
//! check that both agree.

use std::cell::Cell;
use std::f64::consts::{PI, TAU};

/// Makes `angles` consistent over the graph whose links are `links` (pairs of node indices):
/// Kruskal's minimum spanning forest under cost `|α_a − α_b|` (ties broken by the link's node
/// indices, so the result is deterministic), then an iterative depth-first traversal from each
/// tree's node of smallest `|α|` (ties: lowest index) correcting each child by the multiple of 2π
/// that brings it within π of its parent. Angles all within a half turn of each other are
/// handed back as they are, without the forest: no child would move ([`within_half_turn`]).
pub(crate) fn consistent_angles(angles: &[f64], links: &[(u32, u32)]) -> Vec<f64> {
    if within_half_turn(angles) {
        return angles.to_vec();
    }
    along_spanning_forest(angles, links)
}

/// [`consistent_angles`] over the graph that links every two nodes of the same clique — clique
/// `c`'s nodes are `members[start[c]..start[c + 1]]`, each clique given by `cliques` only when
/// it is needed (not for angles within a half turn). The disc method's rotation graph is such
/// a graph: its edges meeting at a vertex are all linked, about five links per mesh edge.
///
/// The result is that of [`consistent_angles`] on all those links, bit for bit, with a third
/// of them sorted: a link that is not in its own clique's minimum spanning tree is the
/// heaviest link of a cycle within the clique, so it is in no minimum spanning forest of the
/// whole graph either (keys are distinct, so each forest is unique), and only the cliques'
/// trees (found by Prim's algorithm, `d − 1` links for `d` nodes) go on to Kruskal.
///
/// Smooth deformations, where neighbours turn by less than a quarter turn relative to each
/// other, skip the forest: [`lifted_through_cliques`] gives its angles without it.
pub(crate) fn consistent_angles_in_cliques(
    angles: &[f64],
    cliques: impl FnOnce() -> Cliques,
) -> Vec<f64> {
    if within_half_turn(angles) {
        // No two angles are π apart, so no child is ever shifted, whatever the tree: the
        // traversal would hand back the angles as they are.
        return angles.to_vec();
    }
    let cliques = cliques();
    if let Some(lifted) = lifted_through_cliques(angles, &cliques) {
        return lifted;
    }
    let Cliques { start, members, .. } = cliques;
    let candidates: usize = start
        .windows(2)
        .map(|w| (w[1] - w[0]).saturating_sub(1))
        .sum();
    let mut keys = Vec::with_capacity(candidates);
    let mut prim = Prim::default();
    for w in start.windows(2) {
        prim.tree(angles, &members[w[0]..w[1]], &mut keys);
    }
    forest_from_keys(angles, keys)
}

/// Nodes grouped in cliques, both ways round, in compressed rows: clique `c`'s nodes are
/// `members[start[c]..start[c + 1]]`, and node `v` is in the cliques
/// `of_node[of_start[v]..of_start[v + 1]]`.
pub(crate) struct Cliques {
    /// Where each clique's nodes start in `members`, and a last entry for the end.
    pub(crate) start: Vec<usize>,
    /// The cliques' nodes.
    pub(crate) members: Vec<u32>,
    /// Where each node's cliques start in `of_node`, and a last entry for the end.
    pub(crate) of_start: Vec<usize>,
    /// The nodes' cliques.
    pub(crate) of_node: Vec<u32>,
}

impl Cliques {
    /// The cliques `members[start[c]..start[c + 1]]` over `n` nodes, with each node's cliques
    /// found by a counting sort.
    #[cfg(test)]
    pub(crate) fn new(n: usize, start: Vec<usize>, members: Vec<u32>) -> Cliques {
        let (of_start, of_node) = crate::mesh::compressed_rows(
            n,
            start
                .windows(2)
                .enumerate()
                .flat_map(|(c, w)| members[w[0]..w[1]].iter().map(move |&v| (v, c as u32))),
        );
        Cliques {
            start,
            members,
            of_start,
            of_node,
        }
    }

    /// Clique `c`'s nodes.
    fn clique(&self, c: u32) -> &[u32] {
        &self.members[self.start[c as usize]..self.start[c as usize + 1]]
    }

    /// Node `v`'s cliques.
    fn of(&self, v: u32) -> &[u32] {
        &self.of_node[self.of_start[v as usize]..self.of_start[v as usize + 1]]
    }

    /// How many cliques there are.
    fn len(&self) -> u32 {
        self.start.len().saturating_sub(1) as u32
    }
}

/// Angles lifted further than this from the origin are left to the spanning forest: the
/// margin of [`lifted_through_cliques`] covers rounding well below it.
const LIFT_LIMIT: f64 = 1e6;

/// How far below π every light link's lifted difference must stay for
/// [`lifted_through_cliques`] to hand its lifting back: far above the rounding of angles within
/// [`LIFT_LIMIT`] (about 1e-10), so the spanning forest's traversal picks the same branch for
/// every child.
const LIFT_MARGIN: f64 = 1e-6;

/// Links that turn by less than this are the light links of [`lifted_through_cliques`].
const LIGHT: f64 = std::f64::consts::FRAC_PI_2;

/// The angles of [`consistent_angles_in_cliques`], bit for bit, without a spanning forest, in
/// the case §4.1.1 is designed for: neighbouring transformations that turn by less than a
/// quarter turn relative to each other hold the shape together, and no loop of them winds
/// around. `None` otherwise, and the forest decides.
///
/// Why the bits are the same. Call a link light when it turns by less than [`LIGHT`]
/// ([`turn_between`]). When the light links join every part of the graph, every heavier link
/// closes a loop of lighter ones and is in no minimum spanning forest, so the forest is made
/// of light links. A walk over the light links from each part's root (the forest's: smallest
/// `|α|`, lowest index) puts every node on the branch ([`nearest_branch`]) nearest to the node
/// it was reached from. If then every light link's lifted ends are less than `π − LIFT_MARGIN`
/// apart, so are the forest's. The forest's traversal starts at the same root, unchanged, and
/// gives each child `α + 2kπ` for the one integer `k` within π of its parent: by induction the
/// parent's value here, so the child's value here, to the bit (both compute `α + 2π·k` from
/// the same `k`, or hand back `α` when `k` is 0).
fn lifted_through_cliques(angles: &[f64], cliques: &Cliques) -> Option<Vec<f64>> {
    if angles.iter().any(|a| !a.is_finite()) {
        return None;
    }
    let n = angles.len();
    // Each part's root.
    let mut parent: Vec<u32> = (0..n as u32).collect();
    for c in 0..cliques.len() {
        if let Some((&first, rest)) = cliques.clique(c).split_first() {
            for &v in rest {
                let (ra, rb) = (find_root(&mut parent, first), find_root(&mut parent, v));
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
    }
    let root_of = roots(angles, &mut parent);
    drop(parent);
    let light = |a: u32, b: u32| turn_between(angles[a as usize], angles[b as usize]) < LIGHT;
    // How many of each clique's nodes are still unreached. A clique whose nodes have all been
    // reached has nothing more to give the walk, so it is not read again: each clique is then
    // read about once rather than once from each of its nodes.
    let unreached: Vec<Cell<u32>> = (0..cliques.len())
        .map(|c| Cell::new(cliques.clique(c).len() as u32))
        .collect();
    let (out, lifted) = lift_from_roots(
        angles,
        &root_of,
        |v| {
            cliques
                .of(v)
                .iter()
                .filter(|&&c| unreached[c as usize].get() > 0)
                .map(|&c| cliques.clique(c))
        },
        light,
        |u| {
            for &c in cliques.of(u) {
                let left = &unreached[c as usize];
                left.set(left.get() - 1);
            }
        },
    );
    if lifted.contains(&false) {
        return None; // the light links leave a part in pieces
    }
    if out.iter().any(|a| a.abs() > LIFT_LIMIT) {
        return None;
    }
    for c in 0..cliques.len() {
        let nodes = cliques.clique(c);
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in nodes {
            lo = lo.min(out[v as usize]);
            hi = hi.max(out[v as usize]);
        }
        if hi - lo < PI - LIFT_MARGIN {
            continue; // no two of the clique are a half turn apart
        }
        for (k, &a) in nodes.iter().enumerate() {
            let la = out[a as usize];
            for &b in &nodes[k + 1..] {
                if light(a, b) && (la - out[b as usize]).abs() >= PI - LIFT_MARGIN {
                    return None;
                }
            }
        }
    }
    Some(out)
}

/// Scratch of Prim's algorithm on one clique.
#[derive(Default)]
struct Prim {
    /// Nodes not yet in the tree, with the key of their lightest link into it.
    outside: Vec<(u32, u128)>,
}

impl Prim {
    /// Pushes the keys of the minimum spanning tree of the clique on `nodes` (every two
    /// linked, repeated nodes and self-links ignored as [`along_spanning_forest`] ignores
    /// them) onto `keys`.
    fn tree(&mut self, angles: &[f64], nodes: &[u32], keys: &mut Vec<u128>) {
        let Some((&first, rest)) = nodes.split_first() else {
            return;
        };
        self.outside.clear();
        self.outside
            .extend(rest.iter().map(|&v| (v, link_key(angles, first, v))));
        while let Some(k) = (0..self.outside.len()).min_by_key(|&k| self.outside[k].1) {
            let (v, key) = self.outside.swap_remove(k);
            if key != u128::MAX {
                keys.push(key);
            }
            for (u, best) in self.outside.iter_mut() {
                *best = (*best).min(link_key(angles, v, *u));
            }
        }
    }
}

/// The key of the link `a`–`b` in Kruskal's order: its cost's bits in [`f64::total_cmp`]'s
/// order, then its smaller and its larger node, as one integer (ordering plain integers is
/// several times faster than comparing tuples, and the order is the same). A self-link has
/// the key `u128::MAX` and is never taken.
#[inline]
fn link_key(angles: &[f64], a: u32, b: u32) -> u128 {
    if a == b {
        return u128::MAX;
    }
    let (a, b) = (a.min(b), a.max(b));
    let cost = turn_between(angles[a as usize], angles[b as usize]);
    (u128::from(total_order_bits(cost)) << 64) | (u128::from(a) << 32) | u128::from(b)
}

/// [`consistent_angles`] by its definition: the spanning forest and the traversal.
fn along_spanning_forest(angles: &[f64], links: &[(u32, u32)]) -> Vec<f64> {
    let keys = links
        .iter()
        .filter(|(a, b)| a != b)
        .map(|&(a, b)| link_key(angles, a, b))
        .collect();
    forest_from_keys(angles, keys)
}

/// Kruskal's spanning forest over the links whose keys ([`link_key`]) are `order`, then the
/// traversal that puts each child on its parent's branch ([`consistent_angles`]).
fn forest_from_keys(angles: &[f64], mut order: Vec<u128>) -> Vec<f64> {
    let n = angles.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let mut tree: Vec<(u32, u32)> = Vec::with_capacity(n.saturating_sub(1));
    filter_kruskal(&mut order, &mut parent, &mut tree, n);
    drop(order);
    // Tree adjacency in compressed rows.
    let (start, adj) =
        crate::mesh::compressed_rows(n, tree.iter().flat_map(|&(a, b)| [(a, b), (b, a)]));
    let root_of = roots(angles, &mut parent);
    lift_from_roots(
        angles,
        &root_of,
        |v| std::iter::once(&adj[start[v as usize]..start[v as usize + 1]]),
        |_, _| true,
        |_| {},
    )
    .0
}

/// A depth-first traversal from each root of `root_of` ([`roots`]) over the links that
/// `neighbours` lists (as runs of nodes: a clique, a row of the tree) and `follow` takes,
/// putting each node reached on the branch ([`nearest_branch`]) nearest to the node it was
/// reached from, and telling `on_reach` of each node as it is reached (the roots too). Returns
/// the angles and which nodes were reached.
fn lift_from_roots<'a, I: Iterator<Item = &'a [u32]>>(
    angles: &[f64],
    root_of: &[u32],
    neighbours: impl Fn(u32) -> I,
    follow: impl Fn(u32, u32) -> bool,
    on_reach: impl Fn(u32),
) -> (Vec<f64>, Vec<bool>) {
    let mut out = angles.to_vec();
    let mut reached = vec![false; angles.len()];
    let mut stack: Vec<u32> = Vec::new();
    for &root in root_of.iter().filter(|&&r| r != u32::MAX) {
        reached[root as usize] = true;
        on_reach(root);
        stack.push(root);
        while let Some(v) = stack.pop() {
            let av = out[v as usize];
            for run in neighbours(v) {
                for &u in run {
                    if !reached[u as usize] && follow(v, u) {
                        reached[u as usize] = true;
                        on_reach(u);
                        out[u as usize] = nearest_branch(angles[u as usize], av);
                        stack.push(u);
                    }
                }
            }
        }
    }
    (out, reached)
}

/// The root of each part of the union-find forest `parent`, where the traversal starts: its
/// node of smallest `|α|`, the lowest index on ties; indexed by the part's union-find root,
/// `u32::MAX` elsewhere.
fn roots(angles: &[f64], parent: &mut [u32]) -> Vec<u32> {
    let mut root_of = vec![u32::MAX; angles.len()];
    for v in 0..angles.len() as u32 {
        let r = find_root(parent, v) as usize;
        let best = root_of[r];
        if best == u32::MAX || angles[v as usize].abs() < angles[best as usize].abs() {
            root_of[r] = v;
        }
    }
    root_of
}

/// Whether all of `angles` lie within an interval shorter than π: then every difference
/// `α_parent − α_child` that [`nearest_branch`] computes is below π in magnitude as well
/// (rounding is monotone, so no computed difference exceeds the computed `max − min`), and
/// [`consistent_angles`] changes nothing. The common case: a shape that turns less than a
/// half turn, with its local rotations spread over less than π.
fn within_half_turn(angles: &[f64]) -> bool {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &a in angles {
        if a.is_nan() {
            return false;
        }
        lo = lo.min(a);
        hi = hi.max(a);
    }
    // An infinite angle takes the full algorithm (∞ − x is not below π).
    hi - lo < PI
}

/// The root of `v`'s set in the union-find forest `parent` (path halving).
fn find_root(parent: &mut [u32], mut v: u32) -> u32 {
    while parent[v as usize] != v {
        let gp = parent[parent[v as usize] as usize];
        parent[v as usize] = gp;
        v = gp;
    }
    v
}

/// Links below this many are sorted outright by [`filter_kruskal`].
const FILTER_KRUSKAL_LEAF: usize = 512;

/// Kruskal's spanning forest of `nodes` nodes over links given as keys `(cost bits, a, b)`
/// (see [`consistent_angles`]), pushed onto `tree` in the order Kruskal accepts them, without
/// sorting every link: Filter-Kruskal (Osipov, Sanders and Singler, 2009) splits the keys at
/// their median, builds the forest of the lighter half, drops the heavier links whose ends it
/// has already joined (most of them, on a mesh's rotation graph) and goes on with the rest.
/// Links are accepted in the order a full sort gives, so the forest is the same. Returns
/// whether the forest spans all nodes (then the rest of the links are not looked at).
fn filter_kruskal(
    keys: &mut [u128],
    parent: &mut [u32],
    tree: &mut Vec<(u32, u32)>,
    nodes: usize,
) -> bool {
    if keys.len() <= FILTER_KRUSKAL_LEAF {
        keys.sort_unstable();
        for &key in keys.iter() {
            let (a, b) = ((key >> 32) as u32, key as u32);
            let (ra, rb) = (find_root(parent, a), find_root(parent, b));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
                tree.push((a, b));
                if tree.len() + 1 == nodes {
                    return true;
                }
            }
        }
        return false;
    }
    let mid = keys.len() / 2;
    keys.select_nth_unstable(mid);
    let (light, heavy) = keys.split_at_mut(mid + 1);
    if filter_kruskal(light, parent, tree, nodes) {
        return true;
    }
    let mut kept = 0;
    for r in 0..heavy.len() {
        let key = heavy[r];
        let (a, b) = ((key >> 32) as u32, key as u32);
        if find_root(parent, a) != find_root(parent, b) {
            heavy[kept] = key;
            kept += 1;
        }
    }
    filter_kruskal(&mut heavy[..kept], parent, tree, nodes)
}

/// The bits of `x` as an unsigned integer that orders as [`f64::total_cmp`] orders the floats:
/// negative values have every bit flipped, the others only the sign bit.
fn total_order_bits(x: f64) -> u64 {
    let b = x.to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | (1 << 63)
    }
}

/// The angle between two rotations, `|α_a − α_b|` taken modulo 2π into [0, π]: the cost of a
/// link in the spanning tree. The raw difference (the paper's `|α₁ − α₂|`) makes two
/// neighbours on either side of ±π look a full turn apart, so the tree joins them through any
/// disc with a small angle instead, a badly fitted one in a distorted region, and that disc,
/// as the root of smallest `|α|`, then leaves the two sides on different branches.
fn turn_between(a: f64, b: f64) -> f64 {
    let d = a - b;
    // `rem_euclid` without its division when `d` is already within a turn, as the raw angles'
    // differences are: `d % TAU` is then `d` exactly, so the bits are the same.
    let d = if d.abs() < TAU {
        if d < 0.0 {
            d + TAU
        } else {
            d
        }
    } else {
        d.rem_euclid(TAU)
    };
    d.min(TAU - d)
}

/// `alpha + 2kπ` for the integer `k` that brings it closest to `reference` (so the difference is
/// at most π; unchanged when it already is below π).
pub(crate) fn nearest_branch(alpha: f64, reference: f64) -> f64 {
    let d = reference - alpha;
    if d.abs() < PI {
        alpha
    } else {
        alpha + TAU * (d / TAU).round()
    }
}

/// A list of index pairs.
#[cfg(test)]
pub(crate) type EdgeList = Vec<(u32, u32)>;

/// Every link of the cliques `members[start[c]..start[c + 1]]`: each two nodes of a clique.
#[cfg(test)]
pub(crate) fn clique_links(start: &[usize], members: &[u32]) -> EdgeList {
    start
        .windows(2)
        .flat_map(|w| {
            let m = &members[w[0]..w[1]];
            (0..m.len()).flat_map(move |a| (a + 1..m.len()).map(move |b| (m[a], m[b])))
        })
        .collect()
}

/// The paper's literal graph (§4.1.1) for discs `discs`: one node per directed local
/// transformation `(i, j)` with `j ∈ P_i`, numbered in the order of `discs`, and a link between
/// `(i₁, j₁)` and `(i₂, j₂)` when `p_j₁ ∈ P_j₂` or `p_j₂ ∈ P_j₁`. Large (about 36 links per
/// transformation on a triangle mesh); used by tests to validate the reduced graph.
#[cfg(test)]
pub(crate) fn full_disc_graph(discs: &[Vec<u32>]) -> (EdgeList, EdgeList) {
    let n = discs.len();
    let mut nodes = Vec::new();
    let mut by_end: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (i, d) in discs.iter().enumerate() {
        for &j in d {
            by_end[j as usize].push(nodes.len() as u32);
            nodes.push((i as u32, j));
        }
    }
    // Symmetric closure of "is in the disc of".
    let mut near: Vec<Vec<u32>> = discs.to_vec();
    for (i, d) in discs.iter().enumerate() {
        for &j in d {
            near[j as usize].push(i as u32);
        }
    }
    let mut links = Vec::new();
    for (k1, &(_, j1)) in nodes.iter().enumerate() {
        let mut ends = near[j1 as usize].clone();
        ends.sort_unstable();
        ends.dedup();
        for j2 in ends {
            for &k2 in &by_end[j2 as usize] {
                if (k1 as u32) < k2 {
                    links.push((k1 as u32, k2));
                }
            }
        }
    }
    (nodes, links)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_keys_order_floats_as_total_cmp_does() {
        let xs = [
            f64::NAN,
            -f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            -1.5,
            -0.0,
            0.0,
            1e-300,
            -1e-300,
            f64::MIN_POSITIVE,
            std::f64::consts::PI,
            3.0,
        ];
        let mut by_cmp = xs.to_vec();
        by_cmp.sort_by(|a, b| a.total_cmp(b));
        let mut by_key = xs.to_vec();
        by_key.sort_by_key(|&x| total_order_bits(x));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&by_cmp), bits(&by_key));
    }

    /// Two neighbours either side of ±π and a badly fitted disc of small angle linked to both:
    /// the tree must join the neighbours directly (0.28 apart), not through the outlier
    /// (2.9 and 3.1 from them), which as the root of smallest |α| would leave them a full turn
    /// apart.
    #[test]
    fn neighbours_across_the_half_turn_share_a_branch() {
        let out = consistent_angles(&[3.0, -3.0, 0.1], &[(0, 1), (0, 2), (1, 2)]);
        assert!((out[0] - out[1]).abs() < 0.3, "{out:?}");
        assert!((turn_between(3.0, -3.0) - (TAU - 6.0)).abs() < 1e-12);
    }

    #[test]
    fn nearest_branch_takes_the_smallest_correction() {
        assert_eq!(nearest_branch(0.3, 0.1), 0.3);
        assert!((nearest_branch(-3.0, 3.0) - (TAU - 3.0)).abs() < 1e-15);
        assert!((nearest_branch(3.0, -3.0) - (3.0 - TAU)).abs() < 1e-15);
        assert!((nearest_branch(0.1, 4.0 * PI) - (0.1 + 4.0 * PI)).abs() < 1e-12);
    }

    /// A chain of angles turning past π: the raw values wrap to −π, the corrected ones keep
    /// increasing from the root (smallest |α|).
    #[test]
    fn a_chain_crossing_pi_is_unwrapped() {
        let true_angles: Vec<f64> = (0..40).map(|k| 0.1 * k as f64).collect();
        let raw: Vec<f64> = true_angles
            .iter()
            .map(|a| {
                let w = a.rem_euclid(TAU);
                if w > PI {
                    w - TAU
                } else {
                    w
                }
            })
            .collect();
        let links: Vec<(u32, u32)> = (0..39).map(|k| (k, k + 1)).collect();
        let fixed = consistent_angles(&raw, &links);
        for (f, t) in fixed.iter().zip(&true_angles) {
            assert!((f - t).abs() < 1e-12, "{f} vs {t}");
        }
    }

    /// Kruskal over fully sorted keys: what [`filter_kruskal`] must reproduce.
    fn sorted_kruskal(keys: &mut [u128], nodes: usize) -> Vec<(u32, u32)> {
        keys.sort_unstable();
        let mut parent: Vec<u32> = (0..nodes as u32).collect();
        let mut tree = Vec::new();
        for &key in keys.iter() {
            let (a, b) = ((key >> 32) as u32, key as u32);
            let (ra, rb) = (find_root(&mut parent, a), find_root(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
                tree.push((a, b));
            }
        }
        tree
    }

    proptest::proptest! {
        /// Filter-Kruskal accepts the same links in the same order as Kruskal over a full
        /// sort, with costs drawn from few values (many ties) and graphs large enough to
        /// split several times, disconnected ones included.
        #[test]
        fn filter_kruskal_builds_the_sorted_kruskal_forest(
            nodes in 2usize..400,
            raw in proptest::collection::vec((0u32..400, 0u32..400, 0u64..6), 0..3000),
        ) {
            let mut keys: Vec<u128> = raw
                .iter()
                .map(|&(a, b, c)| (a % nodes as u32, b % nodes as u32, c))
                .filter(|(a, b, _)| a != b)
                .map(|(a, b, c)| (u128::from(c) << 64) | (u128::from(a.min(b)) << 32) | u128::from(a.max(b)))
                .collect();
            let expected = sorted_kruskal(&mut keys.clone(), nodes);
            let mut parent: Vec<u32> = (0..nodes as u32).collect();
            let mut tree = Vec::new();
            filter_kruskal(&mut keys, &mut parent, &mut tree, nodes);
            proptest::prop_assert_eq!(tree, expected);
        }

        /// Angles spread over less than a half turn come out of the spanning forest and its
        /// traversal unchanged, bit for bit, so [`consistent_angles`] may skip both. The band
        /// is drawn up to just below π wide (and anywhere on the circle, across ±π too), on
        /// random graphs; a band a little wider than π makes some child move, so the test
        /// would see a shortcut taken too early.
        #[test]
        fn angles_within_a_half_turn_need_no_forest(
            centre in -4.0f64..4.0,
            width in 0.0f64..1.0,
            spread in proptest::collection::vec(0.0f64..=1.0, 2..200),
            raw in proptest::collection::vec((0u32..200, 0u32..200), 0..800),
        ) {
            let width = width * PI * (1.0 - 1e-12);
            let angles: Vec<f64> = spread.iter().map(|&u| centre - width / 2.0 + u * width).collect();
            let n = angles.len() as u32;
            let links: Vec<(u32, u32)> = raw.iter().map(|&(a, b)| (a % n, b % n)).collect();
            proptest::prop_assert!(within_half_turn(&angles));
            let full = along_spanning_forest(&angles, &links);
            proptest::prop_assert_eq!(
                full.iter().map(|a| a.to_bits()).collect::<Vec<_>>(),
                angles.iter().map(|a| a.to_bits()).collect::<Vec<_>>()
            );
            proptest::prop_assert_eq!(consistent_angles(&angles, &links), full);
        }
    }

    proptest::proptest! {
        /// Each clique's own spanning tree stands in for all its links: the angles come out
        /// bit for bit as from every link of every clique, on random cliques (overlapping,
        /// nested, of one node, with repeated nodes) and angles drawn from a few values
        /// across the whole circle (many equal costs, so the key order's ties are tried).
        #[test]
        fn clique_trees_give_the_angles_of_all_links(
            levels in proptest::collection::vec(-3.2f64..3.2, 1..6),
            pick in proptest::collection::vec(0usize..6, 2..120),
            cliques in proptest::collection::vec(
                proptest::collection::vec(0u32..120, 0..9), 0..60),
        ) {
            let angles: Vec<f64> = pick.iter().map(|&k| levels[k % levels.len()]).collect();
            let n = angles.len() as u32;
            let cliques: Vec<Vec<u32>> =
                cliques.iter().map(|c| c.iter().map(|&v| v % n).collect()).collect();
            let links: Vec<(u32, u32)> = cliques
                .iter()
                .flat_map(|c| {
                    (0..c.len()).flat_map(move |a| (a + 1..c.len()).map(move |b| (c[a], c[b])))
                })
                .collect();
            let mut start = vec![0usize];
            let mut members = Vec::new();
            for c in &cliques {
                members.extend_from_slice(c);
                start.push(members.len());
            }
            let want = along_spanning_forest(&angles, &links);
            let got = consistent_angles_in_cliques(&angles, || Cliques::new(angles.len(), start, members));
            proptest::prop_assert_eq!(
                got.iter().map(|a| a.to_bits()).collect::<Vec<_>>(),
                want.iter().map(|a| a.to_bits()).collect::<Vec<_>>()
            );
        }

        /// A smooth turn of many windings (each clique a window of neighbouring nodes on a
        /// line, less than a quarter turn across) is lifted without the forest, to the bits
        /// of the forest over every link; the nodes are shuffled so the walk's order is not
        /// the line's.
        #[test]
        fn smooth_turns_are_lifted_to_the_bits_of_the_forest(
            offset in -3.2f64..3.2,
            rate in -0.2f64..0.2,
            noise in proptest::collection::vec(-0.02f64..0.02, 20..200),
            widths in proptest::collection::vec(1usize..7, 1..80),
            shuffle in proptest::collection::vec(0usize..1000, 200),
        ) {
            let n = noise.len();
            // Node `place[k]` sits at position `k` of the line.
            let mut place: Vec<u32> = (0..n as u32).collect();
            for k in (1..n).rev() {
                place.swap(k, shuffle[k] % (k + 1));
            }
            let mut angles = vec![0.0; n];
            for (k, &v) in place.iter().enumerate() {
                let a = offset + rate * k as f64 + noise[k];
                angles[v as usize] = a - TAU * (a / TAU).round();
            }
            // Windows that cover every consecutive pair, so the line is one part.
            let (mut start, mut members) = (vec![0usize], Vec::new());
            let mut k = 0;
            for &w in widths.iter().cycle() {
                let end = (k + w).min(n - 1);
                members.extend_from_slice(&place[k..=end]);
                start.push(members.len());
                if end == n - 1 {
                    break;
                }
                k = end;
            }
            let links = clique_links(&start, &members);
            let cliques = Cliques::new(n, start, members);
            let lifted = lifted_through_cliques(&angles, &cliques);
            proptest::prop_assert!(lifted.is_some());
            let want = along_spanning_forest(&angles, &links);
            let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
            proptest::prop_assert_eq!(bits(&lifted.unwrap_or_default()), bits(&want));
        }

        /// The shortcut in [`turn_between`] gives the bits of `rem_euclid` over differences
        /// within a turn and beyond it.
        #[test]
        fn turn_between_keeps_the_bits_of_rem_euclid(a in -20.0f64..20.0, b in -20.0f64..20.0) {
            let d = (a - b).rem_euclid(TAU);
            proptest::prop_assert_eq!(turn_between(a, b).to_bits(), d.min(TAU - d).to_bits());
        }
    }

    #[test]
    fn a_band_of_a_half_turn_or_more_takes_the_forest() {
        // Two linked angles π + 0.1 apart: the child moves to the other branch.
        let angles = [-1.6, 1.6];
        assert!(!within_half_turn(&angles));
        let fixed = consistent_angles(&angles, &[(0, 1)]);
        assert_eq!(fixed[0], -1.6);
        assert!((fixed[1] - (1.6 - TAU)).abs() < 1e-15);
        assert!(!within_half_turn(&[0.0, f64::NAN]));
        assert!(!within_half_turn(&[0.0, f64::INFINITY]));
    }

    /// A ring of eight nodes turning a whole turn in steps of an eighth: every link is light,
    /// but the loop winds around, so no lifting keeps every link within a half turn and the
    /// forest decides (it cuts the ring at its heaviest link).
    #[test]
    fn a_winding_loop_is_left_to_the_forest() {
        let angles: Vec<f64> = (0..8)
            .map(|k| {
                let a = 0.1 + k as f64 * TAU / 8.0;
                a - TAU * (a / TAU).round()
            })
            .collect();
        let start: Vec<usize> = (0..=8).map(|k| 2 * k).collect();
        let members: Vec<u32> = (0..8u32).flat_map(|k| [k, (k + 1) % 8]).collect();
        let links: Vec<(u32, u32)> = members.chunks(2).map(|p| (p[0], p[1])).collect();
        let cliques = Cliques::new(8, start.clone(), members.clone());
        assert!(lifted_through_cliques(&angles, &cliques).is_none());
        let got = consistent_angles_in_cliques(&angles, || Cliques::new(8, start, members));
        assert_eq!(got, along_spanning_forest(&angles, &links));
        // One branch cut: the other seven links turn by an eighth.
        let steps = links
            .iter()
            .filter(|&&(a, b)| ((got[a as usize] - got[b as usize]).abs() - TAU / 8.0).abs() < 1e-9)
            .count();
        assert_eq!(steps, 7);
    }

    #[test]
    fn disconnected_parts_get_their_own_root() {
        let raw = [3.0, -3.0, 0.2, -3.1];
        let fixed = consistent_angles(&raw, &[(0, 1), (2, 3)]);
        // First part: root is the smaller |α| (3.0 vs −3.0 tie → index 0 stays).
        assert_eq!(fixed[0], 3.0);
        assert!((fixed[1] - (TAU - 3.0)).abs() < 1e-15);
        // Second part: root 0.2; −3.1 is 3.3 away, so it moves to 2π − 3.1 (2.98 away).
        assert_eq!(fixed[2], 0.2);
        assert!((fixed[3] - (TAU - 3.1)).abs() < 1e-15);
    }
}
