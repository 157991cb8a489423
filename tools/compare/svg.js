// Reads a plain SVG icon into outline contours (polylines in the root's user units), the geometry both
// morphing tools are measured against and the input handed to flubber.
//
// - Shapes: path, circle, ellipse, rect (with rx/ry), line, polyline, polygon; transforms of the element
//   and its ancestors applied; <defs>, <clipPath>, <mask>, <symbol>, <marker>, <pattern>, gradients,
//   <title>/<desc>/<metadata>/<style> skipped; display="none" subtrees and visibility="hidden" skipped.
// - A visible element contributes its outline: with a fill (anything but "none", default black), every
//   subpath as a closed ring (fill regions; holes are just further rings); with no fill but a stroke,
//   every subpath as a centre line, closed only when the subpath is (Z, circle, rect, polygon).
//   Elements with neither (e.g. tabler's invisible 24×24 frame) contribute nothing.
// - Marked-up crmorph drawings (ids feature-*): the contours are the feature curves instead, the
//   non-boundary curves crmorph reports, so the harness can be tried on the existing fixtures.
// - Curves are flattened uniformly with segments of about size/100 (size = the larger viewBox side).
"use strict";

const fs = require("node:fs");
const svgpath = require("svgpath");

const SKIP = new Set(["defs", "clipPath", "mask", "symbol", "marker", "pattern", "linearGradient", "radialGradient", "title", "desc", "metadata", "style", "script", "filter", "text"]);
const SHAPES = new Set(["path", "circle", "ellipse", "rect", "line", "polyline", "polygon"]);
const INHERITED = ["fill", "stroke", "stroke-width", "visibility"];

function decode(s) {
  return s.replace(/&lt;/g, "<").replace(/&gt;/g, ">").replace(/&quot;/g, '"').replace(/&apos;/g, "'").replace(/&amp;/g, "&");
}

