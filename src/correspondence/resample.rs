//! Distribution of the remaining vertices (§3, after \[15\]): between consecutive associated points
//! both curves get the same number of vertices.
//!
//! Within a span, the normalized arc-length parameters of the source's own vertices and of the
//! target's own vertices are merged, so each curve keeps every one of its original vertices and
//! no detail of its shape is lost. A source vertex and a target vertex that would land closer than
//! `merge` to each other's partner become one pair, each side keeping its own original vertex
//! (so corners stay exactly where they are and no needlessly short edge appears). Every other
//! vertex gets a partner by arc-length sampling of the other curve at the same normalized
//! parameter. Finally every edge longer than `max_edge` (on either side) is split uniformly.

use super::measure::Polyline;
use crate::geometry::Point;
use crate::{Error, Result};

/// Upper bound on the vertices of one curve pair, against absurd density settings.
const MAX_VERTICES: usize = 2_000_000;

/// One vertex pair under construction: its arc length on each curve and, where it is one of the
/// curve's original vertices, that vertex's index.
#[derive(Debug, Clone, Copy)]
struct Entry {
    s_src: f64,
    s_tgt: f64,
    v_src: Option<usize>,
    v_tgt: Option<usize>,
    associated: bool,
}

/// Corresponding vertex lists of `src` and `tgt` given the associated vertex pairs `pairs`
/// (strictly increasing on both sides; the first is `(0, 0)`; an open curve's last is its two end
/// points). Returns both vertex lists and the indices of the associated pairs in them.
pub(crate) fn distribute(
    src: &Polyline,
    tgt: &Polyline,
    pairs: &[(usize, usize)],
    max_edge: f64,
    merge: f64,
    snap: f64,
) -> Result<(Vec<Point>, Vec<Point>, Vec<usize>)> {
    let closed = src.closed();
    let (n, m) = (src.len(), tgt.len());
    // The span ends: a closed curve's last span ends back at its start, one length further on.
    let mut ends: Vec<(usize, usize, f64, f64)> = pairs
        .iter()
        .map(|&(a, b)| (a, b, src.s(a), tgt.s(b)))
        .collect();
    if closed {
        ends.push((n, m, src.length(), tgt.length()));
    }
    let mut entries: Vec<Entry> = Vec::new();
    for w in ends.windows(2) {
        let ((a0, b0, s0, t0), (a1, b1, s1, t1)) = (w[0], w[1]);
        if a1 <= a0 || b1 <= b0 || s1 <= s0 || t1 <= t0 {
            return Err(Error::internal(
                "associated points are not in order along the curves",
            ));
        }
        entries.push(Entry {
            s_src: s0,
            s_tgt: t0,
            v_src: Some(a0),
            v_tgt: Some(b0),
            associated: true,
        });
        span(
            &mut entries,
            src,
            tgt,
            (a0, a1, s0, s1),
            (b0, b1, t0, t1),
            merge,
        );
    }
    if !closed {
        let &(a, b, s, t) = ends
            .last()
            .ok_or_else(|| Error::internal("no associated points"))?;
        entries.push(Entry {
            s_src: s,
            s_tgt: t,
            v_src: Some(a),
            v_tgt: Some(b),
            associated: true,
        });
    }
    let mut entries = split_long_edges(&entries, closed, max_edge, src.length(), tgt.length())?;
    spread(
        &mut entries,
        closed,
        src.length(),
        4.0 * snap,
        |e| (e.s_src, e.v_src.is_some()),
        |e, s| e.s_src = s,
    );
    spread(
        &mut entries,
        closed,
        tgt.length(),
        4.0 * snap,
        |e| (e.s_tgt, e.v_tgt.is_some()),
        |e, s| e.s_tgt = s,
    );
    let point = |line: &Polyline, v: Option<usize>, s: f64| match v {
        Some(i) => line.points()[i % line.len()],
        None => line.point_at(s),
    };
    // Drop a constructed vertex that coincides with its neighbour on either side.
    let mut out_src: Vec<Point> = Vec::with_capacity(entries.len());
    let mut out_tgt: Vec<Point> = Vec::with_capacity(entries.len());
    let mut kept: Vec<Entry> = Vec::with_capacity(entries.len());
    for e in entries {
        let (p, q) = (point(src, e.v_src, e.s_src), point(tgt, e.v_tgt, e.s_tgt));
        if let (Some(&lp), Some(&lq), Some(last)) = (out_src.last(), out_tgt.last(), kept.last()) {
            if lp.distance(p) <= snap || lq.distance(q) <= snap {
                let original = |x: &Entry| x.v_src.is_some() || x.v_tgt.is_some();
                if !original(&e) {
                    continue;
                }
                if original(last) {
                    return Err(coincident());
                }
                out_src.pop();
                out_tgt.pop();
                kept.pop();
            }
        }
        out_src.push(p);
        out_tgt.push(q);
        kept.push(e);
    }
    if closed && out_src.len() > 1 {
        let k = out_src.len() - 1;
        if out_src[k].distance(out_src[0]) <= snap || out_tgt[k].distance(out_tgt[0]) <= snap {
            if kept[k].v_src.is_some() || kept[k].v_tgt.is_some() {
                return Err(coincident());
            }
            out_src.pop();
            out_tgt.pop();
            kept.pop();
        }
    }
    let salient = kept
        .iter()
        .enumerate()
        .filter(|(_, e)| e.associated)
        .map(|(i, _)| i)
        .collect();
    Ok((out_src, out_tgt, salient))
}

