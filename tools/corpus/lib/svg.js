// Reads an SVG document (an input icon or a frame written by any of the tools) into its drawn elements
// and their rings: the one geometry reader every measure of every tool goes through.
//
// - Elements: path, circle, ellipse, rect (rx/ry), line, polyline, polygon, with the transforms of the
//   element and its ancestors applied (CTM = product of the `transform` lists down the tree). Skipped:
//   <defs>, <clipPath>, <mask>, <symbol>, <marker>, <pattern>, gradients, <filter>, <title>, <desc>,
//   <metadata>, <style>, <script>, <text>, display="none" subtrees, visibility hidden/collapse. Nested
//   <svg> elements are read as plain groups (their own viewport is not applied); <use> is not followed;
//   CSS style sheets are not applied (style="" attributes are); clip paths are not applied (a clipped
//   element counts whole). None of the icon sets nor crmorph's frames need these.
// - Filters: one kind is understood, the two-layer blend crmorph's frames use for cross-fades:
//   <filter> = feOffset(SourceGraphic, dx, dy) + feComposite(SourceGraphic, offset, arithmetic, k1 = 0,
//   k2, k3, k4 = 0) cropped to the composite's (or the filter's) region. Everything drawn under a group
//   with such a filter is read twice: in place with its alpha × k2, and moved by (dx, dy) with its
//   alpha × k3; a copy with weight 0 or whose bounding box misses the crop region draws nothing. Any other
//   filter is ignored (its content is read as if unfiltered).
// - Paint: fill (default black), stroke (default none), fill-/stroke-opacity and the product of the
//   `opacity` of the element and its ancestors. An element is *filled* when its fill is not none and its
//   fill alpha is above 0, *stroked* when its stroke is not none, its width above 0 and its stroke alpha
//   above 0. Invisible elements (neither, e.g. tabler's 24×24 frame) draw nothing.
// - Rings: a filled element gives every subpath as a closed ring (a hole is just another ring); a
//   stroked element without fill gives every subpath as its centre line, closed only when the subpath is
//   (Z; circle, ellipse, rect and polygon are); a zero-length stroked subpath under round or square caps
//   (a dot) is a ring of one point, a closed stroked subpath of two points an open ring of two; a filled
//   subpath needs three points. Curves and arcs are flattened with chords of about size/100 (size = the
//   larger viewBox side), at most 256 chords per curve.
"use strict";

const svgpath = require("svgpath");

const SKIP = new Set(["defs", "clipPath", "mask", "symbol", "marker", "pattern", "linearGradient", "radialGradient", "filter", "title", "desc", "metadata", "style", "script", "text"]);
const SHAPES = new Set(["path", "circle", "ellipse", "rect", "line", "polyline", "polygon"]);
const INHERITED = ["fill", "stroke", "stroke-width", "stroke-linecap", "stroke-linejoin", "stroke-miterlimit", "fill-rule", "fill-opacity", "stroke-opacity", "visibility", "color"];

