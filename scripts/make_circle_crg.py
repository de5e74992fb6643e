#!/usr/bin/env python3
"""Writes data/roads/circle_50m.crg: a closed OpenCRG track (docs/roads.md "Closed reference lines"), this
project's own file. A left-turning circle whose lap is 314 m (radius 314/(2 pi) = 49.97 m), 12 m wide (cross
sections every 1 m from v = -6 to 6 m), level, its reference line given by its heading phi every 0.2 m
(OpenCRG's LRFI ASCII format): the last point lies one increment before the first, and
REFLINE_CONTINUATION = 1 asks for the closed track.

    python3 scripts/make_circle_crg.py
"""
import math
import pathlib

LAP, INCREMENT, HALF_WIDTH = 314.0, 0.2, 6
RADIUS = LAP / (2 * math.pi)
points = round(LAP / INCREMENT)  # u = 0, 0.2, ..., 313.8: the lap's last increment closes the line
end_u = (points - 1) * INCREMENT
sections = list(range(-HALF_WIDTH, HALF_WIDTH + 1))
head = f"""$CT
Closed circle for lapping tests (rt-vehicle, scripts/make_circle_crg.py): lap {LAP} m, radius {RADIUS:.4f} m,
left turn, 12 m wide, level.
$
$ROAD_CRG
REFERENCE_LINE_START_U   = 0.0
REFERENCE_LINE_END_U     = {end_u!r}
REFERENCE_LINE_INCREMENT = {INCREMENT!r}
REFERENCE_LINE_START_X   = 0.0
REFERENCE_LINE_START_Y   = 0.0
LONG_SECTION_V_RIGHT     = {-HALF_WIDTH}.0
LONG_SECTION_V_LEFT      = {HALF_WIDTH}.0
$
$ROAD_CRG_OPTS
REFLINE_CONTINUATION     = 1
$
$KD_Definition
#:LRFI
U:reference line u,m,0,{INCREMENT!r}
D:reference line phi,rad
""" + "".join(f"D:long section at v = {v:.3f},m\n" for v in sections) + "$\n"
# LRFI: each cross section (phi, then each long section) in 10-character fields, eight to an 80-character
# line, its last line filled with blanks (a record is whole 80-character lines).
rows = []
for i in range(points):
    section = [i * INCREMENT / RADIUS] + [0.0] * len(sections)
    for k in range(0, len(section), 8):
        rows.append("".join(f"{x:10.7f}" for x in section[k : k + 8]).ljust(80))
path = pathlib.Path(__file__).resolve().parent.parent / "data/roads/circle_50m.crg"
path.write_text(head + "$$$$\n" + "\n".join(rows) + "\n")
print(f"wrote {path}: {points} points, lap {LAP} m")
