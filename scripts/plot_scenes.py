#!/usr/bin/env python3
"""One PNG per scene with the quantities of the paper's figures (Figs. 9-15), from `rtv scene` CSVs.

    python3 scripts/plot_scenes.py DIR     reads DIR/{bump,jturn,sine}.csv, writes docs/scene_*.png
"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

G = 9.81


def load(path):
    rows = list(csv.DictReader(open(path)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


d = sys.argv[1]
b = load(f"{d}/bump.csv")
fig, ax = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
for w in ["fl", "fr", "rl", "rr"]:
    z = b[f"wheel_z_{w}"]
    ax[0].plot(b["time"], [1e3 * (v - z[0]) for v in z], label=w.upper())
ax[0].set_ylabel("wheel-centre z - z(0) [mm]")
ax[0].legend(ncol=4)
ax[1].plot(b["time"], b["az"])
ax[1].set_ylabel("chassis vertical accel. [m/s²]")
ax[2].plot(b["time"], b["roll_rate"])
ax[2].set_ylabel("roll rate [rad/s]")
ax[2].set_xlabel("time [s]")
ax[0].set_title("Unsymmetric bump run, 10 km/h (paper Figs. 9-10)")
for a in ax:
    a.grid(True)
fig.tight_layout()
fig.savefig("docs/scene_bump.png", dpi=100)

j = load(f"{d}/jturn.csv")
fig, ax = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
ax[0].plot(j["time"], [a / G for a in j["ay"]])
ax[0].set_ylabel("lateral acceleration [g]")
ax[1].plot(j["time"], j["yaw_rate"])
ax[1].set_ylabel("yaw rate [rad/s]")
ax[1].set_xlabel("time [s]")
ax[0].set_title("J-turn, 100 km/h, calibrated rack step (paper Figs. 11-12)")
for a in ax:
    a.grid(True)
fig.tight_layout()
fig.savefig("docs/scene_jturn.png", dpi=100)

s = load(f"{d}/sine.csv")
fig, ax = plt.subplots(3, 1, figsize=(9, 9))
ax[0].plot(s["time"], s["roll_rate"])
ax[0].set_ylabel("roll rate [rad/s]")
ax[1].plot(s["time"], s["yaw_rate"])
ax[1].set_ylabel("yaw rate [rad/s]")
ax[1].set_xlabel("time [s]")
ax[2].plot(s["x"], s["y"])
ax[2].set_xlabel("x [m]")
ax[2].set_ylabel("y [m]")
ax[0].set_title("Sine steer (out and back), 60 km/h (paper Figs. 13-15)")
for a in ax:
    a.grid(True)
fig.tight_layout()
fig.savefig("docs/scene_sine.png", dpi=100)
