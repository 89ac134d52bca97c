#!/usr/bin/python3
"""Where a quick profile's minimum lies: its lowest point against the parabola and the V.

Reads the --json outputs of diagnoses (bench/diagnose_study.sh: CASES/study/NAME.json) and, for
every round-1 physics candidate whose profile was refined (at least 9 points), takes the quick
ladder's points (u0 +- 0.01 x 2^k in scaled units: the 4x ladder and its 2x extensions), their
lowest point and its two neighbours, and three estimates of the minimum from them: the lowest
point itself, the parabola through the three (freestand's profile_minimum with span 3) and the
V of equal and opposite slopes (equiangular lines, the steeper side's slope). Each is scored by
its distance from the reference, the tested value (the ensemble's) or else the refined
profile's lowest point, in units of the bracket's width. A profile seen in several studies with
the same quick points counts once. docs/diagnose-studies.md, study 43.

    bench/quick_profile_minimum.py 'out/**/study'
"""
import glob
import json
import math
import statistics
import sys


def scaled(c, v):
    lo, hi = c["range"]
    if c.get("standard_error_of_log"):
        return math.log(v / lo) / math.log(hi / lo)
    return (v - lo) / (hi - lo)


def on_ladder(offset):
    if abs(offset) < 1e-12:
        return True
    k = math.log(abs(offset) / 0.01, 2)
    return abs(k - round(k)) < 1e-6


def parabola(trio):
    (x1, y1), (x0, y0), (x2, y2) = trio
    d1, d2 = (y0 - y1) / (x0 - x1), (y2 - y0) / (x2 - x0)
    a = (d2 - d1) / (x2 - x1)
    return 0.5 * (x1 + x0) - d1 / (2 * a) if a > 0 else None


def equiangular(trio):
    (x1, y1), (x0, y0), (x2, y2) = trio
    left, right = (y1 - y0) / (x0 - x1), (y2 - y0) / (x2 - x0)
    s = max(left, right)
    if s <= 0:
        return None
    return (y1 - y0) / (2 * s) + 0.5 * (x1 + x0) if right >= left else (y0 - y2) / (2 * s) + 0.5 * (x0 + x2)


def errors(c):
    u0 = scaled(c, c["nominal"])
    points = sorted((scaled(c, v), y) for v, y in c["profile"])
    quick = [(u, y) for u, y in points if on_ladder(u - u0)]
    if len(quick) < 5:
        return None
    i = min(range(len(quick)), key=lambda k: quick[k][1])
    if i in (0, len(quick) - 1):
        return None
    trio = quick[i - 1:i + 2]
    reference = scaled(c, c["value"]) if c["members"] > 0 else min(points, key=lambda q: q[1])[0]
    width = trio[2][0] - trio[0][0]
    out = [abs(trio[1][0] - reference) / width]
    for estimate in (parabola, equiangular):
        x = estimate(trio)
        out.append(abs((x if x is not None and trio[0][0] <= x <= trio[2][0] else trio[1][0]) - reference) / width)
    return tuple(quick), out


def main(pattern):
    seen, rows = set(), []
    for path in sorted(glob.glob(pattern + "/case*.json", recursive=True)):
        if path.endswith(".diagnosed.json"):
            continue
        for c in json.load(open(path))["candidates"]:
            if c["round"] != 1 or len(c["profile"]) < 9:
                continue
            found = errors(c)
            if found is None or (c["candidate"], found[0]) in seen:
                continue
            seen.add((c["candidate"], found[0]))
            rows.append((path, c["candidate"], found[1]))
    for path, name, e in rows:
        print(f"{path:60s} {name:38s} lowest {e[0]:.3f} parabola {e[1]:.3f} V {e[2]:.3f}")
    for k, name in enumerate(["lowest point", "parabola", "V"]):
        v = [e[k] for _, _, e in rows]
        best = sum(1 for _, _, e in rows if e[k] == min(e))
        print(f"{name}: mean {statistics.mean(v):.3f}, median {statistics.median(v):.3f} of the bracket; "
              f"nearest (ties to each) in {best} of {len(rows)}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/**/study")
