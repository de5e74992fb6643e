#!/usr/bin/env python3
"""MFeval's Magic Formula, steady state, in numpy-free Python: the reference tables of
data/mfeval_reference/ (issue 35, part 5) that tests/mfeval_reference.rs compares rtv's tire against.

MATLAB MFeval (Marco Furlan) could not be run here (its repository was not reachable and no MATLAB/Octave);
this follows its Julia port MFeval.jl (github.com/matheusft/MFeval_julia, commit
a3b3ba49c121928e5dfbf0a351843de5a5d153d0, MIT licence, validated by its authors against MATLAB MFeval at 0.0
absolute error on the forces), file by file: src/io/read_tir.jl (the parser and every default value, copied
into DEFAULTS below), src/solver/parse_inputs.jl, basic_vars.jl, Fx0.jl, Fy0.jl, combined_slip.jl, Mz.jl,
Mx.jl, My.jl. useMode 121: limit checks, alpha* = tan(alpha) sign(Vcx) and gamma* = sin(gamma) (MF 6.x's
starred slips), no turn slip. It is written from that code, not from rtv's: the verdict must not depend on
the thing it judges.

MIT notice of MFeval.jl, whose structure this follows:
  Copyright (c) 2026 MFeval.jl contributors. Permission is hereby granted, free of charge, to any person
  obtaining a copy of this software and associated documentation files (the "Software"), to deal in the
  Software without restriction, including without limitation the rights to use, copy, modify, merge,
  publish, distribute, sublicense, and/or sell copies of the Software, and to permit persons to whom the
  Software is furnished to do so, subject to the following conditions: The above copyright notice and this
  permission notice shall be included in all copies or substantial portions of the Software. THE SOFTWARE IS
  PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND.

Usage: python3 scripts/mfeval_reference.py   (writes data/mfeval_reference/*.csv; a few seconds)
"""
import csv
import math
import re
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "data", "mfeval_reference")
MFEVAL_JL_COMMIT = "a3b3ba49c121928e5dfbf0a351843de5a5d153d0"

