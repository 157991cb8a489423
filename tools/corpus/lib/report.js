// The Markdown table and the contact sheet, from the rows run.js writes (one per pair and tool).
"use strict";

const fs = require("node:fs");
const path = require("node:path");
const { median, percentile } = require("./measures.js");
const { render } = require("./render.js");
const { CRISP } = require("./score.js");

const pct = (k, n) => (n ? `${((100 * k) / n).toFixed(1)}% (${k}/${n})` : "–");
const num3 = (x) => (x === null || x === undefined ? "–" : Number.isFinite(x) ? x.toFixed(3) : "∞");
const sci = (x) => (x === null || x === undefined ? "–" : x === 0 ? "0" : Number.isFinite(x) ? x.toExponential(2) : "∞");
const ms = (x) => (x === null || x === undefined ? "–" : x < 10 ? x.toFixed(2) : x.toFixed(1));

function stats(rows, tool) {
  const all = rows.filter((r) => r.tool === tool);
  const ok = all.filter((r) => r.ok);
  const single = all.filter((r) => r.single);
  const vals = (f) => ok.map(f).filter((x) => x !== null && x !== undefined);
  const s = {
    run: all.length, ok: ok.length, failures: all.length - ok.length,
    crisp: ok.filter((r) => r.crisp).length,
    singleRun: single.length, singleCrisp: single.filter((r) => r.ok && r.crisp).length,
    ghostMedian: median(vals((r) => r.ghost)), ghostP90: percentile(vals((r) => r.ghost), 0.9),
    crossingPairs: ok.filter((r) => r.crossingFrames > 0).length,
    crossingMean: ok.length ? ok.reduce((a, r) => a + r.crossingShare, 0) / ok.length : null,
    selfPairs: ok.filter((r) => r.selfCrossingShare > 0).length,
    selfMean: ok.length ? ok.reduce((a, r) => a + r.selfCrossingShare, 0) / ok.length : null,
    areaMinMedian: median(vals((r) => r.areaMin)), areaMinWorst: vals((r) => r.areaMin).reduce((a, x) => Math.min(a, x), Infinity),
    areaMaxMedian: median(vals((r) => r.areaMax)), areaMaxWorst: vals((r) => r.areaMax).reduce((a, x) => Math.max(a, x), -Infinity),
    areaNone: ok.filter((r) => r.areaMin === null).length,
    endsMedian: median(vals((r) => r.ends)), endsWorst: vals((r) => r.ends).reduce((a, x) => Math.max(a, x), -Infinity),
    endsInfinite: ok.filter((r) => !Number.isFinite(r.ends)).length,
  };
  if (!Number.isFinite(s.areaMinWorst)) s.areaMinWorst = null;
  if (s.areaMaxWorst === -Infinity) s.areaMaxWorst = null;
  if (s.endsWorst === -Infinity) s.endsWorst = null;
  if (tool === "crmorph") {
    s.flipPairs = ok.filter((r) => r.flips > 0).length;
    s.flipTotal = ok.reduce((a, r) => a + (r.flips || 0), 0);
    s.wallMedian = median(vals((r) => r.time && r.time.wallMs));
    s.wallP99 = percentile(vals((r) => r.time && r.time.wallMs), 0.99);
    s.cpuMedian = median(vals((r) => r.time && r.time.cpuMs));
    s.cpuP99 = percentile(vals((r) => r.time && r.time.cpuMs), 0.99);
  } else {
    s.msMedian = median(vals((r) => r.time && r.time.ms));
    s.msP99 = percentile(vals((r) => r.time && r.time.ms), 0.99);
  }
  return s;
}

