#!/usr/bin/env bash
# Fresh machine to results: install Debian packages, build, and run the
# flagship example, the seed paper's dual-body case: a slender marble tower on
# a stocky marble pedestal on a shake table playing the unscaled 1999 Duzce
# Bolu record (inputs/scenarios/statue_pedestal_duzce.json). Produces
# results.h5, the ParaView series and report.html in out/statue_pedestal/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/setup.sh"
"$root/scripts/build.sh"

out="$root/out/statue_pedestal"
mkdir -p "$out"
echo "demo: tower on pedestal under Duzce Bolu 090 (56 s of shaking)"
"$root/build/freestand" run "$root/inputs/scenarios/statue_pedestal_duzce.json" -o "$out"
"$root/build/freestand" report "$out/results.h5" -o "$out/report.html"
echo
echo "demo: results      $out/results.h5   (docs/results-format.md; h5py, HDFView)"
echo "demo: ParaView     $out/paraview/bodies.pvd and table.pvd   (docs/paraview.md)"
echo "demo: report       $out/report.html   (open in a browser; self-contained)"
echo "demo: channels     $out/channels.csv   (recording format)"
echo "demo: input script $out/run.in   (rerun or edit: cd $out && $root/build/freestand-lmp -in run.in)"
