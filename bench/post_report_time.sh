#!/usr/bin/env bash
# Time `freestand post` + `freestand report` on the demo's results (tower on
# pedestal, whole 56 s Duzce record, 200 Hz output): fastest of N (default 3).
# Usage: bench/post_report_time.sh [N] [RUN_DIR]   (the run is made when RUN_DIR has no results.h5)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tool="$root/build/freestand"
repeats=${1:-3}
dir=${2:-$(mktemp -d)}
[ -f "$dir/results.h5" ] || "$tool" run "$root/inputs/scenarios/statue_pedestal_duzce.json" -o "$dir" --no-post > /dev/null 2>&1
seconds() { local start; start=$(date +%s.%N); "$@" > /dev/null; awk -v s="$start" -v e="$(date +%s.%N)" 'BEGIN{print e - s}'; }
for _ in $(seq "$repeats"); do
  echo "$(seconds "$tool" post "$dir/results.h5") $(seconds "$tool" report "$dir/results.h5")"
done | awk -v n="$repeats" -v load="$(cut -d' ' -f1 /proc/loadavg)" '
  NR == 1 || $1 < p {p = $1} NR == 1 || $2 < r {r = $2} NR == 1 || $1 + $2 < t {t = $1 + $2}
  END {printf "freestand post: %.2f s; freestand report: %.2f s; both: %.2f s (fastest of %d; load average %s)\n", p, r, t, n, load}'
