// Metrics computed identically for every morphing tool from the polygons of its frames.
//
// A contour is { points: [[x, y], ...], closed: bool }; a frame is { t, contours: [contour, ...] }.
// Closed contours never repeat their first point at the end.
"use strict";

/** Signed area of a closed polygon (shoelace formula); positive when counter-clockwise in y-up axes. */
function signedArea(points) {
  let s = 0;
  for (let i = 0, n = points.length; i < n; i++) {
    const [x0, y0] = points[i];
    const [x1, y1] = points[(i + 1) % n];
    s += x0 * y1 - x1 * y0;
  }
  return s / 2;
}

/** Total absolute area of the closed contours of a frame (open contours enclose nothing). */
function totalArea(contours) {
  let a = 0;
  for (const c of contours) if (c.closed && c.points.length >= 3) a += Math.abs(signedArea(c.points));
  return a;
}

function orient(a, b, c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Sign of orient(a, b, c) with a tolerance relative to the lengths involved, so that a vertex lying on
// an edge up to rounding counts as touching (0), not as crossing.
function side(a, b, c, scale) {
  const o = orient(a, b, c);
  return Math.abs(o) <= 1e-10 * scale ? 0 : Math.sign(o);
}

/** True when segments ab and cd cross properly: each one's ends lie strictly on both sides of the other. */
function segmentsCross(a, b, c, d) {
  const lab = Math.hypot(b[0] - a[0], b[1] - a[1]);
  const lcd = Math.hypot(d[0] - c[0], d[1] - c[1]);
  const scale = lab * lcd;
  if (scale === 0) return false;
  return side(a, b, c, scale) * side(a, b, d, scale) < 0 && side(c, d, a, scale) * side(c, d, b, scale) < 0;
}

/**
 * True when a contour crosses itself: a proper intersection between two non-adjacent edges. Edges are
 * swept in order of their left end (sort and sweep on x intervals), so typical contours cost far less
 * than the O(n²) all-pairs check.
 */
function selfCrosses(points, closed) {
  const n = points.length;
  const m = closed ? n : n - 1;
  if (m < 3) return false;
  const edges = [];
  for (let i = 0; i < m; i++) {
    const a = points[i];
    const b = points[(i + 1) % n];
    edges.push({ i, a, b, x0: Math.min(a[0], b[0]), x1: Math.max(a[0], b[0]), y0: Math.min(a[1], b[1]), y1: Math.max(a[1], b[1]) });
  }
  edges.sort((e, f) => e.x0 - f.x0 || e.i - f.i);
  let active = [];
  for (const e of edges) {
    active = active.filter((f) => f.x1 >= e.x0);
    for (const f of active) {
      const d = Math.abs(e.i - f.i);
      if (d <= 1 || (closed && d === m - 1)) continue; // adjacent edges share a vertex
      if (f.y1 < e.y0 || e.y1 < f.y0) continue;
      if (segmentsCross(e.a, e.b, f.a, f.b)) return true;
    }
    active.push(e);
  }
  return false;
}

/** Distance from point p to segment ab. */
function pointSegmentDistance(p, a, b) {
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const l2 = dx * dx + dy * dy;
  let u = l2 === 0 ? 0 : ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2;
  u = Math.max(0, Math.min(1, u));
  return Math.hypot(p[0] - (a[0] + u * dx), p[1] - (a[1] + u * dy));
}

function segmentsOf(contours) {
  const segs = [];
  for (const c of contours) {
    const n = c.points.length;
    if (n === 1) segs.push([c.points[0], c.points[0]]);
    const m = c.closed ? n : n - 1;
    for (let i = 0; i < m; i++) segs.push([c.points[i], c.points[(i + 1) % n]]);
  }
  return segs;
}

/** Largest distance from a vertex of `from` to the nearest edge of `to` (one-sided Hausdorff on vertices). */
function oneSidedDistance(from, to) {
  const segs = segmentsOf(to);
  if (segs.length === 0) return Infinity;
  let worst = 0;
  for (const c of from) {
    for (const p of c.points) {
      let best = Infinity;
      for (const [a, b] of segs) {
        const d = pointSegmentDistance(p, a, b);
        if (d < best) {
          best = d;
          if (best <= worst) break; // cannot raise the maximum any more
        }
      }
      if (best > worst) worst = best;
    }
  }
  return worst;
}

/**
 * Symmetric distance between two sets of contours: the larger of the two one-sided vertex-to-edge
 * distances. Zero when every vertex of each set lies on the other's outline, so a shape cut into
 * pieces along its own vertices (flubber's separate/combine) still counts as exact.
 */
function outlineDistance(a, b) {
  if (a.length === 0 && b.length === 0) return 0;
  return Math.max(oneSidedDistance(a, b), oneSidedDistance(b, a));
}

/**
 * Per-morph statistics over a frame sequence:
 * - crossingShare: share of frames in which any contour crosses itself;
 * - areaMin / areaMax: min / max over frames of totalArea(t) / ((1 − t)·A0 + t·A1), A0 and A1 being the
 *   totals of the first and last frames (null when both ends enclose (almost) no area, e.g. line icons);
 *   frames whose blend is below 1e-9 of `size`² are skipped.
 */
function morphStats(frames, size) {
  let crossing = 0;
  for (const f of frames) if (f.contours.some((c) => selfCrosses(c.points, c.closed))) crossing++;
  const areas = frames.map((f) => totalArea(f.contours));
  const a0 = areas[0];
  const a1 = areas[areas.length - 1];
  const tiny = 1e-9 * size * size;
  let areaMin = null;
  let areaMax = null;
  if (Math.max(a0, a1) > 1e-6 * size * size) {
    frames.forEach((f, i) => {
      const blend = (1 - f.t) * a0 + f.t * a1;
      if (blend <= tiny) return;
      const r = areas[i] / blend;
      areaMin = areaMin === null ? r : Math.min(areaMin, r);
      areaMax = areaMax === null ? r : Math.max(areaMax, r);
    });
  }
  return { frames: frames.length, crossingFrames: crossing, crossingShare: frames.length ? crossing / frames.length : 0, areaMin, areaMax };
}

/** End error: the larger outline distance at t = 0 (first frame vs source) and t = 1 (last vs target), over `size`. */
function endError(frames, sourceContours, targetContours, size) {
  const e0 = outlineDistance(frames[0].contours, sourceContours);
  const e1 = outlineDistance(frames[frames.length - 1].contours, targetContours);
  return Math.max(e0, e1) / size;
}

module.exports = { signedArea, totalArea, segmentsCross, selfCrosses, pointSegmentDistance, outlineDistance, morphStats, endError };
