//! Association of salient points (§3, after \[15\]): an order-preserving match of source salient
//! points to target salient points by dynamic programming, allowing points to stay unmatched.
//!
//! Within a span (between two forced pairs: end points, anchors), each salient point has a
//! normalized arc-length position `u ∈ (0, 1)`. Pairing source point `a` with target point `b`
//! costs `|u_a − u_b| + angle_weight · |θ_a − θ_b| / π` (θ the signed turning), and is only
//! allowed when the turnings have the same sign and sizes within a factor `max_turning_ratio`.
//! Leaving a point unmatched costs `skip_cost`. The match of least total cost is kept.
//!
//! A closed curve without anchors has no natural start, so the match is cyclic: every allowed
//! pair is tried as the start, positions are measured from it, and the rest is matched as one
//! span ending back at the start. That is O(n²·m²) for n and m salient points, bounded by
//! [`CorrespondenceOptions::max_salient`] (32 × 32 points: about a million table cells).

use super::salient::Salient;
use super::CorrespondenceOptions;

/// A salient point reduced to what the association looks at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mark {
    /// Normalized position in the span, in `[0, 1]`.
    pub(crate) u: f64,
    /// Signed turning angle (radians).
    pub(crate) turning: f64,
    /// Direction (radians) from the curve's centroid, when the match should respect the
    /// shapes' own turn ([`CorrespondenceOptions::outline_turn`]).
    pub(crate) bearing: Option<f64>,
}

/// Weight of a pair's disagreement with the shapes' own turn, per half turn, in the pairing
/// cost (against normalized arc length): a tip paired with a tip a quarter turn away from
/// where the shapes' turn puts it costs as much as a fifth of the outline's length.
const TURN_WEIGHT: f64 = 0.4;

/// The parts of pairing a point of turning `ta` (direction `ba` from its centroid) with one of
/// turning `tb` (direction `bb`) that do not depend on where a span starts: the turning term and
/// the turn term of [`pair_cost`], or `None` when they may not be paired.
fn pair_terms(
    (ta, ba): (f64, Option<f64>),
    (tb, bb): (f64, Option<f64>),
    opts: &CorrespondenceOptions,
) -> Option<(f64, f64)> {
    if ta * tb <= 0.0 {
        return None;
    }
    let (lo, hi) = {
        let (x, y) = (ta.abs(), tb.abs());
        (x.min(y), x.max(y))
    };
    if hi > lo * opts.max_turning_ratio.max(1.0) {
        return None;
    }
    let turn = match (ba, bb, opts.outline_turn) {
        (Some(x), Some(y), Some(th)) => {
            let d = y - x - th;
            TURN_WEIGHT * d.sin().atan2(d.cos()).abs() / std::f64::consts::PI
        }
        _ => 0.0,
    };
    Some((
        opts.angle_weight * (ta - tb).abs() / std::f64::consts::PI,
        turn,
    ))
}

/// A pair's cost from its positions in the span and its [`pair_terms`], added in one order
/// everywhere so that a cost looked up from a table has the bits of one computed afresh.
fn cost_of(ua: f64, ub: f64, (turning, turn): (f64, f64)) -> f64 {
    (ua - ub).abs() + turning + turn
}

/// The cost of pairing `a` with `b`, or `None` when they may not be paired.
fn pair_cost(a: Mark, b: Mark, opts: &CorrespondenceOptions) -> Option<f64> {
    let terms = pair_terms((a.turning, a.bearing), (b.turning, b.bearing), opts)?;
    Some(cost_of(a.u, b.u, terms))
}

/// The least-cost order-preserving match between `src` and `tgt` (each sorted by `u`): its total
/// cost (pairs plus skipped points) and the matched `(source, target)` index pairs, in order.
pub(crate) fn associate_span(
    src: &[Mark],
    tgt: &[Mark],
    opts: &CorrespondenceOptions,
) -> (f64, Vec<(usize, usize)>) {
    span_by(src.len(), tgt.len(), opts.skip_cost, |a, b| {
        pair_cost(src[a], tgt[b], opts)
    })
}

