#!/usr/bin/env python3
"""Generate the scenes of the issue-3 multi-body examples (python3 stdlib only).

  python3 wall.py column [--drums 8] [--sides 16] [--per-edge 2] > column.json
  python3 wall.py wall [--courses 10] [--per-course 100] > wall.json

column: N marble drums (regular prisms, circumradius 0.45 m, height 0.6 m) stacked by a
  supported_by chain on the table, topped by a box capital (1.2 x 1.2 x 0.3 m). Face node
  grids (per_edge) on every face, interfaces marble on marble (mu 0.7).
wall: a dry-stone wall in running bond, COURSES courses of PER_COURSE limestone blocks
  0.4 x 0.2 x 0.2 m (x along the wall); odd courses are shifted by half a block. Every block
  has an explicit "position" (base-face centre) because supported_by places a body on one
  support only. The bottom course has table interfaces (a block that falls to the table
  without one uses the fix's defaults); block-on-block contact uses the fix's defaults.
"""
import argparse
import json
import sys


def column(drums, sides, per_edge, radius=0.45, height=0.6, mu=0.7):
    bodies, interfaces = [], []
    below = "table"
    for k in range(drums):
        name = "drum%d" % (k + 1)
        bodies.append({"name": name, "shape": "prism", "radius": radius, "sides": sides,
                       "height": height, "density": 2700, "supported_by": below,
                       "nodes": {"per_edge": per_edge}})
        interfaces.append({"lower": below, "upper": name, "mu": mu})
        below = name
    bodies.append({"name": "capital", "shape": "box", "half_extents": [0.6, 0.6, 0.15],
                   "density": 2700, "supported_by": below, "nodes": {"per_edge": per_edge}})
    interfaces.append({"lower": below, "upper": "capital", "mu": mu})
    return {"bodies": bodies, "interfaces": interfaces,
            "ground_motion": "1994 Northridge, Sylmar County Hospital, x"}


def wall(courses, per_course, lx=0.4, ly=0.2, lz=0.2, mu=0.6, gap=0.0):
    bodies, interfaces = [], []
    x0 = -0.5 * per_course * lx
    for c in range(courses):
        shift = 0.5 * lx if c % 2 else 0.0
        for b in range(per_course):
            name = "b%d_%d" % (c, b)
            x = x0 + shift + (b + 0.5) * lx
            bodies.append({"name": name, "shape": "box",
                           "half_extents": [0.5 * lx - 0.5 * gap, 0.5 * ly, 0.5 * lz],
                           "density": 2400, "position": [round(x, 9), 0.0, round(c * lz, 9)],
                           "nodes": {"layout": "vertices"}})
            if c == 0:
                interfaces.append({"lower": "table", "upper": name, "mu": mu})
    return {"bodies": bodies, "interfaces": interfaces,
            "ground_motion": "moderate shaking (see wall.in)"}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("kind", choices=["column", "wall"])
    p.add_argument("--drums", type=int, default=8)
    p.add_argument("--sides", type=int, default=16)
    p.add_argument("--per-edge", type=int, default=2)
    p.add_argument("--courses", type=int, default=10)
    p.add_argument("--per-course", type=int, default=100)
    a = p.parse_args()
    scene = column(a.drums, a.sides, a.per_edge) if a.kind == "column" else wall(a.courses, a.per_course)
    # One body or interface per line: readable and diffable at 1000 bodies.
    out = sys.stdout
    out.write("{\n")
    for key in ("bodies", "interfaces"):
        out.write(' "%s": [\n' % key)
        out.write(",\n".join("  " + json.dumps(item) for item in scene[key]))
        out.write("\n ],\n")
    out.write(' "ground_motion": %s\n}\n' % json.dumps(scene["ground_motion"]))


if __name__ == "__main__":
    main()
