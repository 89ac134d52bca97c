#!/usr/bin/env bash
# Issue 3 section 5: the seed paper's dual-body case (tower on pedestal,
# inputs/convex/duzce_statue.in) under the whole unscaled Duzce Bolu record
# (56 s), one core, no output; the fastest of REPEAT runs. Target: at most 5 s.
# Usage: bench/statue_pedestal.sh [REPEAT] [DT]   (needs build/freestand-lmp)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
repeat=${1:-3}
dt=${2:-2e-5}
log=$(mktemp)
trap 'rm -f "$log"' EXIT
best=""
for _ in $(seq "$repeat"); do
  (cd "$root/inputs/convex" && "$root/build/freestand-lmp" -in duzce_statue.in -var nout 0 \
     -var dt "$dt" -log "$log" -screen /dev/null) || { tail -5 "$log"; exit 1; }
  t=$(grep -a '^Loop time' "$log" | tail -1 | awk '{ print $4 }')
  best=$(awk -v t="$t" -v b="$best" 'BEGIN { print (b == "" || t < b) ? t : b }')
done
awk -v t="$best" -v dt="$dt" 'BEGIN {
  printf "tower on pedestal, Duzce Bolu 56 s, dt %s s: %.2f s wall (%.3f us/step, %.4f s per simulated s)\n",
         dt, t, 1e6 * t * dt / 56.0, t / 56.0 }'
