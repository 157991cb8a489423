#!/bin/sh
# Pairs per second and peak memory of `crmorph batch` on the 40 pairs of fixtures/corpus/pairs.json
# (docs/batch.md has the results): animated SVG and GIF outputs, 30 frames, --jobs 2 and 1, each run
# RUNS times (default 5) with /usr/bin/time -v. Needs jq and a release build
# (cargo build --release -p crmorph-cli). Usage: tools/batch-bench.sh [WORK_DIR]
set -eu
REPO=$(cd "$(dirname "$0")/.." && pwd)
BIN=${CRMORPH:-${CARGO_TARGET_DIR:-$REPO/target}/release/crmorph}
W=${1:-${TMPDIR:-/tmp}/crmorph-batch-bench}
RUNS=${RUNS:-5}
rm -rf "$W" && mkdir -p "$W" && cd "$W"
for ext in svg gif; do
  jq -c --arg d "$REPO/fixtures/corpus" --arg e "$ext" \
    '.pairs[] | {source: ($d + "/" + .source), target: ($d + "/" + .target),
                 output: ("out-" + $e + "/" + .id + "." + $e)}' \
    "$REPO/fixtures/corpus/pairs.json" > "corpus-$ext.jsonl"
done
echo "format jobs run wall_s pairs_per_s peak_rss_mib cpu load_1min summary"
for ext in svg gif; do
  for jobs in 2 1; do
    run=1
    while [ "$run" -le "$RUNS" ]; do
      load=$(cut -d' ' -f1 /proc/loadavg)
      /usr/bin/time -v "$BIN" batch "corpus-$ext.jsonl" --frames 30 --jobs "$jobs" --force \
        --quiet --report "report-$ext-$jobs.jsonl" 2> time.txt || true
      wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' time.txt |
        awk -F: '{ s = 0; for (i = 1; i <= NF; i++) s = s * 60 + $i; print s }')
      rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' time.txt)
      cpu=$(sed -n 's/.*Percent of CPU this job got: //p' time.txt)
      n=$(wc -l < "report-$ext-$jobs.jsonl")
      summary=$(jq -s -c '{ok: map(select(.status == "ok")) | length,
        failed: map(select(.status == "failed")) | length,
        crisp: map(select(.crisp == true)) | length,
        inverted: (map(.inverted_triangles // 0) | add)}' "report-$ext-$jobs.jsonl")
      echo "$ext $jobs $run $wall $(echo "$n $wall" | awk '{ printf "%.1f", $1 / $2 }') \
$(echo "$rss" | awk '{ printf "%.1f", $1 / 1024 }') $cpu $load $summary"
      run=$((run + 1))
    done
  done
done
