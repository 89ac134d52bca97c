#!/usr/bin/env bash
# Issue 3 section 5: one block on the shake table under the unscaled Duzce Bolu
# record, as a stock multisphere clump on a moving mesh (inputs/shake_table/duzce_rocking.in)
# and as a convex body on the analytic table plane (inputs/convex/duzce_rocking.in), side by
# side in this script. Same block (1.0 x 1.0 x 3.0 m, 8100 kg, mu 0.55), no output.
# Each engine runs at the time step at which it is within 1 % of Housner's free-rocking
# amplitude map (docs/benchmarks.md): the clump at 2e-5 s (issue 2), the convex body
# (corner nodes, k_a 1e10, e 0.05) at half its critical step 6.25e-5 s (0.20 %) and at
# 1.2e-4 s (0.45 %); the convex body also at the clump's 2e-5 s (equal time step).
# Each case runs REPEAT times; the fastest run counts.
# Usage: bench/convex_vs_multisphere.sh [REPEAT]   (needs build/freestand-lmp)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
lmp="$root/build/freestand-lmp"
repeat=${1:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

fastest() {  # DIR SCRIPT DT [VARIABLES...]: fastest loop time of the longest run, in seconds
  local dir=$1 script=$2 dt=$3 best=""
  shift 3
  for _ in $(seq "$repeat"); do
    (cd "$dir" && "$lmp" -in "$script" -var nout 0 -var dt "$dt" "$@" -log "$work/log" -screen /dev/null)
    t=$(grep -a '^Loop time' "$work/log" | awk '{ if ($9 + 0 > n) { n = $9; t = $4 } } END { print t }')
    best=$(awk -v t="$t" -v b="$best" 'BEGIN { print (b == "" || t < b) ? t : b }')
  done
  echo "$best"
}

row() {  # LABEL DT WALL
  awk -v l="$1" -v dt="$2" -v w="$3" -v ref="$clump" 'BEGIN {
    n = 56.0 / dt
    printf "| %s | %s | %.2f | %.2f | %.4f | %.1f |\n", l, dt, w, 1e6 * w / n, w / 56, ref / w }'
}

clump=$(fastest "$root/inputs/shake_table" duzce_rocking.in 2e-5)
printf "| body (56 s record) | dt (s) | wall s | us/step | wall s per simulated s | speed-up over the clump |\n"
printf "|---|---|---|---|---|---|\n"
row "stock multisphere clump, mesh table (1 %: dt 2e-5)" 2e-5 "$clump"
for dt in 2e-5 6.25e-5 1.2e-4; do
  row "fix rigid/convex, table plane, e 0.05" "$dt" "$(fastest "$root/inputs/convex" duzce_rocking.in "$dt" -var e 0.05)"
done
