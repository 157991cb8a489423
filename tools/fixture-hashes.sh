#!/usr/bin/env bash
# The outputs of every bundled fixture pair, hashed, so that two builds can be checked to write
# the same bytes (a refactor's "behaviour kept"): `crmorph morph` to .svg, .json, .gif, .png
# (APNG) and .html, and `crmorph frame --at 0.37` to .png, .svg and .json, for each
# fixtures/**/source.svg with its target.svg. Failures are listed as FAIL lines; stderr goes to
# OUTDIR/err.txt.
#
# Usage: bash tools/fixture-hashes.sh CRMORPH OUTDIR   (then diff two OUTDIR/hashes.txt, e.g.
#        diff <(sed 's# .*/# #' A/hashes.txt) <(sed 's# .*/# #' B/hashes.txt))
set -u
bin=$(realpath "$1"); out=$(realpath -m "$2"); mkdir -p "$out"
cd "$(dirname "$0")/.."
: > "$out/hashes.txt"
: > "$out/err.txt"
for s in $(find fixtures -name source.svg | sort); do
  d=$(dirname "$s"); n=$(echo "$d" | tr / _)
  for ext in svg json gif png html; do
    "$bin" --quiet morph "$s" "$d/target.svg" -o "$out/$n.$ext" 2>>"$out/err.txt" \
      || echo "FAIL $n.$ext" >> "$out/hashes.txt"
  done
  for ext in png svg json; do
    "$bin" --quiet frame "$s" "$d/target.svg" --at 0.37 -o "$out/$n.f.$ext" 2>>"$out/err.txt" \
      || echo "FAIL $n.f.$ext" >> "$out/hashes.txt"
  done
done
(cd "$out" && sha256sum -- *.svg *.json *.gif *.png *.html >> hashes.txt)
