#!/usr/bin/env python3
"""Writes resources/roads/test_track.xodr and resources/roads/rms_course_1in.xodr.

test_track.xodr: an OpenDRIVE road that exercises every reference-line geometry and
the profiles rt-vehicle evaluates (docs/roads.md, "OpenDRIVE").

The road: 80 m straight, a 40 m clothoid into a 120 m arc of radius 150 m (banked 4 %), a 40 m clothoid out,
a 60 m paramPoly3 (a gentle S, arc-length parametrised over [0, 1]) and 80 m straight; a 1.5 m crest in the
elevation profile over the first straight and the clothoid; one driving lane each side, 3.75 m wide, and a
2.5 m shoulder. Each record's start pose is the previous record's end, integrated here independently of the
model's evaluator (composite Simpson's rule on 20 000 intervals per record, a relative error far below 1e-12).

rms_course_1in.xodr: a straight 520 m road on a 1 % grade with the NRMM 1 in RMS course
(detrended_rms_course_1in.crg, Project Chrono, BSD-3) attached to it from s = 0 to its end at 504.75 m:
OpenDRIVE's way of putting a measured surface on a road.
"""
import math
import pathlib
import numpy as np

OUT = pathlib.Path(__file__).resolve().parent.parent / "resources" / "roads" / "test_track.xodr"


def integrate(heading, length, n=20000):
    """End offset (dx, dy) of a curve of unit speed with heading(s) over [0, length] (Simpson)."""
    s = np.linspace(0.0, length, n + 1)
    w = np.ones(n + 1)
    w[1:-1:2] = 4.0
    w[2:-1:2] = 2.0
    h = heading(s)
    return float(length / (3 * n) * np.dot(w, np.cos(h))), float(length / (3 * n) * np.dot(w, np.sin(h)))


def lane_section(left, right):
    """The <lanes> of a road with one lane section: lanes (id, type, width) left and right of the centre."""
    def lane(i, kind, w):
        return (f'          <lane id="{i}" type="{kind}" level="false">\n'
                f'            <width sOffset="0.0" a="{w}" b="0.0" c="0.0" d="0.0"/>\n'
                f'          </lane>')
    side = lambda lanes: "\n".join(lane(*l) for l in lanes)
    return f'''    <lanes>
      <laneSection s="0.0">
        <left>
{side(left)}
        </left>
        <center>
          <lane id="0" type="none" level="false"/>
        </center>
        <right>
{side(right)}
        </right>
      </laneSection>
    </lanes>'''


