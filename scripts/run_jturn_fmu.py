#!/usr/bin/env python3
"""Simulate the J-turn through the packaged FMU with fmpy's low-level API.

0-8 s, 0.01 s communication step, speed hold at 100 km/h. Rack input (left turn positive):
    s(t) = A S((t - 3.0)/0.1),  S(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 on [0, 1],
set at every communication point together with its analytic first and second derivatives
(fmi2SetRealInputDerivatives), so the FMU follows the profile within each step. A is read from
resources/calibration.json (key jturn_amplitude_m), default 0.003 m while that file does not exist.

Writes out/jturn.csv (time and every output), out/jturn.png (a_y in g and yaw rate), prints a summary.
"""

import argparse
import json
import math
import pathlib
import shutil
import sys
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2LastSuccessfulTime, fmi2Terminated

ROOT = pathlib.Path(__file__).resolve().parents[1]
G = 9.81  # the paper's g (docs/physics.md §1), also the model's gravity
T_START, T_RAMP = 3.0, 0.1
DEFAULT_AMPLITUDE = 0.003


def amplitude():
    path = ROOT / "resources" / "calibration.json"
    if not path.is_file():
        return DEFAULT_AMPLITUDE, f"default {DEFAULT_AMPLITUDE} m ({path.relative_to(ROOT)} does not exist yet)"
    data = json.loads(path.read_text())
    a = float(data["jturn_amplitude_m"])
    return a, f"{a} m from {path.relative_to(ROOT)}"


def rack(t, a):
    """s, ds/dt, d2s/dt2 of the smootherstep ramp."""
    tau = (t - T_START) / T_RAMP
    if tau <= 0.0:
        return 0.0, 0.0, 0.0
    if tau >= 1.0:
        return a, 0.0, 0.0
    s = tau**3 * (10 - 15 * tau + 6 * tau**2)
    ds = 30 * tau**2 * (1 - tau) ** 2
    dds = 60 * tau * (1 - tau) * (1 - 2 * tau)
    return a * s, a * ds / T_RAMP, a * dds / T_RAMP**2


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "RtVehicle.fmu"))
    ap.add_argument("--out", default=str(ROOT / "out"))
    ap.add_argument("--stop", type=float, default=8.0)
    ap.add_argument("--step", type=float, default=0.01)
    args = ap.parse_args()

    a, a_source = amplitude()
    md = read_model_description(args.fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    out_vrs = [vr[n] for n in outputs]
    unzipdir = extract(args.fmu)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="jturn")
    rows, times = [], []
    step_times = []
    ended_early = None
    try:
        fmu.instantiate(loggingOn=False)
        fmu.setupExperiment(startTime=0.0, stopTime=args.stop)
        fmu.enterInitializationMode()
        fmu.setReal([vr["initial_speed"]], [100 / 3.6])
        fmu.setInteger([vr["speed_mode"]], [2])
        fmu.exitInitializationMode()

        n = int(round(args.stop / args.step))
        t = 0.0
        times.append(t)
        rows.append(fmu.getReal(out_vrs))
        wall0 = time.perf_counter()
        for k in range(n):
            s, ds, dds = rack(t, a)
            fmu.setReal([vr["rack_displacement"]], [s])
            fmu.setRealInputDerivatives([vr["rack_displacement"]] * 2, [1, 2], [ds, dds])
            t_next = (k + 1) * args.step
            c0 = time.perf_counter()
            try:
                fmu.doStep(t, t_next - t)
            except FMICallException as e:
                if e.status == 2 and fmu.getBooleanStatus(fmi2Terminated):
                    ended_early = fmu.getRealStatus(fmi2LastSuccessfulTime)
                    break
                raise
            step_times.append(time.perf_counter() - c0)
            t = t_next
            times.append(t)
            rows.append(fmu.getReal(out_vrs))
        wall = time.perf_counter() - wall0
        fmu.terminate()
    finally:
        fmu.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)

    out_dir = pathlib.Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    data = np.column_stack([np.array(times), np.array(rows)])
    names = ["time"] + outputs
    np.savetxt(out_dir / "jturn.csv", data, delimiter=",", header=",".join(names), comments="", fmt="%.10g")
    col = {name: data[:, i] for i, name in enumerate(names)}
    tt = col["time"]

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    ax1.plot(tt, col["ay"] / G)
    ax1.set_ylabel("lateral acceleration a_y [g]")
    ax1.grid(True)
    ax1.set_title(f"J-turn through RtVehicle.fmu (fmpy): 100 km/h, hold, rack {1e3 * a:.2f} mm")
    ax2.plot(tt, np.degrees(col["yaw_rate"]))
    ax2.set_ylabel("yaw rate [deg/s]")
    ax2.set_xlabel("time [s]")
    ax2.grid(True)
    fig.tight_layout()
    fig.savefig(out_dir / "jturn.png", dpi=120)

    steady = (tt >= 6.0) & (tt <= 8.0)
    simulated = tt[-1]
    print("J-turn through the FMU (fmpy, FMU2Slave)")
    print(f"  FMU            {args.fmu}")
    print(f"  rack amplitude {a_source}, smootherstep 3.0-3.1 s, analytic input derivatives")
    print(f"  speed          100 km/h, hold; communication step {args.step} s")
    if ended_early is not None:
        print(f"  THE RUN ENDED EARLY at t = {ended_early:.4f} s (fmi2Discard, terminated)")
    if steady.any():
        print(f"  steady a_y     {col['ay'][steady].mean() / G:.4f} g   (mean over 6-8 s)")
        print(f"  steady yaw     {math.degrees(col['yaw_rate'][steady].mean()):.3f} deg/s")
    i_ay = np.argmax(np.abs(col["ay"]))
    i_r = np.argmax(np.abs(col["yaw_rate"]))
    print(f"  peak a_y       {col['ay'][i_ay] / G:.4f} g at {tt[i_ay]:.2f} s")
    print(f"  peak yaw rate  {math.degrees(col['yaw_rate'][i_r]):.3f} deg/s at {tt[i_r]:.2f} s")
    if step_times:
        st = np.array(step_times)
        print(f"  wall time      {wall:.3f} s for {simulated:.2f} s simulated: real-time factor {simulated / wall:.1f}")
        print(f"  per step       median {1e3 * np.median(st):.3f} ms, max {1e3 * st.max():.3f} ms "
              f"(communication step {1e3 * args.step:.1f} ms)")
    print(f"  wrote          {out_dir / 'jturn.csv'}, {out_dir / 'jturn.png'}")
    return 1 if ended_early is not None else 0


if __name__ == "__main__":
    sys.exit(main())
