#!/usr/bin/env bash
# Calibrates the contact model on the DAIR Lab cube tosses 0-149 and predicts
# tosses 150-299 with the uncalibrated and the calibrated model
# (docs/validation.md, "Cube tosses: calibration and prediction").
#   bench/cube_toss_calibration.sh [OUT_DIR] [FIT_EVERY]
# FIT_EVERY: fit on every FIT_EVERY-th toss of 0-149 (default 5: 30 tosses per
# evaluation, about 10 s on 2 cores; 1 fits all 150). About 13 min in all;
# bench/cube_toss_study.py breaks the prediction down per toss. ALGORITHM: the
# optimiser, default bobyqa (the documented study was run with it; the tool's default is lm).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-cube_toss_calibration}
every=${2:-5}
tool="$root/build/freestand"
mkdir -p "$out"
"$tool" tosses "$root/../shared/data/experiments/cube_toss/cube_tosses_0-299.csv.gz" -o "$out/tosses"
fit=(); for ((i = 0; i < 150; i += every)); do fit+=("$out/tosses/$(printf 'cube_toss_%03d.csv' $i)"); done
held=(); for ((i = 150; i < 300; i++)); do held+=("$out/tosses/$(printf 'cube_toss_%03d.csv' $i)"); done
time "$tool" calibrate "$root/inputs/calibration/cube_toss_model.json" "${fit[@]}" \
  --fit mu:0.02:1.0:0.15 --fit restitution:0.02:0.95:0.1 --fit stiffness:1e7:3e10:1e10 \
  --fit table_height:-0.004:0.001:-0.001 \
  --max-evaluations "${MAX_EVALUATIONS:-50}" --jobs 2 --algorithm "${ALGORITHM:-bobyqa}" \
  --validate "${held[@]}" -o "$out/cube_toss_model.calibrated.json" --report "$out/report.json"