function decode(s) {
  return s
    .replace(/&#x([0-9a-f]+);/gi, (_, h) => String.fromCodePoint(parseInt(h, 16)))
    .replace(/&#(\d+);/g, (_, d) => String.fromCodePoint(parseInt(d, 10)))
    .replace(/&lt;/g, "<").replace(/&gt;/g, ">").replace(/&quot;/g, '"').replace(/&apos;/g, "'").replace(/&amp;/g, "&");
}

function attributes(text) {
  const out = {};
  for (const m of text.matchAll(/([^\s=/>]+)\s*=\s*(?:"([^"]*)"|'([^']*)')/g)) out[m[1]] = decode(m[2] ?? m[3]);
  if (out.style) {
    for (const decl of out.style.split(";")) {
      const i = decl.indexOf(":");
      if (i > 0) out[decl.slice(0, i).trim()] = decl.slice(i + 1).trim().replace(/\s*!important$/, "");
    }
  }
  return out;
}

/** Tokenises XML into a flat list of { close, name, attrs, selfClosing }. */
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

// ------------------------------------------------------------------------------------------ transforms

const IDENTITY = [1, 0, 0, 1, 0, 0];

/** m1 · m2 for affine matrices [a, b, c, d, e, f] (x' = a x + c y + e, y' = b x + d y + f). */
function multiply(m1, m2) {
  const [a1, b1, c1, d1, e1, f1] = m1;
  const [a2, b2, c2, d2, e2, f2] = m2;
  return [a1 * a2 + c1 * b2, b1 * a2 + d1 * b2, a1 * c2 + c1 * d2, b1 * c2 + d1 * d2, a1 * e2 + c1 * f2 + e1, b1 * e2 + d1 * f2 + f1];
}

function invert(m) {
  const [a, b, c, d, e, f] = m;
  const det = a * d - b * c;
  if (!det) return IDENTITY;
  return [d / det, -b / det, -c / det, a / det, (c * f - d * e) / det, (b * e - a * f) / det];
}

function apply(m, x, y) {
  return [m[0] * x + m[2] * y + m[4], m[1] * x + m[3] * y + m[5]];
}

/** Parses an SVG transform list into one matrix. */
function parseTransform(s) {
  let m = IDENTITY;
  if (!s) return m;
  for (const t of s.matchAll(/(matrix|translate|scale|rotate|skewX|skewY)\s*\(([^)]*)\)/g)) {
    const v = t[2].trim().split(/[\s,]+/).filter(Boolean).map(Number);
    let k;
    switch (t[1]) {
      case "matrix":
        k = v.length === 6 ? v : IDENTITY;
        break;
      case "translate":
        k = [1, 0, 0, 1, v[0] || 0, v[1] || 0];
        break;
      case "scale":
        k = [v[0] ?? 1, 0, 0, v.length > 1 ? v[1] : v[0] ?? 1, 0, 0];
        break;
      case "rotate": {
        const r = ((v[0] || 0) * Math.PI) / 180;
        const [cs, sn] = [Math.cos(r), Math.sin(r)];
        const [cx, cy] = [v[1] || 0, v[2] || 0];
        k = multiply(multiply([1, 0, 0, 1, cx, cy], [cs, sn, -sn, cs, 0, 0]), [1, 0, 0, 1, -cx, -cy]);
        break;
      }
      case "skewX":
        k = [1, 0, Math.tan(((v[0] || 0) * Math.PI) / 180), 1, 0, 0];
        break;
      case "skewY":
        k = [1, Math.tan(((v[0] || 0) * Math.PI) / 180), 0, 1, 0, 0];
        break;
    }
    m = multiply(m, k);
  }
  return m;
}

// ------------------------------------------------------------------------------------------ shapes

function pointsAttr(s) {
  const v = (s || "").trim().split(/[\s,]+/).map(Number).filter(Number.isFinite);
  const pts = [];
  for (let i = 0; i + 1 < v.length; i += 2) pts.push(`${v[i]} ${v[i + 1]}`);
  return pts;
}

/** Path data of a basic shape, in its own coordinates ("" when it draws nothing). */
function shapeToPath(name, a) {
  switch (name) {
    case "path":
      return a.d || "";
    case "circle":
    case "ellipse": {
      const cx = num(a.cx), cy = num(a.cy);
      const rx = name === "circle" ? num(a.r) : num(a.rx, num(a.ry));
      const ry = name === "circle" ? num(a.r) : num(a.ry, num(a.rx));
      if (rx <= 0 || ry <= 0) return "";
      return `M${cx + rx} ${cy}A${rx} ${ry} 0 1 1 ${cx - rx} ${cy}A${rx} ${ry} 0 1 1 ${cx + rx} ${cy}Z`;
    }
    case "rect": {
      const x = num(a.x), y = num(a.y), w = num(a.width), h = num(a.height);
      if (w <= 0 || h <= 0) return "";
      let rx = a.rx !== undefined && a.rx !== "auto" ? num(a.rx) : a.ry !== undefined && a.ry !== "auto" ? num(a.ry) : 0;
      let ry = a.ry !== undefined && a.ry !== "auto" ? num(a.ry) : rx;
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

/** Path data with the matrix applied, absolute commands (curves and arcs kept). */
function transformPath(d, m) {
  return svgpath(d).matrix(m).abs().toString();
}

/**
 * Flattens path data (already in root coordinates) into subpaths { points, closed }. Closed subpaths do
 * not repeat their first point. A subpath of one distinct point is kept when something was drawn from it
 * ("M x y L x y", "M x y Z": a dot under round or square caps), a lone "M x y" is dropped.
 */
function flatten(d, step) {
  // S and T reflect the previous segment only when it is a C/S (Q/T): resolve them before arcs become curves.
  const abs = svgpath(d).unshort().unarc().abs().toString();
  const segs = svgpath(abs).abs().segments;
  const subs = [];
  let cur = null;
  let x = 0, y = 0, sx = 0, sy = 0;
  const push = (px, py) => {
    const last = cur.points[cur.points.length - 1];
    if (!last || last[0] !== px || last[1] !== py) cur.points.push([px, py]);
  };
  const begin = () => {
    cur = { points: [[x, y]], closed: false, drawn: false };
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
    cur.drawn = true;
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
      for (let k = 1; k < n; k++) {
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
    }
    push(x, y);
  }
  const tol = 1e-9 * step;
  const out = [];
  for (const sp of subs) {
    const p = sp.points;
    if (p.length > 1) {
      const [a, b] = [p[0], p[p.length - 1]];
      if (sp.closed && Math.hypot(a[0] - b[0], a[1] - b[1]) <= tol) p.pop(); // an open path back to its start stays open (it has caps)
    }
    if (p.length >= 2 || sp.drawn) out.push(sp);
  }
  return out;
}

// ------------------------------------------------------------------------------------------ filters

/**
 * The two-layer blend filters of the document (see the header): id → { dx, dy, k2, k3, region: [x, y, w, h] }.
 * Only filters of exactly that form (userSpaceOnUse, feOffset of SourceGraphic, arithmetic feComposite of
 * SourceGraphic and that offset with k1 = k4 = 0) are listed.
 */
function blendFilters(list) {
  const out = new Map();
  for (let i = 0; i < list.length; i++) {
    const t = list[i];
    if (t.close || t.name !== "filter" || t.selfClosing || !t.attrs.id) continue;
    const prims = [];
    let j = i + 1;
    for (; j < list.length && !(list[j].close && list[j].name === "filter"); j++) if (!list[j].close) prims.push(list[j]);
    i = j;
    if ((t.attrs.filterUnits || "objectBoundingBox") !== "userSpaceOnUse" || prims.length !== 2) continue;
    const [off, comp] = prims;
    if (off.name !== "feOffset" || comp.name !== "feComposite") continue;
    const oa = off.attrs, ca = comp.attrs;
    if ((oa.in || "SourceGraphic") !== "SourceGraphic" || (ca.in || "SourceGraphic") !== "SourceGraphic" || !oa.result || ca.in2 !== oa.result) continue;
    if (ca.operator !== "arithmetic" || num(ca.k1) !== 0 || num(ca.k4) !== 0) continue;
    const fa = t.attrs;
    const region = [num(ca.x ?? fa.x), num(ca.y ?? fa.y), num(ca.width ?? fa.width), num(ca.height ?? fa.height)];
    out.set(fa.id, { dx: num(oa.dx), dy: num(oa.dy), k2: Math.max(0, num(ca.k2)), k3: Math.max(0, num(ca.k3)), region });
  }
  return out;
}

/** Clip paths made of one <rect> in user space: id → [x, y, w, h] (used for the blend's crop test only). */
function simpleClips(list) {
  const out = new Map();
  for (let i = 0; i < list.length; i++) {
    const t = list[i];
    if (t.close || t.name !== "clipPath" || t.selfClosing || !t.attrs.id) continue;
    const kids = [];
    let j = i + 1;
    for (; j < list.length && !(list[j].close && list[j].name === "clipPath"); j++) if (!list[j].close) kids.push(list[j]);
    i = j;
    if ((t.attrs.clipPathUnits || "userSpaceOnUse") !== "userSpaceOnUse" || kids.length !== 1 || kids[0].name !== "rect" || kids[0].attrs.transform) continue;
    const r = kids[0].attrs;
    out.set(t.attrs.id, [num(r.x), num(r.y), num(r.width), num(r.height)]);
  }
  return out;
}

function boxOfPoints(ps) {
  return [Math.min(...ps.map((p) => p[0])), Math.min(...ps.map((p) => p[1])), Math.max(...ps.map((p) => p[0])), Math.max(...ps.map((p) => p[1]))];
}

function intersectBoxes(a, b) {
  return [Math.max(a[0], b[0]), Math.max(a[1], b[1]), Math.min(a[2], b[2]), Math.min(a[3], b[3])];
}

function bboxOf(subpaths) {
  let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
  for (const sp of subpaths) for (const [x, y] of sp.points) {
    x0 = Math.min(x0, x); y0 = Math.min(y0, y); x1 = Math.max(x1, x); y1 = Math.max(y1, y);
  }
  return [x0, y0, x1, y1];
}

/** The blend's crop region in root coordinates (bounding box of its corners under the group's CTM). */
function regionBox(b) {
  const [x, y, w, h] = b.region;
  return boxOfPoints([apply(b.mg, x, y), apply(b.mg, x + w, y), apply(b.mg, x, y + h), apply(b.mg, x + w, y + h)]);
}

// Strict overlap: a copy that only touches the region's edge draws nothing inside it.
function boxesMeet(a, b) {
  return a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
}

// ------------------------------------------------------------------------------------------ reading

function paintOf(v, color) {
  const s = (v ?? "").trim();
  if (s === "" || s === "none" || s === "transparent") return null;
  if (s === "currentColor") return (color || "black").trim();
  return s;
}

const clamp01 = (x) => Math.max(0, Math.min(1, x));

/**
 * Reads SVG text:
 *   { viewBox: [x, y, w, h], size, diag, elements, rings, kind, stroke }
 * - elements: the drawn elements, each { tag, id, d (root coordinates, absolute), filled, stroked,
 *   fill, stroke, fillRule, strokeWidth (root units), linecap, linejoin, miterlimit, subpaths }
 * - rings: [{ points, closed, filled }] by the rule in the file header, in document order
 * - kind: "fill" (only filled elements), "stroke" (only stroke-only elements), "mixed" or "empty"
 * - stroke: { width, linecap, linejoin, miterlimit } of the first stroked element, or null
 */
function readSvgText(xml, label = "svg") {
  const list = tags(xml);
  const root = list.find((t) => !t.close && t.name === "svg");
  if (!root) throw new Error(`${label}: no <svg> element`);
  let vb = (root.attrs.viewBox || "").trim().split(/[\s,]+/).map(Number);
  if (vb.length !== 4 || vb.some((v) => !Number.isFinite(v)) || vb[2] <= 0 || vb[3] <= 0) vb = [0, 0, num(root.attrs.width, 100), num(root.attrs.height, 100)];
  const size = Math.max(vb[2], vb[3]);
  const step = size / 100;

  const blends = blendFilters(list);
  const clipRects = simpleClips(list);
  const elements = [];
  const stack = [];
  let skipDepth = 0;
  const top = {
    fill: "black", stroke: "none", "stroke-width": "1", "stroke-linecap": "butt", "stroke-linejoin": "miter", "stroke-miterlimit": "4",
    "fill-rule": "nonzero", "fill-opacity": "1", "stroke-opacity": "1", visibility: "visible", color: "black", opacity: 1, ctm: IDENTITY, hidden: false,
  };
  for (const t of list) {
    if (t.close) {
      const s = stack.pop();
      if (s && s.skipping) skipDepth--;
      continue;
    }
    const parent = stack.length ? stack[stack.length - 1].ctx : top;
    const a = t.attrs;
    const ctx = { ...parent };
    for (const k of INHERITED) if (a[k] !== undefined && a[k] !== "inherit") ctx[k] = a[k];
    ctx.opacity = parent.opacity * (a.opacity !== undefined ? clamp01(num(a.opacity, 1)) : 1);
    ctx.ctm = a.transform ? multiply(parent.ctm, parseTransform(a.transform)) : parent.ctm;
    ctx.hidden = parent.hidden || a.display === "none";
    const fm = /^url\(\s*['"]?#([^'")\s]+)['"]?\s*\)$/.exec((a.filter || "").trim());
    if (fm && blends.has(fm[1]) && !parent.blend) ctx.blend = { ...blends.get(fm[1]), mg: ctx.ctm };
    const cm = /^url\(\s*['"]?#([^'")\s]+)['"]?\s*\)$/.exec((a["clip-path"] || "").trim());
    if (cm && clipRects.has(cm[1])) {
      const [x, y, w, h] = clipRects.get(cm[1]);
      const box = boxOfPoints([apply(ctx.ctm, x, y), apply(ctx.ctm, x + w, y), apply(ctx.ctm, x, y + h), apply(ctx.ctm, x + w, y + h)]);
      ctx.clipBox = parent.clipBox ? intersectBoxes(parent.clipBox, box) : box;
    }
    const skipping = SKIP.has(t.name);
    if (SHAPES.has(t.name) && skipDepth === 0 && !ctx.hidden && ctx.visibility !== "hidden" && ctx.visibility !== "collapse") {
      const d0 = shapeToPath(t.name, a);
      const fill = paintOf(ctx.fill, ctx.color);
      const stroke = paintOf(ctx.stroke, ctx.color);
      const b = ctx.blend;
      const variants = b ? [{ w: b.k2, m: ctx.ctm }, { w: b.k3, m: multiply(multiply(multiply(b.mg, [1, 0, 0, 1, b.dx, b.dy]), invert(b.mg)), ctx.ctm) }] : [{ w: 1, m: ctx.ctm }];
      // The in-place bounding box, clipped: the offset copy moves it along (the clip is inside the filter).
      let inPlace = null;
      for (const v of variants) {
        const fillAlpha = v.w * ctx.opacity * clamp01(num(ctx["fill-opacity"], 1));
        const strokeAlpha = v.w * ctx.opacity * clamp01(num(ctx["stroke-opacity"], 1));
        const m = v.m;
        const scale = Math.sqrt(Math.abs(m[0] * m[3] - m[1] * m[2]));
        const strokeWidth = num(ctx["stroke-width"], 1) * scale;
        const filled = !!fill && fillAlpha > 0;
        const stroked = !!stroke && strokeAlpha > 0 && strokeWidth > 0;
        if (!d0 || !(filled || stroked)) continue;
        const d = transformPath(d0, m);
        const subpaths = flatten(d, step);
        if (b) {
          if (!inPlace) {
            const own = transformPath(d0, ctx.ctm);
            inPlace = bboxOf(flatten(own, step));
            if (ctx.clipBox) inPlace = intersectBoxes(inPlace, ctx.clipBox);
          }
          const k = multiply(v.m, invert(ctx.ctm)); // identity for the in-place copy, the offset for the other
          const [x0, y0, x1, y1] = inPlace;
          const box = x0 <= x1 && y0 <= y1 ? boxOfPoints([apply(k, x0, y0), apply(k, x1, y0), apply(k, x0, y1), apply(k, x1, y1)]) : inPlace;
          if (!boxesMeet(box, regionBox(b))) continue;
        }
        elements.push({
          tag: t.name, id: a.id || "", d, filled, stroked, fill, stroke, fillAlpha, strokeAlpha,
          fillRule: (ctx["fill-rule"] || "nonzero").trim(), strokeWidth,
          linecap: (ctx["stroke-linecap"] || "butt").trim(), linejoin: (ctx["stroke-linejoin"] || "miter").trim(), miterlimit: num(ctx["stroke-miterlimit"], 4),
          blended: !!b, subpaths,
        });
      }
    }
    if (!t.selfClosing) {
      stack.push({ ctx, skipping });
      if (skipping) skipDepth++;
    }
  }
  const rings = [];
  for (const e of elements) {
    for (const sp of e.subpaths) {
      const n = sp.points.length;
      if (e.filled) {
        if (n >= 3) rings.push({ points: sp.points, closed: true, filled: true });
        continue;
      }
      // Stroked: a zero-length subpath draws a dot under round or square caps (a ring of one point); a
      // closed subpath of two points is the segment between them, there and back (an open ring of two).
      if (n === 1 && (e.linecap === "round" || e.linecap === "square")) rings.push({ points: sp.points, closed: false, filled: false });
      else if (n === 2) rings.push({ points: sp.points, closed: false, filled: false });
      else if (n >= 3) rings.push({ points: sp.points, closed: sp.closed, filled: false });
    }
  }
  const nFill = elements.filter((e) => e.filled).length;
  const nStroke = elements.filter((e) => !e.filled && e.stroked).length;
  const kind = elements.length === 0 ? "empty" : nStroke === 0 ? "fill" : nFill === 0 ? "stroke" : "mixed";
  const se = elements.find((e) => e.stroked);
  const stroke = se ? { width: se.strokeWidth, linecap: se.linecap, linejoin: se.linejoin, miterlimit: se.miterlimit } : null;
  return { viewBox: vb, size, diag: Math.hypot(vb[2], vb[3]), elements, rings, kind, stroke };
}

/** True when the icon is "a single filled outline": exactly one closed ring, filled, no stroke-only part. */
function isSingleFilledOutline(icon) {
  return icon.kind === "fill" && icon.rings.length === 1 && icon.rings[0].closed && icon.rings[0].filled;
}

/**
 * All drawn geometry of the icon as one path `d` (root coordinates, subpaths concatenated in document
 * order), numbers rounded to 6 decimals so that none is written in exponent notation (svgpath writes
 * e.g. -2.2e-16 after a transform, which path parsers such as MorphSVGPlugin's misread).
 */
function combinedPath(icon) {
  return icon.elements.map((e) => svgpath(e.d).round(6).toString()).join(" ");
}

module.exports = { readSvgText, isSingleFilledOutline, combinedPath, flatten, shapeToPath, parseTransform, multiply, tags, transformPath };
