#!/usr/bin/env python3
"""Figures and tables of docs/tire_magic_formula.md from the runs of scripts/tire_comparison.sh.

Usage: plot_tire_comparison.py OUT_DIR AMPLITUDE_M DOCS_DIR
Writes DOCS_DIR/tire_mf_curves.png, DOCS_DIR/tire_mf_jturn.png and DOCS_DIR/tire_magic_formula.md.
"""
import re
import sys

import matplotlib

matplotlib.use("Agg")  # files only
import matplotlib.pyplot as plt
import numpy as np

LOADS = [3000, 6300, 9500]
G = 9.80665


def load(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def metric(text, name):
    m = re.search(name + r"[^:]*:\s*([-0-9.]+)", text)
    return float(m.group(1)) if m else float("nan")


def curves(out, docs):
    fig, axes = plt.subplots(2, 3, figsize=(16, 9))
    (ax_fy, ax_fx, ax_mz), (ax_comb_x, ax_comb_y, ax_mx) = axes
    colours = dict(zip(LOADS, ["tab:blue", "tab:orange", "tab:green"]))
    rows = []
    for fz in LOADS:
        for tire, style in (("sti", "--"), ("mf", "-")):
            a = load(f"{out}/{tire}_alpha_{fz}.csv")
            k = load(f"{out}/{tire}_kappa_{fz}.csv")
            c = load(f"{out}/{tire}_combined_{fz}.csv")
            label = f"{'STI' if tire == 'sti' else 'MF'} {fz / 1000:g} kN"
            ax_fy.plot(a["alpha_deg"], a["fy_n"] / 1e3, style, color=colours[fz], label=label)
            ax_mz.plot(a["alpha_deg"], a["mz_nm"], style, color=colours[fz], label=label)
            ax_mx.plot(a["alpha_deg"], a["mx_nm"], style, color=colours[fz], label=label)
            ax_fx.plot(k["kappa"], k["fx_n"] / 1e3, style, color=colours[fz], label=label)
            at4 = c[c["alpha_deg"] == 4.0]
            ax_comb_x.plot(at4["kappa"], at4["fx_n"] / 1e3, style, color=colours[fz], label=label)
            ax_comb_y.plot(at4["kappa"], at4["fy_n"] / 1e3, style, color=colours[fz], label=label)
            # Table: cornering stiffness (slope at 0 over ±0.5°), peak |F_y|/F_z, slip stiffness, peak |F_x|/F_z.
            small = np.abs(a["alpha_deg"]) <= 0.5
            c_alpha = -np.polyfit(np.radians(a["alpha_deg"][small]), a["fy_n"][small], 1)[0]
            small_k = np.abs(k["kappa"]) <= 0.01
            c_kappa = np.polyfit(k["kappa"][small_k], k["fx_n"][small_k], 1)[0]
            rows.append((tire, fz, c_alpha, np.max(np.abs(a["fy_n"])) / fz, c_kappa, np.max(np.abs(k["fx_n"])) / fz,
                         np.max(np.abs(a["mz_nm"]))))
    for ax, title, xl, yl in (
        (ax_fy, "pure lateral force (κ = 0)", "α [deg]", "F_y [kN]"),
        (ax_fx, "pure longitudinal force (α = 0)", "κ [-]", "F_x [kN]"),
        (ax_mz, "aligning moment (κ = 0)", "α [deg]", "M_z [N m]"),
        (ax_comb_x, "combined slip at α = 4°: F_x", "κ [-]", "F_x [kN]"),
        (ax_comb_y, "combined slip at α = 4°: F_y", "κ [-]", "F_y [kN]"),
        (ax_mx, "overturning moment (κ = 0)", "α [deg]", "M_x [N m]"),
    ):
        ax.set_title(title)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.grid(True, alpha=0.3)
    ax_fy.legend(fontsize=8)
    fig.suptitle("HMMWV tires, ISO 8855 axes: STI (dashed) and Magic Formula of HMMWV_Pac02Tire.tir (solid)")
    fig.tight_layout()
    fig.savefig(f"{docs}/tire_mf_curves.png", dpi=110)
    return rows


def jturn(out, docs):
    sti, mf = load(f"{out}/sti_jturn.csv"), load(f"{out}/mf_jturn.csv")
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    for ax, col, scale, yl in ((axes[0], "ay", 1 / G, "a_y [g]"), (axes[1], "yaw_rate", 1.0, "yaw rate [rad/s]"),
                               (axes[2], "roll", 180 / np.pi, "roll [deg]")):
        ax.plot(sti["time"], sti[col] * scale, "--", label="STI")
        ax.plot(mf["time"], mf[col] * scale, "-", label="Magic Formula")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(yl)
        ax.grid(True, alpha=0.3)
    axes[0].legend()
    fig.suptitle("J-turn at 100 km/h, the same rack amplitude (the STI tire's 0.4 g calibration)")
    fig.tight_layout()
    fig.savefig(f"{docs}/tire_mf_jturn.png", dpi=110)

    def steady(d):
        w = (d["time"] >= 6) & (d["time"] <= 8)
        return d["ay"][w].mean() / G, d["yaw_rate"][w].mean(), np.degrees(d["roll"][w].mean())

    def rise(d):
        ay = d["ay"]
        final = ay[(d["time"] >= 6) & (d["time"] <= 8)].mean()
        t90 = d["time"][np.argmax(ay >= 0.9 * final)]
        return t90, np.max(ay) / final - 1

    return steady(sti), steady(mf), rise(sti), rise(mf)


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    out, amplitude, docs = argv[1], float(argv[2]), argv[3]
    rows = curves(out, docs)
    (s_ay, s_r, s_roll), (m_ay, m_r, m_roll), (s_t90, s_over), (m_t90, m_over) = jturn(out, docs)
    sti_txt, mf_txt = open(f"{out}/sti_steady.txt").read(), open(f"{out}/mf_steady.txt").read()
    k_sti, k_mf = metric(sti_txt, "understeer gradient"), metric(mf_txt, "understeer gradient")
    max_sti, max_mf = metric(sti_txt, "largest lateral acceleration"), metric(mf_txt, "largest lateral acceleration")
    lines = [
        "# The Magic Formula tire against the STI tire (HMMWV)",
        "",
        "Written by `bash scripts/tire_comparison.sh` (runs `rtv tire`, `rtv manoeuvre steady-state` and",
        "`rtv scene jturn` with and without `--tire resources/tires/HMMWV_Pac02Tire.tir`, then",
        "`scripts/plot_tire_comparison.py`); do not edit by hand above the section \"MF 6.1 / 6.2\", which is",
        "written by hand and kept by the script. The model is described in docs/tire.md, \"Magic Formula\".",
        "",
        "## Steady-state curves (ISO 8855 signs, camber 0, `rtv tire`)",
        "",
        "![curves](tire_mf_curves.png)",
        "",
        "| tire | F_z [N] | C_α [N/rad] | max \\|F_y\\|/F_z | C_κ [N] | max \\|F_x\\|/F_z | max \\|M_z\\| [N m] |",
        "|---|---|---|---|---|---|---|",
    ]
    for tire, fz, ca, muy, ck, mux, mz in rows:
        lines.append(f"| {'STI' if tire == 'sti' else 'MF'} | {fz} | {ca:.0f} | {muy:.3f} | {ck:.0f} | {mux:.3f} | {mz:.1f} |")
    lines += [
        "",
        "## The vehicle",
        "",
        "| | STI | Magic Formula |",
        "|---|---|---|",
        f"| understeer gradient, steady-state cornering at 100 km/h [deg/g] | {k_sti:.3f} | {k_mf:.3f} |",
        f"| largest a_y of that manoeuvre [g] | {max_sti:.3f} | {max_mf:.3f} |",
        f"| J-turn, rack {amplitude * 1e3:.3f} mm: steady a_y (6–8 s) [g] | {s_ay:.4f} | {m_ay:.4f} |",
        f"| J-turn: steady yaw rate [rad/s] | {s_r:.4f} | {m_r:.4f} |",
        f"| J-turn: yaw-rate gain [rad/s per mm of rack] | {s_r / (amplitude * 1e3):.4f} | {m_r / (amplitude * 1e3):.4f} |",
        f"| J-turn: steady roll [deg] | {s_roll:.3f} | {m_roll:.3f} |",
        f"| J-turn: time to 90 % of steady a_y [s] | {s_t90:.3f} | {m_t90:.3f} |",
        f"| J-turn: a_y overshoot | {s_over * 100:.2f} % | {m_over * 100:.2f} % |",
        "",
        "![J-turn](tire_mf_jturn.png)",
        "",
    ]
    # The hand-written section from "## MF 6.1 / 6.2" on is kept as it is.
    path = f"{docs}/tire_magic_formula.md"
    try:
        old = open(path).read()
    except FileNotFoundError:
        old = ""
    kept = old[old.index("## MF 6.1 / 6.2") :] if "## MF 6.1 / 6.2" in old else ""
    open(path, "w").write("\n".join(lines) + ("\n" + kept if kept else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
