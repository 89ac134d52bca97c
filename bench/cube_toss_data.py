#!/usr/bin/python3
"""What the cube-toss recordings themselves say (docs/validation.md, "Cube tosses";
docs/recordings.md): how the file's velocities were made, the free-fall acceleration in the flight samples, the deceleration of face-on sliding,
and how far the corners dip below their resting height during impacts.

  bench/cube_toss_data.py [../shared/data/experiments/cube_toss/cube_tosses_0-299.csv.gz] [--first 0] [--last 149]
"""
import argparse
import gzip
import os

import numpy as np

from cube_toss_study import SIGNS, lowest_corner, rotation_matrices

HZ = 148.0
TABLE = -0.001         # m, the README's table height
CLEARANCE = 0.002      # m: flight while every corner is this far above the table (as cube_flight_state)
FLAT = 0.0015          # m: a corner within this of the lowest counts as down
MIN_SAMPLES = 8        # samples per fitted phase


def read(path):
    with gzip.open(path, "rt") as f:
        data = np.loadtxt(f, delimiter=",", skiprows=1)
    return {int(i): data[data[:, 0] == i] for i in np.unique(data[:, 0])}


def free_fall(toss):
    """Acceleration (world) of a free quadratic through the flight samples, or None."""
    x, q = toss[:, 7:10], toss[:, 3:7]
    n = int(np.argmax(lowest_corner(x, q) < TABLE + CLEARANCE))
    if n < MIN_SAMPLES:
        return None
    t = toss[:n, 1] / HZ
    return np.linalg.lstsq(np.stack([np.ones(n), t, t * t / 2], -1), x[:n], rcond=None)[0][2]


def velocity_differences(tosses):
    """Median |v_file - difference of positions| (m/s, per axis) in the first samples, for
    backward, forward and central differences."""
    rows = {"backward": [], "forward": [], "central": []}
    for toss in tosses:
        x, v = toss[:7, 7:10], toss[:7, 13:16]
        rows["backward"].append(v[1:6] - (x[1:6] - x[0:5]) * HZ)
        rows["forward"].append(v[1:6] - (x[2:7] - x[1:6]) * HZ)
        rows["central"].append(v[1:6] - (x[2:7] - x[0:5]) * HZ / 2)
    return {name: np.median(np.abs(np.concatenate(r)), axis=0) for name, r in rows.items()}


def face_sliding(toss):
    """Deceleration / g of each phase sliding face-on (4 corners down, moving)."""
    x, q = toss[:, 7:10], toss[:, 3:7]
    corners = x[:, None, 2] + (SIGNS @ rotation_matrices(q).transpose(0, 2, 1))[:, :, 2]
    down = (corners < corners.min(axis=1, keepdims=True) + FLAT).sum(axis=1) >= 4
    speed = np.linalg.norm(np.gradient(x[:, :2], 1 / HZ, axis=0), axis=1)
    sliding = np.concatenate([[False], down & (speed > 0.04), [False]])
    edges = np.flatnonzero(np.diff(sliding.astype(int)))
    out = []
    for start, stop in zip(edges[::2], edges[1::2]):
        if stop - start < MIN_SAMPLES:
            continue
        t = np.arange(start, stop) / HZ
        c = np.linalg.lstsq(np.stack([np.ones(len(t)), t, t * t / 2], -1), x[start:stop, :2], rcond=None)[0]
        v = c[1] + c[2] * t.mean()
        out.append(-c[2] @ v / np.linalg.norm(v) / 9.81)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("tosses", nargs="?",
                        default=os.path.join(root, "..", "shared", "data", "experiments", "cube_toss",
                                             "cube_tosses_0-299.csv.gz"))
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--last", type=int, default=149)
    args = parser.parse_args()
    tosses = [t for i, t in read(args.tosses).items() if args.first <= i <= args.last]
    for name, error in velocity_differences(tosses).items():
        print(f"file velocity against the {name} difference of positions: median |difference| "
              f"{np.round(1e3 * error, 1)} mm/s (x, y, z)")
    falls = np.array([a for a in map(free_fall, tosses) if a is not None])
    print(f"free fall over {len(falls)} tosses' flight samples (>= {MIN_SAMPLES}): acceleration "
          f"{np.round(falls.mean(axis=0), 3)} m/s^2, standard error {np.round(falls.std(axis=0) / np.sqrt(len(falls)), 3)}")
    slides = np.concatenate([face_sliding(t) for t in tosses])
    print(f"face-on sliding: {len(slides)} phases, deceleration / 9.81 mean {slides.mean():.3f}, sd {slides.std():.3f}")
    dips = np.array([lowest_corner(t[:, 7:10], t[:, 3:7]) for t in tosses], dtype=object)
    below = np.array([d[-10:].mean() - d.min() for d in dips])
    print(f"lowest corner below its resting height during the toss: median {1e3 * np.median(below):.2f} mm, "
          f"90th percentile {1e3 * np.percentile(below, 90):.2f} mm")


if __name__ == "__main__":
    main()
