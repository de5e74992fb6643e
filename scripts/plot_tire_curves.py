#!/usr/bin/env python3
"""Plot the STI tire curves written by `cargo run --example tire_curves -- IN.csv` (the paper's Fig. 3).

Usage: plot_tire_curves.py IN.csv OUT.png
Panels: F_x against slip ratio (alpha = 0); F_y and M_z against slip angle (kappa = 0); one line per load.
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt
import numpy as np


def load(path):
    data = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    return data


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    data = load(argv[1])
    loads = sorted(set(data["fz_N"]))
    fig, (ax_fx, ax_fy, ax_mz) = plt.subplots(1, 3, figsize=(15, 4.5))
    for fz in loads:
        label = f"F_z = {fz / 1000:g} kN"
        along_kappa = data[(data["sweep"] == "kappa") & (data["fz_N"] == fz)]
        along_alpha = data[(data["sweep"] == "alpha") & (data["fz_N"] == fz)]
        alpha_deg = np.degrees(along_alpha["alpha_rad"])
        ax_fx.plot(along_kappa["kappa"], along_kappa["fx_N"] / 1000, label=label)
        ax_fy.plot(alpha_deg, along_alpha["fy_N"] / 1000, label=label)
        ax_mz.plot(alpha_deg, along_alpha["mz_Nm"], label=label)
    panels = [
        (ax_fx, "slip ratio κ [-]", "longitudinal force F_x [kN]", "F_x (α = 0)"),
        (ax_fy, "slip angle α [deg]", "lateral force F_y [kN]", "F_y (κ = 0)"),
        (ax_mz, "slip angle α [deg]", "aligning moment M_z [N·m]", "M_z (κ = 0)"),
    ]
    for ax, xlabel, ylabel, title in panels:
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.grid(True, alpha=0.3)
        ax.axhline(0, color="k", lw=0.5)
        ax.axvline(0, color="k", lw=0.5)
        ax.legend(fontsize=8)
    fig.suptitle("STI composite-slip tire, HMMWV data (resources/hmmwv.json), γ_w = 0")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
