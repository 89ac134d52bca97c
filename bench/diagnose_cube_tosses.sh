#!/usr/bin/env bash
# freestand diagnose on the real DAIR Lab cube tosses (issue 5, section 3): the nominal
# model of their README (mu 0.15, the project's contact defaults) against every 15th toss
# of 0-149 (the last of them held out by diagnose), then tosses 150-299, which diagnose never
# saw, predicted with the model as given and as diagnose improved it
# (docs/diagnose.md, "Real recordings: the cube tosses").
#   bench/diagnose_cube_tosses.sh [OUT_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-diagnose_cube_tosses}
tool=${FREESTAND_TOOL:-$root/build/freestand}  # a copy keeps a long run off a rebuild
model="$root/inputs/calibration/cube_toss_model.json"
mkdir -p "$out"
"$tool" tosses "$root/../shared/data/experiments/cube_toss/cube_tosses_0-299.csv.gz" -o "$out/tosses"
fit=(); for ((i = 0; i < 150; i += 15)); do fit+=("$out/tosses/$(printf 'cube_toss_%03d.csv' $i)"); done
time "$tool" diagnose "$model" "${fit[@]}" --jobs 2 --json "$out/diagnosis.json" --report "$out/diagnosis.html" \
  -o "$out/improved.json"

# The improved model's interfaces and bodies (what diagnose changed: friction, restitution,
# stiffness, centre of mass) carried into the nominal of every unseen toss; its initial state
# stays the toss's own.
mkdir -p "$out/improved_tosses"
/usr/bin/python3 - "$out" <<'PY'
import json, pathlib, shutil, sys
out = pathlib.Path(sys.argv[1])
improved = json.loads((out / "improved.json").read_text())
for i in range(150, 300):
    stem = f"cube_toss_{i:03d}"
    shutil.copy(out / "tosses" / f"{stem}.csv", out / "improved_tosses" / f"{stem}.csv")
    nominal = json.loads((out / "tosses" / f"{stem}.nominal.json").read_text())
    nominal["interfaces"] = improved["interfaces"]
    kept = ("position", "orientation", "velocity", "omega")
    nominal["bodies"] = [{**b, **{k: n[k] for k in kept if k in n}}
                         for b, n in zip(improved["bodies"], nominal["bodies"])]
    (out / "improved_tosses" / f"{stem}.nominal.json").write_text(json.dumps(nominal, indent=2))
PY
held=(); improved=()
for ((i = 150; i < 300; i++)); do
  held+=("$out/tosses/$(printf 'cube_toss_%03d.csv' $i)"); improved+=("$out/improved_tosses/$(printf 'cube_toss_%03d.csv' $i)")
done
"$tool" calibrate "$model" --no-fit --validate "${held[@]}" --jobs 2 --report "$out/predict_as_given.json"
"$tool" calibrate "$model" --no-fit --validate "${improved[@]}" --jobs 2 --report "$out/predict_improved.json"
/usr/bin/python3 - "$out" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
print("| tosses 150-299 | mean position / edge | final position / edge | final rotation (deg) | same rest face | rest-time error (s) |")
print("| --- | --- | --- | --- | --- | --- |")
for name in ("as_given", "improved"):
    s = json.loads((out / f"predict_{name}.json").read_text())["prediction"][0]["summary"]
    print(f"| {name.replace('_', ' ')} | {100 * s['mean_position_error']:.1f} % | {100 * s['final_position_error']:.1f} % | "
          f"{s['final_rotation_error_deg']:.1f} | {100 * s['same_rest_face']:.0f} % | {s['rest_time_error']:.3f} |")
PY
