"use strict";

const test = require("node:test");
const assert = require("node:assert/strict");
const M = require("../lib/measures.js");
const { render } = require("../lib/render.js");

// A w×h RGBA buffer over white, with `paint(x, y)` giving a grey level (0…255) or null for white.
function buffer(w, h, paint) {
  const px = new Uint8Array(4 * w * h);
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const v = paint(x, y);
      const g = v === null ? 255 : v;
      px.set([g, g, g, 255], 4 * (y * w + x));
    }
  }
  return px;
}

const inSquare = (x, y, x0, x1) => x >= x0 && x < x1 && y >= x0 && y < x1;

test("ghost: a crisp black square is 0, with or without an antialiased rim", () => {
  const sharp = buffer(100, 100, (x, y) => (inSquare(x, y, 30, 70) ? 0 : null));
  assert.equal(M.ghostOfPixels(sharp, 100, 100).ghost, 0);
  // A one-pixel grey rim between black and white: every rim pixel sees both, so none counts.
  const rimmed = buffer(100, 100, (x, y) => (inSquare(x, y, 30, 70) ? 0 : inSquare(x, y, 29, 71) ? 128 : null));
  const g = M.ghostOfPixels(rimmed, 100, 100);
  assert.equal(g.ghost, 0);
  assert.ok(g.inked > g.counted);
});

test("ghost: a half-transparent square is about 1", () => {
  const half = buffer(100, 100, (x, y) => (inSquare(x, y, 30, 70) ? 128 : null));
  assert.equal(M.ghostOfPixels(half, 100, 100).ghost, 1);
  // A soft (antialiased) rim of a grey square has no black neighbour, so it still counts (as grey or faint).
  const soft = buffer(100, 100, (x, y) => (inSquare(x, y, 30, 70) ? 128 : inSquare(x, y, 29, 71) ? 200 : null));
  assert.equal(M.ghostOfPixels(soft, 100, 100).ghost, 1);
});

test("ghost: rendered with resvg, black square ≈ 0, fill-opacity 0.5 ≈ 1, a 50/50 mix in between", () => {
  const svg = (body) => `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24">${body}</svg>`;
  const g = (body) => {
    const img = render(svg(body), 240);
    return M.ghostOfPixels(img.pixels, img.width, img.height).ghost;
  };
  assert.ok(g('<rect x="4.3" y="4.3" width="15.1" height="15.1"/>') < 0.01);
  assert.ok(g('<rect x="4.3" y="4.3" width="15.1" height="15.1" fill-opacity="0.5"/>') > 0.98);
  const mixed = g('<rect x="2" y="2" width="8" height="20"/><rect x="14" y="2" width="8" height="20" fill-opacity="0.5"/>');
  assert.ok(mixed > 0.45 && mixed < 0.55, `mixed ${mixed}`);
});

test("ink and area ratios", () => {
  const a = buffer(10, 10, (x, y) => (x < 5 ? 0 : null));
  assert.equal(M.inkOfPixels(a, 10, 10), 50);
  const r = M.areaRatios([100, 50, 100], [0, 0.5, 1], 1000);
  assert.equal(r.min, 0.5);
  assert.equal(r.max, 1);
  const lin = M.areaRatios([100, 150, 200], [0, 0.5, 1], 1000);
  assert.equal(lin.min, 1);
  assert.equal(lin.max, 1);
  assert.equal(M.areaRatios([0, 0, 0], [0, 0.5, 1], 1000).min, null);
});

const square = (x0, y0, s) => ({ points: [[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]], closed: true });

test("self-crossing: a figure eight crosses itself, a square does not", () => {
  const eight = { points: [[0, 0], [2, 2], [2, 0], [0, 2]], closed: true };
  assert.deepEqual(M.crossings([eight]), { any: true, self: true, other: false });
  assert.deepEqual(M.crossings([square(0, 0, 1)]), { any: false, self: false, other: false });
  // Open polylines: a "Z" does not cross itself, a loop does.
  assert.equal(M.crossings([{ points: [[0, 0], [2, 0], [0, 2], [2, 2]], closed: false }]).any, false);
  assert.equal(M.crossings([{ points: [[0, 0], [2, 2], [2, 0], [0, 2]], closed: false }]).self, true);
});

test("self-crossing: two overlapping rings cross each other; touching or nested ones do not", () => {
  assert.deepEqual(M.crossings([square(0, 0, 2), square(1, 1, 2)]), { any: true, self: false, other: true });
  assert.equal(M.crossings([square(0, 0, 1), square(1, 0, 1)]).any, false); // sharing an edge
  assert.equal(M.crossings([square(0, 0, 4), square(1, 1, 1)]).any, false); // a hole
  assert.equal(M.crossings([square(0, 0, 1), square(1, 1, 1)]).any, false); // touching at a corner
});

test("Hausdorff: shifted squares are the shift apart, both ways", () => {
  const a = [square(0, 0, 10)];
  assert.equal(M.hausdorff(a, a), 0);
  assert.ok(Math.abs(M.hausdorff(a, [square(0.5, 0, 10)]) - 0.5) < 1e-12);
  assert.ok(Math.abs(M.hausdorff(a, [square(3, 4, 10)]) - 5) < 1e-12);
  // Vertex-to-polyline: a square cut at its edge midpoints is the same outline (distance 0).
  const dense = { points: [[0, 0], [5, 0], [10, 0], [10, 5], [10, 10], [5, 10], [0, 10], [0, 5]], closed: true };
  assert.equal(M.hausdorff(a, [dense]), 0);
  // One-sided: a small square inside is 0 from the big one only one way.
  assert.equal(M.hausdorff([square(0, 0, 10)], []), Infinity);
  assert.ok(M.directedHausdorff([square(0, 0, 10)], [square(0, 0, 10), square(20, 0, 1)]) === 0);
  assert.ok(M.directedHausdorff([square(0, 0, 10), square(20, 0, 1)], [square(0, 0, 10)]) === 11); // the far corner (21, 1)
});

test("flips: counted against the mesh's own orientation, degenerate triangles count", () => {
  const tris = [[0, 1, 2], [0, 2, 3]];
  const f0 = [[0, 0], [1, 0], [1, 1], [0, 1]];
  const flipped = [[0, 0], [1, 0], [1, 1], [2, 0.5]]; // vertex 3 moved across the diagonal
  const flat = [[0, 0], [1, 0], [2, 0], [0, 1]]; // triangle 0 has zero area
  assert.equal(M.countFlips(tris, [f0, f0]).flipped, 0);
  assert.equal(M.countFlips(tris, [f0, flipped]).flipped, 1);
  assert.equal(M.countFlips(tris, [f0, flat]).flipped, 1);
  // Mirrored (y down) mesh: same answer.
  const m = (v) => v.map(([x, y]) => [x, -y]);
  assert.equal(M.countFlips(tris, [m(f0), m(flipped)]).flipped, 1);
});

test("median and nearest-rank percentile", () => {
  assert.equal(M.median([3, 1, 2]), 2);
  assert.equal(M.median([4, 1, 2, 3]), 2.5);
  assert.equal(M.median([1, Infinity]), Infinity);
  assert.equal(M.percentile([1, 2, 3, 4, 5, 6, 7, 8, 9, 10], 0.9), 9);
  assert.equal(M.percentile([5], 0.99), 5);
  assert.equal(M.median([]), null);
});
