#!/usr/bin/env python3
"""Root locus against speed of `rtv linearize` (docs/linear_root_locus.png).

    python3 scripts/plot_linear.py SWEEP.csv OUT.png

SWEEP.csv is `rtv linearize --sweep-speeds FROM:TO:STEP --csv SWEEP.csv`: one row per eigenvalue (one of each
complex pair) and speed, with the mode's name. Left, the body and handling modes (|λ| up to 25 1/s); right,
every mode. Colour: speed; marker: the kind of mode (its name without the corners).
"""
import csv
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = list(csv.DictReader(open(sys.argv[1])))
speeds = sorted({float(r["speed_m_s"]) for r in rows})
# "wheel hop fl+fr; in phase" -> "wheel hop": the corners and their phase vary with speed, the kind does not;
# a mode two kinds share ("wheel spin + tread") is marked by the first.
kind = lambda name: re.split(r" (?:fl|fr|rl|rr)\b|;| \+ ", name)[0]
kinds = sorted({kind(r["mode"]) for r in rows})
markers = dict(zip(kinds, "osD^v<>ph*xX+1234"))
cmap = plt.get_cmap("viridis")
colour = lambda v: cmap((v - speeds[0]) / max(speeds[-1] - speeds[0], 1e-9))

fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
for ax, limit in zip(axes, (25.0, None)):
    for k in kinds:
        pts = [r for r in rows if kind(r["mode"]) == k]
        if limit is not None:
            pts = [r for r in pts if abs(complex(float(r["real_1_s"]), float(r["imag_1_s"]))) <= limit]
        if not pts:
            continue
        re_ = [float(r["real_1_s"]) for r in pts]
        im = [float(r["imag_1_s"]) for r in pts]
        ax.scatter(re_, im, c=[colour(float(r["speed_m_s"])) for r in pts], marker=markers[k], s=22, label=k,
                   edgecolors="none")
    ax.axvline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("Re λ [1/s]")
    ax.set_ylabel("Im λ [1/s]")
    ax.grid(alpha=0.3)
axes[0].set_title("body and handling modes (|λ| ≤ 25 1/s)")
axes[1].set_title("every mode")
# The right panel has every kind; its legend sits between the tread modes (Im λ = 0) and the wheel hop.
legend = axes[1].legend(loc="lower left", bbox_to_anchor=(0.01, 0.06), fontsize=8)
for handle in getattr(legend, "legend_handles", None) or legend.legendHandles:
    handle.set_color("grey")  # the marker says the kind; the colour of a point is its speed
sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(speeds[0], speeds[-1]))
fig.colorbar(sm, ax=axes, label="speed [m/s]")
fig.suptitle(f"Eigenvalues of straight running against speed, {speeds[0]:g}–{speeds[-1]:g} m/s (rtv linearize)")
fig.savefig(sys.argv[2], dpi=110)
print(f"wrote {sys.argv[2]}")
