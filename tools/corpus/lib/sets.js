// The icon sets the corpus is drawn from: one entry per "set" (a folder of SVG files inside a pinned npm
// package), in the fixed order the draw indexes them by.
"use strict";

const fs = require("node:fs");
const path = require("node:path");

const MODULES = path.join(__dirname, "..", "node_modules");

// licenceFile: the licence text shipped in the npm package (copied into fixtures' LICENSES/).
// copyright: the holder as that file (or, for simple-icons, the package README) states it.
const SETS = [
  { name: "simple-icons", pkg: "simple-icons", dir: "icons", licence: "CC0-1.0", licenceFile: "LICENSE.md", copyright: "none claimed (CC0 1.0 dedication by the Simple Icons collaborators); the logos are trademarks of their respective owners" },
  { name: "mdi", pkg: "@mdi/svg", dir: "svg", licence: "Apache-2.0", licenceFile: "LICENSE", copyright: "Pictogrammers (Pictogrammers Free License: icons under Apache-2.0)" },
  { name: "tabler-filled", pkg: "@tabler/icons", dir: "icons/filled", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) 2020-2026 Paweł Kuna" },
  { name: "tabler-outline", pkg: "@tabler/icons", dir: "icons/outline", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) 2020-2026 Paweł Kuna" },
  { name: "lucide", pkg: "lucide-static", dir: "icons", licence: "ISC", licenceFile: "LICENSE", copyright: "Copyright (c) 2026 Lucide Icons and Contributors (icons derived from Feather: MIT, Copyright (c) 2013-present Cole Bemis)" },
  { name: "bootstrap", pkg: "bootstrap-icons", dir: "icons", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) 2019-2024 The Bootstrap Authors" },
  { name: "heroicons-solid", pkg: "heroicons", dir: "24/solid", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) Tailwind Labs, Inc." },
  { name: "heroicons-outline", pkg: "heroicons", dir: "24/outline", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) Tailwind Labs, Inc." },
  { name: "feather", pkg: "feather-icons", dir: "dist/icons", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) 2013-2023 Cole Bemis" },
  { name: "phosphor-regular", pkg: "@phosphor-icons/core", dir: "assets/regular", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) 2023 Phosphor Icons" },
  { name: "phosphor-fill", pkg: "@phosphor-icons/core", dir: "assets/fill", licence: "MIT", licenceFile: "LICENSE", copyright: "Copyright (c) 2023 Phosphor Icons" },
];

function pkgDir(set) {
  return path.join(MODULES, ...set.pkg.split("/"));
}

function pkgVersion(set) {
  return JSON.parse(fs.readFileSync(path.join(pkgDir(set), "package.json"), "utf8")).version;
}

/** The set's SVG file names, sorted by UTF-16 code units (Array.prototype.sort's default, locale-free). */
function listIcons(set) {
  const dir = path.join(pkgDir(set), set.dir);
  if (!fs.existsSync(dir)) throw new Error(`${set.name}: ${dir} is missing (run npm ci in tools/corpus)`);
  return fs.readdirSync(dir).filter((f) => f.endsWith(".svg")).sort();
}

function iconPath(set, file) {
  return path.join(pkgDir(set), set.dir, file);
}

function licenceText(set) {
  return fs.readFileSync(path.join(pkgDir(set), set.licenceFile), "utf8");
}

const byName = (name) => {
  const s = SETS.find((x) => x.name === name);
  if (!s) throw new Error(`unknown set ${name}`);
  return s;
};

module.exports = { SETS, MODULES, pkgDir, pkgVersion, listIcons, iconPath, licenceText, byName };
