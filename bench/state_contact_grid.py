#!/usr/bin/python3
"""A copy of a diagnose case set (bench/generate_diagnose_cases.sh) whose recordings state every
body's contact grid (docs/diagnose-studies.md, study 18): each `bodies[i].nodes` of every NAME.nominal.json
set to surface with PER_EDGE segments per edge, so the diagnosis model runs on that grid (the grid
check keeps a stated grid). The answer keys are copied for bench/diagnose_oracle.py.

    bench/state_contact_grid.py CASES OUT PER_EDGE [--case NAME ...]
"""
import argparse
import json
import os
import shutil


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("cases")
    p.add_argument("out")
    p.add_argument("per_edge", type=int)
    p.add_argument("--case", action="append", default=[], help="only these cases (default: all)")
    a = p.parse_args()
    for sub in ("recordings", "answers"):
        os.makedirs(os.path.join(a.out, sub), exist_ok=True)
    names = a.case or [f[: -len(".answer.json")] for f in os.listdir(os.path.join(a.cases, "answers"))
                       if f.endswith(".answer.json")]
    for name in names:
        shutil.copy(os.path.join(a.cases, "answers", name + ".answer.json"), os.path.join(a.out, "answers"))
        shutil.copy(os.path.join(a.cases, "recordings", name + ".csv"), os.path.join(a.out, "recordings"))
        with open(os.path.join(a.cases, "recordings", name + ".nominal.json")) as f:
            nominal = json.load(f)
        for body in nominal["bodies"]:
            body["nodes"] = {"layout": "surface", "per_edge": a.per_edge}
        with open(os.path.join(a.out, "recordings", name + ".nominal.json"), "w") as f:
            json.dump(nominal, f, indent=1)


if __name__ == "__main__":
    main()