fn coincident() -> Error {
    Error::input(
        crate::error::Drawings::Both,
        "corresponding parts of the curve differ so much in length that vertices coincide",
    )
    .with_hint("add anchors so that matching parts of the curves correspond")
}

/// Appends the entries strictly inside one span: source vertices `a0..a1` at arc lengths
/// `s0..s1`, target vertices `b0..b1` at `t0..t1`.
fn span(
    entries: &mut Vec<Entry>,
    src: &Polyline,
    tgt: &Polyline,
    (a0, a1, s0, s1): (usize, usize, f64, f64),
    (b0, b1, t0, t1): (usize, usize, f64, f64),
    merge: f64,
) {
    let (ls, lt) = (s1 - s0, t1 - t0);
    // (u, source vertex, target vertex); sorted by u, source first on ties.
    let mut marks: Vec<(f64, Option<usize>, Option<usize>)> = Vec::new();
    marks.extend((a0 + 1..a1).map(|a| ((src.s(a) - s0) / ls, Some(a), None)));
    marks.extend((b0 + 1..b1).map(|b| ((tgt.s(b) - t0) / lt, None, Some(b))));
    marks.sort_by(|x, y| x.0.total_cmp(&y.0).then(y.1.is_some().cmp(&x.1.is_some())));
    let reach = merge / ls.max(lt);
    let mut k = 0;
    while k < marks.len() {
        let (u, va, vb) = marks[k];
        if k + 1 < marks.len() {
            let (u2, va2, vb2) = marks[k + 1];
            let opposite = va.is_some() != va2.is_some();
            if opposite && u2 - u < reach {
                let a = va.or(va2).unwrap_or(a0);
                let b = vb.or(vb2).unwrap_or(b0);
                entries.push(Entry {
                    s_src: src.s(a),
                    s_tgt: tgt.s(b),
                    v_src: Some(a),
                    v_tgt: Some(b),
                    associated: false,
                });
                k += 2;
                continue;
            }
        }
        entries.push(Entry {
            s_src: va.map_or(s0 + u * ls, |a| src.s(a)),
            s_tgt: vb.map_or(t0 + u * lt, |b| tgt.s(b)),
            v_src: va,
            v_tgt: vb,
            associated: false,
        });
        k += 1;
    }
}

/// Evens out constructed positions on one side where two consecutive ones would come closer than
/// `gap`: between two consecutive original vertices of that side (which bound one straight edge
/// of it), the constructed positions are spread uniformly when any gap there is too small. Such
/// crowding only happens where a short part of one curve corresponds to a long part of the other.
fn spread(
    entries: &mut [Entry],
    closed: bool,
    length: f64,
    gap: f64,
    get: impl Fn(&Entry) -> (f64, bool),
    mut set: impl FnMut(&mut Entry, f64),
) {
    let count = entries.len();
    // Entry 0 is an associated pair, original on both sides; a closed curve's last run ends at
    // its copy one length further on (index `count`).
    let at = |entries: &[Entry], i: usize| {
        if i == count {
            length + get(&entries[0]).0
        } else {
            get(&entries[i]).0
        }
    };
    let mut fixed: Vec<usize> = (0..count).filter(|&i| get(&entries[i]).1).collect();
    if closed {
        fixed.push(count);
    }
    for w in fixed.windows(2) {
        let (f0, f1) = (w[0], w[1]);
        let k = f1 - f0 - 1;
        let (x0, x1) = (at(entries, f0), at(entries, f1));
        if k == 0 || (x1 - x0) / ((k + 1) as f64) < gap {
            continue;
        }
        if (f0..f1).all(|i| at(entries, i + 1) - at(entries, i) >= gap) {
            continue;
        }
        for r in 1..=k {
            set(
                &mut entries[f0 + r],
                x0 + (x1 - x0) * r as f64 / (k + 1) as f64,
            );
        }
    }
}

