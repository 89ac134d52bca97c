#!/usr/bin/env bash
# Issue 3 section 5, first figure: one block on the shake table under the
# unscaled Duzce Bolu record, as a stock multisphere clump on a moving mesh
# (inputs/shake_table/duzce_rocking.in) and as a convex body on the analytic
# table plane (inputs/convex/duzce_rocking.in), side by side in this script.
# Same block (1.0 x 1.0 x 3.0 m, 8100 kg, mu 0.55), same time step, no output.
# Each case runs REPEAT times; the fastest run counts.
# Usage: bench/convex_vs_multisphere.sh [REPEAT] [DT]   (needs build/freestand-lmp)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
lmp="$root/build/freestand-lmp"
repeat=${1:-3}
dt=${2:-2e-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

fastest() {  # DIR SCRIPT: fastest loop time of the longest run, in seconds
  local dir=$1 script=$2 best=""
  for _ in $(seq "$repeat"); do
    (cd "$dir" && "$lmp" -in "$script" -var nout 0 -var dt "$dt" -log "$work/log" -screen /dev/null)
    t=$(grep -a '^Loop time' "$work/log" | awk '{ if ($9 + 0 > n) { n = $9; t = $4 } } END { print t }')
    best=$(awk -v t="$t" -v b="$best" 'BEGIN { print (b == "" || t < b) ? t : b }')
  done
  echo "$best"
}

clump=$(fastest "$root/inputs/shake_table" duzce_rocking.in)
convex=$(fastest "$root/inputs/convex" duzce_rocking.in)
awk -v a="$clump" -v b="$convex" -v dt="$dt" 'BEGIN {
  n = 56.0 / dt
  printf "| body (dt %s s, 56 s record) | wall s | us/step | wall s per simulated s |\n", dt
  printf "|---|---|---|---|\n"
  printf "| stock multisphere clump, mesh table | %.2f | %.2f | %.4f |\n", a, 1e6 * a / n, a / 56
  printf "| fix rigid/convex, table plane | %.2f | %.2f | %.4f |\n", b, 1e6 * b / n, b / 56
  printf "\nconvex is %.1f times faster per simulated second\n", a / b
}'