# MFeval.jl src/io/read_tir.jl: the value of every key a file leaves out.
DEFAULTS = {
"FILE_VERSION": 3.0, "USE_MODE": 124.0, "N_TIRE_STATES": 4.0, "USER_SUB_ID": 815.0, "LONGVL": 16.7, "VXLOW": 
1.0, "ROAD_INCREMENT": 0.01, "ROAD_DIRECTION": 1.0, "UNLOADED_RADIUS": 0.3135, "WIDTH": 0.205, 
"ASPECT_RATIO": 0.6, "RIM_RADIUS": 0.1905, "RIM_WIDTH": 0.152, "INFLPRES": 220000.0, "NOMPRES": 220000.0, 
"MASS1": 9.3, "IXX": 0.391, "IYY": 0.736, "BELT_MASS": 7.0, "BELT_IXX": 0.34, "BELT_IYY": 0.6, "GRAVITY": 
-9.81, "FNOMIN": 4000.0, "VERTICAL_STIFFNESS": 200000.0, "VERTICAL_DAMPING": 50.0, "MC_CONTOUR_A": 0.5, 
"MC_CONTOUR_B": 0.5, "BREFF": 8.4, "DREFF": 0.27, "FREFF": 0.07, "Q_RE0": 1.0, "Q_V1": 0.0, "Q_V2": 0.0, 
"Q_FZ2": 1.0e-4, "Q_FCX": 0.0, "Q_FCY": 0.0, "Q_CAM": 0.0, "PFZ1": 0.0, "BOTTOM_OFFST": 0.01, "BOTTOM_STIFF": 
2000000.0, "LONGITUDINAL_STIFFNESS": 300000.0, "LATERAL_STIFFNESS": 100000.0, "YAW_STIFFNESS": 5000.0, 
"FREQ_LONG": 80.0, "FREQ_LAT": 40.0, "FREQ_YAW": 50.0, "FREQ_WINDUP": 70.0, "DAMP_LONG": 0.04, "DAMP_LAT": 
0.04, "DAMP_YAW": 0.04, "DAMP_WINDUP": 0.04, "DAMP_RESIDUAL": 0.002, "DAMP_VLOW": 0.001, "Q_BVX": 0.0, 
"Q_BVT": 0.0, "PCFX1": 0.0, "PCFX2": 0.0, "PCFX3": 0.0, "PCFY1": 0.0, "PCFY2": 0.0, "PCFY3": 0.0, "PCMZ1": 
0.0, "Q_RA1": 0.5, "Q_RA2": 1.0, "Q_RB1": 1.0, "Q_RB2": -1.0, "ELLIPS_SHIFT": 0.8, "ELLIPS_LENGTH": 1.0, 
"ELLIPS_HEIGHT": 1.0, "ELLIPS_ORDER": 1.8, "ELLIPS_MAX_STEP": 0.025, "ELLIPS_NWIDTH": 10.0, "ELLIPS_NLENGTH": 
10.0, "PRESMIN": 10000.0, "PRESMAX": 1000000.0, "FZMIN": 100.0, "FZMAX": 10000.0, "KPUMIN": -1.5, "KPUMAX": 
1.5, "ALPMIN": -1.5, "ALPMAX": 1.5, "CAMMIN": -0.175, "CAMMAX": 0.175, "LFZO": 1.0, "LCX": 1.0, "LMUX": 1.0, 
"LEX": 1.0, "LKX": 1.0, "LHX": 1.0, "LVX": 1.0, "LCY": 1.0, "LMUY": 1.0, "LEY": 1.0, "LKY": 1.0, "LHY": 1.0, 
"LVY": 1.0, "LTR": 1.0, "LRES": 1.0, "LXAL": 1.0, "LYKA": 1.0, "LVYKA": 1.0, "LS": 1.0, "LKYC": 1.0, "LKZC": 
1.0, "LVMX": 1.0, "LMX": 1.0, "LMY": 1.0, "LMP": 1.0, "PCX1": 1.65, "PDX1": 1.3, "PDX2": -0.15, "PDX3": 0.0, 
"PEX1": 0.0, "PEX2": 0.0, "PEX3": 0.0, "PEX4": 0.0, "PKX1": 20.0, "PKX2": 0.0, "PKX3": 0.0, "PHX1": 0.0, 
"PHX2": 0.0, "PVX1": 0.0, "PVX2": 0.0, "PPX1": 0.0, "PPX2": 0.0, "PPX3": 0.0, "PPX4": 0.0, "RBX1": 20.0, 
"RBX2": 15.0, "RBX3": 0.0, "RCX1": 1.0, "REX1": 0.0, "REX2": 0.0, "RHX1": 0.0, "QSX1": 0.0, "QSX2": 0.0, 
"QSX3": 0.0, "QSX4": 5.0, "QSX5": 1.0, "QSX6": 10.0, "QSX7": 0.0, "QSX8": 0.0, "QSX9": 0.4, "QSX10": 0.0, 
"QSX11": 5.0, "QSX12": 0.0, "QSX13": 0.0, "QSX14": 0.0, "PPMX1": 0.0, "PCY1": 1.3, "PDY1": 1.1, "PDY2": 
-0.15, "PDY3": 0.0, "PEY1": 0.0, "PEY2": 0.0, "PEY3": 0.0, "PEY4": 0.0, "PEY5": 0.0, "PKY1": -20.0, "PKY2": 
1.0, "PKY3": 0.0, "PKY4": 2.0, "PKY5": 0.0, "PKY6": -1.0, "PKY7": 0.0, "PHY1": 0.0, "PHY2": 0.0, "PVY1": 0.0, 
"PVY2": 0.0, "PVY3": 0.0, "PVY4": 0.0, "PPY1": 0.0, "PPY2": 0.0, "PPY3": 0.0, "PPY4": 0.0, "PPY5": 0.0, 
"RBY1": 10.0, "RBY2": 10.0, "RBY3": 0.0, "RBY4": 0.0, "RCY1": 1.0, "REY1": 0.0, "REY2": 0.0, "RHY1": 0.0, 
"RHY2": 0.0, "RVY1": 0.0, "RVY2": 0.0, "RVY3": 0.0, "RVY4": 20.0, "RVY5": 2.0, "RVY6": 10.0, "QSY1": 0.01, 
"QSY2": 0.0, "QSY3": 4.0e-4, "QSY4": 4.0e-5, "QSY5": 0.0, "QSY6": 0.0, "QSY7": 0.85, "QSY8": -0.4, "QBZ1": 
10.0, "QBZ2": 0.0, "QBZ3": 0.0, "QBZ4": 0.0, "QBZ5": 0.0, "QBZ9": 10.0, "QBZ10": 0.0, "QCZ1": 1.1, "QDZ1": 
0.12, "QDZ2": 0.0, "QDZ3": 0.0, "QDZ4": 0.0, "QDZ6": 0.0, "QDZ7": 0.0, "QDZ8": -0.05, "QDZ9": 0.0, "QDZ10": 
0.0, "QDZ11": 0.0, "QEZ1": 0.0, "QEZ2": 0.0, "QEZ3": 0.0, "QEZ4": 0.0, "QEZ5": 0.0, "QHZ1": 0.0, "QHZ2": 0.0, 
"QHZ3": 0.0, "QHZ4": 0.0, "PPZ1": 0.0, "PPZ2": 0.0, "SSZ1": 0.0, "SSZ2": 0.0, "SSZ3": 0.0, "SSZ4": 0.0, 
"PDXP1": 0.4, "PDXP2": 0.0, "PDXP3": 0.0, "PKYP1": 1.0, "PDYP1": 0.4, "PDYP2": 0.0, "PDYP3": 0.0, "PDYP4": 
0.0, "PHYP1": 1.0, "PHYP2": 0.15, "PHYP3": 0.0, "PHYP4": -4.0, "PECP1": 0.5, "PECP2": 0.0, "QDTP1": 10.0, 
"QCRP1": 0.2, "QCRP2": 0.1, "QBRP1": 0.1, "QDRP1": 1.0, "Q_A1": 0.0, "Q_A2": 0.0, "PHY3": 0.0, "PTX1": 0.0, 
"PTX2": 0.0, "PTX3": 0.0, "PTY1": 0.0, "PTY2": 0.0, "LSGKP": 1.0, "LSGAL": 1.0, "SWITCH_INTEG": 0.0, 
"Q_FCY2": 0.0, "Q_CAM1": 0.0, "Q_CAM2": 0.0, "Q_CAM3": 0.0, "Q_FYS1": 0.0, "Q_FYS2": 0.0, "Q_FYS3": 0.0, 
"ENV_C1": 0.0, "ENV_C2": 0.0, "HMAX_LOCAL": 2.5e-4, "TIME_SWITCH_INTEG": 0.1
}


