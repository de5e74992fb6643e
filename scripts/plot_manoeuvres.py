#!/usr/bin/env python3
"""The four manoeuvres of `rtv manoeuvre` in one PNG (docs/manoeuvres.png).

    python3 scripts/plot_manoeuvres.py DIR [PNG]    reads DIR/{step-steer,sine-with-dwell,steady-state,fishhook}.csv,
                                                    writes PNG (default docs/manoeuvres.png)
"""
import csv
import math
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def load(path):
    rows = list(csv.DictReader(open(path)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


d = sys.argv[1]
png = sys.argv[2] if len(sys.argv) > 2 else "docs/manoeuvres.png"
deg = 180 / math.pi
fig, ax = plt.subplots(3, 2, figsize=(12, 11))
s = load(f"{d}/step-steer.csv")
a = ax[0][0]
a.plot(s["time"], [v * deg for v in s["yaw_rate"]], label="yaw rate [deg/s]")
a.plot(s["time"], s["ay"], label="a_y [m/s²]")
a.plot(s["time"], [v * 1e3 for v in s["rack_displacement"]], label="rack [mm]")
a.set_title("ISO 7401 step steer, 80 km/h")
a.set_xlabel("time [s]")
a.legend()
w = load(f"{d}/sine-with-dwell.csv")
a = ax[0][1]
a.plot(w["time"], [v * deg for v in w["yaw_rate"]], label="yaw rate [deg/s]")
a.plot(w["time"], [v * 1e3 for v in w["rack_displacement"]], label="rack [mm]")
a.plot(w["time"], [y - w["y"][0] for y in w["y"]], label="lateral displacement [m]")
a.set_title("FMVSS 126 sine with dwell, 80 km/h, coasting")
a.set_xlabel("time [s]")
a.legend()
c = load(f"{d}/steady-state.csv")
a = ax[1][0]
a.plot([v / 9.81 for v in c["ay"]], [0.5 * (l + r) * deg for l, r in zip(c["steer_fl"], c["steer_fr"])])
a.set_title("ISO 4138 constant speed (100 km/h), slowly increasing steer")
a.set_xlabel("lateral acceleration [g]")
a.set_ylabel("mean front road-wheel steer [deg]")
f = load(f"{d}/fishhook.csv")
a = ax[1][1]
a.plot(f["time"], [v * deg for v in f["roll"]], label="roll [deg]")
a.plot(f["time"], [v * 1e3 for v in f["rack_displacement"]], label="rack [mm]")
for wname in ["fl", "fr", "rl", "rr"]:
    a.plot(f["time"], [v / 1e3 for v in f[f"tire_fz_{wname}"]], lw=0.8, label=f"F_z {wname.upper()} [kN]")
a.set_title("NHTSA fishhook (fixed timing), 80 km/h, coasting")
a.set_xlabel("time [s]")
a.legend(fontsize=7)
l = load(f"{d}/double-lane-change.csv")
a = ax[2][0]
x0, y0 = l["x"][0], l["y"][0]
a.plot([x - x0 - 30 for x in l["x"]], [y - y0 for y in l["y"]], label="CM path")
b = 2.16
w1, w3, w5 = 1.1 * b + 0.25, b + 1.0, min(1.3 * b + 0.25, 3.0)
for (x_from, x_to, lo, hi) in [(0, 12, -w1 / 2, w1 / 2), (25.5, 36.5, w1 / 2 + 1, w1 / 2 + 1 + w3),
                               (49, 61, -w1 / 2, -w1 / 2 + w5)]:
    for yy in (lo, hi):
        a.plot([x_from, x_to], [yy, yy], "k.", ms=4)
a.set_title("ISO 3888-2 double lane change at 80 km/h (cones; the CM)")
a.set_xlabel("x from the entry [m]")
a.set_ylabel("y [m]")
a.legend()
ax[2][1].axis("off")
fig.tight_layout()
fig.savefig(png, dpi=110)
print(f"wrote {png}")
