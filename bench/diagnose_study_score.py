#!/usr/bin/python3
"""Scores the diagnose study (bench/diagnose_study.sh) against the answer key, after every
diagnosis has finished: confusion matrix (concealed effect against the first named one),
top-1 rate, false discoveries on the no-effect cases, parameter recovery, held-out
improvement, time per case. Writes CASES/study/summary.md and summary.json.

    bench/diagnose_study_score.py CASES
"""
import glob
import json
import math
import os
import sys

# The generator's effect names (docs/diagnose-cases.md) and the diagnose catalogue entries
# that name them (docs/diagnose.md).
NAMED_AS = {
    "com_eccentricity": {"com_offset_x"},
    "restitution": {"restitution"},
    "interface_stiffness": {"contact_stiffness"},
    "static_kinetic_friction": {"static_kinetic_friction"},
    "velocity_friction": {"velocity_weakening"},
    "corner_gap": {"base_not_flat"},
    "edge_inset": {"edge_inset"},
    "table_vertical": {"vertical_table_motion"},
    "table_pitch": {"table_pitch"},
    "pedestal_compliance": {"interface_compliance"},
    "sensor_delay_gain": {"sensor_delay", "sensor_gain"},
    "none": {"none"},
}
# Measurement issues every recording has (the table accelerometer's gain, drift): reported,
# but not what a case conceals, so not counted as the named effect.
BACKGROUND = {"table_gain", "sensor_drift"}


def named(diagnosis):
    """Everything accepted, in the order of the rounds: (round, catalogue, entry)."""
    out = []
    for key in ("effects", "recalibrated", "measurement_issues"):
        for e in diagnosis.get(key, []):
            out.append((e.get("round", 0), e["catalogue"], e))
    return sorted(out, key=lambda x: x[0])


def recovery_error(answer, entry):
    """Relative error of the recovered change against the concealed one (None: not comparable)."""
    effect, m = answer["effect"]["name"], answer["effect"]["magnitude"]
    truth = answer["effect"].get("truth_changes", {})
    if effect == "sensor_delay_gain":  # a measurement issue: a delay or a gain, no "value"
        if entry["catalogue"] == "sensor_delay":
            return abs(entry["delay"] - truth["delay_s"]) / truth["delay_s"]
        return abs(entry["gain"] - truth["body_gain"]) / (truth["body_gain"] - 1)
    value, nominal = entry["value"], entry.get("nominal", 0.0)
    if effect in ("interface_stiffness", "pedestal_compliance"):
        true_log = math.log(truth["contact_stiffness_truth"] / truth["contact_stiffness_nominal"])
        return abs(math.log(value / nominal) - true_log) / abs(true_log)
    if effect == "restitution":
        t = truth[0]
        return abs((value - nominal) - (t["truth"] - t["nominal"])) / abs(t["truth"] - t["nominal"])
    if effect in ("static_kinetic_friction", "velocity_friction"):
        t = truth[0]
        return abs((1 - value) * t["mu_s"] - (t["mu_s"] - t["mu_k"])) / (t["mu_s"] - t["mu_k"])
    if effect == "corner_gap":
        return abs(value - m) / m if entry["candidate"].endswith(":+x+y]") else None
    if effect in ("com_eccentricity", "edge_inset", "table_vertical", "table_pitch"):
        return abs(value - m) / m
    return None


def main(cases):
    study = os.path.join(cases, "study")
    rows = []
    for path in sorted(glob.glob(os.path.join(study, "*.json"))):
        name = os.path.basename(path)[:-5]
        if name == "summary" or name.endswith(".diagnosed"):
            continue
        answer = json.load(open(os.path.join(cases, "answers", name + ".answer.json")))
        d = json.load(open(path))
        seconds = float(open(os.path.join(study, name + ".seconds")).read())
        accepted = named(d)
        physics = [a for a in accepted if a[1] not in BACKGROUND]
        first = physics[0] if physics else (0, "none", None)
        concealed = answer["effect"]["name"]
        correct = first[1] in NAMED_AS[concealed]
        error = recovery_error(answer, first[2]) if correct and first[2] is not None else None
        rows.append({
            "case": name, "concealed": concealed, "magnitude": answer["effect"]["magnitude"],
            "named": first[1], "value": first[2].get("value", first[2].get("delay")) if first[2] else None,
            "correct": correct, "recovery_error": error,
            "held_out_delta": first[2].get("held_out_delta_chi2") if first[2] else None,
            "all_named": [f"{a[1]}(r{a[0]})" for a in accepted],
            # A background table gain is right only near 1 / the accelerometer's drawn gain.
            "table_gain": [(a[2]["value"], 1 / answer["measurement"]["channel_gains"]["table_ax"])
                           for a in accepted if a[1] == "table_gain"],
            "chi2_nominal": d["chi2_nominal"], "chi2_final": d["chi2_final"], "features": d["feature_count"],
            "simulations": d["simulations"], "seconds": seconds})
    failed = sorted(os.path.basename(p)[:-4] for p in glob.glob(os.path.join(study, "*.log"))
                    if not os.path.exists(p[:-4] + ".json"))
    write(study, rows, failed)


