// How each tool is driven. Every driver returns the same shape, so that the measures see only frame SVGs:
//   { frames: [svg × N] (t = i/(N−1)), exact: { "0.25": svg, "0.5": svg, "0.75": svg }, time: {…}, … }
// or throws / returns { error } on failure.
"use strict";

const fs = require("node:fs");
const path = require("node:path");
const { spawnSync } = require("node:child_process");
const { combinedPath } = require("./svg.js");

const EXACT_T = [0.25, 0.5, 0.75];

// ------------------------------------------------------------------------------------------ frame SVGs

const fmt = (x) => (Math.abs(x) < 1e-9 ? "0" : String(+x.toFixed(4)));

/** Path data of rings { points, closed } ("M x y L … Z"). */
function ringsToPath(rings) {
  return rings
    .filter((r) => r.points.length)
    .map((r) => `M${r.points.map((p) => `${fmt(p[0])} ${fmt(p[1])}`).join("L")}${r.closed ? "Z" : ""}`)
    .join("");
}

/**
 * How flubber's and gsap's frames are painted: for a source icon of kind "fill", fill #000000 with
 * fill-rule evenodd; otherwise (stroke or mixed icons) no fill and a #000000 stroke with the width, caps,
 * joins and miter limit of the source's first stroked element.
 */
function paintFor(icon) {
  if (icon.kind === "fill" || !icon.stroke) return { kind: "fill", attrs: 'fill="#000000" fill-rule="evenodd"' };
  const s = icon.stroke;
  return {
    kind: "stroke",
    attrs: `fill="none" stroke="#000000" stroke-width="${fmt(s.width)}" stroke-linecap="${s.linecap}" stroke-linejoin="${s.linejoin}" stroke-miterlimit="${fmt(s.miterlimit)}"`,
  };
}

/** A frame: one <path> with the given data and paint, in the icon's viewBox. */
function frameSvg(viewBox, d, paint) {
  const [x, y, w, h] = viewBox;
  return `<svg xmlns="http://www.w3.org/2000/svg" width="${fmt(w)}" height="${fmt(h)}" viewBox="${fmt(x)} ${fmt(y)} ${fmt(w)} ${fmt(h)}"><path d="${d}" ${paint.attrs}/></svg>`;
}

// ------------------------------------------------------------------------------------------ crmorph

const TIMER = `s=$EPOCHREALTIME; "$@"; rc=$?; e=$EPOCHREALTIME; { echo "$s $e"; times; } > "$CRMORPH_TIMES"; exit $rc`;

function seconds(s) {
  const m = /^(\d+)m([\d.]+)s$/.exec(s);
  return m ? 60 * +m[1] + +m[2] : NaN;
}

/**
 * Runs one crmorph command line. With `timed`, through bash: wall time from $EPOCHREALTIME around the
 * command, CPU time (user + system) of the command from bash's `times` (its children's line).
 */
function crmorphRun(bin, args, o, timed) {
  const opts = { encoding: "utf8", maxBuffer: 64 << 20, timeout: o.timeoutMs, killSignal: "SIGKILL", cwd: o.cwd };
  let r;
  let time = null;
  if (timed) {
    const tf = path.join(o.tmp, "times.txt");
    fs.rmSync(tf, { force: true });
    r = spawnSync("bash", ["-c", TIMER, "crmorph-timer", bin, ...args], { ...opts, env: { ...process.env, CRMORPH_TIMES: tf } });
    if (!r.error && fs.existsSync(tf)) {
      const lines = fs.readFileSync(tf, "utf8").trim().split("\n");
      const [s, e] = lines[0].split(" ").map(Number);
      const child = (lines[2] || "").trim().split(/\s+/).map(seconds);
      time = { wallMs: (e - s) * 1000, cpuMs: (child[0] + child[1]) * 1000, userMs: child[0] * 1000, sysMs: child[1] * 1000 };
    }
  } else r = spawnSync(bin, args, opts);
  const stderr = (r.stderr || "").trim();
  if (r.error) {
    const why = r.error.code === "ETIMEDOUT" ? `timed out after ${o.timeoutMs / 1000} s` : r.error.code || r.error.message;
    return { error: `${why}`, stderr };
  }
  if (r.signal) return { error: `killed by ${r.signal}`, stderr };
  if (r.status !== 0) {
    const msg = stderr.split("\n").filter(Boolean).find((l) => /^error/.test(l)) || stderr.split("\n").filter(Boolean)[0] || "";
    return { error: `exit ${r.status}${msg ? `: ${msg}` : ""}`, stderr };
  }
  return { stderr, time };
}

