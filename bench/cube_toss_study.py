#!/usr/bin/python3
"""Per-toss breakdown of a cube-toss prediction (docs/validation.md, "Cube tosses").

Re-simulates converted tosses (`freestand tosses`) with a model and fixed contact values set
on top of each toss's scenario, as `freestand calibrate --validate` does, and reports where
simulation and recording part: the position error at the recorded first impact and 0.1 s,
0.2 s later, the distance travelled after the first impact, the final error along that travel,
and the tool's metrics (mean / final position error per edge, final rotation, same rest face,
rest-time error).

  bench/cube_toss_study.py TOSS_DIR MODEL.json --set mu=0.174 --set restitution=0.02 \\
      --set stiffness=8.8e9 --set table_height=-0.00099 [--first 150] [--last 299] \\
      [--time-step 1e-6] [--gravity 9.606] [--jobs 2] [--rows rows.json]
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import subprocess
import tempfile

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EDGE = 0.1048
SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * EDGE / 2
CONTACT_CLEARANCE = 0.003  # m: a corner this close to the table counts as the first impact


def rotation_matrices(q):
    """Rotation matrices of unit quaternions q (n x 4, scalar first)."""
    w, x, y, z = q.T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def lowest_corner(x, q):
    return x[:, 2] + (SIGNS @ rotation_matrices(q).transpose(0, 2, 1))[:, :, 2].min(axis=1)


def down_face(q):
    down = -rotation_matrices(q[None])[0][2]  # world -z in body axes
    axis = int(np.argmax(np.abs(down)))
    return 2 * axis + int(down[axis] < 0)


def rest_index(x, q):
    """First sample after which the pose stays within 2 % of the edge and 2 degrees of the last."""
    turn = np.degrees(2 * np.arccos(np.clip(np.abs(q @ q[-1]), 0, 1)))
    moved = np.linalg.norm(x - x[-1], axis=1) > 0.02 * EDGE
    away = np.nonzero(moved | (turn > 2))[0]
    return 0 if len(away) == 0 else min(away[-1] + 1, len(x) - 1)


def read_toss(stem):
    data = np.genfromtxt(stem + ".csv", delimiter=",", names=True, comments=None)
    x = np.stack([data["cubex"], data["cubey"], data["cubez"]], -1)
    q = np.stack([data["cubeqw"], data["cubeqx"], data["cubeqy"], data["cubeqz"]], -1)
    with open(stem + ".nominal.json") as f:
        return data["t"], x, q, json.load(f)


def toss_scenario(model, nominal, t, values, time_step, gravity):
    doc = json.loads(json.dumps(model))
    for key in ("bodies", "interfaces", "gravity", "table_height"):
        if key in nominal:
            doc[key] = nominal[key]
    doc.setdefault("simulation", {})
    doc["simulation"]["duration"] = t[-1] - t[0]
    doc["simulation"]["output_rate"] = (len(t) - 1) / (t[-1] - t[0])
    if time_step:
        doc["simulation"]["time_step"] = time_step
    if gravity:
        doc["gravity"] = gravity
    for name, value in values.items():
        if name == "stiffness":
            doc.setdefault("contact", {})["stiffness"] = value
        elif name == "table_height":
            doc["table_height"] = value
        else:
            for interface in doc["interfaces"]:
                interface[name] = value
    return doc


def simulate(doc, directory):
    with open(os.path.join(directory, "scenario.json"), "w") as f:
        json.dump(doc, f)
    run = subprocess.run([os.path.join(ROOT, "build", "freestand"), "run", os.path.join(directory, "scenario.json"),
                          "-o", os.path.join(directory, "run")], capture_output=True, text=True)
    if run.returncode:
        raise RuntimeError(run.stderr + run.stdout)
    with h5py.File(os.path.join(directory, "run", "results.h5")) as f:
        body = f["bodies/cube"]
        return (f["time"][:], np.stack([body[c][:] for c in "xyz"], -1),
                np.stack([body[c][:] for c in ("qw", "qx", "qy", "qz")], -1))


def compare(toss, t, x, q, st, sx, sq, table):
    nearest = np.abs(st[None, :] - t[:, None]).argmin(axis=1)  # output sample nearest each recorded one
    sx, sq = sx[nearest], sq[nearest]
    error = np.linalg.norm(sx - x, axis=1) / EDGE
    impact = int(np.argmax(lowest_corner(x, q) < table + CONTACT_CLEARANCE))
    impact_sim = int(np.argmax(lowest_corner(sx, sq) < table + CONTACT_CLEARANCE))
    travel = x[-1, :2] - x[impact, :2]
    along = (sx[-1, :2] - x[-1, :2]) @ travel / max(np.linalg.norm(travel), 1e-12) / EDGE
    at = lambda k: float(error[min(k, len(t) - 1)])
    samples_per_tenth = int(round(0.1 / (t[1] - t[0])))
    return {"toss": toss, "mean": float(error.mean()), "final": at(len(t) - 1),
            "final_rotation_deg": float(np.degrees(2 * np.arccos(min(1.0, abs(sq[-1] @ q[-1]))))),
            "same_face": down_face(sq[-1]) == down_face(q[-1]),
            "rest_time_error": float(abs(t[rest_index(sx, sq)] - t[rest_index(x, q)])),
            "at_impact": at(impact), "impact_plus_0.1s": at(impact + samples_per_tenth),
            "impact_plus_0.2s": at(impact + 2 * samples_per_tenth),
            "travel_recorded": float(np.linalg.norm(travel) / EDGE),
            "travel_simulated": float(np.linalg.norm(sx[-1, :2] - sx[impact_sim, :2]) / EDGE),
            "final_along_travel": float(along)}


def study_toss(args, model, values, toss, base):
    t, x, q, nominal = read_toss(os.path.join(args.toss_dir, f"cube_toss_{toss:03d}"))
    doc = toss_scenario(model, nominal, t, values, args.time_step, args.gravity)
    directory = tempfile.mkdtemp(dir=base)
    try:
        st, sx, sq = simulate(doc, directory)
    finally:
        shutil.rmtree(directory)
    return compare(toss, t, x, q, st + t[0], sx, sq, doc.get("table_height", -0.001))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("toss_dir")
    parser.add_argument("model")
    parser.add_argument("--set", action="append", default=[], help="NAME=VALUE: mu, restitution, stiffness, table_height")
    parser.add_argument("--first", type=int, default=150)
    parser.add_argument("--last", type=int, default=299)
    parser.add_argument("--time-step", type=float)
    parser.add_argument("--gravity", type=float)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--rows", help="write the per-toss rows as JSON")
    args = parser.parse_args()
    with open(args.model) as f:
        model = json.load(f)
    values = {k: float(v) for k, v in (s.split("=", 1) for s in args.set)}
    base = tempfile.mkdtemp(prefix="cube_toss_study_")
    try:
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(lambda i: study_toss(args, model, values, i, base), range(args.first, args.last + 1)))
    finally:
        shutil.rmtree(base)
    if args.rows:
        with open(args.rows + ".part", "w") as f:
            json.dump(rows, f, indent=1)
        os.replace(args.rows + ".part", args.rows)
    mean = lambda key: np.mean([r[key] for r in rows])
    same = np.array([r["same_face"] for r in rows])
    final = np.array([r["final"] for r in rows])
    print(f"{len(rows)} tosses: position error / edge mean {100 * mean('mean'):.1f} %, final {100 * mean('final'):.1f} %; "
          f"final rotation {mean('final_rotation_deg'):.1f} deg; same rest face {100 * same.mean():.1f} %; "
          f"|rest time error| {mean('rest_time_error'):.3f} s")
    print(f"  error / edge at the first impact {100 * mean('at_impact'):.1f} %, 0.1 s later "
          f"{100 * mean('impact_plus_0.1s'):.1f} %, 0.2 s later {100 * mean('impact_plus_0.2s'):.1f} %")
    print(f"  travel after the first impact: recorded {mean('travel_recorded'):.2f} edges, simulated "
          f"{mean('travel_simulated'):.2f}; final error along it: mean {100 * mean('final_along_travel'):+.0f} %, "
          f"RMS {100 * np.sqrt(np.mean([r['final_along_travel'] ** 2 for r in rows])):.0f} %")
    print(f"  final error: same face {100 * final[same].mean():.1f} % ({same.sum()} tosses), "
          f"other face {100 * final[~same].mean() if (~same).any() else 0:.1f} % ({(~same).sum()})")


if __name__ == "__main__":
    main()
