#!/usr/bin/env bash
# Issue 4 section 7: what writing results.h5 at the default output rate adds to a run.
# The demo scenario (tower on pedestal, whole Duzce Bolu record) is prepared by
# `freestand run --dry-run`; its run.in is then timed as written (fix rockslide/hdf5 at
# 200 samples per simulated second, with the energy ledger) and with that fix removed,
# each REPEAT times in alternation; the fastest loop time of each counts.
# Usage: bench/hdf5_overhead.sh [REPEAT] [SCENARIO]   (needs build/freestand, build/freestand-lmp)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
repeat=${1:-3}
scenario=${2:-$root/inputs/scenarios/statue_pedestal_duzce.json}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$root/build/freestand" run "$scenario" -o "$work" --dry-run > /dev/null
grep -v '^fix             h5 ' "$work/run.in" > "$work/no_output.in"

best_with="" best_without=""
loop() { grep -a '^Loop time' "$work/log" | tail -1 | awk '{ print $4 }'; }
for _ in $(seq "$repeat"); do
  (cd "$work" && "$root/build/freestand-lmp" -in run.in -log log -screen /dev/null)
  t=$(loop); best_with=$(awk -v t="$t" -v b="$best_with" 'BEGIN { print (b == "" || t < b) ? t : b }')
  (cd "$work" && "$root/build/freestand-lmp" -in no_output.in -log log -screen /dev/null)
  t=$(loop); best_without=$(awk -v t="$t" -v b="$best_without" 'BEGIN { print (b == "" || t < b) ? t : b }')
done
size=$(du -k "$work/results.h5" | awk '{ print $1 }')
awk -v a="$best_with" -v b="$best_without" -v kb="$size" 'BEGIN {
  printf "run with results.h5 (200 samples/s): %.2f s; without: %.2f s; HDF5 adds %.1f %% (file %.1f MB)\n",
         a, b, 100 * (a - b) / b, kb / 1024 }'
