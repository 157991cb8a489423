#!/usr/bin/env node
// Runs crmorph, flubber and gsap MorphSVG on every pair of the drawn corpus, scores their frames with the
// same code (lib/score.js) and writes one JSON row per pair and tool, a Markdown table and a contact
// sheet. See README.md.
"use strict";

const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { fork, spawnSync } = require("node:child_process");

const HERE = __dirname;
const ROOT = path.resolve(HERE, "..", "..");
const TOOLS = ["crmorph", "flubber", "gsap"];

const USAGE = `usage: node run.js [--corpus .cache/corpus] [--crmorph PATH] [--tools crmorph,flubber,gsap]
                   [--only ID[,ID…]] [--limit N] [--jobs 1] [--out-json rows.jsonl] [--out-md table.md]
                   [--sheet sheet.png] [--frames 60] [--px 240] [--seg 0.01] [--timeout 300]
                   [--work .cache/run] [--sample 12] [--report-only]`;

function parseArgs(argv) {
  const o = {
    corpus: path.join(HERE, ".cache", "corpus"), crmorph: path.join(ROOT, "target", "release", "crmorph"), tools: TOOLS.join(","),
    only: null, limit: null, jobs: 1, outJson: null, outMd: null, sheet: null, frames: 60, px: 240, seg: 0.01, timeout: 300,
    work: path.join(HERE, ".cache", "run"), sample: 12, reportOnly: false, worker: false,
  };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const val = () => {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      return argv[++i];
    };
    if (a === "--corpus") o.corpus = path.resolve(val());
    else if (a === "--crmorph") o.crmorph = path.resolve(val());
    else if (a === "--tools") o.tools = val();
    else if (a === "--only") o.only = val();
    else if (a === "--limit") o.limit = parseInt(val(), 10);
    else if (a === "--jobs") o.jobs = parseInt(val(), 10);
    else if (a === "--out-json") o.outJson = path.resolve(val());
    else if (a === "--out-md") o.outMd = path.resolve(val());
    else if (a === "--sheet") o.sheet = path.resolve(val());
    else if (a === "--frames") o.frames = parseInt(val(), 10);
    else if (a === "--px") o.px = parseInt(val(), 10);
    else if (a === "--seg") o.seg = parseFloat(val());
    else if (a === "--timeout") o.timeout = parseFloat(val());
    else if (a === "--work") o.work = path.resolve(val());
    else if (a === "--sample") o.sample = parseInt(val(), 10);
    else if (a === "--report-only") o.reportOnly = true;
    else if (a === "--worker") o.worker = true;
    else if (a === "-h" || a === "--help") {
      console.log(USAGE);
      process.exit(0);
    } else throw new Error(`unknown argument ${a}\n${USAGE}`);
  }
  o.toolList = o.tools.split(",").map((s) => s.trim()).filter(Boolean);
  for (const t of o.toolList) if (!TOOLS.includes(t)) throw new Error(`unknown tool ${t} (crmorph, flubber, gsap)`);
  if (!(o.frames >= 2)) throw new Error("--frames must be at least 2");
  if (!(o.jobs >= 1 && o.jobs <= 2)) throw new Error("--jobs must be 1 or 2 (the machine has 2 cores)");
  o.timeoutMs = o.timeout * 1000;
  return o;
}

function loadPairs(o) {
  const file = path.join(o.corpus, "pairs.json");
  if (!fs.existsSync(file)) throw new Error(`${file} is missing: run draw.js first`);
  const doc = JSON.parse(fs.readFileSync(file, "utf8"));
  let pairs = doc.pairs.map((p) => ({ ...p, src: path.join(o.corpus, p.source), tgt: path.join(o.corpus, p.target) }));
  if (o.only) {
    const ids = new Set(o.only.split(",").map((s) => s.trim()));
    pairs = pairs.filter((p) => ids.has(p.id));
  }
  if (o.limit) pairs = pairs.slice(0, o.limit);
  return { doc, pairs };
}

/** The contact sheet's pairs: every k-th of the pairs run, k = max(1, ⌊n / sample⌋), from the first. */
function samplePairs(pairs, n) {
  const k = Math.max(1, Math.floor(pairs.length / n));
  const out = [];
  for (let i = 0; i < pairs.length && out.length < n; i += k) out.push(pairs[i].id);
  return out;
}