def read_tir(path):
    """read_tir.jl's _parse_tir_file and _build_tireparams: KEY = value lines, [SHAPE] skipped, '$' ends a
    value, the second MASS is MASS1; then DEFAULTS for every key left out. FITTYP is required."""
    values = {}
    skip = False
    mass_count = 0
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            if line.startswith("["):
                skip = line == "[SHAPE]"
                continue
            if line.startswith("$") or line.startswith("!") or skip or "=" not in line:
                continue
            key, raw = line.split("=", 1)
            key = key.strip()
            text = raw.split("$", 1)[0].strip()
            if not key or not text:
                continue
            if key == "MASS":
                mass_count += 1
                key = "MASS" if mass_count == 1 else "MASS1"
            try:
                values[key] = float(text)
            except ValueError:
                values[key] = text.strip("'\"")
    if "FITTYP" not in values:
        raise ValueError(f"{path}: FITTYP not found (read_tir.jl requires it)")
    p = dict(DEFAULTS)
    p.update({k: v for k, v in values.items() if isinstance(v, float)})
    p["ABSENT"] = sorted(k for k in COEFFICIENT_DEFAULTS_CHANGED if k not in values)
    for k in p["ABSENT"]:
        p[k] = FORMAT_NEUTRAL.get(k, 0.0)
    return p


# The one change to MFeval's reading: read_tir.jl fills a coefficient the file leaves out with the value of
# its example tire (QSX4 = 5, QSY1 = 0.01, RBX1 = 20, ...), which adds terms an MF 5.x / PAC2002 file does
# not have (its M_x has no QSX4-QSX11, and a missing combined-slip R* coefficient means none). Here a
# coefficient left out has its neutral value, as the MF-Tyre and ADAMS readers take it: 0, or the value
# that switches the term off. Only the coefficients below differ from read_tir.jl's defaults; each table
# names the ones its file leaves out. MFeval's example files MagicFormula61/62 have them all.
FORMAT_NEUTRAL = {"PKY4": 2.0, "RCX1": 1.0, "RCY1": 1.0, "QSY7": 1.0}
COEFFICIENT_DEFAULTS_CHANGED = [
    k for k, v in DEFAULTS.items()
    if re.fullmatch(r"[PQRS][A-Z]{2,3}[0-9]{1,2}", k) and v != FORMAT_NEUTRAL.get(k, 0.0)
    # turn slip's (xxxP n): useMode 121 has no turn slip
    and not re.fullmatch(r"[PQ][A-Z]{2}P[0-9]", k)
]


