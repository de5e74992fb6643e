#!/usr/bin/env python3
"""Suspension and steering kinematic curves from `rtv kinematics` / `rtv steering` CSVs.

    bash scripts/plots.sh        (runs the CLI, then this script)
"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def load(path):
    rows = list(csv.DictReader(open(path)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


front, rear, steer = load(sys.argv[1]), load(sys.argv[2]), load(sys.argv[3])
fig, ax = plt.subplots(1, 3, figsize=(14, 4.5))
for name, d, style in [("front", front, "-"), ("rear", rear, "--")]:
    ax[0].plot([c for c in d["camber_l_deg"]], [1e3 * t for t in d["travel_m"]], style, label=f"{name} left")
    ax[1].plot([c for c in d["steer_l_deg"]], [1e3 * t for t in d["travel_m"]], style, label=f"{name} left")
ax[0].set_xlabel("camber [deg] (+ top of wheel outboard)")
ax[0].set_ylabel("wheel travel [mm] (+ bump)")
ax[0].set_title("Camber against wheel travel (chassis fixed)")
ax[1].set_xlabel("toe / steer angle [deg] (+ wheel heading left)")
ax[1].set_title("Bump steer (rack centred)")
ax[2].plot([1e3 * u for u in steer["rack_displacement_m"]], steer["steer_l_deg"], label="left wheel")
ax[2].plot([1e3 * u for u in steer["rack_displacement_m"]], steer["steer_r_deg"], "--", label="right wheel")
ax[2].set_xlabel("rack input [mm] (+ left turn)")
ax[2].set_ylabel("road-wheel angle [deg] (+ left)")
ax[2].set_title("Steering: rack to road-wheel angle")
for a in ax:
    a.grid(True)
    a.legend()
fig.tight_layout()
fig.savefig(sys.argv[4], dpi=110)
