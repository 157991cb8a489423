#!/usr/bin/env node
// Copies the first N pairs of the drawn corpus (icons as drawn, a pairs.json, the icon sets' licence
// texts from their npm packages and a README) into a folder of the repository, for tests that cannot
// run npm. See README.md.
"use strict";

const fs = require("node:fs");
const path = require("node:path");
const S = require("./lib/sets.js");

function parseArgs(argv) {
  const o = { n: 40, corpus: path.join(__dirname, ".cache", "corpus"), out: path.resolve(__dirname, "..", "..", "fixtures", "corpus") };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const val = () => {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      return argv[++i];
    };
    if (a === "--n") o.n = parseInt(val(), 10);
    else if (a === "--corpus") o.corpus = path.resolve(val());
    else if (a === "--out") o.out = path.resolve(val());
    else if (a === "-h" || a === "--help") {
      console.log("usage: node export-sample.js [--n 40] [--corpus .cache/corpus] [--out ../../fixtures/corpus]");
      process.exit(0);
    } else throw new Error(`unknown argument ${a}`);
  }
  if (!(o.n >= 1)) throw new Error("--n must be at least 1");
  return o;
}

/** The licence file's name in LICENSES/: the package name without @ and with / → -, then the file's own name. */
function licenceName(set) {
  return `${set.pkg.replace(/^@/, "").replace(/\//g, "-")}-${set.licenceFile}`;
}

function main() {
  const o = parseArgs(process.argv.slice(2));
  const doc = JSON.parse(fs.readFileSync(path.join(o.corpus, "pairs.json"), "utf8"));
  const pairs = doc.pairs.slice(0, o.n);
  if (pairs.length < o.n) throw new Error(`the corpus has only ${pairs.length} pairs`);
  // Start clean: the folder is generated (only what this script writes is removed).
  for (const sub of ["icons", "LICENSES"]) fs.rmSync(path.join(o.out, sub), { recursive: true, force: true });
  fs.mkdirSync(path.join(o.out, "LICENSES"), { recursive: true });
  const files = new Set();
  for (const p of pairs) {
    for (const rel of [p.source, p.target]) {
      if (files.has(rel)) continue;
      files.add(rel);
      fs.mkdirSync(path.dirname(path.join(o.out, rel)), { recursive: true });
      fs.copyFileSync(path.join(o.corpus, rel), path.join(o.out, rel));
    }
  }
  const setNames = S.SETS.map((s) => s.name).filter((n) => pairs.some((p) => p.set === n));
  const licenceFiles = new Map();
  for (const name of setNames) {
    const set = S.byName(name);
    const file = licenceName(set);
    licenceFiles.set(name, file);
    fs.writeFileSync(path.join(o.out, "LICENSES", file), S.licenceText(set));
    if (set.licence === "Apache-2.0" && !/TERMS AND CONDITIONS/.test(S.licenceText(set))) {
      // @mdi/svg's LICENSE names Apache-2.0 by its URL only; the Apache licence asks for its text to go along.
      const apache = "/usr/share/common-licenses/Apache-2.0"; // Debian's base-files
      if (fs.existsSync(apache)) fs.copyFileSync(apache, path.join(o.out, "LICENSES", "Apache-2.0.txt"));
      else process.stderr.write(`warning: ${apache} is missing: LICENSES/ has no full Apache-2.0 text for ${name}\n`);
    }
    if (name === "simple-icons") {
      const disc = path.join(S.pkgDir(set), "DISCLAIMER.md");
      if (fs.existsSync(disc)) fs.copyFileSync(disc, path.join(o.out, "LICENSES", "simple-icons-DISCLAIMER.md"));
    }
  }
  const out = { ...doc, count: pairs.length, note: `the first ${pairs.length} of the ${doc.count} pairs drawn by tools/corpus/draw.js (seed ${doc.seed})`, pairs };
  fs.writeFileSync(path.join(o.out, "pairs.json"), JSON.stringify(out, null, 1) + "\n");

  const L = [];
  L.push("# Corpus sample (automatic mode)");
  L.push("");
  L.push(`The first ${pairs.length} of the ${doc.count} icon pairs that \`tools/corpus/draw.js --seed ${doc.seed} --pairs ${doc.count}\` draws at random`);
  L.push("from npm icon sets (see `tools/corpus/README.md`), copied by `tools/corpus/export-sample.js` so that Rust");
  L.push("integration tests can use them without npm. Generated: do not edit by hand; rerun the script instead.");
  L.push("");
  L.push("`pairs.json` lists each pair (`id`, `set`, `package`, `source`, `target`, `licence`, the icons' kinds and ring");
  L.push("counts as tools/corpus reads them, and `single_filled_outline`: both icons are exactly one closed filled ring).");
  L.push(`The icons are the files of the npm packages with one change: ${doc.normalisation}.`);
  L.push("");
  L.push("| set | package | icons here | licence | copyright | licence text |");
  L.push("|---|---|--:|---|---|---|");
  for (const name of setNames) {
    const set = S.byName(name);
    const n = [...files].filter((f) => f.startsWith(`icons/${name}/`)).length;
    L.push(`| ${name} | ${set.pkg}@${S.pkgVersion(set)} (\`${set.dir}/\`) | ${n} | ${set.licence} | ${set.copyright} | [\`LICENSES/${licenceFiles.get(name)}\`](LICENSES/${licenceFiles.get(name)}) |`);
  }
  L.push("");
  if (fs.existsSync(path.join(o.out, "LICENSES", "Apache-2.0.txt"))) {
    L.push("@mdi/svg's licence file (the Pictogrammers Free License) names Apache-2.0 for the icons by its URL;");
    L.push("the full text is in `LICENSES/Apache-2.0.txt` (copied from Debian's `/usr/share/common-licenses/Apache-2.0`).");
    L.push("");
  }
  if (setNames.includes("simple-icons")) {
    L.push("simple-icons: the package is CC0-1.0, but the logos are trademarks of their owners and may be subject to");
    L.push("their brand guidelines; see `LICENSES/simple-icons-DISCLAIMER.md`.");
    const own = pairs.flatMap((p) => [["source", p.source, p.source_icon_licence], ["target", p.target, p.target_icon_licence]]).filter((x) => x[2]);
    if (own.length) {
      L.push("Logos for which simple-icons' data states a licence of their own:");
      L.push("");
      for (const [, f, lic] of own) L.push(`- \`${f}\`: ${lic.type}${lic.url ? ` (${lic.url})` : ""}`);
    } else L.push("None of the logos here has a licence of its own in simple-icons' data (`data/simple-icons.json`).");
    L.push("");
  }
  L.push("## Pairs");
  L.push("");
  L.push("| id | set | source | target | single filled outline |");
  L.push("|---|---|---|---|---|");
  for (const p of pairs) L.push(`| ${p.id} | ${p.set} | \`${path.basename(p.source)}\` | \`${path.basename(p.target)}\` | ${p.single_filled_outline ? "yes" : ""} |`);
  L.push("");
  fs.writeFileSync(path.join(o.out, "README.md"), L.join("\n"));
  process.stderr.write(`${pairs.length} pairs, ${files.size} icons, ${setNames.length} licences → ${o.out}\n`);
}

if (require.main === module) {
  try {
    main();
  } catch (e) {
    console.error(`export-sample: ${e.message}`);
    process.exit(2);
  }
}

module.exports = { licenceName };