def sign(x):
    """MFeval.jl's (x >= 0 ? 1 : -1)."""
    return 1.0 if x >= 0.0 else -1.0


def magic_cos(b, c, e, x):
    return math.cos(c * math.atan(b * x - e * (b * x - math.atan(b * x))))


def fy0_gamma0(p, alpha_star, Fz, Vcx, dfz, dpi, Fz0p):
    """Fy0.jl _fy0_gamma0: the pure lateral force at gamma = 0 (for M_z's F_y')."""
    Kya = p["PKY1"] * Fz0p * (1 + p["PPY1"] * dpi) * math.sin(
        p["PKY4"] * math.atan((Fz / Fz0p) / (p["PKY2"] * (1 + p["PPY2"] * dpi)))) * p["LKY"]
    SHy = (p["PHY1"] + p["PHY2"] * dfz) * p["LHY"]
    SVy = Fz * (p["PVY1"] + p["PVY2"] * dfz) * p["LVY"] * p["LMUY"]
    alphay = alpha_star + SHy
    Cy = p["PCY1"] * p["LCY"]
    muy = (p["PDY1"] + p["PDY2"] * dfz) * (1 + p["PPY3"] * dpi + p["PPY4"] * dpi ** 2) * p["LMUY"]
    muy = 0.0 if Fz == 0.0 else muy
    Dy = muy * Fz
    Ey = min((p["PEY1"] + p["PEY2"] * dfz) * (1 - p["PEY3"] * sign(alphay)) * p["LEY"], 1.0)
    By = Kya / (Cy * Dy + 1e-6 * sign(Dy))
    Fy0 = Dy * math.sin(Cy * math.atan(By * alphay - Ey * (By * alphay - math.atan(By * alphay)))) + SVy
    if Vcx < 0:
        Fy0 = -Fy0
    return Fy0, muy


def gyk_svyk(p, kappa, alpha_star, gamma_star, dfz, Fz, muy, smooth):
    """combined_slip.jl calc_Fy's G_yk and S_Vyk."""
    DVyk = muy * Fz * (p["RVY1"] + p["RVY2"] * dfz + p["RVY3"] * gamma_star) * math.cos(
        math.atan(p["RVY4"] * alpha_star))
    SVyk = DVyk * math.sin(p["RVY5"] * math.atan(p["RVY6"] * kappa)) * p["LVYKA"]
    SHyk = p["RHY1"] + p["RHY2"] * dfz
    Eyk = min(p["REY1"] + p["REY2"] * dfz, 1.0)
    Cyk = p["RCY1"]
    Byk = (p["RBY1"] + p["RBY4"] * gamma_star ** 2) * math.cos(
        math.atan(p["RBY2"] * (alpha_star - p["RBY3"]))) * p["LYKA"]
    Gyk = magic_cos(Byk, Cyk, Eyk, kappa + SHyk) / magic_cos(Byk, Cyk, Eyk, SHyk)
    return Gyk, SVyk * smooth


