#!/usr/bin/env bash
# What Open MPI's singleton start-up costs a single-rank freestand-lmp run, and what the
# environment run_liggghts gives single ranks (OMPI_MCA_ess_singleton_isolated=1,
# OMPI_MCA_pml=ob1, the session directory in the run's directory; postprocess/liggghts_runner.cpp)
# saves. Side by side in this script:
#   1. an empty input (`print`), the start-up alone;
#   2. the tower on its pedestal (inputs/scenarios/statue_pedestal_duzce.json) for 12.87 s,
#      a profile point of bench/diagnose_tower.sh.
# Wall time of the whole process, fastest of REPEAT runs (least disturbed).
# Usage: bench/singleton_startup.sh [REPEAT]   (needs build/freestand and build/freestand-lmp)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
lmp="$root/build/freestand-lmp"
repeat=${1:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset OMPI_MCA_ess_singleton_isolated OMPI_MCA_pml OMPI_MCA_orte_tmpdir_base

fastest() {  # DIR SCRIPT [VARIABLES...]: fastest wall seconds of REPEAT runs
  local dir=$1 script=$2 best="" t
  shift 2
  for _ in $(seq "$repeat"); do
    t=$( { cd "$dir" && /usr/bin/time -f '%e' env "$@" "$lmp" -in "$script" -log none -screen /dev/null; } 2>&1 | tail -1)
    best=$(awk -v t="$t" -v b="$best" 'BEGIN { print (b == "" || t < b) ? t : b }')
  done
  echo "$best"
}

echo 'print "start-up"' > "$work/empty.in"
"$root/build/freestand" run "$root/inputs/scenarios/statue_pedestal_duzce.json" -o "$work/tower" \
  --var simulation.duration=12.87 > /dev/null 2>&1
isolated=(OMPI_MCA_ess_singleton_isolated=1 OMPI_MCA_pml=ob1)
printf '%-40s %10s %10s %7s\n' case "default/s" "isolated/s" ratio
for c in "empty input:$work:empty.in" "tower on pedestal, 12.87 s:$work/tower:run.in"; do
  IFS=: read -r name dir script <<< "$c"
  a=$(fastest "$dir" "$script" BENCH=default)
  b=$(fastest "$dir" "$script" "${isolated[@]}" OMPI_MCA_orte_tmpdir_base="$dir")
  awk -v n="$name" -v a="$a" -v b="$b" 'BEGIN { printf "%-40s %10.2f %10.2f %7.2f\n", n, a, b, a / b }'
done
