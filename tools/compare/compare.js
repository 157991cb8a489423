#!/usr/bin/env node
// Morphs the icon pairs with flubber and with crmorph and tabulates, per pair, the share of frames in
// which a morphing contour crosses itself, the area's dip and bulge relative to the linear blend of the
// end areas, the error at the ends and the time per transition. See README.md.
"use strict";

const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { spawnSync } = require("node:child_process");
const flubber = require("flubber");
const { readIcon } = require("./svg.js");
const metrics = require("./metrics.js");

const HERE = __dirname;
const ROOT = path.resolve(HERE, "..", "..");

function parseArgs(argv) {
  const o = { crmorph: path.join(ROOT, "target", "release", "crmorph"), out: null, frames: 60, seg: 0.01, only: null, tools: "flubber,crmorph", json: null, pairs: path.join(HERE, "pairs.json"), fixtures: true };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const val = () => {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      return argv[++i];
    };
    if (a === "--crmorph") o.crmorph = val();
    else if (a === "--out") o.out = val();
    else if (a === "--frames") o.frames = parseInt(val(), 10);
    else if (a === "--seg") o.seg = parseFloat(val());
    else if (a === "--only") o.only = val();
    else if (a === "--tools") o.tools = val();
    else if (a === "--json") o.json = val();
    else if (a === "--pairs") o.pairs = path.resolve(val());
    else if (a === "--no-fixtures") o.fixtures = false;
    else if (a === "-h" || a === "--help") {
      console.log("usage: node tools/compare/compare.js [--crmorph PATH] [--out FILE.md] [--json FILE] [--frames 60] [--seg 0.01] [--only SUBSTRING] [--tools flubber,crmorph] [--pairs FILE.json] [--no-fixtures]");
      process.exit(0);
    } else throw new Error(`unknown argument ${a}`);
  }
  if (!(o.frames >= 2)) throw new Error("--frames must be at least 2");
  return o;
}

/** The pairs: every fixtures/icons/NAME/{source,target}.svg, then the list in pairs.json (paths relative to that file). */
function loadPairs(o) {
  const pairs = [];
  const fx = path.join(ROOT, "fixtures", "icons");
  if (o.fixtures && fs.existsSync(fx)) {
    for (const name of fs.readdirSync(fx).sort()) {
      const s = path.join(fx, name, "source.svg");
      const t = path.join(fx, name, "target.svg");
      if (fs.existsSync(s) && fs.existsSync(t)) pairs.push({ name, source: s, target: t });
    }
  }
  const dir = path.dirname(o.pairs);
  const list = JSON.parse(fs.readFileSync(o.pairs, "utf8")).pairs;
  for (const p of list) pairs.push({ name: p.name, source: path.resolve(dir, p.source), target: path.resolve(dir, p.target) });
  return pairs;
}

// ---------------------------------------------------------------------------------------------- flubber

/**
 * Builds flubber interpolators for all contours (rings) of the two icons, one per output piece.
 * flubber morphs single rings and has no notion of holes or of matching, so the pieces are paired in
 * document order:
 *   n = m       interpolateAll(S, T)            (n = m = 1: interpolate)
 *   n = 1 < m   separate(S0, T)                 (the one ring is triangulated into m pieces)
 *   n > 1 = m   combine(S, T0)
 *   otherwise   interpolateAll on the first k − 1 = min(n, m) − 1 rings, and combine / separate of the
 *               rest into / out of ring k.
 */
function flubberInterpolators(S, T, opts) {
  const n = S.length, m = T.length;
  if (n === 0 || m === 0) throw new Error("an icon has no contour");
  if (n === m) return n === 1 ? [flubber.interpolate(S[0], T[0], opts)] : flubber.interpolateAll(S, T, opts);
  if (n === 1) return flubber.separate(S[0], T, opts);
  if (m === 1) return flubber.combine(S, T[0], opts);
  const k = Math.min(n, m);
  const head = k > 1 ? flubber.interpolateAll(S.slice(0, k - 1), T.slice(0, k - 1), opts) : [];
  const tail = n > m ? flubber.combine(S.slice(k - 1), T[k - 1], opts) : flubber.separate(S[k - 1], T.slice(k - 1), opts);
  return head.concat(tail);
}

/** Parses flubber's output ("M x,y L x,y … Z", possibly several rings) into closed contours. */
function parseRings(d) {
  const out = [];
  for (const part of d.split(/(?=M)/)) {
    const nums = part.match(/-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) || [];
    const pts = [];
    for (let i = 0; i + 1 < nums.length; i += 2) pts.push([+nums[i], +nums[i + 1]]);
    if (pts.length) out.push({ points: pts, closed: /Z\s*$/i.test(part) });
  }
  return out;
}

