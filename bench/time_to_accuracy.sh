#!/usr/bin/env bash
# Issue 3 section 5: time to accuracy against a peer. The free-rocking block of
# inputs/convex/free_rocking.in (0.25 x 0.25 x 1.0 m, 100 kg, released at rest
# from half its slenderness) in freestand (fix rigid/convex) and in MuJoCo
# 2.2.2 (bench/mujoco_free_rocking.cpp), 2.6 simulated s each, over a sweep of
# time steps and contact settings. Both records go through one analysis
# (build/housner_error: the validation tests' rocking_cycles against Housner's
# exact amplitude map). Cost: wall time of the stepping loop alone, start-up
# excluded (freestand: LIGGGHTS' "Loop time", from runs that write no output;
# MuJoCo: the program's own clock around its mj_step loop), best of REPEAT
# runs, per simulated second; the whole process (start-up included) is shown
# beside it. The accuracy figure is the largest |error| of theta_1..5.
# Usage: bench/time_to_accuracy.sh [REPEAT]
#   (needs build/freestand-lmp, build/housner_error, build/mujoco_free_rocking:
#    scripts/setup.sh installs libmujoco-dev, scripts/build.sh builds them)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
repeat=${1:-3}
tend=2.6      # six impacts: the sixth at 2.52 s closes half-cycle 5
sample=5e-4   # s between rock_x samples, both engines
for tool in freestand-lmp housner_error mujoco_free_rocking; do
  [ -x "$build/$tool" ] || { echo "missing $build/$tool: run scripts/setup.sh and scripts/build.sh" >&2; exit 1; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
results="$work/results"

# Cases: engine|label|dt|settings, settings ';'-separated (freestand: k_a;e;scene,
# tangential_damping normal throughout; mujoco: mujoco_free_rocking options).
cases=()
add() { cases+=("$1|$2|$3|$4"); }

# freestand: Housner's corner contact (layout vertices, the scene's nodes).
block=free_rocking_block.json
for dt in 8e-5 6e-5 4e-5 2e-5; do add freestand "k_a 1e10, e 0.1 (defaults)" $dt "1e10;0.1;$block"; done
for dt in 5.4e-5 4e-5 2e-5; do add freestand "k_a 1e10, e 0.05" $dt "1e10;0.05;$block"; done
for dt in 7.7e-5 6e-5 4e-5 2e-5 1e-5; do add freestand "k_a 5e9, e 0.05" $dt "5e9;0.05;$block"; done
for dt in 1.15e-4 1.05e-4 9e-5 6e-5 1e-5; do add freestand "k_a 5e9, e 0.1" $dt "5e9;0.1;$block"; done
for dt in 1e-4 6e-5 1e-5; do add freestand "k_a 3e9, e 0.05" $dt "3e9;0.05;$block"; done
# The default distributed base instead of corner nodes: face grid, 4 cells per edge.
python3 - "$root/inputs/convex/$block" "$work/surface.json" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["bodies"][0]["nodes"] = {"layout": "surface", "per_edge": 4}
json.dump(scene, open(sys.argv[2], "w"))
PY
add freestand "k_a 1e10, e 0.1, layout surface, 4 per edge" 4e-5 "1e10;0.1;$work/surface.json"

# MuJoCo: its defaults (dt 2e-3, solref 0.02 1, solimp 0.9 0.95 0.001, Euler,
# pyramidal cone, Newton), then the stiffest contact its refsafe allows
# (timeconst = 2 dt, critically damped; timeconst = dt with refsafe off blows
# up), alone and with a harder impedance, the elliptic cone, impratio, RK4.
stiffest() {  # LABEL DT [OPTIONS]
  add mujoco "solref 2dt 1$1" "$2" "--solref=$(awk -v d="$2" 'BEGIN { print 2 * d }') 1${3:+;$3}"
}
for dt in 2e-3 1e-3 5e-4 2.5e-4; do add mujoco "defaults" $dt ""; done
for dt in 1e-3 5e-4 3.5e-4 2.5e-4 1.25e-4; do stiffest "" $dt; done
for dt in 1e-3 5e-4 3.5e-4 2.5e-4 1.25e-4; do
  stiffest ", solimp 0.99 0.99, elliptic" $dt "--solimp=0.99 0.99 0.001 0.5 2;--cone=elliptic"
done
for dt in 1e-3 5e-4 3.5e-4 2.5e-4 1.25e-4; do stiffest ", elliptic, impratio 10" $dt "--cone=elliptic;--impratio=10"; done
for dt in 1e-3 5e-4 3.5e-4 2.5e-4; do stiffest ", RK4" $dt "--integrator=RK4"; done

# run INDEX RECORD: runs case INDEX (freestand writes the record only when
# RECORD is set: its timing runs write nothing); prints its loop seconds.
run() {
  local engine label dt settings s nout
  IFS='|' read -r engine label dt settings <<< "${cases[$1]}"
  IFS=';' read -ra s <<< "$settings"
  if [ "$engine" = freestand ]; then
    nout=0
    [ -z "$2" ] || nout=$(awk -v dt="$dt" -v s="$sample" 'BEGIN { n = int(s / dt + 0.5); print n < 1 ? 1 : n }')
    (cd "$root/inputs/convex" &&
     "$build/freestand-lmp" -in free_rocking.in -var dt "$dt" -var tend "$tend" -var k "${s[0]}" \
       -var e "${s[1]}" -var zt normal -var scene "${s[2]}" -var nout "$nout" -var out "$work/record" \
       -log "$work/log" -screen /dev/null > /dev/null)
    grep -a '^Loop time' "$work/log" | awk '{ print $4 }'
  else
    "$build/mujoco_free_rocking" --dt "$dt" --tend "$tend" --sample "$sample" --out "$work/record" \
      "${s[@]}" | awk '{ print $2 }'
  fi
}

# Accuracy: one recorded run per case.
errors=()
for i in "${!cases[@]}"; do
  run "$i" record > /dev/null
  errors[i]=$("$build/housner_error" "$work/record")
done
# Cost: REPEAT rounds over all cases (a burst of load on the shared machine
# then hits one round, not every run of a case); the fastest run counts.
loop=() whole=()
for _ in $(seq "$repeat"); do
  for i in "${!cases[@]}"; do
    t0=$(date +%s.%N)
    t=$(run "$i" "")
    w=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
    loop[i]=$(awk -v a="$t" -v b="${loop[i]:-}" 'BEGIN { print (b == "" || a + 0 < b + 0) ? a : b }')
    whole[i]=$(awk -v a="$w" -v b="${whole[i]:-}" 'BEGIN { print (b == "" || a + 0 < b + 0) ? a : b }')
  done
done
for i in "${!cases[@]}"; do
  IFS='|' read -r engine label dt _ <<< "${cases[$i]}"
  echo "$engine|$label|$dt|${loop[i]}|${whole[i]}|${errors[i]}"
done > "$results"

awk -F'|' -v tend="$tend" -v repeat="$repeat" '
  {
    split($6, e, " ")
    engine[NR] = $1; label[NR] = $2; dt[NR] = $3; cost[NR] = $4 / tend; err[NR] = e[1]
    printf "| %s | %s | %s | %s %s %s %s %s | %s | %s | %.4f | %.4f |\n", $1, $2, $3,
           e[2], e[3], e[4], e[5], e[6], e[1], e[7], $4 / tend, $5 / tend
  }
  BEGIN {
    printf "| engine | settings | dt (s) | theta_1..5 error (%%) | largest (%%) | half-cycles, largest (%%) | loop s per simulated s | process s per simulated s |\n"
    printf "|---|---|---|---|---|---|---|---|\n"
  }
  function within(i, target) { return err[i] != "nan" && err[i] + 0 <= target }
  # Within the target at its dt and at every smaller dt of the same settings.
  function robust(i, target,   j) {
    for (j = 1; j <= NR; ++j)
      if (engine[j] == engine[i] && label[j] == label[i] && dt[j] + 0 <= dt[i] + 0 && !within(j, target)) return 0
    return 1
  }
  function report(name, target, strict,   i, best) {
    best = 0
    for (i = 1; i <= NR; ++i)
      if (engine[i] == name && within(i, target) && (!strict || robust(i, target)) && (best == 0 || cost[i] < cost[best])) best = i
    if (best) printf "  %-9s %.4f s per simulated s (%s, dt %s: %s %%)\n", name, cost[best], label[best], dt[best], err[best]
    else printf "  %-9s none in the sweep\n", name
  }
  END {
    split("1 0.5", targets, " ")
    for (t = 1; t <= 2; ++t) {
      printf "\nWithin %s %% (largest theta_1..5 error), loop time best of %d:\n", targets[t], repeat
      printf " cheapest run:\n"; report("freestand", targets[t], 0); report("mujoco", targets[t], 0)
      printf " cheapest run whose settings stay within it at every smaller dt of the sweep:\n"
      report("freestand", targets[t], 1); report("mujoco", targets[t], 1)
    }
  }' "$results"