function table(rows, tools, meta) {
  const S = Object.fromEntries(tools.map((t) => [t, stats(rows, t)]));
  const L = [];
  L.push(`# crmorph vs flubber vs gsap MorphSVG on ${meta.pairsRun} random icon pairs`);
  L.push("");
  L.push(`Command: \`${meta.command}\``);
  L.push("");
  const v = meta.versions;
  L.push(`Versions: Node ${v.node}; crmorph \`${meta.crmorph}\` (${meta.crmorphVersion || "not run"}); flubber ${v.flubber}; gsap ${v.gsap} (MorphSVGPlugin) in jsdom ${v.jsdom}; @resvg/resvg-js ${v.resvg}; svgpath ${v.svgpath}.`);
  L.push("");
  const sets = meta.corpus.sets.map((s) => `${s.name} (${s.package}, ${s.icons} icons)`).join(", ");
  L.push(`Corpus: seed ${meta.corpus.seed}, ${meta.corpus.count} pairs drawn (draw.js); sets: ${sets}.`);
  L.push("");
  L.push(`${meta.frames} frames per morph (t = i/${meta.frames - 1}); renders ${meta.px} px on the longer side over white; ghost at the exact t = 0.25, 0.5, 0.75; flubber maxSegmentLength = ${meta.seg} × icon size.` +
    (meta.elapsed !== null && meta.elapsed !== undefined ? ` Run time ${(meta.elapsed / 60).toFixed(1)} min with --jobs ${meta.jobs}.` : ""));
  L.push("");
  L.push("Medians, p90 and worst values are over the pairs the tool handled; crisp shares count every pair run (a failure is not crisp). Definitions: README.md.");
  L.push("");
  const row = (label, f) => L.push(`| ${label} | ${tools.map((t) => f(S[t], t)).join(" | ")} |`);
  L.push(`| measure | ${tools.join(" | ")} |`);
  L.push(`|---|${tools.map(() => "--:").join("|")}|`);
  row("pairs run", (s) => `${s.run}`);
  row("failures", (s) => `${s.failures}`);
  row(`crisp (ghost < ${CRISP.toFixed(2)}), all pairs`, (s) => pct(s.crisp, s.run));
  row("crisp, pairs of two single filled outlines", (s) => pct(s.singleCrisp, s.singleRun));
  row("ghost median", (s) => num3(s.ghostMedian));
  row("ghost p90", (s) => num3(s.ghostP90));
  row("pairs with a self-crossing frame", (s) => pct(s.crossingPairs, s.ok));
  row("mean self-crossing share of frames", (s) => (s.crossingMean === null ? "–" : `${(100 * s.crossingMean).toFixed(1)}%`));
  row("… of which a ring crossing itself: pairs", (s) => pct(s.selfPairs, s.ok));
  row("… of which a ring crossing itself: mean share", (s) => (s.selfMean === null ? "–" : `${(100 * s.selfMean).toFixed(1)}%`));
  row("area min: median", (s) => num3(s.areaMinMedian));
  row("area min: worst", (s) => num3(s.areaMinWorst));
  row("area max: median", (s) => num3(s.areaMaxMedian));
  row("area max: worst", (s) => num3(s.areaMaxWorst));
  row("ends: median", (s) => sci(s.endsMedian));
  row("ends: worst", (s) => sci(s.endsWorst));
  row("flips: pairs with any", (s, t) => (t === "crmorph" ? pct(s.flipPairs, s.ok) : "n/a"));
  row("flips: inverted triangles, total", (s, t) => (t === "crmorph" ? `${s.flipTotal}` : "n/a"));
  row("time median, ms", (s, t) => (t === "crmorph" ? `wall ${ms(s.wallMedian)}, CPU ${ms(s.cpuMedian)}` : ms(s.msMedian)));
  row("time p99, ms", (s, t) => (t === "crmorph" ? `wall ${ms(s.wallP99)}, CPU ${ms(s.cpuP99)}` : ms(s.msP99)));
  L.push("");
  L.push("Time: crmorph is the whole CLI writing the 60-frame animated SVG (process start-up and file I/O included); flubber and gsap are in-process (interpolators + 60 frames, after one untimed warm-up): not like for like.");
  L.push("");

  // Context.
  const pairs = [...new Map(rows.map((r) => [r.id, r])).values()];
  const inputCross = pairs.filter((r) => (r.sourceIcon && r.sourceIcon.crossing) || (r.targetIcon && r.targetIcon.crossing)).length;
  const kinds = {};
  for (const r of pairs) {
    const k = r.sourceIcon ? `${r.sourceIcon.kind}→${r.targetIcon.kind}` : "?";
    kinds[k] = (kinds[k] || 0) + 1;
  }
  const repainted = pairs.filter((r) => r.sourceIcon && [r.sourceIcon.repaint, r.targetIcon.repaint].some((x) => x !== null && x > 0.01));
  const repaintedFill = repainted.filter((r) => r.sourceIcon.kind === "fill").length;
  L.push(`Repainting: flubber's and gsap's frames draw all rings as one path, fill-rule evenodd for filled icons, one stroke style for the others. For ${repainted.length} of ${pairs.length} pairs (${repaintedFill} of them filled) the source or target icon itself has more than 1 % less or more ink when drawn that way (overlapping subpaths cancel under evenodd; filled parts of mixed icons become outlines); the end frames of those pairs differ from the icons for that reason alone (area uses each tool's own end frames, ends is geometric, so neither counts it).`);
  L.push("");
  const ghostly = pairs.filter((r) => r.sourceIcon && Math.max(r.sourceIcon.ghost, r.targetIcon.ghost) >= CRISP).length;
  L.push(`Context: for ${ghostly} of ${pairs.length} pairs the source or target icon itself, rendered as shipped, has a ghost ≥ ${CRISP.toFixed(2)} (thin lines have no solid core), so even a cut from one to the other would not count as crisp.` +
    ` ${inputCross} of ${pairs.length} pairs have a source or target icon whose own rings already cross (e.g. the two strokes of an "x"), so their first or last frame counts as self-crossing for any tool that reproduces the ends. Icon kinds (source→target): ${Object.entries(kinds).map(([k, n]) => `${k} ${n}`).join(", ")}.` +
    ` Area is "–" for ${tools.map((t) => `${t} ${S[t].areaNone}`).join(", ")} pairs (no ink at either end); ends is ∞ for ${tools.map((t) => `${t} ${S[t].endsInfinite}`).join(", ")} pairs (an end frame with no ring at all).`);
  L.push("");

  // Per set.
  L.push("## Crisp pairs per set");
  L.push("");
  L.push(`| set | pairs | ${tools.join(" | ")} |`);
  L.push(`|---|--:|${tools.map(() => "--:").join("|")}|`);
  const setNames = meta.corpus.sets.map((s) => s.name).filter((n) => rows.some((r) => r.set === n));
  for (const name of setNames) {
    const n = pairs.filter((r) => r.set === name).length;
    L.push(`| ${name} | ${n} | ${tools.map((t) => {
      const rs = rows.filter((r) => r.tool === t && r.set === name);
      return pct(rs.filter((r) => r.ok && r.crisp).length, rs.length);
    }).join(" | ")} |`);
  }
  L.push("");

  // Failures.
  const fails = rows.filter((r) => !r.ok);
  L.push(`## Failures (${fails.length})`);
  L.push("");
  if (!fails.length) L.push("None.");
  for (const r of fails) L.push(`- ${r.id} (${r.set}: ${path.basename(r.source)} → ${path.basename(r.target)}), ${r.tool}: ${r.error.replace(/\s+/g, " ").slice(0, 300)}`);
  L.push("");
  return L.join("\n");
}

