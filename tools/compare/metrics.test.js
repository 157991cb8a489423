"use strict";
const test = require("node:test");
const assert = require("node:assert/strict");
const m = require("./metrics.js");

const square = [[0, 0], [1, 0], [1, 1], [0, 1]];
const figureEight = [[0, 0], [1, 1], [1, 0], [0, 1]]; // bow-tie: edges 0 and 2 cross
const closed = (points) => ({ points, closed: true });

test("area of the unit square is 1, signed by orientation", () => {
  assert.equal(m.signedArea(square), 1);
  assert.equal(m.signedArea([...square].reverse()), -1);
  assert.equal(m.totalArea([closed(square), closed([...square].reverse())]), 2);
  assert.equal(m.totalArea([{ points: square, closed: false }]), 0);
});

test("a figure-eight crosses itself, a square and a concave L do not", () => {
  assert.equal(m.selfCrosses(figureEight, true), true);
  assert.equal(m.selfCrosses(square, true), false);
  const ell = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]];
  assert.equal(m.selfCrosses(ell, true), false);
});

test("open polylines: a zig-zag does not cross, a loop does; the missing closing edge is not tested", () => {
  assert.equal(m.selfCrosses([[0, 0], [1, 1], [2, 0], [3, 1]], false), false);
  assert.equal(m.selfCrosses([[0, 0], [2, 0], [2, 1], [1, 1], [1, -1]], false), true);
  // Closed, this is a bow-tie (the closing edge crosses edge 1); open it is a Z shape.
  const zed = [[0, 0], [1, 0], [0, 1], [1, 1]];
  assert.equal(m.selfCrosses(zed, true), true);
  assert.equal(m.selfCrosses(zed, false), false);
});

test("touching at a vertex or repeated points is not a proper crossing", () => {
  assert.equal(m.segmentsCross([0, 0], [2, 0], [1, 0], [1, 1]), false); // T-junction
  assert.equal(m.segmentsCross([0, 0], [2, 0], [1, -1], [1, 1]), true);
  assert.equal(m.selfCrosses([[0, 0], [1, 0], [1, 0], [1, 1], [0, 1]], true), false);
});

test("a large simple polygon (circle) does not cross itself; one with a twisted pair does", () => {
  const n = 2000;
  const circle = Array.from({ length: n }, (_, i) => [Math.cos((2 * Math.PI * i) / n), Math.sin((2 * Math.PI * i) / n)]);
  assert.equal(m.selfCrosses(circle, true), false);
  const twisted = circle.slice();
  [twisted[10], twisted[11]] = [twisted[11], twisted[10]];
  assert.equal(m.selfCrosses(twisted, true), true);
});

test("outline distance: zero for the same outline cut differently, the offset otherwise", () => {
  const a = [closed(square)];
  const halves = [closed([[0, 0], [1, 0], [1, 1]]), closed([[0, 0], [1, 1], [0, 1]])];
  assert.equal(m.outlineDistance(halves, a), 0);
  const shifted = [closed(square.map(([x, y]) => [x + 0.25, y]))];
  assert.ok(Math.abs(m.outlineDistance(shifted, a) - 0.25) < 1e-12);
  assert.equal(m.pointSegmentDistance([0, 1], [0, 0], [2, 0]), 1);
  assert.equal(m.pointSegmentDistance([3, 0], [0, 0], [2, 0]), 1);
});

test("morph stats: a linear scale of a square keeps the area on the blend only at the ends", () => {
  const frames = [];
  for (let i = 0; i < 11; i++) {
    const t = i / 10;
    const s = 1 + t; // side 1 → 2: area 1 → 4, blend 1 + 3t, actual (1 + t)² ≤ blend
    frames.push({ t, contours: [closed(square.map(([x, y]) => [x * s, y * s]))] });
  }
  const st = m.morphStats(frames, 2);
  assert.equal(st.crossingShare, 0);
  assert.ok(Math.abs(st.areaMin - 1.69 / 1.9) < 1e-12); // (1+t)²/(1+3t) is least at t = 1/3; sampled at 0.3
  assert.ok(Math.abs(st.areaMax - 1) < 1e-12);
  frames[5] = { t: 0.5, contours: [closed(figureEight)] };
  assert.equal(m.morphStats(frames, 2).crossingFrames, 1);
  const lines = [{ t: 0, contours: [{ points: [[0, 0], [1, 0]], closed: false }] }, { t: 1, contours: [{ points: [[0, 0], [0, 1]], closed: false }] }];
  assert.equal(m.morphStats(lines, 1).areaMin, null);
});

test("end error is relative to the icon size", () => {
  const frames = [{ t: 0, contours: [closed(square)] }, { t: 1, contours: [closed(square.map(([x, y]) => [x + 0.5, y]))] }];
  assert.equal(m.endError(frames, [closed(square)], [closed(square)], 10), 0.05);
});