/// [`associate_span`] over `n` source and `m` target points whose pair costs `pair(a, b)` gives
/// (`None` where they may not be paired).
fn span_by(
    n: usize,
    m: usize,
    skip: f64,
    pair: impl Fn(usize, usize) -> Option<f64>,
) -> (f64, Vec<(usize, usize)>) {
    let w = m + 1;
    // cost[a*w + b]: best cost of matching src[..a] with tgt[..b]; step records the move.
    let mut cost = vec![0.0; (n + 1) * w];
    let mut step = vec![0u8; (n + 1) * w];
    for a in 0..=n {
        for b in 0..=m {
            if a == 0 && b == 0 {
                continue;
            }
            let mut best = f64::INFINITY;
            let mut mv = 0u8;
            if a > 0 && b > 0 {
                if let Some(c) = pair(a - 1, b - 1) {
                    best = cost[(a - 1) * w + b - 1] + c;
                    mv = 1;
                }
            }
            if a > 0 && cost[(a - 1) * w + b] + skip < best {
                best = cost[(a - 1) * w + b] + skip;
                mv = 2;
            }
            if b > 0 && cost[a * w + b - 1] + skip < best {
                best = cost[a * w + b - 1] + skip;
                mv = 3;
            }
            cost[a * w + b] = best;
            step[a * w + b] = mv;
        }
    }
    let mut pairs = Vec::new();
    let (mut a, mut b) = (n, m);
    while a > 0 || b > 0 {
        match step[a * w + b] {
            1 => {
                pairs.push((a - 1, b - 1));
                a -= 1;
                b -= 1;
            }
            2 => a -= 1,
            _ => b -= 1,
        }
    }
    pairs.reverse();
    (cost[n * w + m], pairs)
}

