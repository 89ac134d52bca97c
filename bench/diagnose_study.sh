#!/usr/bin/env bash
# The proof study of `freestand diagnose` (docs/diagnose.md, "Proof on concealed effects"):
# diagnoses every recording of a case set made by bench/generate_diagnose_cases.sh, then,
# only after every diagnosis has finished, compares the verdicts with the answer key.
#
#   bench/diagnose_study.sh [CASES] [PARALLEL]   (defaults: out/diagnose_cases, 2)
#   FREESTAND_TOOL=PATH: the freestand binary to use (default build/freestand)
#   FREESTAND_DIAGNOSE_ARGS="...": more options for every diagnosis (e.g. --profile-members 2)
#
# Diagnose reads CASES/recordings only (NAME.csv + NAME.nominal.json) and the base scenario
# of the case's name (the lab's model: contact stiffness, time step); the answers in
# CASES/answers are read by bench/diagnose_study_score.py alone. PARALLEL cases run at a
# time, each diagnosis with --jobs 1, under nice. Per case: CASES/study/NAME.json (--json),
# NAME.log (verdict and candidate tables), NAME.seconds (wall time). A rerun skips cases
# whose NAME.json exists. The summary: CASES/study/summary.md and summary.json.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cases=${1:-out/diagnose_cases}
parallel=${2:-2}
tool=${FREESTAND_TOOL:-$root/build/freestand}  # a copy keeps a long study off a rebuild
[ -x "$tool" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
[ -d "$cases/recordings" ] || { echo "$cases/recordings: no case set (bench/generate_diagnose_cases.sh)" >&2; exit 1; }
study="$cases/study"
mkdir -p "$study"

# The lab's model of each base (docs/diagnose-cases.md, "The case set"): the case name names
# the base, never the effect.
scenario_of() {
  case "$1" in
    *_rock_*) echo "$root/inputs/scenarios/marble_block_duzce.json" ;;
    *_stack_*) echo "$root/inputs/scenarios/statue_pedestal_duzce.json" ;;
    *_slide_*) echo "$root/inputs/scenarios/squat_block_sliding.json" ;;
    *_plinth_*) echo "$root/inputs/scenarios/equipment_on_plinth.json" ;;
    *) echo "unknown base of case '$1'" >&2; return 1 ;;
  esac
}

diagnose_one() {
  local recording=$1 name
  name=$(basename "$recording" .csv)
  [ -s "$study/$name.json" ] && return 0
  local scenario start
  scenario=$(scenario_of "$name")
  start=$(date +%s.%N)
  if nice -n 10 "$tool" diagnose "$scenario" "$recording" --jobs 1 ${diagnose_args} --json "$study/$name.json.part" \
       -o "$study/$name.diagnosed.json" > "$study/$name.log" 2>&1; then
    mv "$study/$name.json.part" "$study/$name.json"
  else
    echo "$name: diagnose failed (see $study/$name.log)" >&2
  fi
  echo "$(date +%s.%N) - $start" | bc > "$study/$name.seconds"
  echo "$name: $(cat "$study/$name.seconds") s"
}
export -f diagnose_one scenario_of
diagnose_args=${FREESTAND_DIAGNOSE_ARGS:-}
export tool study root diagnose_args

start=$(date +%s)
ls "$cases"/recordings/*.csv | xargs -P "$parallel" -I{} bash -c 'diagnose_one "$1"' _ {}
echo "wall time: $(( $(date +%s) - start )) s"
/usr/bin/python3 "$root/bench/diagnose_study_score.py" "$cases"