// ------------------------------------------------------------------------------------------ one pair

function processPair(pair, o, sheetIds) {
  const { readSvgText } = require("./lib/svg.js");
  const T = require("./lib/tools.js");
  const { score, describeIcon } = require("./lib/score.js");
  const { render } = require("./lib/render.js");
  const srcText = fs.readFileSync(pair.src, "utf8"), tgtText = fs.readFileSync(pair.tgt, "utf8");
  const src = readSvgText(srcText, pair.source);
  const tgt = readSvgText(tgtText, pair.target);
  const base = {
    id: pair.id, set: pair.set, source: pair.source, target: pair.target, single: !!pair.single_filled_outline,
    sourceIcon: describeIcon(src, srcText, src), targetIcon: describeIcon(tgt, tgtText, src),
  };
  const rows = [];
  for (const tool of o.toolList) {
    const row = { ...base, tool };
    const t0 = Date.now();
    let res;
    try {
      if (tool === "crmorph") res = T.runCrmorph(pair, o);
      else if (tool === "flubber") res = T.runFlubber(src, tgt, o);
      else res = T.runGsap(src, tgt, o);
    } catch (e) {
      res = { error: `${e.message}`.split("\n")[0] };
    }
    if (res.stderr !== undefined) row.stderr = res.stderr;
    if (res.error) {
      row.ok = false;
      row.error = res.error;
    } else {
      try {
        Object.assign(row, { ok: true }, score(res, src, tgt, o), { time: res.time });
        if (sheetIds.has(pair.id)) {
          const dir = path.join(o.work, "sheet");
          fs.mkdirSync(dir, { recursive: true });
          const cells = [res.frames[0], res.exact[0.25], res.exact[0.5], res.exact[0.75], res.frames[res.frames.length - 1]];
          cells.forEach((svg, k) => fs.writeFileSync(path.join(dir, `${pair.id}-${tool}-${k}.png`), render(svg, 96, { png: true }).png));
        }
      } catch (e) {
        row.ok = false;
        row.error = `scoring failed: ${e.message}`;
      }
    }
    row.seconds = (Date.now() - t0) / 1000;
    rows.push(row);
  }
  return rows;
}

function logLine(rows) {
  const r0 = rows[0];
  const f = (r) => {
    if (!r.ok) return `${r.tool} FAIL (${r.error.slice(0, 80)})`;
    const ms = r.time.wallMs !== undefined ? `${r.time.wallMs.toFixed(0)} ms` : `${r.time.ms.toFixed(1)} ms`;
    return `${r.tool} ghost ${r.ghost.toFixed(3)} x ${(100 * r.crossingShare).toFixed(0)}% ends ${r.ends.toExponential(1)} ${ms}`;
  };
  return `${r0.id} ${r0.set}: ${rows.map(f).join(" | ")}`;
}

// ------------------------------------------------------------------------------------------ main

async function runAll(o, pairs, sheetIds, onRows) {
  if (o.jobs <= 1) {
    for (const p of pairs) {
      onRows(processPair(p, o, sheetIds), process.memoryUsage().rss);
      // Back to the event loop after each pair: resvg-js frees a rendered image's native memory in a
      // finalizer that only runs from the event loop, so a loop that never yields grows by ~0.5 MB a render.
      await new Promise((resolve) => setImmediate(resolve));
    }
    return;
  }
  await new Promise((resolve, reject) => {
    let next = 0, live = 0;
    const start = () => {
      const w = fork(__filename, ["--worker"], { stdio: ["ignore", "inherit", "inherit", "ipc"] });
      live++;
      const feed = () => {
        if (next < pairs.length) w.send({ pair: pairs[next++] });
        else w.send({ done: true });
      };
      w.on("message", (m) => {
        if (m.ready) w.send({ o: { ...o }, sheetIds: [...sheetIds] });
        else if (m.rows) onRows(m.rows, m.rss);
        if (m.ready || m.rows) feed();
      });
      w.on("exit", (code) => {
        live--;
        if (code !== 0) reject(new Error(`a worker exited with ${code}`));
        else if (live === 0) resolve();
      });
    };
    for (let j = 0; j < Math.min(o.jobs, pairs.length); j++) start();
    if (pairs.length === 0) resolve();
  });
}

