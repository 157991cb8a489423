"use strict";

const test = require("node:test");
const assert = require("node:assert/strict");
const { readSvgText } = require("../lib/svg.js");
const T = require("../lib/tools.js");
const { score } = require("../lib/score.js");

const doc = (body) => `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24">${body}</svg>`;
const square = readSvgText(doc('<rect x="4" y="4" width="16" height="16"/>'));
const disc = readSvgText(doc('<circle cx="12" cy="12" r="9"/>'));
const o = { frames: 12, seg: 0.01, px: 120 };

test("jsdom reports SVG presentation attributes to MorphSVGPlugin's computed-style test", () => {
  const { win } = T.gsapEnv();
  const el = win.document.createElementNS("http://www.w3.org/2000/svg", "path");
  el.setAttribute("fill", "#000000");
  el.setAttribute("fill-rule", "evenodd");
  const cs = win.getComputedStyle(el);
  assert.equal(cs.fill, "#000000");
  assert.equal(cs.fillRule, "evenodd");
});

for (const [name, run] of [["flubber", T.runFlubber], ["gsap", T.runGsap]]) {
  test(`${name}: square → disc gives N frames that start and end on the icons`, () => {
    const r = run(square, disc, o);
    assert.equal(r.frames.length, o.frames);
    assert.deepEqual(Object.keys(r.exact).map(Number), [0.25, 0.5, 0.75]);
    assert.ok(r.time.ms >= 0);
    const s = score(r, square, disc, o);
    assert.ok(s.ends < 0.01, `ends ${s.ends}`);
    assert.ok(s.ghost < 0.1 && s.crisp);
    assert.equal(s.crossingFrames, 0);
    assert.ok(s.areaMin > 0.8 && s.areaMax < 1.2, `area ${s.areaMin} ${s.areaMax}`);
  });
}

test("stroke icons are drawn as strokes with the source's width, caps and joins", () => {
  const line = readSvgText(doc('<path d="M4 12H20" fill="none" stroke="#000" stroke-width="2" stroke-linecap="round" stroke-linejoin="round"/>'));
  assert.match(T.paintFor(line).attrs, /fill="none" stroke="#000000" stroke-width="2" stroke-linecap="round" stroke-linejoin="round"/);
  assert.equal(T.paintFor(square).attrs, 'fill="#000000" fill-rule="evenodd"');
});

test("crmorph: the four steps run and their outputs parse (skipped without a binary; CRMORPH=PATH)", (t) => {
  const fs = require("node:fs");
  const os = require("node:os");
  const path = require("node:path");
  const bin = process.env.CRMORPH || path.join(__dirname, "..", "..", "..", "target", "release", "crmorph");
  if (!fs.existsSync(bin)) return t.skip(`no ${bin}`);
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "corpus-test-"));
  try {
    const src = path.join(dir, "s.svg"), tgt = path.join(dir, "t.svg");
    fs.writeFileSync(src, doc('<rect x="4" y="4" width="16" height="16"/>'));
    fs.writeFileSync(tgt, doc('<circle cx="12" cy="12" r="9"/>'));
    const r = T.runCrmorph({ src, tgt }, { crmorph: bin, frames: 12, tmp: dir, timeoutMs: 60000 });
    assert.equal(r.error, undefined, r.error);
    assert.equal(r.frames.length, 12);
    assert.equal(r.mesh.frames, 12);
    assert.ok(r.mesh.triangles.length > 0);
    assert.ok(r.time.wallMs > 0 && r.time.cpuMs >= 0);
    const s = score(r, square, disc, o);
    assert.ok(s.ends < 0.01, `ends ${s.ends}`);
    assert.equal(s.flips, 0);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});
