#!/usr/bin/env python3
"""Write a flat square shake-table surface as an ASCII STL (python3 stdlib only).

The table is the square [-L/2, L/2] x [-L/2, L/2] (shifted by --x0 --y0) in the
plane z = --z, split into n x n squares of 2 triangles each, all with upward
normals (+z, counter-clockwise seen from above), so a block standing on it
touches the side the normals point to.  One planar face: usable with
fix mesh/surface/planar.

usage: python3 gen_table_stl.py [--L 1.6] [--n 1] [--z 0.0] [--x0 0] [--y0 0] [--out table.stl]
"""
import argparse


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--L", type=float, default=1.6, help="side length [m]")
    ap.add_argument("--n", type=int, default=1, help="subdivisions per side")
    ap.add_argument("--z", type=float, default=0.0, help="height of the table surface [m]")
    ap.add_argument("--x0", type=float, default=0.0, help="centre x [m]")
    ap.add_argument("--y0", type=float, default=0.0, help="centre y [m]")
    ap.add_argument("--out", default="table.stl")
    a = ap.parse_args()
    h = a.L / a.n
    tris = []
    for i in range(a.n):
        for j in range(a.n):
            x0 = a.x0 - a.L / 2 + i * h
            y0 = a.y0 - a.L / 2 + j * h
            p00, p10 = (x0, y0, a.z), (x0 + h, y0, a.z)
            p11, p01 = (x0 + h, y0 + h, a.z), (x0, y0 + h, a.z)
            tris.append((p00, p10, p11))
            tris.append((p00, p11, p01))
    with open(a.out, "w") as f:
        f.write("solid table\n")
        for t in tris:
            f.write("  facet normal 0 0 1\n    outer loop\n")
            for p in t:
                f.write("      vertex %.9g %.9g %.9g\n" % p)
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid table\n")
    print("wrote %s: %d triangles, %.4g x %.4g m at z = %g" % (a.out, len(tris), a.L, a.L, a.z))


if __name__ == "__main__":
    main()