function runFlubber(src, tgt, o) {
  const S = src.contours.map((c) => c.points);
  const T = tgt.contours.map((c) => c.points);
  const seg = o.seg * Math.max(src.size, tgt.size);
  const opts = { maxSegmentLength: seg, string: true, single: false };
  const start = process.hrtime.bigint();
  const fns = flubberInterpolators(S, T, opts);
  const strings = [];
  for (let i = 0; i < o.frames; i++) {
    const t = i / (o.frames - 1);
    strings.push({ t, ds: fns.map((f) => f(t)) });
  }
  const ms = Number(process.hrtime.bigint() - start) / 1e6;
  const frames = strings.map(({ t, ds }) => ({ t, contours: ds.flatMap(parseRings) }));
  return { frames, ms };
}

// ---------------------------------------------------------------------------------------------- crmorph

/** Runs `crmorph morph SRC TGT -o JSON --frames N --quiet`, timed; the contours are the non-boundary curves. */
function runCrmorph(pair, o, tmp) {
  const out = path.join(tmp, "frames.json");
  fs.rmSync(out, { force: true });
  const start = process.hrtime.bigint();
  const r = spawnSync(o.crmorph, ["morph", pair.source, pair.target, "-o", out, "--frames", String(o.frames), "--quiet"], { encoding: "utf8", maxBuffer: 64 << 20 });
  const ms = Number(process.hrtime.bigint() - start) / 1e6;
  if (r.error) return { error: `cannot run ${o.crmorph}: ${r.error.code || r.error.message}` };
  if (r.status !== 0) {
    const msg = (r.stderr || "").trim().split("\n").filter(Boolean)[0] || `exit ${r.status}`;
    return { error: `exit ${r.status}: ${msg}` };
  }
  const doc = JSON.parse(fs.readFileSync(out, "utf8"));
  const frames = doc.frames.map((f) => ({
    t: f.t,
    contours: f.curves
      .filter((c) => c.name !== "boundary")
      .map((c) => {
        let idx = c.vertices;
        if (c.closed && idx.length > 1 && idx[0] === idx[idx.length - 1]) idx = idx.slice(0, -1);
        return { points: idx.map((i) => f.vertices[i]), closed: !!c.closed, name: c.name };
      }),
  }));
  if (frames.length === 0) return { error: "no frames in the output" };
  return { frames, ms };
}

// ---------------------------------------------------------------------------------------------- table

function measure(run, src, tgt) {
  const size = Math.max(src.size, tgt.size);
  const st = metrics.morphStats(run.frames, size);
  return { ...st, endError: metrics.endError(run.frames, src.contours, tgt.contours, size), ms: run.ms };
}

const pct = (x) => (x === undefined || x === null ? "–" : `${(100 * x).toFixed(0)}%`);
const fix = (x, d = 3) => (x === undefined || x === null ? "–" : x.toFixed(d));
const sci = (x) => (x === undefined || x === null ? "–" : x === 0 ? "0" : Number.isFinite(x) ? x.toExponential(1) : "∞");
const ms = (x) => (x === undefined || x === null ? "–" : x < 10 ? x.toFixed(2) : x.toFixed(1));

function describe(src, tgt) {
  const kind = (ic) => (ic.contours.length === 0 ? "none" : ic.contours.every((c) => !c.closed) ? "open" : ic.contours.some((c) => !c.closed) ? "mixed" : "");
  const k = [kind(src), kind(tgt)].filter(Boolean);
  return `${src.contours.length}→${tgt.contours.length}${k.length ? " " + [...new Set(k)].join("/") : ""}`;
}

function mean(xs) {
  const v = xs.filter((x) => x !== null && x !== undefined && Number.isFinite(x));
  return v.length ? v.reduce((a, b) => a + b, 0) / v.length : null;
}