/// Splits every edge longer than `max_edge` on either side into equal parts (equal in arc length
/// on each side, so the new vertices lie on the original edges).
fn split_long_edges(
    entries: &[Entry],
    closed: bool,
    max_edge: f64,
    len_src: f64,
    len_tgt: f64,
) -> Result<Vec<Entry>> {
    let count = entries.len();
    let mut out = Vec::with_capacity(count);
    let edges = if closed { count } else { count - 1 };
    for i in 0..count {
        let e = entries[i];
        out.push(e);
        if i >= edges {
            continue;
        }
        let f = entries[(i + 1) % count];
        let (fs, ft) = if i + 1 == count {
            (len_src + f.s_src, len_tgt + f.s_tgt)
        } else {
            (f.s_src, f.s_tgt)
        };
        let (ds, dt) = (fs - e.s_src, ft - e.s_tgt);
        let parts = (ds.max(dt) / max_edge).ceil();
        if !parts.is_finite() || out.len() as f64 + parts > MAX_VERTICES as f64 {
            return Err(Error::input(
                crate::error::Drawings::Both,
                format!("a curve would need more than {MAX_VERTICES} vertices at this density"),
            )
            .with_hint("lower the density"));
        }
        let parts = parts as usize;
        for k in 1..parts {
            let t = k as f64 / parts as f64;
            out.push(Entry {
                s_src: e.s_src + ds * t,
                s_tgt: e.s_tgt + dt * t,
                v_src: None,
                v_tgt: None,
                associated: false,
            });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn open_spans_keep_every_vertex_of_both_curves() {
        let src = Polyline::new(vec![p(0., 0.), p(1., 0.), p(4., 0.)], false);
        let tgt = Polyline::new(vec![p(0., 0.), p(0., 2.), p(0., 3.), p(0., 4.)], false);
        let (a, b, sal) = distribute(&src, &tgt, &[(0, 0), (2, 3)], 10.0, 1e-6, 1e-9).unwrap();
        assert_eq!(a.len(), b.len());
        assert_eq!(sal, vec![0, a.len() - 1]);
        for q in src.points() {
            assert!(a.contains(q));
        }
        for q in tgt.points() {
            assert!(b.contains(q));
        }
        // Source vertex 1 at u = 1/4 gets the target point at a quarter of the length.
        assert!(b.contains(&p(0., 1.)));
        assert!(a.contains(&p(2., 0.)) && a.contains(&p(3., 0.)));
    }

    #[test]
    fn close_vertices_merge_and_long_edges_split() {
        let src = Polyline::new(vec![p(0., 0.), p(1., 0.), p(2., 0.)], false);
        let tgt = Polyline::new(vec![p(0., 0.), p(1.01, 0.), p(2., 0.)], false);
        let (a, b, _) = distribute(&src, &tgt, &[(0, 0), (2, 2)], 0.25, 0.05, 1e-9).unwrap();
        assert!(a.contains(&p(1., 0.)) && b.contains(&p(1.01, 0.)));
        let k = a.iter().position(|&q| q == p(1., 0.)).unwrap();
        assert_eq!(b[k], p(1.01, 0.));
        for w in a.windows(2).chain(b.windows(2)) {
            assert!(w[0].distance(w[1]) <= 0.25 + 1e-12);
        }
    }

    #[test]
    fn closed_curves_wrap_and_do_not_repeat_the_start() {
        let sq = Polyline::new(vec![p(0., 0.), p(1., 0.), p(1., 1.), p(0., 1.)], true);
        let (a, b, sal) = distribute(&sq, &sq, &[(0, 0), (2, 2)], 0.5, 1e-3, 1e-9).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.len(), 8);
        assert_eq!(sal, vec![0, 4]);
        assert!(a[7].distance(a[0]) > 0.1);
    }
}