const esc = (s) => s.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;").replace(/"/g, "&quot;");

/**
 * The contact sheet: one row per sample pair and tool, columns t = 0, ¼, ½, ¾, 1 (cells rendered at 96 px
 * by run.js into `cellDir`), composed as one SVG with the cells as PNG data URIs, rendered by resvg-js.
 */
function sheet(rows, tools, ids, cellDir) {
  const CELL = 96, GAP = 4, LABEL = 170, HEAD = 26;
  const cols = ["t = 0", "t = 1/4", "t = 1/2", "t = 3/4", "t = 1"];
  const W = LABEL + cols.length * (CELL + GAP) + GAP;
  const lines = ids.flatMap((id) => tools.map((tool) => ({ id, tool, row: rows.find((r) => r.id === id && r.tool === tool) })));
  const H = HEAD + lines.length * (CELL + GAP) + GAP;
  const parts = [`<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" width="${W}" height="${H}" viewBox="0 0 ${W} ${H}" font-family="DejaVu Sans" font-size="12">`];
  parts.push(`<rect width="${W}" height="${H}" fill="#ffffff"/>`);
  cols.forEach((c, k) => parts.push(`<text x="${LABEL + GAP + k * (CELL + GAP) + CELL / 2}" y="17" text-anchor="middle" fill="#333">${c}</text>`));
  lines.forEach(({ id, tool, row }, i) => {
    const y = HEAD + i * (CELL + GAP);
    if (i > 0 && lines[i - 1].id !== id) parts.push(`<line x1="0" x2="${W}" y1="${y - GAP / 2}" y2="${y - GAP / 2}" stroke="#999" stroke-width="1"/>`);
    const set = row ? row.set : "";
    const names = row ? `${path.basename(row.source, ".svg")} → ${path.basename(row.target, ".svg")}` : "";
    parts.push(`<text x="6" y="${y + 22}" font-weight="bold">${esc(id)} ${esc(tool)}</text>`);
    parts.push(`<text x="6" y="${y + 40}" fill="#555" font-size="10">${esc(set)}</text>`);
    parts.push(`<text x="6" y="${y + 54}" fill="#555" font-size="9">${esc(names.length > 34 ? names.slice(0, 33) + "…" : names)}</text>`);
    if (row && row.ok) parts.push(`<text x="6" y="${y + 70}" fill="#555" font-size="10">ghost ${row.ghost.toFixed(2)}${row.crisp ? " (crisp)" : ""}</text>`);
    cols.forEach((_, k) => {
      const x = LABEL + GAP + k * (CELL + GAP);
      parts.push(`<rect x="${x - 0.5}" y="${y - 0.5}" width="${CELL + 1}" height="${CELL + 1}" fill="none" stroke="#ddd"/>`);
      const f = path.join(cellDir, `${id}-${tool}-${k}.png`);
      if (row && row.ok && fs.existsSync(f)) {
        parts.push(`<image x="${x}" y="${y}" width="${CELL}" height="${CELL}" xlink:href="data:image/png;base64,${fs.readFileSync(f).toString("base64")}"/>`);
      } else if (k === 0) {
        parts.push(`<text x="${x + 4}" y="${y + 20}" fill="#b00" font-size="11">${row ? "failed" : "not run"}</text>`);
      }
    });
  });
  parts.push("</svg>");
  return render(parts.join(""), Math.max(W, H), { fonts: true, png: true }).png;
}

module.exports = { table, sheet, stats };
