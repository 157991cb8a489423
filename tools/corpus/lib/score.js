// Scores one tool's result on one pair: every measure from the frame SVGs alone (README.md, "Measures").
"use strict";

const { readSvgText } = require("./svg.js");
const { render } = require("./render.js");
const M = require("./measures.js");

const CRISP = 0.1;

/**
 * result: { frames: [svg × N], exact: { t: svg }, time, mesh? }; src, tgt: icons read by readSvgText.
 * o: { px (ghost and area renders), frames }.
 */
function score(result, src, tgt, o) {
  const N = result.frames.length;
  const ts = result.frames.map((_, i) => i / (N - 1));
  // Geometry of every frame.
  let crossingFrames = 0, selfFrames = 0, otherFrames = 0, ringsMax = 0;
  const rings = [];
  for (const svg of result.frames) {
    const f = readSvgText(svg, "frame");
    const c = M.crossings(f.rings);
    if (c.any) crossingFrames++;
    if (c.self) selfFrames++;
    if (c.other) otherFrames++;
    ringsMax = Math.max(ringsMax, f.rings.length);
    rings.push(f.rings);
  }
  const end0 = M.hausdorff(rings[0], src.rings) / src.diag;
  const end1 = M.hausdorff(rings[N - 1], tgt.rings) / tgt.diag;
  // Pixels: ink of every frame, ghost of the exact frames.
  const inks = result.frames.map((svg) => {
    const img = render(svg, o.px);
    return M.inkOfPixels(img.pixels, img.width, img.height);
  });
  const img0 = render(result.frames[0], o.px);
  const area = M.areaRatios(inks, ts, img0.width * img0.height);
  const ghostAt = {};
  for (const [t, svg] of Object.entries(result.exact)) {
    const img = render(svg, o.px);
    ghostAt[t] = M.ghostOfPixels(img.pixels, img.width, img.height).ghost;
  }
  const ghost = Math.max(...Object.values(ghostAt));
  const out = {
    ghost, ghostAt, crisp: ghost < CRISP,
    crossingFrames, crossingShare: crossingFrames / N, selfCrossingShare: selfFrames / N, otherCrossingShare: otherFrames / N,
    areaMin: area.min, areaMax: area.max,
    ends: Math.max(end0, end1), end0, end1,
    ringsMax,
  };
  if (result.mesh) {
    const f = M.countFlips(result.mesh.triangles, result.mesh.vertices);
    out.flips = f.flipped;
    out.triangles = f.triangles;
    out.meshFrames = f.frames;
  }
  return out;
}

/**
 * Tool-independent facts about an input icon. `ghost`: the icon's own ghost (as shipped, 240 px), which
 * thin lines raise (they have no solid core). `repaint`: how much the icon's ink changes when it is drawn
 * the way flubber's and gsap's frames are (all its geometry as one path with the paint of `paintIcon`, the
 * pair's source: fill-rule evenodd, or one stroke style), |ink(repainted) − ink(icon)| / ink(icon).
 */
function describeIcon(icon, text, paintIcon) {
  const { frameSvg, paintFor } = require("./tools.js");
  const { combinedPath } = require("./svg.js");
  const inkOf = (svg) => {
    const img = render(svg, 240);
    return M.inkOfPixels(img.pixels, img.width, img.height);
  };
  const img = render(text, 240);
  const own = M.inkOfPixels(img.pixels, img.width, img.height);
  const re = inkOf(frameSvg(icon.viewBox, combinedPath(icon), paintFor(paintIcon)));
  return {
    kind: icon.kind, rings: icon.rings.length, crossing: M.crossings(icon.rings, true).any,
    ghost: M.ghostOfPixels(img.pixels, img.width, img.height).ghost, repaint: own > 0 ? Math.abs(re - own) / own : null,
  };
}

module.exports = { score, describeIcon, CRISP };
