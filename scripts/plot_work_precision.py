#!/usr/bin/env python3
"""The work-precision figure: error against derivative evaluations, one panel per case, from the CSV that
`rtv work-precision` writes.

    python3 scripts/plot_work_precision.py out/work_precision.csv docs/work_precision.png
"""
import csv
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = list(csv.DictReader(open(sys.argv[1])))
cases = list(dict.fromkeys(r["case"] for r in rows))
cols = 3
nrows = math.ceil(len(cases) / cols)
fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 4 * nrows), squeeze=False)
series = [
    # Fixed colours: a series with no stable run in a panel must not shift the others' colours.
    ("RK4", lambda r: r["scheme"] == "RK4", "o-C0"),
    ("AB3", lambda r: r["scheme"] == "AB3", "s-C1"),
    ("IMEX-AB3", lambda r: r["scheme"] == "IMEX-AB3", "D-C2"),
    ("DOPRI5, 10 ms intervals", lambda r: r["scheme"] == "DOPRI5" and float(r["interval_s"]) == 0.01, "^-C3"),
    ("DOPRI5, 40 ms intervals", lambda r: r["scheme"] == "DOPRI5" and float(r["interval_s"]) == 0.04, "v-C4"),
]
for ax, case in zip(axes.flat, cases):
    for label, keep, style in series:
        pts = [(float(r["evaluations"]), float(r["error"])) for r in rows if r["case"] == case and keep(r)]
        pts = [(n, e) for n, e in pts if math.isfinite(e) and e > 0]
        if pts:
            pts.sort()
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], style, ms=4, label=label)
    for target in (1e-2, 1e-3, 1e-4):
        ax.axhline(target, color="grey", lw=0.6, ls=":")
    ax.set_title(case)
    ax.set_xlabel("derivative evaluations (8 s)")
    ax.set_ylabel("max error / peak")
    ax.grid(True, which="major", lw=0.3)
for ax in list(axes.flat)[len(cases):]:
    ax.axis("off")
axes.flat[0].legend(fontsize=8)
fig.suptitle("Error against work (rtv work-precision; unstable runs left out)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=90)
print(f"written {sys.argv[2]}")