def main():
    records = []
    x, y, hdg, s = 0.0, 0.0, 0.0, 0.0

    def add(length, shape, heading, end_hdg, end_xy=None):
        nonlocal x, y, hdg, s
        records.append((s, x, y, hdg, length, shape))
        if end_xy is None:
            dx, dy = integrate(heading, length)
        else:
            dx, dy = end_xy
        x, y, hdg, s = x + dx, y + dy, end_hdg, s + length

    k = 1.0 / 150.0
    add(80.0, "<line/>", lambda u: hdg + 0 * u, hdg)
    h0 = hdg
    add(40.0, f'<spiral curvStart="0.0" curvEnd="{k!r}"/>', lambda u: h0 + k * u * u / (2 * 40.0), h0 + k * 40.0 / 2)
    h0 = hdg
    add(120.0, f'<arc curvature="{k!r}"/>', lambda u: h0 + k * u, h0 + k * 120.0)
    h0 = hdg
    add(40.0, f'<spiral curvStart="{k!r}" curvEnd="0.0"/>', lambda u: h0 + k * u - k * u * u / (2 * 40.0),
        h0 + k * 40.0 / 2)
    # paramPoly3 over p in [0, 1]: u(p) = L p, v(p) = A (3p^2 - 2p^3)... a smooth lateral shift of A that
    # starts and ends along the heading; its arc length is computed here for the record's length.
    L, A = 60.0, 2.0
    au, bu, cu, du = 0.0, L, 0.0, 0.0
    av, bv, cv, dv = 0.0, 0.0, 3 * A, -2 * A
    p = np.linspace(0.0, 1.0, 200001)
    speed = np.hypot(bu + 2 * cu * p + 3 * du * p * p, bv + 2 * cv * p + 3 * dv * p * p)
    wts = np.ones_like(p)
    wts[1:-1:2] = 4.0
    wts[2:-1:2] = 2.0
    length = float(np.dot(wts, speed) / (3 * (len(p) - 1)))
    c, sn = math.cos(hdg), math.sin(hdg)
    u1, v1 = au + bu + cu + du, av + bv + cv + dv
    add(length,
        f'<paramPoly3 aU="{au!r}" bU="{bu!r}" cU="{cu!r}" dU="{du!r}" aV="{av!r}" bV="{bv!r}" cV="{cv!r}" '
        f'dV="{dv!r}" pRange="normalized"/>', None, hdg, end_xy=(u1 * c - v1 * sn, u1 * sn + v1 * c))
    add(80.0, "<line/>", None, hdg, end_xy=(80.0 * math.cos(hdg), 80.0 * math.sin(hdg)))
    total = s

    geoms = "\n".join(
        f'      <geometry s="{s0!r}" x="{x0!r}" y="{y0!r}" hdg="{h!r}" length="{ln!r}">\n        {shape}\n'
        f'      </geometry>' for (s0, x0, y0, h, ln, shape) in records)
    # Crest: a cubic rise of 1.5 m over s in [30, 90], flat before, then a cubic fall back to 0 over [90, 150].
    rise = lambda a, b, H: (3 * H / (b - a) ** 2, -2 * H / (b - a) ** 3)
    c1, d1 = rise(30.0, 90.0, 1.5)
    c2, d2 = rise(90.0, 150.0, -1.5)
    elevation = (
        '      <elevation s="0.0" a="0.0" b="0.0" c="0.0" d="0.0"/>\n'
        f'      <elevation s="30.0" a="0.0" b="0.0" c="{c1!r}" d="{d1!r}"/>\n'
        f'      <elevation s="90.0" a="1.5" b="0.0" c="{c2!r}" d="{d2!r}"/>\n'
        '      <elevation s="150.0" a="0.0" b="0.0" c="0.0" d="0.0"/>')
    # Bank: 0 on the straight, a linear ramp to atan(0.04) over the entry clothoid, held over the arc, back to 0.
    bank = math.atan(0.04)
    super_ = (
        '      <superelevation s="0.0" a="0.0" b="0.0" c="0.0" d="0.0"/>\n'
        f'      <superelevation s="80.0" a="0.0" b="{bank / 40.0!r}" c="0.0" d="0.0"/>\n'
        f'      <superelevation s="120.0" a="{bank!r}" b="0.0" c="0.0" d="0.0"/>\n'
        f'      <superelevation s="240.0" a="{bank!r}" b="{-bank / 40.0!r}" c="0.0" d="0.0"/>\n'
        '      <superelevation s="280.0" a="0.0" b="0.0" c="0.0" d="0.0"/>')
    lanes = lane_section
    text = f'''<?xml version="1.0" encoding="UTF-8"?>
<!-- Written by scripts/make_test_track.py (rt-vehicle): every reference-line geometry (line, spiral, arc,
     paramPoly3), an elevation crest and a banked curve. Public domain. -->
<OpenDRIVE>
  <header revMajor="1" revMinor="6" name="rt-vehicle test track" version="1" date="2026-11-25" north="0" south="0" east="0" west="0" vendor="rt-vehicle"/>
  <road name="test track" length="{total!r}" id="1" junction="-1">
    <link/>
    <planView>
{geoms}
    </planView>
    <elevationProfile>
{elevation}
    </elevationProfile>
    <lateralProfile>
{super_}
    </lateralProfile>
{lanes([(2, "shoulder", 2.5), (1, "driving", 3.75)], [(-1, "driving", 3.75), (-2, "shoulder", 2.5)])}
  </road>
</OpenDRIVE>
'''
    OUT.write_text(text)
    print(f"{OUT}: {total:.6f} m, end at x = {x:.9f} m, y = {y:.9f} m, heading {hdg:.12f} rad")
    rms = OUT.parent / "rms_course_1in.xodr"
    rms.write_text(f'''<?xml version="1.0" encoding="UTF-8"?>
<!-- Written by scripts/make_test_track.py (rt-vehicle): the NRMM 1 in RMS course (detrended_rms_course_1in.crg,
     Project Chrono, BSD-3, see LICENSE-chrono) attached to a straight road on a 1 % grade. -->
<OpenDRIVE>
  <header revMajor="1" revMinor="6" name="rt-vehicle RMS course on a road" version="1" date="2026-11-25" north="0" south="0" east="0" west="0" vendor="rt-vehicle"/>
  <road name="rms course" length="520.0" id="1" junction="-1">
    <link/>
    <planView>
      <geometry s="0.0" x="0.0" y="0.0" hdg="0.0" length="520.0">
        <line/>
      </geometry>
    </planView>
    <elevationProfile>
      <elevation s="0.0" a="0.0" b="0.01" c="0.0" d="0.0"/>
    </elevationProfile>
{lanes([(1, "driving", 3.0)], [(-1, "driving", 3.0)])}
    <surface>
      <CRG file="detrended_rms_course_1in.crg" sStart="0.0" sEnd="504.75" orientation="same" mode="attached" purpose="elevation" sOffset="0.0" tOffset="0.0" zOffset="0.0" zScale="1.0"/>
    </surface>
  </road>
</OpenDRIVE>
''')
    print(rms)


if __name__ == "__main__":
    main()
