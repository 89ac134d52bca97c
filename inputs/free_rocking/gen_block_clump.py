#!/usr/bin/env python3
"""Generate a stock-LIGGGHTS multisphere clump for a rigid rectangular block.

python3 stdlib only.  Writes two files:

  <prefix>.clump  sphere list "x y z r" in BODY coordinates, origin = centre of
                  mass of the solid box, for
                  fix particletemplate/multisphere ... spheres file <prefix>.clump
  <prefix>.in     LIGGGHTS include file: geometry variables (b, d, h, rbase,
                  nspheres, IDs of the angle-measurement spheres, box inertia)

Geometry rules (why the spheres sit where they sit)
---------------------------------------------------
* A sphere rigidly fixed to a body and touching a plane always has its centre
  one radius above the plane, so the body pivots about the sphere CENTRE, not
  about the sphere's contact point.  The base-corner spheres are therefore
  centred exactly on the base corners (x = +-b, y = +-d, z = -h): the pivot is
  exactly at the corner of the real block, pivot-to-COM distance is exactly
  R = sqrt(b^2 + h^2) and the slenderness exactly alpha = atan(b/h).  The
  spheres protrude rbase below the base, so the floor must be placed at
  z_base - rbase (the input scripts do that).
* A rigidly attached sphere that rolls without slip moves its centre by
  rbase*dtheta: the block behaves like a block with rounded corners of radius
  rbase and its moment of inertia about the instantaneous contact point grows
  by about m(2 R rbase) -> the rocking period grows by about 0.75*rbase/R.
  So the base spheres are small (default 1 mm: +0.14 % period); larger
  spheres (rside) only describe the rest of the envelope (side/top edges)
  and never touch the floor (lowest one is 2h/nz above the base).
* Only the base spheres can touch the floor while |theta| < 60 deg.

Sphere order (atom IDs of the first inserted clump are 1..N in this order):
  1  base corner (-b,-d,-h)         -> angle measurement, "base" point
  2  top  corner (-b,-d,+h)         -> angle measurement, "top" point
  3  base corner (+b,+d,-h)         -> out-of-plane (twist/wobble) check with 1
  4  top  corner (+b,+d,+h)
  5..  remaining base corners, base-edge spheres, vertical-edge spheres,
       top corners, top-edge spheres, optional side-face spheres.
Rocking angle about y:  theta = atan2(x2 - x1, z2 - z1)   (> 0: top toward +x)

Usage:
  python3 gen_block_clump.py [--W 0.25] [--D 0.25] [--H 1.0] [--rbase 0.001]
        [--rside 0.025] [--nz 8] [--nbase 0] [--ntop 1] [--nface 0]
        [--mass 100] [--prefix block]
"""
import argparse
import math


