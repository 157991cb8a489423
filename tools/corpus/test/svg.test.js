"use strict";

const test = require("node:test");
const assert = require("node:assert/strict");
const { readSvgText, isSingleFilledOutline } = require("../lib/svg.js");
const { drawPairs, normalise } = require("../draw.js");
const { mulberry32 } = require("../lib/prng.js");

const doc = (body, attrs = 'viewBox="0 0 24 24"') => `<svg xmlns="http://www.w3.org/2000/svg" ${attrs}>${body}</svg>`;

test("rings: filled subpaths are closed rings, stroked ones keep their closedness", () => {
  const ic = readSvgText(doc('<path d="M2 2H10V10H2Z M12 12h4v4"/><path d="M0 20H20" fill="none" stroke="#000"/>'));
  assert.equal(ic.kind, "mixed");
  assert.deepEqual(ic.rings.map((r) => [r.closed, r.points.length]), [[true, 4], [true, 3], [false, 2]]);
});

test("invisible and hidden elements draw nothing; tabler's frame is skipped", () => {
  const ic = readSvgText(doc('<path stroke="none" d="M0 0h24v24H0z" fill="none"/><g display="none"><path d="M1 1H5V5Z"/></g><path d="M1 1H5V5Z" fill-opacity="0"/><defs><path d="M1 1H9V9Z"/></defs><circle cx="12" cy="12" r="5"/>'));
  assert.equal(ic.rings.length, 1);
  assert.ok(isSingleFilledOutline(ic));
});

test("transforms of the element and its ancestors apply, stroke width scales", () => {
  const ic = readSvgText(doc('<g transform="translate(10 0) scale(2)"><path d="M0 0L1 0" fill="none" stroke="#000" stroke-width="1.5" transform="rotate(90)"/></g>'));
  const [a, b] = ic.rings[0].points;
  assert.ok(Math.hypot(a[0] - 10, a[1]) < 1e-9 && Math.hypot(b[0] - 10, b[1] - 2) < 1e-9);
  assert.ok(Math.abs(ic.stroke.width - 3) < 1e-12);
});

test("crmorph's two-layer blend: each layer weighted, the off-view copies dropped", () => {
  const svg = doc(
    '<defs><clipPath id="v"><rect x="0" y="0" width="24" height="24"/></clipPath>' +
      '<filter id="b" filterUnits="userSpaceOnUse" x="0" y="0" width="48" height="24"><feOffset in="SourceGraphic" dx="-24" dy="0" result="t"/>' +
      '<feComposite in="SourceGraphic" in2="t" operator="arithmetic" k1="0" k2="0.75" k3="0.25" k4="0" x="0" y="0" width="24" height="24"/></filter></defs>' +
      '<g filter="url(#b)"><g clip-path="url(#v)"><path d="M2 2H8V8H2Z"/></g><g transform="translate(24 0)"><g clip-path="url(#v)"><path d="M-5 10H14V14H-5Z"/></g></g></g>' +
      '<path d="M20 20h2v2h-2z"/>',
    'viewBox="0 0 24 24"'
  );
  const ic = readSvgText(svg);
  assert.deepEqual(ic.elements.map((e) => +e.fillAlpha.toFixed(2)), [0.75, 0.25, 1]);
  const xs = ic.rings[1].points.map((p) => p[0]);
  assert.deepEqual([Math.min(...xs), Math.max(...xs)], [-5, 14]); // moved back by dx, not clipped
});

test("mulberry32 is deterministic and uniform enough", () => {
  const a = mulberry32(2026), b = mulberry32(2026);
  const xs = Array.from({ length: 1000 }, () => a());
  assert.deepEqual(xs.slice(0, 5), Array.from({ length: 5 }, () => b()));
  assert.ok(xs.every((x) => x >= 0 && x < 1));
  const mean = xs.reduce((s, x) => s + x, 0) / xs.length;
  assert.ok(Math.abs(mean - 0.5) < 0.05);
});

test("the draw: deterministic, ordered pairs of distinct icons, no repeats", () => {
  const lists = [["a", "b"], ["c", "d", "e"]];
  const p1 = drawPairs(7, 8, lists), p2 = drawPairs(7, 8, lists);
  assert.deepEqual(p1, p2); // 2 + 6 = 8 ordered pairs exist: all of them
  assert.equal(new Set(p1.map((p) => `${p.set}:${p.i}:${p.j}`)).size, 8);
  assert.ok(p1.every((p) => p.i !== p.j));
  assert.notDeepEqual(drawPairs(8, 8, lists), p1);
  assert.equal(normalise('<svg fill="currentColor" stroke="currentColor">'), '<svg fill="#000000" stroke="#000000">');
});