function worker() {
  let o = null, sheetIds = null;
  process.on("message", (m) => {
    if (m.o) {
      o = m.o;
      sheetIds = new Set(m.sheetIds);
      o.tmp = fs.mkdtempSync(path.join(os.tmpdir(), `crmorph-corpus-${process.pid}-`));
      return;
    }
    if (m.done) {
      fs.rmSync(o.tmp, { recursive: true, force: true });
      process.disconnect();
      process.exit(0);
    }
    if (m.pair) process.send({ rows: processPair(m.pair, o, sheetIds), rss: process.memoryUsage().rss });
  });
  process.send({ ready: true });
}

function crmorphVersion(bin) {
  const r = spawnSync(bin, ["--version"], { encoding: "utf8" });
  return r.status === 0 ? r.stdout.trim() : `not runnable (${r.error ? r.error.code : `exit ${r.status}`})`;
}

async function main() {
  const o = parseArgs(process.argv.slice(2));
  if (o.worker) return worker();
  const report = require("./lib/report.js");
  const { doc, pairs } = loadPairs(o);
  const sheetIds = new Set(samplePairs(pairs, o.sample));
  const outJson = o.outJson || path.join(o.work, "rows.jsonl");
  let rows = [];
  let elapsed = null;
  if (o.reportOnly) {
    rows = fs.readFileSync(outJson, "utf8").split("\n").filter(Boolean).map((l) => JSON.parse(l));
  } else {
    fs.mkdirSync(o.work, { recursive: true });
    fs.rmSync(path.join(o.work, "sheet"), { recursive: true, force: true });
    o.tmp = fs.mkdtempSync(path.join(os.tmpdir(), `crmorph-corpus-${process.pid}-`));
    fs.mkdirSync(path.dirname(outJson), { recursive: true });
    const partial = `${outJson}.partial`;
    fs.writeFileSync(partial, "");
    const t0 = Date.now();
    let done = 0;
    await runAll(o, pairs, sheetIds, (rs, rss) => {
      rows.push(...rs);
      fs.appendFileSync(partial, rs.map((r) => JSON.stringify(r)).join("\n") + "\n");
      done++;
      process.stderr.write(`[${done}/${pairs.length}] ${logLine(rs)} (rss ${(rss / 2 ** 20).toFixed(0)} MiB)\n`);
    });
    elapsed = (Date.now() - t0) / 1000;
    fs.rmSync(o.tmp, { recursive: true, force: true });
    const order = new Map(pairs.map((p, i) => [p.id, i]));
    rows.sort((a, b) => order.get(a.id) - order.get(b.id) || o.toolList.indexOf(a.tool) - o.toolList.indexOf(b.tool));
    fs.writeFileSync(outJson, rows.map((r) => JSON.stringify(r)).join("\n") + "\n");
    fs.rmSync(partial, { force: true });
  }
  const tools = o.toolList.filter((t) => rows.some((r) => r.tool === t));
  const meta = {
    command: `node tools/corpus/run.js ${process.argv.slice(2).join(" ")}`.trim(),
    crmorph: o.crmorph, crmorphVersion: tools.includes("crmorph") ? crmorphVersion(o.crmorph) : null,
    versions: { node: process.version, ...require("./lib/tools.js").versions() },
    corpus: { seed: doc.seed, count: doc.count, sets: doc.sets }, frames: o.frames, px: o.px, seg: o.seg, jobs: o.jobs,
    elapsed, pairsRun: new Set(rows.map((r) => r.id)).size,
  };
  if (o.outMd) {
    fs.mkdirSync(path.dirname(o.outMd), { recursive: true });
    fs.writeFileSync(o.outMd, report.table(rows, tools, meta));
  } else if (!o.sheet) process.stdout.write(report.table(rows, tools, meta));
  if (o.sheet) {
    fs.mkdirSync(path.dirname(o.sheet), { recursive: true });
    const ids = [...sheetIds].filter((id) => rows.some((r) => r.id === id));
    fs.writeFileSync(o.sheet, report.sheet(rows, tools, ids, path.join(o.work, "sheet")));
  }
  if (elapsed !== null) process.stderr.write(`done: ${meta.pairsRun} pairs in ${elapsed.toFixed(0)} s\n`);
}

if (require.main === module) {
  main().catch((e) => {
    console.error(`run: ${e.stack || e.message}`);
    process.exit(2);
  });
}

module.exports = { samplePairs, parseArgs };