function table(rows, tools) {
  const has = (t) => tools.includes(t);
  const cols = [];
  const add = (head, f) => cols.push({ head, f });
  add("pair", (r) => r.name);
  add("contours", (r) => r.shape);
  const metricCols = [
    ["self-crossing frames", (m) => pct(m.crossingShare)],
    ["area min", (m) => fix(m.areaMin)],
    ["area max", (m) => fix(m.areaMax)],
    ["end error", (m) => sci(m.endError)],
    ["ms", (m) => ms(m.ms)],
  ];
  for (const [head, f] of metricCols) {
    for (const tool of ["flubber", "crmorph"]) {
      if (has(tool)) add(`${head} (${tool === "flubber" ? "fl" : "cr"})`, (r) => (r[tool] && r[tool].m ? f(r[tool].m) : r[tool] ? "fail" : "–"));
    }
  }
  const lines = [];
  lines.push(`| ${cols.map((c) => c.head).join(" | ")} |`);
  lines.push(`|${cols.map((c, i) => (i < 2 ? "---" : "--:")).join("|")}|`);
  for (const r of rows) lines.push(`| ${cols.map((c) => c.f(r)).join(" | ")} |`);

  // Aggregate over the pairs every selected tool handled.
  const both = rows.filter((r) => tools.every((t) => r[t] && r[t].m));
  const agg = {};
  for (const t of tools) {
    const ms_ = both.map((r) => r[t].m);
    agg[t] = {
      crossingShare: mean(ms_.map((m) => m.crossingShare)),
      areaMin: mean(ms_.map((m) => m.areaMin)),
      areaMax: mean(ms_.map((m) => m.areaMax)),
      endError: mean(ms_.map((m) => m.endError)),
      ms: mean(ms_.map((m) => m.ms)),
      crossingPairs: ms_.filter((m) => m.crossingFrames > 0).length,
      worstMin: ms_.reduce((a, m) => (m.areaMin === null ? a : Math.min(a, m.areaMin)), Infinity),
      worstEnd: ms_.reduce((a, m) => Math.max(a, m.endError), 0),
    };
  }
  const aggRow = (label, pick) => `| ${cols.map((c, i) => (i === 0 ? label : i === 1 ? `${both.length} pairs` : pick(c))).join(" | ")} |`;
  const colTool = (c) => (c.head.endsWith("(fl)") ? "flubber" : "crmorph");
  const byHead = (c, a) => {
    const h = c.head.replace(/ \((fl|cr)\)$/, "");
    const m = a[colTool(c)];
    if (!m) return "–";
    return { "self-crossing frames": pct(m.crossingShare), "area min": fix(m.areaMin), "area max": fix(m.areaMax), "end error": sci(m.endError), ms: ms(m.ms) }[h];
  };
  const worst = (c) => {
    const h = c.head.replace(/ \((fl|cr)\)$/, "");
    const m = agg[colTool(c)];
    if (!m) return "–";
    return { "self-crossing frames": `${m.crossingPairs} pair${m.crossingPairs === 1 ? "" : "s"}`, "area min": Number.isFinite(m.worstMin) ? fix(m.worstMin) : "–", "area max": "", "end error": sci(m.worstEnd), ms: "" }[h];
  };
  if (both.length) {
    lines.push(aggRow("**mean**", (c) => byHead(c, agg)));
    lines.push(aggRow("**worst**", worst));
  }
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------------- main

function main() {
  const o = parseArgs(process.argv.slice(2));
  const tools = o.tools.split(",").map((s) => s.trim()).filter((s) => s === "flubber" || s === "crmorph");
  let pairs = loadPairs(o);
  if (o.only) pairs = pairs.filter((p) => p.name.includes(o.only));
  if (tools.includes("flubber") && pairs.length) {
    // One untimed run first, so that the timed runs do not pay for compiling flubber's code.
    try {
      runFlubber(readIcon(pairs[0].source), readIcon(pairs[0].target), o);
    } catch (e) {
      /* the timed run reports it */
    }
  }
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), "crmorph-compare-"));
  const rows = [];
  const failures = [];
  for (const p of pairs) {
    const row = { name: p.name };
    let src, tgt;
    try {
      src = readIcon(p.source);
      tgt = readIcon(p.target);
      row.shape = describe(src, tgt);
    } catch (e) {
      failures.push(`${p.name}: cannot read: ${e.message}`);
      continue;
    }
    for (const tool of tools) {
      let run;
      try {
        run = tool === "flubber" ? runFlubber(src, tgt, o) : runCrmorph(p, o, tmp);
      } catch (e) {
        run = { error: e.message };
      }
      if (run.error) {
        row[tool] = { error: run.error };
        failures.push(`${p.name}: ${tool}: ${run.error}`);
      } else row[tool] = { m: measure(run, src, tgt) };
    }
    rows.push(row);
    process.stderr.write(`${p.name}: ${tools.map((t) => `${t} ${row[t].m ? `${ms(row[t].m.ms)} ms` : "fail"}`).join(", ")}\n`);
  }
  fs.rmSync(tmp, { recursive: true, force: true });

  const fl = require("flubber/package.json").version;
  const md = [
    `Icon morphs, ${o.frames} frames each (t = i/${o.frames - 1}); flubber ${fl} with maxSegmentLength = ${o.seg} × icon size; crmorph: \`${path.relative(ROOT, o.crmorph) || o.crmorph}\`.`,
    "",
    "Self-crossing frames: share of frames where a contour crosses itself. Area min/max: extremes over frames of the total enclosed area over the linear blend of the end areas (1 = no dip or bulge; – for line icons). End error: largest vertex-to-outline distance at t = 0 and t = 1 against the input outlines, in units of the icon size. ms: one whole transition (flubber: interpolators + frames in-process; crmorph: the CLI run incl. start-up, reading and writing JSON). Mean/worst rows: over the pairs every tool handled.",
    "",
    table(rows, tools),
    "",
  ];
  if (failures.length) md.push(`Failures (${failures.length}):`, "", ...failures.map((f) => `- ${f}`), "");
  const text = md.join("\n");
  if (o.out) fs.writeFileSync(o.out, text);
  else process.stdout.write(text);
  if (o.json) fs.writeFileSync(o.json, JSON.stringify(rows, null, 1));
}

if (require.main === module) {
  try {
    main();
  } catch (e) {
    console.error(`compare: ${e.message}`);
    process.exit(2);
  }
}

module.exports = { flubberInterpolators, parseRings, loadPairs };