def build(W, D, H, rbase, rside, nz, nbase, ntop, nface):
    b, d, h = W / 2, D / 2, H / 2
    S = []                                     # (x, y, z, r, comment)
    # measurement spheres first (IDs 1..4)
    S.append((-b, -d, -h, rbase, "base corner (-,-) : angle base point, ID 1"))
    S.append((-b, -d, +h, rside, "top corner  (-,-) : angle top point, ID 2"))
    S.append((+b, +d, -h, rbase, "base corner (+,+) : ID 3"))
    S.append((+b, +d, +h, rside, "top corner  (+,+) : ID 4"))
    S.append((+b, -d, -h, rbase, "base corner (+,-)"))
    S.append((-b, +d, -h, rbase, "base corner (-,+)"))
    # optional intermediate spheres along the 4 base edges (same small radius)
    for k in range(1, nbase + 1):
        s = -1 + 2.0 * k / (nbase + 1)
        for (x, y) in ((s * b, -d), (s * b, +d), (-b, s * d), (+b, s * d)):
            S.append((x, y, -h, rbase, "base edge"))
    # vertical edges: nz-1 spheres between base and top (top corner separately)
    for k in range(1, nz):
        z = -h + H * k / nz
        for (x, y) in ((-b, -d), (+b, -d), (+b, +d), (-b, +d)):
            S.append((x, y, z, rside, "vertical edge"))
    S.append((+b, -d, +h, rside, "top corner (+,-)"))
    S.append((-b, +d, +h, rside, "top corner (-,+)"))
    # top edges: ntop intermediate spheres per edge
    for k in range(1, ntop + 1):
        s = -1 + 2.0 * k / (ntop + 1)
        for (x, y) in ((s * b, -d), (s * b, +d), (-b, s * d), (+b, s * d)):
            S.append((x, y, +h, rside, "top edge"))
    # optional side-face spheres (nface x nface interior grid on the 4 side faces)
    for i in range(1, nface + 1):
        for k in range(1, nz):
            z = -h + H * k / nz
            u = -1 + 2.0 * i / (nface + 1)
            for (x, y) in ((u * b, -d), (u * b, +d), (-b, u * d), (+b, u * d)):
                S.append((x, y, z, rside, "side face"))
    return S


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--W", type=float, default=0.25, help="width along x [m]")
    ap.add_argument("--D", type=float, default=0.25, help="depth along y [m]")
    ap.add_argument("--H", type=float, default=1.0, help="height along z [m]")
    ap.add_argument("--rbase", type=float, default=0.001, help="radius of base spheres [m]")
    ap.add_argument("--rside", type=float, default=0.025, help="radius of envelope spheres [m]")
    ap.add_argument("--nz", type=int, default=8, help="vertical-edge subdivisions")
    ap.add_argument("--nbase", type=int, default=0, help="extra spheres per base edge")
    ap.add_argument("--ntop", type=int, default=1, help="extra spheres per top edge")
    ap.add_argument("--nface", type=int, default=0, help="face-grid columns per side face")
    ap.add_argument("--mass", type=float, default=100.0, help="block mass [kg]")
    ap.add_argument("--prefix", default="block")
    a = ap.parse_args()

    b, d, h = a.W / 2, a.D / 2, a.H / 2
    if 2 * h / a.nz < (a.rside - a.rbase) / math.cos(math.radians(60)):
        raise SystemExit("lowest envelope sphere could touch the floor: increase nz or reduce rside")
    S = build(a.W, a.D, a.H, a.rbase, a.rside, a.nz, a.nbase, a.ntop, a.nface)
    m = a.mass
    Ixx = m * (a.D ** 2 + a.H ** 2) / 12
    Iyy = m * (a.W ** 2 + a.H ** 2) / 12
    Izz = m * (a.W ** 2 + a.D ** 2) / 12
    cmd = "python3 gen_block_clump.py " + " ".join(
        "--%s %s" % (k, getattr(a, k)) for k in ("W", "D", "H", "rbase", "rside", "nz", "nbase", "ntop", "nface", "mass", "prefix"))

    with open(a.prefix + ".clump", "w") as f:
        f.write("# multisphere clump of a %g x %g x %g m block (x y z r, body coords, origin = COM)\n" % (a.W, a.D, a.H))
        f.write("# generated by: %s\n" % cmd)
        f.write("# %d spheres; base spheres r=%g centred on the base corners/edges (z=-h)\n" % (len(S), a.rbase))
        for (x, y, z, r, c) in S:
            f.write("%.9f %.9f %.9f %.9f\n" % (x, y, z, r))

    with open(a.prefix + ".in", "w") as f:
        f.write("# generated by: %s  (do not edit; regenerate)\n" % cmd)
        f.write("# geometry of %s.clump: half-sizes, sphere radii, IDs of measurement spheres\n" % a.prefix)
        f.write("variable blk_b      equal %.9g   # half width  along x [m]\n" % b)
        f.write("variable blk_d      equal %.9g   # half depth  along y [m]\n" % d)
        f.write("variable blk_h      equal %.9g   # half height along z [m]\n" % h)
        f.write("variable blk_rbase  equal %.9g   # radius of the base (floor-contact) spheres [m]\n" % a.rbase)
        f.write("variable blk_rside  equal %.9g   # radius of the envelope spheres [m]\n" % a.rside)
        f.write("variable blk_rmax   equal %.9g   # largest sphere radius [m]\n" % max(a.rbase, a.rside))
        f.write("variable blk_nsph   equal %d   # number of spheres in the clump\n" % len(S))
        f.write("variable blk_mass   equal %.9g   # mass [kg]\n" % m)
        f.write("variable blk_Ixx    equal %.9g   # solid-box inertia about COM [kg m^2]\n" % Ixx)
        f.write("variable blk_Iyy    equal %.9g\n" % Iyy)
        f.write("variable blk_Izz    equal %.9g\n" % Izz)
        f.write("variable blk_idbase equal 1   # atom ID (1st clump) of base corner (-b,-d,-h)\n")
        f.write("variable blk_idtop  equal 2   # atom ID (1st clump) of top  corner (-b,-d,+h)\n")
        f.write("variable blk_idbase2 equal 3  # atom ID (1st clump) of base corner (+b,+d,-h)\n")
    print("wrote %s.clump (%d spheres) and %s.in" % (a.prefix, len(S), a.prefix))


if __name__ == "__main__":
    main()