/**
 * crmorph, four steps per pair (all with --frames N):
 *  (a) `morph SRC TGT -o OUT.svg --frames N --quiet`, timed: the 60-frame animated SVG;
 *  (b) `morph SRC TGT -o OUT.svg --frames N --frames-dir DIR --frame-format svg --quiet`: the frames;
 *  (c) `morph SRC TGT -o OUT.json --frames N` (without --quiet, so that its stderr holds crmorph's note
 *      about the automatic mode): the meshes, for the flips;
 *  (d) `frame SRC TGT --at T -o F.svg --quiet` for T = 0.25, 0.5, 0.75: the exact frames for the ghost.
 * A non-zero exit (or a timeout) in any step fails the pair; the message names the step.
 */
function runCrmorph(pair, o) {
  const bin = o.crmorph;
  fs.mkdirSync(o.tmp, { recursive: true }); // recreated if something removed it under a running job
  const dir = fs.mkdtempSync(path.join(o.tmp, "cr-"));
  // Run in the corpus folder with the icons' relative paths, so that crmorph's messages name them short.
  const rel = !!(o.corpus && pair.source && pair.target);
  const opt = { ...o, tmp: dir, cwd: rel ? o.corpus : undefined };
  pair = rel ? { ...pair, src: pair.source, tgt: pair.target } : pair;
  try {
    const N = String(o.frames);
    const a = crmorphRun(bin, ["morph", pair.src, pair.tgt, "-o", path.join(dir, "anim.svg"), "--frames", N, "--view", "source", "--quiet"], opt, true);
    if (a.error) return { error: `morph → .svg: ${a.error}`, stderr: a.stderr };
    const fdir = path.join(dir, "frames");
    const b = crmorphRun(bin, ["morph", pair.src, pair.tgt, "-o", path.join(dir, "anim2.svg"), "--frames", N, "--frames-dir", fdir, "--frame-format", "svg", "--view", "source", "--quiet"], opt, false);
    if (b.error) return { error: `morph --frames-dir: ${b.error}`, stderr: b.stderr };
    const files = fs.readdirSync(fdir).filter((f) => /^frame_\d+\.svg$/.test(f)).sort((x, y) => parseInt(x.slice(6), 10) - parseInt(y.slice(6), 10));
    if (files.length !== o.frames) return { error: `morph --frames-dir wrote ${files.length} frames, not ${o.frames}` };
    const frames = files.map((f) => fs.readFileSync(path.join(fdir, f), "utf8"));
    const c = crmorphRun(bin, ["morph", pair.src, pair.tgt, "-o", path.join(dir, "mesh.json"), "--frames", N], opt, false);
    if (c.error) return { error: `morph → .json: ${c.error}`, stderr: c.stderr };
    const mesh = JSON.parse(fs.readFileSync(path.join(dir, "mesh.json"), "utf8"));
    const exact = {};
    for (const t of EXACT_T) {
      const out = path.join(dir, `at-${t}.svg`);
      const r = crmorphRun(bin, ["frame", pair.src, pair.tgt, "--at", String(t), "-o", out, "--quiet"], opt, false);
      if (r.error) return { error: `frame --at ${t}: ${r.error}`, stderr: r.stderr };
      exact[t] = fs.readFileSync(out, "utf8");
    }
    // The mesh JSON: { frames: [{ t, triangles?, vertices, curves }] }, triangles per frame or at the top.
    const tris = mesh.triangles || (mesh.frames[0] && mesh.frames[0].triangles) || [];
    const verts = mesh.frames.map((f) => f.vertices);
    return { frames, exact, time: a.time, stderr: c.stderr, mesh: { triangles: tris, vertices: verts, frames: mesh.frames.length } };
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
}

// ------------------------------------------------------------------------------------------ flubber

let flubber = null;

/**
 * flubber interpolators for the rings of the two icons, paired in document order:
 *   n = m       interpolateAll(S, T)            (n = m = 1: interpolate)
 *   n = 1 < m   separate(S0, T)
 *   n > 1 = m   combine(S, T0)
 *   otherwise   interpolateAll on the first k − 1 = min(n, m) − 1 rings, combine / separate of the rest
 *               into / out of ring k.
 */
function flubberInterpolators(S, T, opts) {
  flubber = flubber || require("flubber");
  const n = S.length, m = T.length;
  if (n === 0 || m === 0) throw new Error("an icon has no ring");
  if (n === m) return n === 1 ? [flubber.interpolate(S[0], T[0], opts)] : flubber.interpolateAll(S, T, opts);
  if (n === 1) return flubber.separate(S[0], T, opts);
  if (m === 1) return flubber.combine(S, T[0], opts);
  const k = Math.min(n, m);
  const head = k > 1 ? flubber.interpolateAll(S.slice(0, k - 1), T.slice(0, k - 1), opts) : [];
  const tail = n > m ? flubber.combine(S.slice(k - 1), T[k - 1], opts) : flubber.separate(S[k - 1], T.slice(k - 1), opts);
  return head.concat(tail);
}

function flubberOnce(src, tgt, o) {
  const S = src.rings.map((r) => r.points);
  const T = tgt.rings.map((r) => r.points);
  const opts = { maxSegmentLength: o.seg * Math.max(src.size, tgt.size), string: true, single: false };
  const start = process.hrtime.bigint();
  const fns = flubberInterpolators(S, T, opts);
  const ds = [];
  for (let i = 0; i < o.frames; i++) {
    const t = i / (o.frames - 1);
    ds.push(fns.map((f) => f(t)).join(""));
  }
  const ms = Number(process.hrtime.bigint() - start) / 1e6;
  return { fns, ds, ms };
}

/** flubber: one untimed warm-up run, then the timed run (interpolators + the N frame strings). */
function runFlubber(src, tgt, o) {
  flubberOnce(src, tgt, o);
  const { fns, ds, ms } = flubberOnce(src, tgt, o);
  const paint = paintFor(src);
  const frames = ds.map((d) => frameSvg(src.viewBox, d, paint));
  const exact = {};
  for (const t of EXACT_T) exact[t] = frameSvg(src.viewBox, fns.map((f) => f(t)).join(""), paint);
  return { frames, exact, time: { ms } };
}

// ------------------------------------------------------------------------------------------ gsap

let G = null;

/**
 * gsap + MorphSVGPlugin in a jsdom window (set up once per process). MorphSVGPlugin reads the target's
 * computed `fill` and `fillRule` (its "fillSafe" test, which decides whether it may reverse a subpath's
 * direction); jsdom's getComputedStyle does not map SVG presentation attributes, so for SVG elements it
 * is wrapped to report them as a browser would.
 */
function gsapEnv() {
  if (G) return G;
  const { JSDOM } = require("jsdom");
  const dom = new JSDOM('<!DOCTYPE html><html><body><svg xmlns="http://www.w3.org/2000/svg"></svg></body></html>');
  const win = dom.window;
  const orig = win.getComputedStyle.bind(win);
  win.getComputedStyle = (el, pseudo) => {
    const cs = orig(el, pseudo);
    if (!el || el.namespaceURI !== "http://www.w3.org/2000/svg") return cs;
    return new Proxy(cs, {
      get(target, prop) {
        if (prop === "fill") return el.getAttribute("fill") ?? (target.fill || "rgb(0, 0, 0)");
        if (prop === "fillRule") return el.getAttribute("fill-rule") ?? (target.fillRule || "nonzero");
        const v = target[prop];
        return typeof v === "function" ? v.bind(target) : v;
      },
    });
  };
  global.window = win;
  global.document = win.document;
  const { gsap } = require("gsap");
  const { MorphSVGPlugin } = require("gsap/MorphSVGPlugin");
  gsap.registerPlugin(MorphSVGPlugin);
  G = { gsap, MorphSVGPlugin, win, svg: win.document.querySelector("svg") };
  return G;
}

function gsapOnce(srcD, tgtD, paint, o, exactTs) {
  const { gsap, win, svg } = gsapEnv();
  const el = win.document.createElementNS("http://www.w3.org/2000/svg", "path");
  if (paint.kind === "fill") {
    el.setAttribute("fill", "#000000");
    el.setAttribute("fill-rule", "evenodd");
  } else {
    el.setAttribute("fill", "none");
    el.setAttribute("stroke", "#000000");
  }
  svg.appendChild(el);
  try {
    const start = process.hrtime.bigint();
    el.setAttribute("d", srcD);
    const tween = gsap.to(el, { morphSVG: tgtD, duration: 1, ease: "none", paused: true });
    const ds = [];
    for (let i = 0; i < o.frames; i++) {
      tween.progress(i / (o.frames - 1));
      ds.push(el.getAttribute("d"));
    }
    const ms = Number(process.hrtime.bigint() - start) / 1e6;
    const exact = {};
    for (const t of exactTs) {
      tween.progress(t);
      exact[t] = el.getAttribute("d");
    }
    tween.kill();
    return { ds, ms, exact };
  } finally {
    el.remove();
  }
}

/**
 * gsap MorphSVGPlugin: each icon's drawn geometry as one path `d` (the subpaths of all its drawn elements
 * in document order, transforms applied, curves and arcs kept), a <path> with the source's `d` in the
 * jsdom document, `gsap.to(path, { morphSVG: targetD, duration: 1, ease: "none", paused: true })` with
 * MorphSVG's defaults otherwise (shapeIndex "auto", map "size", type "linear"), and the `d` attribute read
 * after `tween.progress(i/(N−1))`. One untimed warm-up run, then the timed run.
 */
function runGsap(src, tgt, o) {
  const srcD = combinedPath(src), tgtD = combinedPath(tgt);
  if (!srcD || !tgtD) throw new Error("an icon draws nothing");
  const paint = paintFor(src);
  gsapOnce(srcD, tgtD, paint, o, []);
  const { ds, ms, exact: ex } = gsapOnce(srcD, tgtD, paint, o, EXACT_T);
  if (ds.some((d) => !d)) throw new Error("MorphSVGPlugin left the path without d");
  const frames = ds.map((d) => frameSvg(src.viewBox, d, paint));
  const exact = {};
  for (const t of EXACT_T) exact[t] = frameSvg(src.viewBox, ex[t], paint);
  return { frames, exact, time: { ms } };
}

function versions() {
  const v = (p) => {
    try {
      return require(`${p}/package.json`).version;
    } catch (e) {
      return "?";
    }
  };
  return { flubber: v("flubber"), gsap: v("gsap"), jsdom: v("jsdom"), resvg: v("@resvg/resvg-js"), svgpath: v("svgpath") };
}

module.exports = { runCrmorph, runFlubber, runGsap, flubberInterpolators, frameSvg, paintFor, ringsToPath, gsapEnv, versions, EXACT_T, crmorphRun };
