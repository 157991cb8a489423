// Rendering with resvg-js (@resvg/resvg-js, pinned): every pixel measure goes through here.
"use strict";

const { Resvg } = require("@resvg/resvg-js");

const NO_FONTS = { loadSystemFonts: false };

/**
 * Renders SVG text over white with its longer side at `px` pixels (the other side scaled to keep the
 * aspect ratio). Returns { pixels (RGBA, Uint8Array-like), width, height }.
 */
function render(svg, px, opts = {}) {
  const r = new Resvg(svg, {
    fitTo: { mode: longerSide(svg) === "height" ? "height" : "width", value: px },
    background: "#ffffff",
    font: opts.fonts ? { loadSystemFonts: true, defaultFontFamily: "DejaVu Sans" } : NO_FONTS,
    shapeRendering: 2, // geometricPrecision (antialiased)
  });
  const img = r.render();
  return { pixels: img.pixels, width: img.width, height: img.height, png: opts.png ? img.asPng() : null };
}

/** "width" or "height": which side of the SVG's viewBox (or width/height) is the longer one. */
function longerSide(svg) {
  const m = /<svg\b[^>]*?\bviewBox\s*=\s*["']([^"']+)["']/.exec(svg);
  let w = 1, h = 1;
  if (m) {
    const v = m[1].trim().split(/[\s,]+/).map(Number);
    if (v.length === 4 && v[2] > 0 && v[3] > 0) [w, h] = [v[2], v[3]];
  } else {
    const wm = /<svg\b[^>]*?\bwidth\s*=\s*["']([\d.]+)/.exec(svg);
    const hm = /<svg\b[^>]*?\bheight\s*=\s*["']([\d.]+)/.exec(svg);
    if (wm && hm) [w, h] = [+wm[1], +hm[1]];
  }
  return h > w ? "height" : "width";
}

module.exports = { render, longerSide };
