#!/usr/bin/env bash
# Instructions of whole-CLI automatic-mode runs under callgrind (issue 16), for changes too
# small for the VM's drifting clock: `crmorph morph SRC TGT -o out.svg --frames 30 -q` on a
# fixed set of corpus pairs, one line per pair and the total. Two builds' totals compare
# exactly; time them with tools/auto-cpu-ab.py as well.
#
#   median   eight pairs whose CPU time lay at the median of the two corpora (seeds 2026 and 7)
#   slowest  the six slowest pairs of each corpus (measured 2026-12-07)
#
# Usage: bash tools/icount.sh CRMORPH [median|slowest]
# (the corpora as docs/benchmarks-auto.md makes them, in tools/corpus/.cache; valgrind needed)
set -eu
bin=$(realpath "$1")
set_name=${2:-median}
cache="$(cd "$(dirname "$0")" && pwd)/corpus/.cache"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
case "$set_name" in
median)
  pairs='corpus icons/mdi/blinds-vertical.svg icons/mdi/account-music.svg
corpus icons/tabler-filled/arrow-big-up-lines.svg icons/tabler-filled/battery-2.svg
corpus icons/simple-icons/mingww64.svg icons/simple-icons/maildotcom.svg
corpus icons/tabler-filled/military-rank.svg icons/tabler-filled/mountain.svg
corpus7 icons/heroicons-solid/clock.svg icons/heroicons-solid/phone-x-mark.svg
corpus7 icons/phosphor-fill/currency-eur-fill.svg icons/phosphor-fill/screencast-fill.svg
corpus7 icons/phosphor-fill/parallelogram-fill.svg icons/phosphor-fill/arrow-bend-right-down-fill.svg
corpus7 icons/mdi/door-sliding-open.svg icons/mdi/tshirt-v.svg' ;;
slowest)
  pairs='corpus7 icons/phosphor-fill/google-chrome-logo-fill.svg icons/phosphor-fill/mask-sad-fill.svg
corpus7 icons/mdi/clipboard-account.svg icons/mdi/cart-outline.svg
corpus7 icons/mdi/kettle-alert-outline.svg icons/mdi/fridge-alert.svg
corpus7 icons/simple-icons/aboutdotme.svg icons/simple-icons/paradoxinteractive.svg
corpus7 icons/bootstrap/twitch.svg icons/bootstrap/building-fill.svg
corpus7 icons/simple-icons/ray.svg icons/simple-icons/7zip.svg
corpus icons/phosphor-regular/currency-btc.svg icons/phosphor-regular/compass-tool.svg
corpus icons/phosphor-regular/sphere.svg icons/phosphor-regular/train.svg
corpus icons/simple-icons/underscoredotjs.svg icons/simple-icons/theguardian.svg
corpus icons/simple-icons/asda.svg icons/simple-icons/optimism.svg
corpus icons/phosphor-fill/fingerprint-simple-fill.svg icons/phosphor-fill/newspaper-clipping-fill.svg
corpus icons/simple-icons/hotelsdotcom.svg icons/simple-icons/applepay.svg' ;;
*) echo "usage: bash tools/icount.sh CRMORPH [median|slowest]" >&2; exit 2 ;;
esac
total=0
while read -r corpus src tgt; do
  n=$(cd "$cache/$corpus" && valgrind --tool=callgrind --callgrind-out-file=/dev/null \
        "$bin" morph "$src" "$tgt" -o "$out/out.svg" --frames 30 -q 2>&1 \
      | awk '/refs:/ { gsub(",", "", $NF); print $NF }')
  echo "$corpus $src $tgt $n"
  total=$((total + n))
done <<< "$pairs"
echo "total $total"