function attributes(text) {
  const out = {};
  for (const m of text.matchAll(/([^\s=/>]+)\s*=\s*(?:"([^"]*)"|'([^']*)')/g)) out[m[1]] = decode(m[2] ?? m[3]);
  if (out.style) {
    for (const decl of out.style.split(";")) {
      const i = decl.indexOf(":");
      if (i > 0) out[decl.slice(0, i).trim()] = decl.slice(i + 1).trim();
    }
  }
  return out;
}

/** Tokenises XML into a flat list of { open|close, name, attrs, selfClosing }. */
function tags(xml) {
  const re = /<!--[\s\S]*?-->|<\?[\s\S]*?\?>|<!\[CDATA\[[\s\S]*?\]\]>|<![^>]*>|<(\/?)([A-Za-z_][\w:.-]*)((?:\s+[^\s=/>]+(?:\s*=\s*(?:"[^"]*"|'[^']*'))?)*)\s*(\/?)>/g;
  const out = [];
  for (const m of xml.matchAll(re)) {
    if (!m[2]) continue;
    const name = m[2].replace(/^svg:/, "");
    if (m[1]) out.push({ close: true, name });
    else out.push({ close: false, name, attrs: attributes(m[3] || ""), selfClosing: m[4] === "/" });
  }
  return out;
}

const num = (v, d = 0) => {
  const x = parseFloat(v);
  return Number.isFinite(x) ? x : d;
};

function pointsAttr(s) {
  const v = (s || "").trim().split(/[\s,]+/).map(Number).filter(Number.isFinite);
  const pts = [];
  for (let i = 0; i + 1 < v.length; i += 2) pts.push(`${v[i]} ${v[i + 1]}`);
  return pts;
}

/** Path data of a basic shape, in its own coordinates. */
function shapeToPath(name, a) {
  switch (name) {
    case "path":
      return a.d || "";
    case "circle":
    case "ellipse": {
      const cx = num(a.cx), cy = num(a.cy);
      const rx = name === "circle" ? num(a.r) : num(a.rx, num(a.ry)), ry = name === "circle" ? num(a.r) : num(a.ry, num(a.rx));
      if (rx <= 0 || ry <= 0) return "";
      return `M${cx + rx} ${cy}A${rx} ${ry} 0 1 1 ${cx - rx} ${cy}A${rx} ${ry} 0 1 1 ${cx + rx} ${cy}Z`;
    }
    case "rect": {
      const x = num(a.x), y = num(a.y), w = num(a.width), h = num(a.height);
      if (w <= 0 || h <= 0) return "";
      let rx = a.rx !== undefined ? num(a.rx) : a.ry !== undefined ? num(a.ry) : 0;
      let ry = a.ry !== undefined ? num(a.ry) : rx;
      rx = Math.min(rx, w / 2);
      ry = Math.min(ry, h / 2);
      if (rx <= 0 || ry <= 0) return `M${x} ${y}H${x + w}V${y + h}H${x}Z`;
      return `M${x + rx} ${y}H${x + w - rx}A${rx} ${ry} 0 0 1 ${x + w} ${y + ry}V${y + h - ry}A${rx} ${ry} 0 0 1 ${x + w - rx} ${y + h}` +
        `H${x + rx}A${rx} ${ry} 0 0 1 ${x} ${y + h - ry}V${y + ry}A${rx} ${ry} 0 0 1 ${x + rx} ${y}Z`;
    }
    case "line":
      return `M${num(a.x1)} ${num(a.y1)}L${num(a.x2)} ${num(a.y2)}`;
    case "polyline":
    case "polygon": {
      const p = pointsAttr(a.points);
      return p.length ? `M${p.join("L")}${name === "polygon" ? "Z" : ""}` : "";
    }
  }
  return "";
}

/** Flattens path data (with a transform applied) into subpaths { points, closed }. */
function flatten(d, transform, step) {
  const abs = svgpath(d).transform(transform || "").unarc().unshort().abs().toString();
  const segs = svgpath(abs).abs().segments;
  const subs = [];
  let cur = null;
  let x = 0, y = 0, sx = 0, sy = 0;
  const push = (px, py) => {
    const last = cur.points[cur.points.length - 1];
    if (!last || last[0] !== px || last[1] !== py) cur.points.push([px, py]);
  };
  const begin = () => {
    cur = { points: [[x, y]], closed: false };
    subs.push(cur);
  };
  for (const s of segs) {
    const c = s[0];
    if (c === "M") {
      x = sx = s[1];
      y = sy = s[2];
      begin();
      continue;
    }
    if (!cur || cur.closed) begin(); // drawing after Z starts a new subpath at the current point
    if (c === "L") [x, y] = [s[1], s[2]];
    else if (c === "H") x = s[1];
    else if (c === "V") y = s[1];
    else if (c === "Z") {
      cur.closed = true;
      x = sx;
      y = sy;
      continue;
    } else if (c === "C" || c === "Q") {
      const ctrl = c === "C" ? [[x, y], [s[1], s[2]], [s[3], s[4]], [s[5], s[6]]] : [[x, y], [s[1], s[2]], [s[3], s[4]]];
      let len = 0;
      for (let i = 1; i < ctrl.length; i++) len += Math.hypot(ctrl[i][0] - ctrl[i - 1][0], ctrl[i][1] - ctrl[i - 1][1]);
      const n = Math.min(256, Math.max(2, Math.ceil(len / step)));
      for (let k = 1; k <= n; k++) {
        const u = k / n, v = 1 - u;
        let px, py;
        if (c === "C") {
          const [p0, p1, p2, p3] = ctrl;
          px = v * v * v * p0[0] + 3 * v * v * u * p1[0] + 3 * v * u * u * p2[0] + u * u * u * p3[0];
          py = v * v * v * p0[1] + 3 * v * v * u * p1[1] + 3 * v * u * u * p2[1] + u * u * u * p3[1];
        } else {
          const [p0, p1, p2] = ctrl;
          px = v * v * p0[0] + 2 * v * u * p1[0] + u * u * p2[0];
          py = v * v * p0[1] + 2 * v * u * p1[1] + u * u * p2[1];
        }
        push(px, py);
      }
      [x, y] = ctrl[ctrl.length - 1];
      cur.points[cur.points.length - 1] = [x, y]; // exact end point
      continue;
    }
    push(x, y);
  }
  for (const sp of subs) {
    const p = sp.points;
    if (sp.closed && p.length > 1) {
      const [a, b] = [p[0], p[p.length - 1]];
      if (Math.hypot(a[0] - b[0], a[1] - b[1]) <= 1e-9 * step) p.pop();
    }
  }
  return subs;
}

/**
 * Reads an SVG file: { file, viewBox: [x, y, w, h], size, contours: [{ points, closed, element }] }.
 * `size` (the larger viewBox side) is the unit of the relative tolerances and of the end error.
 */
function readIcon(file) {
  const xml = fs.readFileSync(file, "utf8");
  const list = tags(xml);
  const root = list.find((t) => !t.close && t.name === "svg");
  if (!root) throw new Error(`${file}: no <svg> element`);
  let vb = (root.attrs.viewBox || "").trim().split(/[\s,]+/).map(Number);
  if (vb.length !== 4 || vb.some((v) => !Number.isFinite(v))) vb = [0, 0, num(root.attrs.width, 100), num(root.attrs.height, 100)];
  const size = Math.max(vb[2], vb[3]);
  const step = size / 100;

  const art = [];
  const features = [];
  const stack = [];
  let skipDepth = 0;
  let seq = 0;
  for (const t of list) {
    if (t.close) {
      const top = stack.pop();
      if (top && top.skipping) skipDepth--;
      continue;
    }
    const parent = stack.length ? stack[stack.length - 1].ctx : { fill: "black", stroke: "none", "stroke-width": "1", visibility: "visible", transform: "", hidden: false };
    const a = t.attrs;
    const ctx = { ...parent };
    for (const k of INHERITED) if (a[k] !== undefined && a[k] !== "inherit") ctx[k] = a[k];
    ctx.transform = [parent.transform, a.transform || ""].join(" ").trim();
    ctx.hidden = parent.hidden || a.display === "none";
    const skipping = SKIP.has(t.name);
    if (SHAPES.has(t.name) && skipDepth === 0) {
      const d = shapeToPath(t.name, a);
      if (d) {
        const id = a.id || "";
        const fill = (ctx.fill || "").trim();
        const filled = fill !== "none" && fill !== "transparent";
        const stroked = (ctx.stroke || "none").trim() !== "none" && num(ctx["stroke-width"], 1) > 0;
        const visible = !ctx.hidden && ctx.visibility !== "hidden" && ctx.visibility !== "collapse";
        const element = `${t.name}#${id || seq}`;
        seq++;
        if (/^feature-/.test(id)) {
          for (const sp of flatten(d, ctx.transform, step)) features.push({ ...sp, element });
        } else if (visible && (filled || stroked) && !/^(boundary|anchor-|skeleton-)/.test(id)) {
          for (const sp of flatten(d, ctx.transform, step)) art.push({ points: sp.points, closed: filled ? true : sp.closed, element });
        }
      }
    }
    if (!t.selfClosing) {
      stack.push({ ctx, skipping });
      if (skipping) skipDepth++;
    }
  }
  const contours = (features.length ? features : art).filter((c) => c.points.length >= (c.closed ? 3 : 2));
  return { file, viewBox: vb, size, contours, marked: features.length > 0 };
}

module.exports = { readIcon, flatten, shapeToPath, tags };
