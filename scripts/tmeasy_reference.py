#!/usr/bin/env python3
"""Chrono's ChTMeasyTire, steady state, in plain Python: the reference tables of data/tmeasy_reference/ that
tests/tmeasy.rs compares rtv's TMeasy tire (src/model/tire/tmeasy.rs) against.

Written from Project Chrono's source at commit 7689fbc02d12c5419fa6acad8791100fd89979dd (BSD-3-Clause), not
from rtv's:
  src/chrono_vehicle/wheeled_vehicle/tire/TMeasyTire.cpp   TMeasyTire::Create (the JSON reader)
  src/chrono_vehicle/wheeled_vehicle/tire/ChTMeasyTire.cpp Synchronize (slips, InterpL/InterpQ of the curve
      parameters at q = min(Fz, pn_max)/pn, contact length), Advance (combined slip), tmxy_combined,
      AlignmentTorque, GetNormalStiffnessForce (the deflection of a load, with the bottoming spring),
      GetTireMaxLoad, GuessTruck80Par, GuessPassCar70Par
  src/chrono_vehicle/wheeled_vehicle/tire/ChTMeasyTire.h   InterpL, InterpQ
Each force is Chrono's above its low-speed range (v_x >= 3 m/s: frblend = 1, no Dahl friction, M_z on),
at the deflection whose spring force is the load (no damping: steady state), road friction mu_road = mu_0.

Tires (their JSON files are written here with Chrono's numbers, and read back by both sides):
  HMMWV_TMeasyTire.json: Chrono's data/vehicle/hmmwv/tire/HMMWV_TMeasyTire.json (load index 108, Truck).
  van_TMeasyTireFull.json: Chrono's data/vehicle/VW_microbus/json/van_TMeasyTireFull.json (full
      parameters, spring from test data), with its damping key spelled as TMeasyTire::Create reads it,
      "Tire Vertical Damping [Ns/m]": Chrono's file says "Vertical Tire Damping [Ns/m]", which Chrono's
      reader does not find (rtv refuses that file, naming the key); and without its bottoming keys: its
      "Tire Bottoming Radius [m]" 0.396 exceeds its unloaded radius 0.3135, so Chrono's bottoming spring
      (500 kN/m) would push from the first contact (Chrono's default, rim radius + 0.01 m, is used).
  branches.json: that tire with slopes and sliding forces that take every branch of tmxy_combined.

Usage: python3 scripts/tmeasy_reference.py   (writes data/tmeasy_reference/; under a second)
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "data", "tmeasy_reference")
COMMIT = "7689fbc02d12c5419fa6acad8791100fd89979dd"

HMMWV = {
    "Name": "HMMWV TMeasy Tire",
    "Type": "Tire",
    "Template": "TMeasyTire",
    "Design": {
        "Unloaded Radius [m]": 0.4699,
        "Mass [kg]": 37.6,
        "Inertia [kg.m2]": [3.84, 6.69, 3.84],
        "Width [m]": 0.3175,
        "Rim Radius [m]": 0.2095,
    },
    "Coefficient of Friction": 0.8,
    "Rolling Resistance Coefficient": 0.015,
    "Vehicle Type": "Truck",
    "Load Index": 108,
    "Maximum Bearing Capacity [N]": 17167.5,
}

VAN_FULL = {
    "Name": "VW Bus TMeasy Tire",
    "Type": "Tire",
    "Template": "TMeasyTire",
    "Design": {
        "Unloaded Radius [m]": 0.3135,
        "Mass [kg]": 9.3,
        "Inertia [kg.m2]": [0.2, 0.37, 0.2],
        "Width [m]": 0.185,
        "Rim Radius [m]": 0.1778,
    },
    "Coefficient of Friction": 0.8,
    "Rolling Resistance Coefficient": 0.015,
    "Vehicle Type": "Passenger",
    "Load Index": 86,
    "Inflation Pressure Design [Pa]": 320000,
    "Inflation Pressure Use [Pa]": 320000,
    "Parameters": {
        "Vertical": {
            "Nominal Vertical Force [N]": 1900,
            "Tire Spring Curve Data": [[0, 0], [0.03, 2900], [0.06, 6000]],
            "Tire Vertical Damping [Ns/m]": 1801.74,
        },
        "Longitudinal": {
            "Initial Slopes dFx/dsx [N]": [34910.7021, 73974.3082],
            "Maximum Fx Load [N]": [2145.5102, 4140.6407],
            "Sliding Fx Load [N]": [1522.8229, 2922.8487],
            "Slip sx at Maximum Fx": [0.13913, 0.13913],
            "Slip sx where sliding begins": [0.66667, 0.66667],
        },
        "Lateral": {
            "Initial Slopes dFy/dsy [N]": [30366.8749, 48833.5824],
            "Maximum Fy Load [N]": [1901.7234, 3471.9636],
            "Sliding Fy Load [N]": [1583.8391, 2938.7727],
            "Slip sy at Maximum Fy": [0.14852, 0.18504],
            "Slip sy where sliding begins": [0.96524, 1.0714],
        },
        "Aligning": {
            "Normalized Trail at Zero Slip sy": [0.178, 0.19],
            "Slip sy where Trail Changes Sign": [0.16337, 0.20355],
            "Slip sy where Trail Tends to Zero": [0.96524, 1.0714],
        },
    },
}

# The van's tire with its slopes and sliding forces changed so that every branch of tmxy_combined is taken:
# an initial slope below 2 F_M/s_M (raised), and a steep lateral slope with a low sliding force (the cubic).
VARIANT = json.loads(json.dumps(VAN_FULL))
VARIANT["Name"] = "TMeasy branches"
VARIANT["Parameters"]["Longitudinal"]["Initial Slopes dFx/dsx [N]"] = [20000.0, 40000.0]
VARIANT["Parameters"]["Lateral"]["Initial Slopes dFy/dsy [N]"] = [3.0e6, 6.0e6]
VARIANT["Parameters"]["Lateral"]["Sliding Fy Load [N]"] = [300.0, 600.0]


def tire_max_load(li):
    """GetTireMaxLoad: kg per load index (the entries the two tires use), times 9.81."""
    kg = {86: 530.0, 108: 1000.0}
    return kg[li] * 9.81


def guess(par, load, width, ratio, rim_dia, mass, truck):
    """GuessTruck80Par / GuessPassCar70Par with pinfl_li = pinfl_use = 1, damping_ratio 0.5."""
    secth = width * ratio
    defl_max = 0.16 * secth
    pn = 0.5 * load
    par["pn"] = pn
    par["pn_max"] = 3.5 * pn
    cz = load / defl_max
    par["d1"], par["d2"] = cz, 0.0
    par["dz"] = 2.0 * 0.5 * math.sqrt(cz * mass)
    par["rr"] = 0.015
    par["rim_radius"] = 0.5 * rim_dia
    par["R0"] = secth + rim_dia / 2.0
    par["mu0"] = 0.8
    if truck:
        n = dict(dfx0=(17.7764, 14.5301), fxm=(0.89965, 0.77751), fxs=(0.46183, 0.42349),
                 sxm=(0.10811, 0.12389), sxs=(0.66667, 0.66667),
                 dfy0=(7.4013, 6.8505), fym=(0.75876, 0.72628), fys=(0.68276, 0.65319),
                 sym=(0.33167, 0.33216), sys=(1.0296, 1.0296),
                 nL0=(0.178, 0.19), sq0=(0.36484, 0.36538), sqe=(1.0296, 1.0296))
    else:
        n = dict(dfx0=(18.3741, 19.4669), fxm=(1.1292, 1.0896), fxs=(0.80149, 0.76917),
                 sxm=(0.13913, 0.13913), sxs=(0.66667, 0.66667),
                 dfy0=(15.9826, 12.8509), fym=(1.0009, 0.91367), fys=(0.8336, 0.77336),
                 sym=(0.14852, 0.18504), sys=(0.96524, 1.0714),
                 nL0=(0.178, 0.19), sq0=(0.16337, 0.20355), sqe=(0.96524, 1.0714))
    for k in ("dfx0", "fxm", "fxs", "dfy0", "fym", "fys"):
        par[k] = (n[k][0] * pn, n[k][1] * 2.0 * pn)
    for k in ("sxm", "sxs", "sym", "sys", "nL0", "sq0", "sqe"):
        par[k] = n[k]


def least_squares_spring(points):
    """SetVerticalStiffness(defl, frc): F = d1 x + d2 x^2 by least squares (solved by Gram-Schmidt QR here,
    Chrono uses Eigen's colPivHouseholderQr)."""
    a1 = [x for x, _ in points]
    a2 = [x * x for x, _ in points]
    b = [f for _, f in points]
    dot = lambda u, v: sum(p * q for p, q in zip(u, v))
    n1 = math.sqrt(dot(a1, a1))
    q1 = [x / n1 for x in a1]
    r12 = dot(q1, a2)
    w = [x - r12 * q for x, q in zip(a2, q1)]
    n2 = math.sqrt(dot(w, w))
    q2 = [x / n2 for x in w]
    c1, c2 = dot(q1, b), dot(q2, b)
    d2 = c2 / n2
    d1 = (c1 - r12 * d2) / n1
    return d1, d2


def create(d):
    """TMeasyTire::Create."""
    des = d["Design"]
    par = dict(mass=des["Mass [kg]"], R0=des["Unloaded Radius [m]"], rim_radius=des["Rim Radius [m]"],
               width=des["Width [m]"], rr=0.01, mu0=0.8, bottom_radius=0.0, bottom_stiffness=0.0)
    if "Parameters" in d:
        p = d["Parameters"]
        v = p["Vertical"]
        par["pn"] = v["Nominal Vertical Force [N]"]
        par["pn_max"] = v.get("Maximum Vertical Force [N]", 3.5 * par["pn"])
        if "Vertical Tire Stiffness [N/m]" in v:
            par["d1"], par["d2"] = v["Vertical Tire Stiffness [N/m]"], 0.0
        else:
            par["d1"], par["d2"] = least_squares_spring(v["Tire Spring Curve Data"])
        par["dz"] = v["Tire Vertical Damping [Ns/m]"]
        par["bottom_radius"] = v.get("Tire Bottoming Radius [m]", 0.0)
        par["bottom_stiffness"] = v.get("Tire Bottoming Stiffness [N/m]", 0.0)
        lo, la, al = p["Longitudinal"], p["Lateral"], p["Aligning"]
        par["dfx0"] = lo["Initial Slopes dFx/dsx [N]"]
        par["fxm"] = lo["Maximum Fx Load [N]"]
        par["fxs"] = lo["Sliding Fx Load [N]"]
        par["sxm"] = lo["Slip sx at Maximum Fx"]
        par["sxs"] = lo["Slip sx where sliding begins"]
        par["dfy0"] = la["Initial Slopes dFy/dsy [N]"]
        par["fym"] = la["Maximum Fy Load [N]"]
        par["fys"] = la["Sliding Fy Load [N]"]
        par["sym"] = la["Slip sy at Maximum Fy"]
        par["sys"] = la["Slip sy where sliding begins"]
        par["nL0"] = al["Normalized Trail at Zero Slip sy"]
        par["sq0"] = al["Slip sy where Trail Changes Sign"]
        par["sqe"] = al["Slip sy where Trail Tends to Zero"]
    else:
        li = d["Load Index"]
        ratio = (par["R0"] - par["rim_radius"]) / par["width"]
        guess(par, tire_max_load(li), par["width"], ratio, 2 * par["rim_radius"], par["mass"],
              d["Vehicle Type"] == "Truck")
    if "Coefficient of Friction" in d:
        par["mu0"] = d["Coefficient of Friction"]
    if "Rolling Resistance Coefficient" in d:
        par["rr"] = d["Rolling Resistance Coefficient"]
    # ChTMeasyTire::Initialize: unset bottoming parameters.
    if par["bottom_radius"] == 0:
        par["bottom_radius"] = par["rim_radius"] + 0.01
    if par["bottom_stiffness"] == 0:
        par["bottom_stiffness"] = 5.0 * par["d1"]
    return par


def spring(par, depth):
    """GetNormalStiffnessForce."""
    f = depth * par["d1"] + depth * depth * par["d2"]
    free = par["R0"] - par["bottom_radius"]
    if depth - free > 0:
        f += (depth - free) * par["bottom_stiffness"]
    return f


def depth_of(par, fz):
    """The deflection whose spring force is fz, by bisection (the spring rises with depth)."""
    lo, hi = 0.0, par["R0"]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if spring(par, mid) < fz:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def tmxy_combined(s, df0, sm, fm, ss, fs):
    df0loc = 0.0
    if sm > 0.0:
        df0loc = max(2.0 * fm / sm, df0)
    if s > 0.0 and df0loc > 0.0:
        if s > ss:
            return fs
        if s < sm:
            p = df0loc * sm / fm - 2.0
            sn = s / sm
            dn = 1.0 + (sn + p) * sn
            return df0loc * sm * sn / dn
        a = (fm / sm) ** 2 / (df0loc * sm)
        sstar = sm + (fm - fs) / (a * (ss - sm))
        if sstar <= ss:
            if s <= sstar:
                return fm - a * (s - sm) * (s - sm)
            b = a * (sstar - sm) / (ss - sstar)
            return fs + b * (ss - s) * (ss - s)
        sn = (s - sm) / (ss - sm)
        return fm - (fm - fs) * sn * sn * (3.0 - 2.0 * sn)
    return 0.0


def alignment_torque(fy, sy, nto0, synto0, syntoE, p_len):
    sy_a = abs(sy)
    syntoE_loc = max(syntoE, synto0)
    if sy_a >= syntoE_loc:
        nto = 0.0
    else:
        wf = synto0 / syntoE_loc
        if sy_a <= synto0:
            sy_n = sy_a / synto0
            nto1 = nto0 * (1.0 - sy_n)
            nto2 = nto0 * (1.0 - (3.0 - 2.0 * sy_n) * sy_n ** 2)
            nto = (1.0 - wf) * nto1 + wf * nto2
        else:
            sy_n = (syntoE_loc - sy_a) / (syntoE_loc - synto0)
            nto = -nto0 * (1.0 - wf) * (sy_a - synto0) / synto0 * sy_n ** 2
    return -fy * p_len * nto


def forces(par, fz, sx, sy):
    """Synchronize + Advance at load fz (spring force only), Rill's slips sx, sy; muscale = 1."""
    depth = depth_of(par, fz)
    q = min(max(fz, 0.0), par["pn_max"]) / par["pn"]
    interp_l = lambda w: w[0] + (w[1] - w[0]) * (q - 1.0)
    interp_q = lambda w: q * (2.0 * w[0] - 0.5 * w[1] - (w[0] - 0.5 * w[1]) * q)
    st = {k: interp_q(par[k]) for k in ("dfx0", "fxm", "fxs", "dfy0", "fym", "fys")}
    st.update({k: interp_l(par[k]) for k in ("sxm", "sxs", "sym", "sys", "nL0", "sq0", "sqe")})
    p_len = 2.0 * math.sqrt(par["R0"] * depth)
    muscale = 1.0
    sc = math.hypot(sx, sy)
    if sc > 0:
        calpha, salpha = sx / sc, sy / sc
    else:
        calpha = salpha = math.sqrt(2.0) / 2.0
    df0 = math.hypot(st["dfx0"] * calpha, st["dfy0"] * salpha)
    fm = muscale * math.hypot(st["fxm"] * calpha, st["fym"] * salpha)
    sm = muscale * math.hypot(st["sxm"] * calpha, st["sym"] * salpha)
    fs = muscale * math.hypot(st["fxs"] * calpha, st["fys"] * salpha)
    ss = muscale * math.hypot(st["sxs"] * calpha, st["sys"] * salpha)
    f = tmxy_combined(sc, df0, sm, fm, ss, fs)
    fx, fy = (f * calpha, f * salpha) if sc > 0 else (0.0, 0.0)
    mz = alignment_torque(fy, sy, st["nL0"], st["sq0"], st["sqe"], p_len)
    return fx, fy, mz, depth


def main():
    os.makedirs(OUT, exist_ok=True)
    slips = [x / 100.0 for x in range(-100, 101, 2)] + [-1.5, 1.5, 3.0]
    combined = [(a / 10.0, b / 10.0) for a in range(-6, 7, 2) for b in range(-6, 7, 2) if a and b]
    for name, d in (("HMMWV_TMeasyTire", HMMWV), ("van_TMeasyTireFull", VAN_FULL), ("branches", VARIANT)):
        with open(os.path.join(OUT, name + ".json"), "w") as f:
            json.dump(d, f, indent=2)
            f.write("\n")
        par = create(d)
        rows = []
        # Half, once and twice the nominal load, and one beyond pn_max (the curves stop growing there).
        for load in (0.5, 1.0, 2.0, 4.0):
            fz = load * par["pn"]
            for s in slips:
                rows.append(("longitudinal", fz, s, 0.0) + forces(par, fz, s, 0.0))
                rows.append(("lateral", fz, 0.0, s) + forces(par, fz, 0.0, s))
            for sx, sy in combined:
                rows.append(("combined", fz, sx, sy) + forces(par, fz, sx, sy))
        with open(os.path.join(OUT, name + ".csv"), "w") as f:
            f.write(f"# {name}.json: ChTMeasyTire at Chrono {COMMIT}, scripts/tmeasy_reference.py; "
                    f"pn {par['pn']!r} N, pn_max {par['pn_max']!r} N, d1 {par['d1']!r}, d2 {par['d2']!r}\n")
            f.write("case,fz,sx,sy,fx,fy,mz,depth\n")
            for r in rows:
                f.write(",".join([r[0]] + [repr(float(x)) for x in r[1:]]) + "\n")
        print(f"{name}: {len(rows)} rows")


if __name__ == "__main__":
    main()
