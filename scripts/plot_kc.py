#!/usr/bin/env python3
"""Figures of a K&C report from the CSVs `rtv kc` writes beside it.

    .venv/bin/python scripts/plot_kc.py docs/kc/hmmwv

reads docs/kc/hmmwv_{front,rear}_travel.csv and docs/kc/hmmwv_steering.csv and writes the PNGs of the
same names. `rtv kc` runs this itself when `.venv/bin/python` and this script are at hand
(`bash scripts/kc.sh` writes every shipped vehicle's report).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(path):
    rows = list(csv.DictReader(open(path)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def finish(fig, axes, xlabel, title, out):
    """Common axis dressing (the design or centre position marked), title, and the PNG."""
    for a in axes:
        a.set_xlabel(xlabel)
        a.axvline(0.0, color="0.6", lw=0.8)
        a.grid(True)
        a.legend(fontsize=9)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def travel_figure(prefix, axle):
    d = load(f"{prefix}_{axle}_travel.csv")
    z = [1e3 * t for t in d["travel_m"]]
    mm = lambda key: [1e3 * v for v in d[key]]  # noqa: E731
    fig, ax = plt.subplots(2, 3, figsize=(15, 8.5))
    panels = [
        ("camber [deg] (+ top outboard)", [("left", d["camber_l_deg"]), ("right", d["camber_r_deg"])]),
        ("toe-in [deg] (+ front of wheel inboard)", [("left", d["toe_in_l_deg"]), ("right", d["toe_in_r_deg"])]),
        ("track change [mm] (contact points)", [("track", mm("track_change_m"))]),
        (
            "wheel-centre displacement [mm], left",
            [("x (+ forward; recession = −x)", mm("wheel_dx_m")), ("y (+ outboard)", mm("wheel_dy_m"))],
        ),
        (
            "motion ratio −dL/dz (compression per jounce)",
            [("spring", d["spring_motion_ratio"]), ("damper", d["damper_motion_ratio"])],
        ),
        ("roll-centre height above ground [mm]", [("kinematic roll centre", mm("roll_centre_height_m"))]),
    ]
    for a, (label, series) in zip(ax.flat, panels):
        for i, (name, values) in enumerate(series):
            a.plot(z, values, "-" if i == 0 else "--", label=name)
        a.set_ylabel(label)
    title = f"{os.path.basename(prefix)}: {axle} axle against parallel wheel travel (chassis fixed, steering centred)"
    return finish(fig, ax.flat, "wheel travel z [mm] (+ jounce)", title, f"{prefix}_{axle}_travel.png")


def steering_figure(prefix):
    d = load(f"{prefix}_steering.csv")
    column = next(iter(d))
    rack = column == "rack_displacement_m"
    u = [1e3 * v for v in d[column]] if rack else d[column]
    xlabel = "rack displacement [mm] (+ left turn)" if rack else "Pitman-arm angle [rad] (+ left turn)"
    ratio_key = next(k for k in d if k.startswith("ratio_"))
    ratio_unit = "m/rad" if rack else "rad/rad"
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    ax[0].plot(u, d["steer_l_deg"], label="left wheel")
    ax[0].plot(u, d["steer_r_deg"], "--", label="right wheel")
    ax[0].set_ylabel("road-wheel angle [deg] (+ heading left)")
    ax[1].plot(u, d["ackermann_error_deg"], label="inside − ideal Ackermann inside")
    ax[1].set_ylabel("Ackermann error [deg] (+ more than Ackermann)")
    ax[2].plot(u, d[ratio_key], label="d input / d mean road-wheel angle")
    ax[2].set_ylabel(f"overall steering ratio [{ratio_unit}]")
    title = f"{os.path.basename(prefix)}: steering (lower arms at design; left wheel inside for input > 0)"
    return finish(fig, ax, xlabel, title, f"{prefix}_steering.png")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    prefix = sys.argv[1]
    # A rigid axle has no travel CSV (its K&C is left out): plot the axles that have one.
    axles = [a for a in ["front", "rear"] if os.path.exists(f"{prefix}_{a}_travel.csv")]
    for out in [travel_figure(prefix, a) for a in axles] + [steering_figure(prefix)]:
        print(f"plot_kc: wrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main()
