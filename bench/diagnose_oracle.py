#!/usr/bin/python3
"""The paired oracle of the proof study (docs/diagnose-studies.md, study 11): can the event features tell
each case's concealed effect at all? Every effect case of a case set (bench/generate_diagnose_cases.sh)
is diagnosed once more with two `--hypothesis` read from the answer key (a study of the method's
power, never part of a verdict): the recorded table acceleration's true gain alone (a measurement
the search may fit first), and that gain with the true effect. So the truth meets the model as
given on paired members and pooled scatter, as an accepted effect would; the two hypotheses meet
each other (the effect's own evidence once the measurement is right); and where the search named
something, the truth meets the improved model too.

    bench/diagnose_oracle.py CASES [--parallel 2] [--tool build/freestand] [-- DIAGNOSE OPTIONS...]

Per case: CASES/oracle/NAME.json (--json), NAME.log, NAME.seconds; a rerun skips cases whose
NAME.json exists. Summary: CASES/oracle/summary.md. Sensor delay and gain cases are left out:
they are corrections of the recording, not a model value a hypothesis can state.
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASES = {"_rock_": "marble_block_duzce.json", "_stack_": "statue_pedestal_duzce.json",
         "_slide_": "squat_block_sliding.json"}
# The candidate value of each friction-law effect is mu_k / mu_s (docs/diagnose.md, catalogue).
FRICTION = {"static_kinetic_friction": "static_kinetic_friction", "velocity_friction": "velocity_weakening"}


def base_area(nominal, body):
    b = next(b for b in nominal["bodies"] if b["name"] == body)
    if b.get("shape") != "box":
        raise ValueError(f"body '{body}': only a box's base area is known here")
    return 4 * b["half_extents"][0] * b["half_extents"][1]


def hypothesis(answer, nominal):
    """The concealed effect as `--hypothesis` values (candidate names of docs/diagnose.md), or None."""
    e = answer["effect"]
    name, m, t = e["name"], e["magnitude"], e.get("truth_changes", {})
    if name == "restitution":
        parts = [(f"restitution[{c['interface']}]", c["truth"]) for c in t]
    elif name in FRICTION:
        parts = [(f"{FRICTION[name]}[{c['interface']}]", c["mu_k"] / c["mu_s"]) for c in t]
    elif name in ("interface_stiffness", "pedestal_compliance"):
        entry = "contact_stiffness" if name == "interface_stiffness" else "interface_compliance"
        upper = t["interface"].split("/")[1]
        parts = [(f"{entry}[{t['interface']}]", t["contact_stiffness_truth"] / base_area(nominal, upper))]
    elif name == "com_eccentricity":
        parts = [(f"com_offset_x[{t['body']}]", t["com_truth"][0])]
    elif name == "corner_gap":
        parts = [(f"base_not_flat[{e['target_body']}:+x+y]", m)]
    elif name == "edge_inset":
        parts = [(f"edge_inset[{e['target_body']}]", m)]
    elif name in ("table_vertical", "table_pitch"):
        parts = [("vertical_table_motion" if name == "table_vertical" else "table_pitch", t["per_unit_of_table_ax"])]
    else:
        return None
    return ",".join(f"{n}={v:.9g}" for n, v in parts)


def table_gain(answer):
    """The replayed table acceleration's true correction: 1 / the accelerometer's drawn gain."""
    return f"table_gain={1 / answer['measurement']['channel_gains']['table_ax']:.9g}"


def run_case(tool, cases, out, name, hypotheses, extra):
    if os.path.exists(os.path.join(out, name + ".json")):
        return name
    scenario = next(os.path.join(ROOT, "inputs/scenarios", s) for k, s in BASES.items() if k in name)
    part = os.path.join(out, name + ".json.part")
    start = time.time()
    with open(os.path.join(out, name + ".log"), "w") as log:
        ok = subprocess.run(["nice", "-n", "10", tool, "diagnose", scenario,
                             os.path.join(cases, "recordings", name + ".csv"), "--jobs", "1",
                             *[a for h in hypotheses for a in ("--hypothesis", h)], "--json", part, "-o", os.path.join(out, name + ".diagnosed.json"), *extra],
                            stdout=log, stderr=subprocess.STDOUT).returncode == 0
    if ok:
        os.replace(part, os.path.join(out, name + ".json"))
    with open(os.path.join(out, name + ".seconds"), "w") as f:
        f.write(f"{time.time() - start:.1f}\n")
    print(f"{name}: {'done' if ok else 'FAILED'} in {time.time() - start:.0f} s", flush=True)
    return name


def summary(cases, out, names):
    lines = ["| case | concealed | table gain + effect: chi2 as given -> at the truth (MC s.e.) | p | dBIC | held-out | "
             "supported | effect against the gain alone: chi2 lower (MC s.e.) | named first | truth against the "
             "improved model | s |", "|---|" + "---|" * 10]
    supported = 0
    for name in names:
        path = os.path.join(out, name + ".json")
        if not os.path.exists(path):
            lines.append(f"| {name} | | | not finished | | | | | | | |")
            continue
        d = json.load(open(path))
        h = d["hypotheses"][1]
        pair = d["hypothesis_pairs"][0]
        answer = json.load(open(os.path.join(cases, "answers", name + ".answer.json")))
        named = [e["candidate"] for k in ("effects", "recalibrated") for e in d[k]]
        against = (f"{h['against_improved']} ({h['improved_delta_chi2']:.1f} +- {h['improved_delta_chi2_se']:.1f})"
                   if "against_improved" in h else "-")
        supported += h["supported"]
        seconds = float(open(os.path.join(out, name + ".seconds")).read())
        lines.append(f"| {name} | {answer['effect']['name']} {answer['effect']['magnitude']:.4g} | "
                     f"{h['chi2'] + h['delta_chi2']:.1f} -> {h['chi2']:.1f} ({h['delta_chi2_se']:.1f}) | "
                     f"{h['p_value']:.2g} | {h['delta_bic']:.1f} | {h['held_out_delta_chi2']:.1f} | "
                     f"{'yes' if h['supported'] else 'no'} | {pair['delta_chi2']:.1f} ({pair['delta_chi2_se']:.1f}) "
                     f"{pair['second_fits']} | {', '.join(named) or '-'} | {against} | {seconds:.0f} |")
    lines += ["", f"Truth supported against the model as given: {supported} of {len(names)}."]
    with open(os.path.join(out, "summary.md.part"), "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(os.path.join(out, "summary.md.part"), os.path.join(out, "summary.md"))
    print("\n".join(lines))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("cases")
    p.add_argument("--parallel", type=int, default=2)
    p.add_argument("--tool", default=os.environ.get("FREESTAND_TOOL", os.path.join(ROOT, "build/freestand")))
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    a = p.parse_args(argv[:cut])
    a.extra = argv[cut + 1:]  # more diagnose options
    out = os.path.join(a.cases, "oracle")
    os.makedirs(out, exist_ok=True)
    jobs = {}
    for f in sorted(os.listdir(os.path.join(a.cases, "answers"))):
        if not f.endswith(".answer.json"):
            continue
        name = f[: -len(".answer.json")]
        if not os.path.exists(os.path.join(a.cases, "recordings", name + ".csv")):
            continue
        answer = json.load(open(os.path.join(a.cases, "answers", f)))
        nominal = json.load(open(os.path.join(a.cases, "recordings", name + ".nominal.json")))
        hyp = hypothesis(answer, nominal)
        if hyp:
            jobs[name] = [table_gain(answer), table_gain(answer) + "," + hyp]
    with concurrent.futures.ThreadPoolExecutor(a.parallel) as pool:
        list(pool.map(lambda n: run_case(a.tool, a.cases, out, n, jobs[n], a.extra), jobs))
    summary(a.cases, out, sorted(jobs))


if __name__ == "__main__":
    sys.exit(main())
