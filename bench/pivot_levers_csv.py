#!/usr/bin/env python3
"""Each side's pivot lever of BODY's rock_x straight from a recording's CSV (docs/diagnose.md
study 34): least squares of uplift + h (1 - cos rock_x) on sin|rock_x| per side, a constant, time
and table_dx, h the stated centre height (half_extents z of a box). A check on the recordings
independent of freestand's analysis (no mode segmentation: every finite sample).

    bench/pivot_levers_csv.py RECORDING.csv BODY
"""
import csv, json, sys
import numpy as np

path, body = sys.argv[1], sys.argv[2]
nominal = json.load(open(path[:-4] + ".nominal.json"))
h = next(b for b in nominal["bodies"] if b["name"] == body)["half_extents"][2]
rows = list(csv.DictReader(open(path)))
col = lambda k: np.array([float(r[k]) if r[k] not in ("", "nan") else np.nan for r in rows])
t, x, u, dx = col("t"), col(body + ".rock_x"), col(body + ".uplift"), col("table_dx")
a = np.column_stack([np.where(x > 0, np.sin(x), 0), np.where(x < 0, -np.sin(x), 0), np.ones_like(x), t, dx])
y = u + h * (1 - np.cos(x))
ok = np.isfinite(a).all(axis=1) & np.isfinite(y)
coef, *_ = np.linalg.lstsq(a[ok], y[ok], rcond=None)
print(f"{path} {body}: lever + {coef[0]:.4f} m, lever - {coef[1]:.4f} m (h = {h} m stated)")
