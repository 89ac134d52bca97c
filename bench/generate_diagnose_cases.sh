#!/usr/bin/env bash
# The diagnose case set (docs/diagnose-cases.md): every catalogue effect twice
# (single bodies and the tower on its pedestal, six ground-motion windows) and
# four cases with no effect, from bench/diagnose_cases.json.
#
#   bench/generate_diagnose_cases.sh [OUT [GENERATE OPTIONS...]]   (default OUT: out/diagnose_cases)
#
# e.g. `--concealment within_scatter` for the second reading of the criterion,
# `--cache DIR` to reuse another set's runs.
#
# OUT/recordings: NAME.csv + NAME.nominal.json and manifest.json, what
# `freestand diagnose` may read. OUT/answers: NAME.answer.json (the concealed
# effect, its magnitude, the concealment numbers), NAME.model.* (the nominal
# model's prediction), answers.json (summary and the cases that could not be
# made) and runs/ (the simulations, reused by a rerun). Cases whose effect
# needs an option this build lacks (corner_gap and edge_inset: the body
# `base` option; table_pitch: table_motion.pitch) are skipped and listed.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-out/diagnose_cases}
tool=${FREESTAND_TOOL:-$root/build/freestand}  # a copy keeps generation off a rebuild
[ -x "$tool" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
start=$(date +%s)
"$tool" generate "$root/bench/diagnose_cases.json" -o "$out/recordings" --answers "$out/answers" -j 2 --keep-going \
  "${@:2}"
echo "wall time: $(( $(date +%s) - start )) s"
/usr/bin/python3 - "$out/answers/answers.json" <<'PY'
import json, sys
a = json.load(open(sys.argv[1]))
print(f"{'case':28s} {'effect':24s} {'magnitude':>10s} {'change m':>10s} {'scatter m':>10s} {'effect m':>10s}")
for c in a["cases"]:
    print(f"{c['case']:28s} {c['effect']:24s} {c['magnitude']:10.4g} {c['change']:10.3g} {c['scatter']:10.3g} {c['effect_rms']:10.3g}")
for f in a["failed"]:
    print(f"{f['case']:28s} {f['effect']:24s} not made: {f['error'][:90]}")
PY