def mfeval(p, Fz_in, kappa, alpha, gamma, Vcx, pressure=0.0):
    """MFeval's steady-state Fx, Fy, Mx, My, Mz (useMode 121) at load Fz_in (N), slip ratio kappa, slip
    angle alpha (rad), inclination gamma (rad), forward speed Vcx (m/s), inflation pressure (Pa, 0: the
    file's INFLPRES). ISO signs as MFeval returns them."""
    mf52 = p["FITTYP"] in (6.0, 21.0)
    eps = 1e-6
    # parse_inputs.jl
    uFz = max(Fz_in, 0.0)
    ukappa = kappa
    press = pressure if pressure != 0 else p["INFLPRES"]
    VXLOW = p["VXLOW"]
    smooth = 1.0
    if abs(Vcx) <= VXLOW:
        lin = abs(Vcx / VXLOW)
        smooth = 1.0 - 0.5 * (1.0 + math.cos(math.pi * (Vcx / VXLOW)))
        kappa = kappa * lin
    Vsy = math.tan(alpha) * Vcx
    speed_sum = abs(Vcx) + abs(Vsy)
    if speed_sum < VXLOW:
        alpha = alpha * speed_sum / VXLOW
    alpha = min(max(alpha, p["ALPMIN"]), p["ALPMAX"])
    gamma = min(max(gamma, p["CAMMIN"]), p["CAMMAX"])
    Fz = min(max(uFz, 0.0), p["FZMAX"])
    press = min(max(press, p["PRESMIN"]), p["PRESMAX"])
    kappa = min(max(kappa, p["KPUMIN"]), p["KPUMAX"])
    Fz_low = p["FZMIN"] if Fz < p["FZMIN"] else Fz
    if uFz <= 0:
        Fz_low = 0.0
    # basic_vars.jl (LMUV = 0: LMUX* = LMUX, LMUY* = LMUY; Amu = 1: the primed ones too)
    Fz0 = p["FNOMIN"]
    Fz0p = p["LFZO"] * Fz0
    dfz = (Fz - Fz0p) / Fz0p
    dpi = (press - p["NOMPRES"]) / p["NOMPRES"]
    alpha_star = math.tan(alpha) * sign(Vcx)
    gamma_star = math.sin(gamma)
    Vsy = math.tan(alpha) * abs(Vcx)
    Vc = math.sqrt(Vcx ** 2 + Vsy ** 2)
    alpha_prime = math.acos(min(max(Vcx / (Vc + eps * sign(Vc)), -1.0), 1.0))
    LMUX, LMUY = p["LMUX"], p["LMUY"]

    # Fx0.jl
    Cx = p["PCX1"] * p["LCX"]
    mux = (p["PDX1"] + p["PDX2"] * dfz) * (1 + p["PPX3"] * dpi + p["PPX4"] * dpi ** 2) * (
        1 - p["PDX3"] * gamma ** 2) * LMUX
    mux = 0.0 if Fz == 0 else mux
    Dx = mux * Fz
    Kxk = Fz * (p["PKX1"] + p["PKX2"] * dfz) * math.exp(p["PKX3"] * dfz) * (
        1 + p["PPX1"] * dpi + p["PPX2"] * dpi ** 2) * p["LKX"]
    Bx = Kxk / (Cx * Dx + eps * sign(Dx))
    SHx = (p["PHX1"] + p["PHX2"] * dfz) * p["LHX"] * smooth
    SVx = Fz * (p["PVX1"] + p["PVX2"] * dfz) * p["LVX"] * LMUX * smooth
    kappax = kappa + SHx
    Ex = min((p["PEX1"] + p["PEX2"] * dfz + p["PEX3"] * dfz ** 2) * (1 - p["PEX4"] * sign(kappax)) * p["LEX"],
             1.0)
    Fx0 = Dx * math.sin(Cx * math.atan(Bx * kappax - Ex * (Bx * kappax - math.atan(Bx * kappax)))) + SVx
    if Vcx < 0:
        Fx0 = -Fx0

    # Fy0.jl
    Kya = p["PKY1"] * Fz0p * (1 + p["PPY1"] * dpi) * (1 - p["PKY3"] * abs(gamma_star)) * math.sin(
        p["PKY4"] * math.atan((Fz / Fz0p) / ((p["PKY2"] + p["PKY5"] * gamma_star ** 2) * (1 + p["PPY2"] * dpi))
                              )) * p["LKY"]
    SVyg = Fz * (p["PVY3"] + p["PVY4"] * dfz) * gamma_star * p["LKYC"] * LMUY
    if mf52:
        SHy = (p["PHY1"] + p["PHY2"] * dfz) * p["LHY"] + p["PHY3"] * gamma_star * p["LKYC"]
    else:
        Kyg0 = Fz * (p["PKY6"] + p["PKY7"] * dfz) * (1 + p["PPY5"] * dpi) * p["LKYC"]
        SHy = (p["PHY1"] + p["PHY2"] * dfz) * p["LHY"] + (Kyg0 * gamma_star - SVyg) / (Kya + eps * sign(Kya))
    SVy = Fz * (p["PVY1"] + p["PVY2"] * dfz) * p["LVY"] * LMUY + SVyg
    SHy, SVy = SHy * smooth, SVy * smooth
    alphay = alpha_star + SHy
    Cy = p["PCY1"] * p["LCY"]
    muy = (p["PDY1"] + p["PDY2"] * dfz) * (1 + p["PPY3"] * dpi + p["PPY4"] * dpi ** 2) * (
        1 - p["PDY3"] * gamma_star ** 2) * LMUY
    Dy = muy * Fz
    Ey = min((p["PEY1"] + p["PEY2"] * dfz) * (
        1 + p["PEY5"] * gamma_star ** 2 - (p["PEY3"] + p["PEY4"] * gamma_star) * sign(alphay)) * p["LEY"], 1.0)
    By = Kya / (Cy * Dy + eps * sign(Dy))
    Fy0 = Dy * math.sin(Cy * math.atan(By * alphay - Ey * (By * alphay - math.atan(By * alphay)))) + SVy
    if Vcx < 0:
        Fy0 = -Fy0
    muy = 0.0 if Fz == 0 else muy

    # Mz.jl calc_Mz0's intermediates (F_z with its FZMIN low limit)
    Fzm = 0.0 if Fz <= 0 else Fz_low
    Kya_prime = Kya + eps * sign(Kya)
    alphar = alpha_star + SHy + SVy / Kya_prime
    SHt = p["QHZ1"] + p["QHZ2"] * dfz + (p["QHZ3"] + p["QHZ4"] * dfz) * gamma_star
    alphat = alpha_star + SHt
    Bt = (p["QBZ1"] + p["QBZ2"] * dfz + p["QBZ3"] * dfz ** 2) * (
        1 + p["QBZ4"] * gamma + p["QBZ5"] * abs(gamma)) * p["LKY"] / LMUY
    Ct = p["QCZ1"]
    Dt = (p["QDZ1"] + p["QDZ2"] * dfz) * (1 - p["PPZ1"] * dpi) * (1 + p["QDZ3"] * gamma + p["QDZ4"] * gamma ** 2
                                                                 ) * Fzm * (p["UNLOADED_RADIUS"] / Fz0p) * p["LTR"]
    Et = min((p["QEZ1"] + p["QEZ2"] * dfz + p["QEZ3"] * dfz ** 2) * (
        1 + (p["QEZ4"] + p["QEZ5"] * gamma_star) * (2 / math.pi) * math.atan(Bt * Ct * alphat)), 1.0)
    Br = p["QBZ9"] * p["LKY"] / LMUY + p["QBZ10"] * By * Cy
    Cr = 1.0
    R0 = p["UNLOADED_RADIUS"]
    Dr = Fzm * R0 * ((p["QDZ6"] + p["QDZ7"] * dfz) * p["LRES"] + (
        (p["QDZ8"] + p["QDZ9"] * dfz) * (1 + p["PPZ2"] * dpi) + (p["QDZ10"] + p["QDZ11"] * dfz) * abs(gamma_star)
    ) * gamma_star * p["LKZC"]) * LMUY * sign(Vcx) * math.cos(alpha_star)

    # combined_slip.jl
    SHxa = p["RHX1"]
    Exa = min(p["REX1"] + p["REX2"] * dfz, 1.0)
    Bxa = (p["RBX1"] + p["RBX3"] * gamma_star ** 2) * math.cos(math.atan(p["RBX2"] * kappa)) * p["LXAL"]
    Gxa = magic_cos(Bxa, p["RCX1"], Exa, alpha_star + SHxa) / magic_cos(Bxa, p["RCX1"], Exa, SHxa)
    Fx = Gxa * Fx0
    Gyk, SVyk = gyk_svyk(p, kappa, alpha_star, gamma_star, dfz, Fz, muy, smooth)
    Fy = Gyk * Fy0 + SVyk

    # Mx.jl (TNO's form; F_z reduced below FZMIN)
    Fze = Fz * (Fz / p["FZMIN"]) ** 2 if Fz < p["FZMIN"] else Fz
    Mx = R0 * Fze * p["LMX"] * (
        p["QSX1"] * p["LVMX"] - p["QSX2"] * gamma * (1 + p["PPMX1"] * dpi) + p["QSX3"] * (Fy / Fz0)
        + p["QSX4"] * math.cos(p["QSX5"] * math.atan((p["QSX6"] * Fze / Fz0) ** 2))
        * math.sin(p["QSX7"] * gamma + p["QSX8"] * math.atan(p["QSX9"] * Fy / Fz0))
        + p["QSX10"] * math.atan(p["QSX11"] * Fze / Fz0) * gamma) + R0 * p["LMX"] * (
        Fy * (p["QSX13"] + p["QSX14"] * abs(gamma)) - Fze * p["QSX12"] * gamma * abs(gamma))

    # My.jl (F_z, kappa unlimited; the low-speed fade near a locked wheel)
    Fzy = uFz * (uFz / p["FZMIN"]) if uFz < p["FZMIN"] else uFz
    V0 = p["LONGVL"]
    if mf52:
        My = -R0 * Fzy * p["LMY"] * (p["QSY1"] + p["QSY2"] * (Fx / Fz0) + p["QSY3"] * abs(Vcx / V0)
                                     + p["QSY4"] * (Vcx / V0) ** 4)
    else:
        My = -R0 * Fz0 * p["LMY"] * (p["QSY1"] + p["QSY2"] * (Fx / Fz0) + p["QSY3"] * abs(Vcx / V0)
                                     + p["QSY4"] * (Vcx / V0) ** 4
                                     + (p["QSY5"] + p["QSY6"] * (Fzy / Fz0)) * gamma ** 2) * (
            (Fzy / Fz0) ** p["QSY7"] * (press / p["NOMPRES"]) ** p["QSY8"])
    if Vcx == 0:
        My = 0.0
    else:
        if Vcx < 0:
            My = -My
        high = VXLOW / abs(Vcx) - 1.0
        low = -1.0 - VXLOW - high
        if low <= ukappa <= high:
            My = My * math.sin((math.pi / 2) * (ukappa + 1.0) / (high + 1.0))
        elif ukappa < low:
            My = -My

    # Mz.jl calc_Mz
    ratio_sq = (Kxk / Kya_prime) ** 2 * kappa ** 2
    alphar_eq = math.atan(math.sqrt(math.tan(alphar) ** 2 + ratio_sq)) * sign(alphar)
    alphat_eq = math.atan(math.sqrt(math.tan(alphat) ** 2 + ratio_sq)) * sign(alphat)
    s = R0 * (p["SSZ1"] + p["SSZ2"] * (Fy / Fz0) + (p["SSZ3"] + p["SSZ4"] * dfz) * gamma) * p["LS"]
    Mzr = Dr * math.cos(Cr * math.atan(Br * alphar_eq))
    Fy0_g0, muy_g0 = fy0_gamma0(p, alpha_star, Fz, Vcx, dfz, dpi, Fz0p)
    Gyk_g0, _ = gyk_svyk(p, kappa, alpha_star, gamma_star, dfz, Fz, muy_g0, smooth)
    t = Dt * magic_cos(Bt, Ct, Et, alphat_eq) * math.cos(alpha_prime) * p["LFZO"]
    t, Mzr = t * smooth, Mzr * smooth
    if mf52:
        Mz = -t * (Fy - SVyk) + Mzr + s * Fx
    else:
        Mz = -t * (Gyk_g0 * Fy0_g0) + Mzr + s * Fx
    return Fx, Fy, Mx, My, Mz