def write(study, rows, failed):
    effects = sorted({r["concealed"] for r in rows})
    columns = sorted({r["named"] for r in rows})
    lines = [f"Cases diagnosed: {len(rows)}" + (f"; not finished or failed: {', '.join(failed)}" if failed else ""), ""]
    lines.append("| case | concealed | magnitude | named first | value | recovery error | held-out dchi2 | everything accepted (round) | table gain fitted (ideal) | chi2 nominal -> final (features) | sims | s |")
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        fmt = lambda v, f: "-" if v is None else format(v, f)
        lines.append(f"| {r['case']} | {r['concealed']} | {r['magnitude']:.4g} | {r['named']}{'' if r['correct'] else ' (wrong)'} | "
                     f"{fmt(r['value'], '.4g')} | {fmt(r['recovery_error'], '.0%')} | {fmt(r['held_out_delta'], '.1f')} | "
                     f"{', '.join(r['all_named']) or '-'} | "
                     f"{', '.join(f'{g:.3f} ({i:.3f})' for g, i in r['table_gain']) or '-'} | "
                     f"{r['chi2_nominal']:.0f} -> {r['chi2_final']:.0f} ({r['features']}) | "
                     f"{r['simulations']} | {r['seconds']:.0f} |")
    lines += ["", "Confusion matrix (rows: concealed, columns: named first; background measurement issues left out):", ""]
    lines.append("| concealed \\ named | " + " | ".join(columns) + " |")
    lines.append("|---|" + "---|" * len(columns))
    for e in effects:
        counts = [sum(1 for r in rows if r["concealed"] == e and r["named"] == c) for c in columns]
        lines.append(f"| {e} | " + " | ".join(str(c) if c else "." for c in counts) + " |")
    with_effect = [r for r in rows if r["concealed"] != "none"]
    none = [r for r in rows if r["concealed"] == "none"]
    top1 = sum(r["correct"] for r in with_effect)
    false = sum(not r["correct"] for r in none)
    recovered = [r["recovery_error"] for r in rows if r["recovery_error"] is not None]
    within = sum(e <= 0.25 for e in recovered)
    held = [r["held_out_delta"] for r in with_effect if r["correct"] and r["held_out_delta"] is not None]
    seconds = [r["seconds"] for r in rows]
    summary = {
        "cases": len(rows), "not_finished": failed,
        "top1": f"{top1}/{len(with_effect)}", "false_discoveries_on_no_effect": f"{false}/{len(none)}",
        "recovered_within_25_percent": f"{within}/{len(recovered)}",
        "held_out_improved": f"{sum(h > 0 for h in held)}/{len(held)}",
        "seconds_per_case": {"mean": sum(seconds) / len(seconds) if seconds else None,
                             "max": max(seconds) if seconds else None},
    }
    lines += ["", f"Top-1: {summary['top1']}; false discoveries on no-effect cases: {summary['false_discoveries_on_no_effect']}; "
              f"recovered within 25 %: {summary['recovered_within_25_percent']}; held-out improved (correctly named): "
              f"{summary['held_out_improved']}; time per case: mean {summary['seconds_per_case']['mean'] or 0:.0f} s, "
              f"max {summary['seconds_per_case']['max'] or 0:.0f} s (2 cases at a time, --jobs 1 each)."]
    for name, text in (("summary.md", "\n".join(lines) + "\n"), ("summary.json", json.dumps({"summary": summary, "rows": rows}, indent=1))):
        tmp = os.path.join(study, name + ".part")
        open(tmp, "w").write(text)
        os.replace(tmp, os.path.join(study, name))
    print("\n".join(lines))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/diagnose_cases")
