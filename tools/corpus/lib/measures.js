// The measures, computed by the same code for every tool (README.md, "Measures").
//
// Pixel measures work on an RGBA buffer rendered over white (alpha is composited over white anyway);
// geometric measures on rings { points: [[x, y], …], closed } as lib/svg.js reads them. Closed rings do
// not repeat their first point.
"use strict";

// ------------------------------------------------------------------------------------------ pixels

/** Rec. 709 luma of the (gamma-encoded) sRGB values, 0…255, of every pixel, composited over white. */
function lumaOf(rgba, w, h) {
  const n = w * h;
  const L = new Float32Array(n);
  for (let i = 0; i < n; i++) {
    const a = rgba[4 * i + 3] / 255;
    const r = rgba[4 * i] * a + 255 * (1 - a);
    const g = rgba[4 * i + 1] * a + 255 * (1 - a);
    const b = rgba[4 * i + 2] * a + 255 * (1 - a);
    L[i] = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  }
  return L;
}

const INKED = 250; // luma below this is ink
const DARK = 40; // below: solid ink
const LIGHT = 215; // above: (nearly) paper

/**
 * Ghost: among inked pixels (luma < 250), the share with luma in [40, 215] ("grey"), leaving out — from
 * both counts — every pixel whose 3×3 neighbourhood (itself included, clipped at the image border) holds
 * both a pixel with luma < 40 and one with luma > 215 (an antialiased edge between ink and paper).
 * Returns { ghost, inked, counted, grey }; ghost is 0 when no pixel is counted.
 */
function ghostOfLuma(L, w, h) {
  let counted = 0, grey = 0, inked = 0;
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const v = L[y * w + x];
      if (!(v < INKED)) continue;
      inked++;
      let dark = false, light = false;
      for (let dy = -1; dy <= 1 && !(dark && light); dy++) {
        const yy = y + dy;
        if (yy < 0 || yy >= h) continue;
        for (let dx = -1; dx <= 1; dx++) {
          const xx = x + dx;
          if (xx < 0 || xx >= w) continue;
          const u = L[yy * w + xx];
          if (u < DARK) dark = true;
          else if (u > LIGHT) light = true;
        }
      }
      if (dark && light) continue;
      counted++;
      if (v >= DARK && v <= LIGHT) grey++;
    }
  }
  return { ghost: counted ? grey / counted : 0, inked, counted, grey };
}

function ghostOfPixels(rgba, w, h) {
  return ghostOfLuma(lumaOf(rgba, w, h), w, h);
}

/** Ink: Σ over pixels of (255 − luma) / 255. */
function inkOfPixels(rgba, w, h) {
  const L = lumaOf(rgba, w, h);
  let s = 0;
  for (let i = 0; i < L.length; i++) s += (255 - L[i]) / 255;
  return s;
}

/**
 * Area ratios: ink(t_i) / ((1 − t_i)·ink(0) + t_i·ink(1)) for every frame, ink(0) and ink(1) being the
 * tool's own first and last frames. Frames whose blend is below 1e-9 of the pixel count are skipped;
 * null when both ends have no ink. Returns { min, max, ratios }.
 */
function areaRatios(inks, ts, pixels) {
  const a0 = inks[0], a1 = inks[inks.length - 1];
  const tiny = 1e-9 * pixels;
  if (!(Math.max(a0, a1) > tiny)) return { min: null, max: null, ratios: [] };
  let min = null, max = null;
  const ratios = [];
  inks.forEach((ink, i) => {
    const t = ts[i];
    const blend = (1 - t) * a0 + t * a1;
    if (blend <= tiny) {
      ratios.push(null);
      return;
    }
    const r = ink / blend;
    ratios.push(r);
    min = min === null ? r : Math.min(min, r);
    max = max === null ? r : Math.max(max, r);
  });
  return { min, max, ratios };
}

// ------------------------------------------------------------------------------------------ geometry