# The files: MFeval's own examples (data/mfeval_reference/tir/), every .tir file the repository ships, and
# TyreDyn's MF 6.2 examples.
FILES = [
    "data/mfeval_reference/tir/MagicFormula52_Parameters.tir",
    "data/mfeval_reference/tir/MagicFormula61_Parameters.tir",
    "data/mfeval_reference/tir/MagicFormula62_Parameters.tir",
    "data/chrono/feda/tires/335_65R22_5_G275MSA_60psi.tir",
    "data/chrono/generic/tire/Generic_Pac02Tire.tir",
    "data/chrono/hmmwv/tire/HMMWV_Pac02Tire.tir",
    "data/chrono/sedan/tire/Sedan_Pac02Tire.tir",
    "data/chrono/VW_microbus/json/mf_185_80R14.tir",
    "resources/tires/mf61_example.tir",
] + [
    # Seven MF 6.2 example files from TyreDyn (MIT; data/mfeval_reference/README.md says where from).
    f"data/mfeval_reference/tir/tyredyn/{name}.tir"
    for name in ["Bus_270_70R22", "Truck_430_50R38", "car145_70R13", "car205_60R19", "car213_40R21",
                 "car235_50R24", "fsae190_50R10"]
]
CAMBERS_DEG = [-3.0, 0.0, 3.0]
LOAD_FACTORS = [0.5, 1.0, 1.5]


