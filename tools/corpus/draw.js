#!/usr/bin/env node
// Draws the benchmark corpus: `--pairs N` ordered icon pairs from the icon sets of lib/sets.js, at random
// with a fixed seed, and copies the icons (currentColor → #000000) with a pairs.json. See README.md.
//
// The draw, with rand = mulberry32(seed) (lib/prng.js) and the sets in the order of lib/sets.js:
//   repeat until N pairs:
//     set    = SETS[floor(rand() · 11)]
//     files  = that set's *.svg names sorted by UTF-16 code units
//     i      = floor(rand() · n)            (n = files.length)
//     j      = floor(rand() · (n − 1)); if j ≥ i then j += 1      (so j ≠ i, uniform over the others)
//     if (set, i, j) was drawn before, drop it and go on (ordered pairs: (i, j) and (j, i) are different)
"use strict";

const fs = require("node:fs");
const path = require("node:path");
const { mulberry32, randInt } = require("./lib/prng.js");
const S = require("./lib/sets.js");
const { readSvgText, isSingleFilledOutline } = require("./lib/svg.js");

function parseArgs(argv) {
  const o = { seed: 2026, pairs: 320, out: path.join(__dirname, ".cache", "corpus") };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const val = () => {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      return argv[++i];
    };
    if (a === "--seed") o.seed = Number(val());
    else if (a === "--pairs") o.pairs = parseInt(val(), 10);
    else if (a === "--out") o.out = path.resolve(val());
    else if (a === "-h" || a === "--help") {
      console.log("usage: node draw.js [--seed 2026] [--pairs 320] [--out .cache/corpus]");
      process.exit(0);
    } else throw new Error(`unknown argument ${a}`);
  }
  if (!Number.isInteger(o.seed)) throw new Error("--seed must be an integer");
  if (!(o.pairs >= 1)) throw new Error("--pairs must be at least 1");
  return o;
}

/** The icon copy: the file as shipped, with every `currentColor` replaced by #000000. */
function normalise(text) {
  return text.replace(/currentColor/g, "#000000");
}

/** The draw itself (pure: seed, count and the sets' sorted file lists in, the list of picks out). */
function drawPairs(seed, count, lists) {
  const rand = mulberry32(seed);
  const seen = new Set();
  const picks = [];
  let draws = 0;
  while (picks.length < count) {
    if (++draws > count * 100) throw new Error("too many repeated draws");
    const s = randInt(rand, lists.length);
    const n = lists[s].length;
    if (n < 2) continue;
    const i = randInt(rand, n);
    let j = randInt(rand, n - 1);
    if (j >= i) j += 1;
    const key = `${s}:${i}:${j}`;
    if (seen.has(key)) continue;
    seen.add(key);
    picks.push({ set: s, i, j });
  }
  return picks;
}

/**
 * simple-icons states a licence for some logos in its data file (data/simple-icons.json, `license`):
 * file name → { type, url? } for those.
 */
function simpleIconsLicences() {
  const set = S.byName("simple-icons");
  const file = require("node:path").join(S.pkgDir(set), "data", "simple-icons.json");
  const out = new Map();
  if (!fs.existsSync(file)) return out;
  const data = JSON.parse(fs.readFileSync(file, "utf8"));
  for (const ic of Array.isArray(data) ? data : data.icons || []) if (ic.license && ic.slug) out.set(`${ic.slug}.svg`, ic.license);
  return out;
}

function main() {
  const o = parseArgs(process.argv.slice(2));
  const lists = S.SETS.map((s) => S.listIcons(s));
  const siLicences = simpleIconsLicences();
  const picks = drawPairs(o.seed, o.pairs, lists);
  fs.mkdirSync(path.join(o.out, "icons"), { recursive: true });
  const width = Math.max(3, String(o.pairs).length);
  const copied = new Map();
  const copy = (set, file) => {
    const rel = path.posix.join("icons", set.name, file);
    if (!copied.has(rel)) {
      const text = normalise(fs.readFileSync(S.iconPath(set, file), "utf8"));
      fs.mkdirSync(path.join(o.out, "icons", set.name), { recursive: true });
      fs.writeFileSync(path.join(o.out, rel), text);
      const icon = readSvgText(text, rel);
      copied.set(rel, { kind: icon.kind, rings: icon.rings.length, single: isSingleFilledOutline(icon) });
    }
    return { rel, ...copied.get(rel) };
  };
  const pairs = picks.map((p, k) => {
    const set = S.SETS[p.set];
    const src = copy(set, lists[p.set][p.i]);
    const tgt = copy(set, lists[p.set][p.j]);
    const pair = {
      id: `p${String(k + 1).padStart(width, "0")}`,
      set: set.name,
      package: `${set.pkg}@${S.pkgVersion(set)}`,
      source: src.rel,
      target: tgt.rel,
      licence: set.licence,
      source_kind: src.kind,
      target_kind: tgt.kind,
      source_rings: src.rings,
      target_rings: tgt.rings,
      single_filled_outline: src.single && tgt.single,
    };
    if (set.name === "simple-icons") {
      // The logo's own licence where simple-icons' data states one (else the package's CC0-1.0 applies).
      for (const [k, f] of [["source_icon_licence", lists[p.set][p.i]], ["target_icon_licence", lists[p.set][p.j]]]) {
        if (siLicences.has(f)) pair[k] = siLicences.get(f);
      }
    }
    return pair;
  });
  const doc = {
    seed: o.seed,
    count: pairs.length,
    prng: "mulberry32; set = floor(u·11), i = floor(u·n), j = floor(u·(n−1)) (+1 when ≥ i); repeats redrawn",
    sets: S.SETS.map((s, k) => ({ name: s.name, package: `${s.pkg}@${S.pkgVersion(s)}`, dir: s.dir, licence: s.licence, copyright: s.copyright, icons: lists[k].length })),
    normalisation: "currentColor → #000000; otherwise the files as shipped",
    pairs,
  };
  fs.writeFileSync(path.join(o.out, "pairs.json"), JSON.stringify(doc, null, 1) + "\n");
  const single = pairs.filter((p) => p.single_filled_outline).length;
  const perSet = {};
  for (const p of pairs) perSet[p.set] = (perSet[p.set] || 0) + 1;
  process.stderr.write(`${pairs.length} pairs (${single} single filled outline → single filled outline), ${copied.size} icons in ${o.out}\n`);
  process.stderr.write(`per set: ${Object.entries(perSet).map(([k, v]) => `${k} ${v}`).join(", ")}\n`);
}

if (require.main === module) {
  try {
    main();
  } catch (e) {
    console.error(`draw: ${e.message}`);
    process.exit(2);
  }
}

module.exports = { drawPairs, normalise };
