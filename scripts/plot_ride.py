#!/usr/bin/env python3
"""The NRMM ride curves of docs/ride.md as a figure (called by scripts/ride.sh).

Usage: plot_ride.py docs/ride.md docs/ride.png
Left: peak seat acceleration (30 Hz low-pass) against speed per half-round height, with the 2.5 g line;
right: absorbed power against speed per RMS course, with the 6 W line. Refused speeds are left out.
"""
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def tables(md):
    """{section title: [(speed, value)]} for every table of the file."""
    out, title = {}, None
    for line in md.splitlines():
        if line.startswith("## "):
            title = line[3:].split(":")[0]
            out[title] = []
        m = re.match(r"\| ([0-9.]+) \| ([0-9.]+) \|", line)
        if m and title:
            out[title].append((float(m.group(1)), float(m.group(2))))
    return out


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    t = tables(open(argv[1]).read())
    fig, (ax_hr, ax_rms) = plt.subplots(1, 2, figsize=(13, 4.8))
    for title, points in t.items():
        if not points:
            continue
        ax = ax_hr if title.startswith("Half-round") else ax_rms
        label = title.replace("Half-round obstacle, ", "half-round ").replace("RMS course, ", "RMS ")
        ax.plot([p[0] for p in points], [p[1] for p in points], "o-", label=label)
    ax_hr.axhline(2.5, color="k", ls="--", lw=1, label="2.5 g")
    ax_rms.axhline(6.0, color="k", ls="--", lw=1, label="6 W")
    ax_hr.set(xlabel="speed [km/h]", ylabel="peak seat a_z, 30 Hz low-pass [g]", title="Half-round obstacles")
    ax_rms.set(xlabel="speed [km/h]", ylabel="absorbed power at the seat [W]", title="RMS courses", yscale="log")
    for ax in (ax_hr, ax_rms):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("HMMWV ride (NRMM method; the model's answer, not validated: docs/roads.md)")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