def sweep(lo, hi, n):
    return [lo + (hi - lo) * i / (n - 1) for i in range(n)]


def cases(p):
    """(case, Fz, kappa, alpha, gamma, Vx): pure longitudinal, pure lateral and combined slip at 3 loads and 3
    cambers, both signs of every slip, inside the file's own ranges (KPUMIN/KPUMAX, ALPMIN/ALPMAX: outside
    them MFeval clamps), at the measurement speed LONGVL; and the low-speed fade of M_y near a locked wheel
    (kappa -1.2 ... -0.8 at 1.5-3 VXLOW)."""
    k_lo, k_hi = max(p["KPUMIN"], -0.8), min(p["KPUMAX"], 0.8)
    a_lo, a_hi = max(p["ALPMIN"], -0.5), min(p["ALPMAX"], 0.5)
    vx = p["LONGVL"]
    for lf in LOAD_FACTORS:
        fz = min(lf * p["FNOMIN"], p["FZMAX"])
        for g in CAMBERS_DEG:
            gamma = math.radians(g)
            for k in sweep(k_lo, k_hi, 17):
                yield "pure_kappa", fz, k, 0.0, gamma, vx
            for a in sweep(a_lo, a_hi, 17):
                yield "pure_alpha", fz, 0.0, a, gamma, vx
            for k in sweep(k_lo, k_hi, 5):
                for a in sweep(a_lo, a_hi, 5):
                    yield "combined", fz, k, a, gamma, vx
        if p["KPUMIN"] <= -1.2:
            # |Vx| > VXLOW: only M_y's fade acts (the slips' low-speed reductions start below VXLOW).
            for v in [1.5 * p["VXLOW"], 2.0 * p["VXLOW"], 3.0 * p["VXLOW"]]:
                for k in sweep(-1.2, -0.8, 9):
                    yield "rolling_low_speed", fz, k, 0.0, 0.0, v


