#!/usr/bin/env bash
# Issue 3 section 5: scale benchmark of fix rigid/convex + pair_style convex, a dry-stone
# wall in running bond (inputs/convex/wall.in, scene from inputs/convex/wall.py) on the
# shake table (El Centro NS at PGA 0.2 g, out of plane), dt 2e-5 s, TEND s simulated.
# Prints: cost per body-step (us) on 1 rank; memory per body (peak RSS of the 1-rank run
# minus that of a 20-body wall, per extra body; and LIGGGHTS' own "Memory usage" line);
# the speedup of `mpirun -np 2` (processors * 1 1, the wall cut across its length) over
# 1 rank, and the kinetic energy at the end of both runs (they should agree).
# Usage: bench/wall.sh [TEND] [COURSES] [PER_COURSE] [BUILD]
#   defaults 0.2 10 100 build   (needs BUILD/freestand-lmp, mpirun, /usr/bin/time)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
tend=${1:-0.2}
courses=${2:-10}
per_course=${3:-100}
build=${4:-build}
[[ $build = /* ]] || build="$root/$build"
exe="$build/freestand-lmp"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$root/inputs/convex"
python3 wall.py wall --courses "$courses" --per-course "$per_course" > "$work/wall.json"
python3 wall.py wall --courses 2 --per-course 10 > "$work/small.json"
nbody=$((courses * per_course))
half=$(awk -v n="$per_course" 'BEGIN { print 0.2 * n + 1 }')

run() {  # run NAME SCENE TEND HALF [mpirun prefix...]
  local name=$1 scene=$2 t=$3 h=$4; shift 4
  /usr/bin/time -f %M -o "$work/$name.rss" "$@" "$exe" -in wall.in -var scene "$scene" \
    -var tend "$t" -var half "$h" -log "$work/$name.log" -screen /dev/null \
    || { tail -5 "$work/$name.log"; exit 1; }
}
run small "$work/small.json" 0.01 3
run serial "$work/wall.json" "$tend" "$half"
run mpi "$work/wall.json" "$tend" "$half" mpirun --allow-run-as-root --oversubscribe -np 2

loop() { grep -a '^Loop time' "$work/$1.log" | tail -1 | awk '{ print $4 }'; }
steps() { grep -a '^Loop time' "$work/$1.log" | tail -1 | awk '{ print $9 }'; }
ke() { grep -a -B1 '^Loop time' "$work/$1.log" | head -1 | awk '{ print $4 }'; }
t1=$(loop serial); t2=$(loop mpi); n=$(steps serial)
rss1=$(cat "$work/serial.rss"); rss0=$(cat "$work/small.rss")
lmem=$(grep -a 'Memory usage per processor' "$work/serial.log" | tail -1 | awk '{ print $6 }')
awk -v t1="$t1" -v t2="$t2" -v n="$n" -v nb="$nbody" -v r1="$rss1" -v r0="$rss0" -v lm="$lmem" \
    -v tend="$tend" -v c="$courses" -v p="$per_course" -v k1="$(ke serial)" -v k2="$(ke mpi)" 'BEGIN {
  printf "wall %d x %d = %d blocks, %s s simulated (%d steps of 2e-5 s)\n", c, p, nb, tend, n
  printf "1 rank:  %.2f s wall, %.2f us per body-step, %.3f s wall per simulated s\n", t1, 1e6 * t1 / (n * nb), t1 / tend
  printf "2 ranks: %.2f s wall, speedup %.2f (mpirun -np 2 over 1 rank)\n", t2, t1 / t2
  printf "memory: peak RSS %.1f MB (20-body wall %.1f MB): %.1f kB per body; LIGGGHTS memory line %s MB\n", r1 / 1024, r0 / 1024, (r1 - r0) / (nb - 20), lm
  printf "kinetic energy at the end: 1 rank %s J, 2 ranks %s J\n", k1, k2
}'