function orient(a, b, c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Sign of orient(a, b, c) with a tolerance relative to the lengths involved, so that a vertex lying on an
// edge up to rounding counts as touching (0), not as crossing.
function side(a, b, c, scale) {
  const o = orient(a, b, c);
  return Math.abs(o) <= 1e-10 * scale ? 0 : Math.sign(o);
}

/** True when segments ab and cd cross properly: each one's ends lie strictly on both sides of the other. */
function segmentsCross(a, b, c, d) {
  const scale = Math.hypot(b[0] - a[0], b[1] - a[1]) * Math.hypot(d[0] - c[0], d[1] - c[1]);
  if (scale === 0) return false;
  return side(a, b, c, scale) * side(a, b, d, scale) < 0 && side(c, d, a, scale) * side(c, d, b, scale) < 0;
}

/**
 * Whether any ring crosses itself or another ring: a proper crossing (segmentsCross) between two edges
 * that are not consecutive edges of one ring (those share a vertex). Sort and sweep on the edges' x
 * extents. Returns { any, self, other }: any crossing, a crossing within one ring, between two rings.
 * With `stopAtFirst`, returns as soon as one crossing of any kind is found (self/other then tell which).
 */
function crossings(rings, stopAtFirst = false) {
  const edges = [];
  rings.forEach((r, k) => {
    const p = r.points;
    const n = p.length;
    const m = r.closed ? n : n - 1;
    if (n < 2) return;
    for (let i = 0; i < m; i++) {
      const a = p[i], b = p[(i + 1) % n];
      if (a[0] === b[0] && a[1] === b[1]) continue;
      edges.push({ k, i, m, closed: r.closed, a, b, x0: Math.min(a[0], b[0]), x1: Math.max(a[0], b[0]), y0: Math.min(a[1], b[1]), y1: Math.max(a[1], b[1]) });
    }
  });
  edges.sort((e, f) => e.x0 - f.x0);
  let active = [];
  let self = false, other = false;
  for (const e of edges) {
    let w = 0;
    for (const f of active) if (f.x1 >= e.x0) active[w++] = f;
    active.length = w;
    for (const f of active) {
      if (f.y1 < e.y0 || e.y1 < f.y0) continue;
      const same = f.k === e.k;
      if (same) {
        if (self) continue;
        const d = Math.abs(e.i - f.i);
        if (d <= 1 || (e.closed && d === e.m - 1)) continue;
      } else if (other) continue;
      if (segmentsCross(e.a, e.b, f.a, f.b)) {
        if (same) self = true;
        else other = true;
        if (stopAtFirst || (self && other)) return { any: true, self, other };
      }
    }
    active.push(e);
  }
  return { any: self || other, self, other };
}

/** Distance from point p to segment ab. */
function pointSegmentDistance(p, a, b) {
  const dx = b[0] - a[0], dy = b[1] - a[1];
  const l2 = dx * dx + dy * dy;
  let u = l2 === 0 ? 0 : ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2;
  u = Math.max(0, Math.min(1, u));
  return Math.hypot(p[0] - (a[0] + u * dx), p[1] - (a[1] + u * dy));
}

function segmentsOf(rings) {
  const segs = [];
  for (const r of rings) {
    const n = r.points.length;
    if (n === 1) segs.push([r.points[0], r.points[0]]);
    const m = r.closed ? n : n - 1;
    for (let i = 0; i < m; i++) segs.push([r.points[i], r.points[(i + 1) % n]]);
  }
  return segs;
}

/** Largest distance from a vertex of `from` to the nearest edge (polyline) of `to`. */
function directedHausdorff(from, to) {
  const segs = segmentsOf(to);
  if (segs.length === 0) return from.some((r) => r.points.length) ? Infinity : 0;
  // Bounding boxes of runs of 16 segments, to skip runs that cannot beat the best distance so far.
  const B = 16;
  const boxes = [];
  for (let s = 0; s < segs.length; s += B) {
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let k = s; k < Math.min(segs.length, s + B); k++) {
      for (const q of segs[k]) {
        x0 = Math.min(x0, q[0]); y0 = Math.min(y0, q[1]); x1 = Math.max(x1, q[0]); y1 = Math.max(y1, q[1]);
      }
    }
    boxes.push([s, x0, y0, x1, y1]);
  }
  let worst = 0;
  for (const r of from) {
    for (const p of r.points) {
      let best = Infinity;
      for (const [s, x0, y0, x1, y1] of boxes) {
        const bx = Math.max(x0 - p[0], 0, p[0] - x1), by = Math.max(y0 - p[1], 0, p[1] - y1);
        if (Math.hypot(bx, by) >= best) continue;
        for (let k = s; k < Math.min(segs.length, s + B); k++) {
          const d = pointSegmentDistance(p, segs[k][0], segs[k][1]);
          if (d < best) best = d;
        }
        if (best <= worst) break; // this vertex cannot raise the maximum
      }
      if (best > worst) worst = best;
    }
  }
  return worst;
}