/// Candidate cyclic matches of two closed curves' salient points (lengths `src_len`,
/// `tgt_len`): every match whose cost is within a hair of the least, each as matched
/// `(source, target)` index pairs starting with its start pair. Empty when no pair is allowed.
///
/// `bearings` are the salient points' directions from their curve's centroid (source, target),
/// used when [`CorrespondenceOptions::outline_turn`] is set.
pub(crate) fn associate_cyclic(
    src: &[Salient],
    src_len: f64,
    tgt: &[Salient],
    tgt_len: f64,
    bearings: (&[f64], &[f64]),
    opts: &CorrespondenceOptions,
) -> Vec<Vec<(usize, usize)>> {
    let (n, m) = (src.len(), tgt.len());
    // From a start, each other point's index and position along the curve (in span order:
    // span position x is point (start + 1 + x) mod len); the turning and the bearing are in
    // the pair table below, not here.
    let span = |pts: &[Salient], len: f64, start: usize| -> Vec<(usize, f64)> {
        let s0 = pts[start].s;
        (1..pts.len())
            .map(|k| {
                let q = (start + k) % pts.len();
                (q, (pts[q].s - s0).rem_euclid(len) / len)
            })
            .collect()
    };
    // What a pair costs besides its positions depends on the two points only, not on the
    // start: found once per pair here rather than once per start and pair (the turn term's
    // trigonometry was most of a cyclic match's time).
    let terms: Vec<Option<(f64, f64)>> = (0..n)
        .flat_map(|p| (0..m).map(move |q| (p, q)))
        .map(|(p, q)| {
            pair_terms(
                (src[p].turning, bearings.0.get(p).copied()),
                (tgt[q].turning, bearings.1.get(q).copied()),
                opts,
            )
        })
        .collect();
    // The target's spans depend on their start only: made once, not once per source start.
    let tgt_spans: Vec<Vec<(usize, f64)>> = (0..m).map(|j| span(tgt, tgt_len, j)).collect();
    let mut found: Vec<(f64, Vec<(usize, usize)>)> = Vec::new();
    for i in 0..n {
        let a = span(src, src_len, i);
        for (j, b) in tgt_spans.iter().enumerate() {
            let Some(head) = terms[i * m + j] else {
                continue;
            };
            let c0 = cost_of(0.0, 0.0, head);
            let (c, rest) = span_by(a.len(), b.len(), opts.skip_cost, |x, y| {
                let ((p, ua), (q, ub)) = (a[x], b[y]);
                terms[p * m + q].map(|t| cost_of(ua, ub, t))
            });
            let mut pairs = vec![(i, j)];
            pairs.extend(rest.into_iter().map(|(x, y)| (a[x].0, b[y].0)));
            found.push((c0 + c, pairs));
        }
    }
    let best = found.iter().map(|f| f.0).fold(f64::INFINITY, f64::min);
    let limit = best + 1e-9 * (1.0 + best.abs());
    found
        .into_iter()
        .filter(|f| f.0 <= limit)
        .map(|f| f.1)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mk(u: f64, deg: f64) -> Mark {
        Mark {
            u,
            turning: deg.to_radians(),
            bearing: None,
        }
    }

    #[test]
    fn span_match_pairs_near_points_of_like_turning() {
        let opts = CorrespondenceOptions::default();
        let src = [mk(0.2, 90.), mk(0.5, -60.), mk(0.8, 90.)];
        let tgt = [mk(0.25, 80.), mk(0.55, 70.), mk(0.82, 100.)];
        let (_, pairs) = associate_span(&src, &tgt, &opts);
        // The reflex source point has no partner; the middle target point stays unmatched too.
        assert_eq!(pairs, vec![(0, 0), (2, 2)]);
        let (cost, none) = associate_span(&src, &[], &opts);
        assert!(none.is_empty());
        assert!((cost - 3.0 * opts.skip_cost).abs() < 1e-12);
    }

    #[test]
    fn span_match_never_crosses() {
        let opts = CorrespondenceOptions::default();
        // The allowed pairs (a convex and a reflex one) cross: only one of them can be kept.
        let src = [mk(0.2, 90.), mk(0.3, -90.)];
        let tgt = [mk(0.2, -90.), mk(0.3, 90.)];
        let (_, pairs) = associate_span(&src, &tgt, &opts);
        assert_eq!(pairs.len(), 1);
    }

    #[test]
    fn cyclic_match_from_its_table_equals_each_starts_span_match() {
        // Salient points of mixed turning and direction, with the shapes' own turn set, so
        // that every term of a pair's cost and every refusal takes part.
        let opts = CorrespondenceOptions {
            outline_turn: Some(0.4),
            ..Default::default()
        };
        for (n, m) in [(7, 9), (12, 5), (1, 4), (10, 10)] {
            let pts = |k: usize, len: f64| -> (Vec<Salient>, Vec<f64>) {
                let phase = k as f64 * 0.37;
                let pts = (0..k)
                    .map(|i| {
                        let x = i as f64;
                        Salient {
                            index: i,
                            s: len * (x + 0.5 + 0.3 * (1.7 * x + phase).sin()) / k as f64,
                            turning: 1.5 * (2.3 * x + phase).sin() + 0.4,
                        }
                    })
                    .collect();
                (
                    pts,
                    (0..k)
                        .map(|i| 3.0 * (0.9 * i as f64 - phase).sin())
                        .collect(),
                )
            };
            let (src, sb) = pts(n, 5.0);
            let (tgt, tb) = pts(m, 7.0);
            // The match as first written: every start's span matched afresh from its marks.
            let mark = |p: &[Salient], b: &[f64], len: f64, start: usize, k: usize| Mark {
                u: (p[(start + k) % p.len()].s - p[start].s).rem_euclid(len) / len,
                turning: p[(start + k) % p.len()].turning,
                bearing: Some(b[(start + k) % p.len()]),
            };
            let mut found = Vec::new();
            for i in 0..n {
                for j in 0..m {
                    let head = (mark(&src, &sb, 5.0, i, 0), mark(&tgt, &tb, 7.0, j, 0));
                    let Some(c0) = pair_cost(head.0, head.1, &opts) else {
                        continue;
                    };
                    let a: Vec<Mark> = (1..n).map(|k| mark(&src, &sb, 5.0, i, k)).collect();
                    let b: Vec<Mark> = (1..m).map(|k| mark(&tgt, &tb, 7.0, j, k)).collect();
                    let (c, rest) = associate_span(&a, &b, &opts);
                    let mut pairs = vec![(i, j)];
                    pairs.extend(
                        rest.iter()
                            .map(|&(x, y)| ((i + 1 + x) % n, (j + 1 + y) % m)),
                    );
                    found.push((c0 + c, pairs));
                }
            }
            let best = found.iter().map(|f| f.0).fold(f64::INFINITY, f64::min);
            let limit = best + 1e-9 * (1.0 + best.abs());
            let expected: Vec<_> = found
                .into_iter()
                .filter(|f| f.0 <= limit)
                .map(|f| f.1)
                .collect();
            assert!(!expected.is_empty(), "{n} × {m}: nothing to compare");
            let got = associate_cyclic(&src, 5.0, &tgt, 7.0, (&sb, &tb), &opts);
            assert_eq!(got, expected, "{n} × {m}");
        }
    }

    #[test]
    fn cyclic_match_finds_the_rectangle_corners() {
        let opts = CorrespondenceOptions::default();
        let q = std::f64::consts::FRAC_PI_2;
        // A 2×1 rectangle (length 6) and the same rectangle started at its second corner.
        let rect = |offs: [f64; 4]| -> Vec<Salient> {
            offs.iter()
                .enumerate()
                .map(|(k, &s)| Salient {
                    index: k,
                    s,
                    turning: q,
                })
                .collect()
        };
        let src = rect([0.0, 2.0, 3.0, 5.0]);
        let tgt = rect([0.0, 1.0, 3.0, 4.0]);
        let found = associate_cyclic(&src, 6.0, &tgt, 6.0, (&[], &[]), &opts);
        assert!(!found.is_empty());
        for pairs in &found {
            assert_eq!(pairs.len(), 4);
            // Long sides start at source corners 0 and 2 and at target corners 1 and 3.
            for &(a, b) in pairs {
                assert_eq!(a % 2, (b + 1) % 2);
            }
        }
    }
}
