"use strict";
const test = require("node:test");
const assert = require("node:assert/strict");
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { readIcon } = require("./svg.js");
const { totalArea } = require("./metrics.js");
const { parseRings, flubberInterpolators } = require("./compare.js");

function icon(body, attrs = 'viewBox="0 0 24 24"') {
  const f = path.join(fs.mkdtempSync(path.join(os.tmpdir(), "svgtest-")), "i.svg");
  fs.writeFileSync(f, `<svg xmlns="http://www.w3.org/2000/svg" ${attrs}>${body}</svg>`);
  return readIcon(f);
}

test("a filled circle becomes one closed ring of area ≈ πr²", () => {
  const ic = icon('<circle cx="12" cy="12" r="8"/>');
  assert.equal(ic.size, 24);
  assert.equal(ic.contours.length, 1);
  assert.ok(ic.contours[0].closed);
  assert.ok(Math.abs(totalArea(ic.contours) - Math.PI * 64) / (Math.PI * 64) < 1e-3);
});

test("holes are further rings; transforms of ancestors apply", () => {
  const ic = icon('<g transform="translate(10 0)"><path fill-rule="evenodd" d="M0 0h10v10H0z M2 2h6v6H2z"/></g>');
  assert.equal(ic.contours.length, 2);
  assert.deepEqual(ic.contours[0].points[0], [10, 0]);
  assert.equal(totalArea(ic.contours), 136);
});

test("stroked lines are open centre lines; invisible and hidden elements and defs are skipped", () => {
  const ic = icon(
    '<path stroke="none" d="M0 0h24v24H0z" fill="none"/><line x1="3" y1="12" x2="21" y2="12"/>' +
      '<rect x="1" y="1" width="4" height="4" display="none"/><defs><circle r="3"/></defs>',
    'viewBox="0 0 24 24" fill="none" stroke="#000"'
  );
  assert.equal(ic.contours.length, 1);
  assert.equal(ic.contours[0].closed, false);
  assert.deepEqual(ic.contours[0].points, [[3, 12], [21, 12]]);
});

test("flubber output parses into closed rings; different contour counts still give interpolators", () => {
  assert.deepEqual(parseRings("M0,0L1,0L1,1Z M2,2L3,2L3,3Z"), [
    { points: [[0, 0], [1, 0], [1, 1]], closed: true },
    { points: [[2, 2], [3, 2], [3, 3]], closed: true },
  ]);
  const sq = (x) => [[x, 0], [x + 1, 0], [x + 1, 1], [x, 1]];
  const fns = flubberInterpolators([sq(0), sq(2), sq(4)], [sq(0), sq(3)], { maxSegmentLength: 0.5 });
  assert.ok(fns.length >= 2);
  for (const f of fns) assert.ok(parseRings(f(0.5)).length >= 1);
});