/** Symmetric Hausdorff distance, vertex-to-polyline both ways (0 for two empty sets, ∞ when one is empty). */
function hausdorff(a, b) {
  return Math.max(directedHausdorff(a, b), directedHausdorff(b, a));
}

// ------------------------------------------------------------------------------------------ meshes

/** Twice the signed area of triangle abc (shoelace; positive when counter-clockwise with y up). */
function triangleArea2(a, b, c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
}

/**
 * Flips: triangles whose signed area is ≤ 0 in at least one frame, the sign taken relative to the
 * orientation of the mesh (the sign of its total signed area in the first frame), so that the result
 * does not depend on whether y points up or down. Returns { flipped, triangles, frames, orientation }.
 */
function countFlips(triangles, framesVertices) {
  if (!triangles.length || !framesVertices.length) return { flipped: 0, triangles: triangles.length, frames: framesVertices.length, orientation: 0 };
  const v0 = framesVertices[0];
  let total = 0;
  for (const [a, b, c] of triangles) total += triangleArea2(v0[a], v0[b], v0[c]);
  const s = total >= 0 ? 1 : -1;
  const bad = new Uint8Array(triangles.length);
  for (const v of framesVertices) {
    triangles.forEach(([a, b, c], i) => {
      if (!bad[i] && s * triangleArea2(v[a], v[b], v[c]) <= 0) bad[i] = 1;
    });
  }
  let flipped = 0;
  for (const x of bad) flipped += x;
  return { flipped, triangles: triangles.length, frames: framesVertices.length, orientation: s };
}

// ------------------------------------------------------------------------------------------ statistics

/** Median (mean of the two middle values for an even count); null for no values. ∞ sorts last. */
function median(xs) {
  const v = xs.filter((x) => x !== null && x !== undefined && !Number.isNaN(x)).sort((a, b) => a - b);
  if (!v.length) return null;
  const h = v.length >> 1;
  return v.length % 2 ? v[h] : v[h - 1] === v[h] ? v[h] : (v[h - 1] + v[h]) / 2;
}

/** Nearest-rank percentile: the ⌈q·n⌉-th smallest value; null for no values. */
function percentile(xs, q) {
  const v = xs.filter((x) => x !== null && x !== undefined && !Number.isNaN(x)).sort((a, b) => a - b);
  if (!v.length) return null;
  return v[Math.min(v.length, Math.max(1, Math.ceil(q * v.length))) - 1];
}

module.exports = {
  lumaOf, ghostOfLuma, ghostOfPixels, inkOfPixels, areaRatios,
  segmentsCross, crossings, pointSegmentDistance, directedHausdorff, hausdorff,
  triangleArea2, countFlips, median, percentile, THRESHOLDS: { INKED, DARK, LIGHT },
};
