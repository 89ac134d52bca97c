#!/usr/bin/env bash
# Baseline cost of stock multisphere blocks (issue 2, section 7): microseconds
# per time step and wall seconds per simulated second, each measured side by
# side with a baseline in this same script:
#   1. free rocking (inputs/free_rocking): stock `liggghts` vs `freestand-lmp`
#      on the same script (the plugin's overhead on stock styles);
#   2. Duzce Bolu shake-table block (inputs/shake_table/duzce_rocking.in):
#      without and with fix rockslide/hdf5 output at 1 kHz.
# Each case runs REPEAT times; the fastest run counts (least disturbed).
# Usage: bench/baseline.sh [REPEAT]   (needs build/freestand-lmp)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
lmp="$root/build/freestand-lmp"
repeat=${1:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Prints "<loop seconds> <steps>" of the longest run in a LIGGGHTS log.
loop_time() {
  grep -a '^Loop time' "$1" | awk '{ if ($9 + 0 > steps) { steps = $9; t = $4 } } END { print t, steps }'
}

# bench NAME DT DIR BINARY ARGS...: fastest of $repeat runs -> "us/step s/s"
bench() {
  local name=$1 dt=$2 dir=$3; shift 3
  local best=""
  for _ in $(seq "$repeat"); do
    (cd "$dir" && "$@" -log "$work/$name.log" -screen /dev/null)
    read -r t steps < <(loop_time "$work/$name.log")
    best=$(awk -v t="$t" -v b="$best" 'BEGIN { print (b == "" || t < b) ? t : b }')
  done
  awk -v t="$best" -v n="$steps" -v dt="$dt" -v name="$name" \
    'BEGIN { printf "| %s | %d | %.1f | %.4f |\n", name, n, 1e6 * t / n, t / (n * dt) }'
}

echo "| case | steps | us/step | wall s per simulated s |"
echo "|---|---|---|---|"
fr="$root/inputs/free_rocking"
bench "free rocking, stock liggghts" 2e-5 "$fr" liggghts -in free_rocking.in -var out "$work/fr.dat"
bench "free rocking, freestand-lmp" 2e-5 "$fr" "$lmp" -in free_rocking.in -var out "$work/fr.dat"
# dt = 1e-4: the largest time step of the convergence study still within 3% of Housner.
bench "free rocking, stock liggghts, dt 1e-4" 1e-4 "$fr" liggghts -in free_rocking.in -var dt 1e-4 -var out "$work/fr.dat"
st="$root/inputs/shake_table"
bench "Duzce block, no output" 2e-5 "$st" "$lmp" -in duzce_rocking.in -var nout 0
bench "Duzce block, HDF5 at 1 kHz" 2e-5 "$st" "$lmp" -in duzce_rocking.in -var nout 50 -var out "$work/r.h5"
bench "Duzce block, no output, dt 1e-4" 1e-4 "$st" "$lmp" -in duzce_rocking.in -var nout 0 -var dt 1e-4
