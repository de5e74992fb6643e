#!/usr/bin/env python3
"""Convergence table of the reference traces: max |x(0.1 ms) - x(0.05 ms)| per channel, absolute and
relative to the channel's peak (docs/physics.md §9.12). Usage: convergence.py COMMIT [REFERENCES [HALVED]] > tests/reference/README.md (REFERENCES: the folder of the
0.1 ms traces, default tests/reference; HALVED: that of the 0.05 ms ones, default out/reference)."""
import csv
import sys

CHANNELS = ["ay", "yaw_rate", "roll_rate", "az", "vx", "y", "wheel_z_fl", "wheel_z_rr", "tire_fy_fl", "tire_fz_fl"]


def load(path):
    rows = list(csv.DictReader(open(path)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


print("# Reference traces\n")
print("Each scene from `bash scripts/make_references.sh`: `rtv scene <scene> --formulation conventional "
      "--integrator rk4 --step 0.0001` (0.01 s output interval, defaults otherwise: hold, relaxation slip, "
      f"calibrated amplitude, retuned ride height), generated at commit `{sys.argv[1]}`.\n")
print("Convergence: the same run at 0.05 ms; max |difference| over the 801 samples, and relative to the "
      "channel's peak |value|. RK4's error falls as h^4, so the 0.1 ms trace is within about 1/15 more of "
      "the shown difference of the exact solution (Richardson).\n")
refs = sys.argv[2] if len(sys.argv) > 2 else "tests/reference"
halved = sys.argv[3] if len(sys.argv) > 3 else "out/reference"
for scene in ["bump", "jturn", "sine"]:
    a = load(f"{refs}/{scene}.csv")
    b = load(f"{halved}/{scene}_half.csv")
    print(f"## {scene}\n\n| channel | max abs diff | relative to peak |\n|---|---|---|")
    for c in CHANNELS:
        d = max(abs(x - y) for x, y in zip(a[c], b[c]))
        peak = max(abs(x) for x in a[c]) or 1.0
        print(f"| {c} | {d:.3e} | {d / peak:.3e} |")
    print()