def main():
    os.makedirs(OUT, exist_ok=True)
    for rel in FILES:
        p = read_tir_any(os.path.join(ROOT, rel))
        name = rel.replace("/", "__").removesuffix(".tir") + ".csv"
        with open(os.path.join(OUT, name), "w", newline="") as f:
            w = csv.writer(f)
            absent = " ".join(p["ABSENT"]) or "none"
            w.writerow([f"# {rel}: MFeval (MFeval.jl {MFEVAL_JL_COMMIT}, useMode 121) by scripts/mfeval_reference.py"
                        f"; FITTYP evaluated {p['FITTYP']:g}; left out, taken as neutral: {absent}"])
            w.writerow(["case", "fz", "kappa", "alpha", "gamma", "vx", "fx", "fy", "mx", "my", "mz"])
            n = 0
            for case in cases(p):
                out = mfeval(p, *case[1:])
                w.writerow([case[0]] + [repr(float(x)) for x in case[1:]] + [repr(x) for x in out])
                n += 1
        print(f"{rel}: {n} rows -> data/mfeval_reference/{name}")


def read_tir_any(path):
    """read_tir, with the PAC2002 files that carry no FITTYP (Chrono's) or FITTYP = 5 (the FEDA file) run as
    FITTYP 6: PAC2002 is MF-Tyre 5.x's format, and MFeval's MF 5.x equations are its FITTYP 6/21 branch (with
    FITTYP 5 it would take the MF 6.1 branch, whose PKY6 and other keys such a file does not have)."""
    try:
        p = read_tir(path)
    except ValueError:
        if "PAC2002" not in open(path).read():
            raise
        return read_tir_text_with_fittyp(path)
    if p["FITTYP"] == 5.0:
        p["FITTYP"] = 6.0
    return p


def read_tir_text_with_fittyp(path):
    import tempfile
    with tempfile.NamedTemporaryFile("w", suffix=".tir", delete=False) as t:
        t.write("[MODEL]\nFITTYP = 6\n" + open(path).read())
        name = t.name
    try:
        return read_tir(name)
    finally:
        os.unlink(name)


if __name__ == "__main__":
    sys.exit(main())
