"""Run target/ssp/DoubleLaneChange.ssp (the RtDriver FMU driving the RtVehicle FMU through the ISO 3888-2 double
lane change) in two importers, libcosim (libcosimpy, CosimExecution.from_ssp_file, 10 ms steps) and fmpy
(its SSD reader and FMU2Slave, stepped as libcosim steps; and fmpy's own fmpy.ssp.simulation.simulate_ssp), judge
each run against the course, and compare them.

    .venv/bin/python scripts/run_ssp.py [--ssp target/ssp/DoubleLaneChange.ssp] [--out out/ssp] [--plot docs/ssp_dlc.png]

Writes <out>/libcosim.csv, <out>/fmpy.csv and <out>/fmpy.ssp.csv (time and the recorded signals) and prints the
metrics: smallest clearance of the tire footprint to a lane edge in each lane (pass: >= 0 everywhere), exit
speed, peak lateral acceleration, and the largest difference of each fmpy run from libcosim's. Exit status 1 if a
run fails the course.

All three step the two FMUs in parallel from the same communication point and then pass the outputs on (Jacobi):
the driver sees the vehicle of the previous communication point. fmpy's simulate_ssp differs at the start: it
does not apply a component's parameter bindings (they are passed to it as one prefixed set here), and it starts
every connection at 0 and passes nothing on in initialization, so the driver's first step sees the vehicle at
rest at the origin (a one-step burst of drive torque). libcosim passes the outputs on in initialization, and so
does the fmpy master here (docs/cosimulation.md).
"""
import argparse
import json
import os
import sys
import tempfile
import zipfile

import numpy as np

STEP = 0.01
VEHICLE = ["x", "y", "yaw", "vx", "yaw_rate", "ay", "roll", "z"]
DRIVER = ["rack_displacement", "drive_torque_fl", "brake_torque_fl", "lateral_error", "target_speed"]
COLUMNS = [f"vehicle.{n}" for n in VEHICLE] + [f"driver.{n}" for n in DRIVER]


def read_course(ssp):
    with zipfile.ZipFile(ssp) as z:
        return json.loads(z.read("resources/course.json"))


def stop_time(ssp):
    import xml.etree.ElementTree as ET
    with zipfile.ZipFile(ssp) as z:
        root = ET.fromstring(z.read("SystemStructure.ssd"))
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}
    return float(root.find("ssd:DefaultExperiment", ns).get("stopTime"))


def run_libcosim(ssp, t_end):
    """Rows (time after the step, signals) of libcosim's run of the SSP."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)
    execution = CosimExecution.from_ssp_file(ssp, step_size=int(round(STEP * 1e9)))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    refs = {}
    for component, names in (("vehicle", VEHICLE), ("driver", DRIVER)):
        index = execution.slave_index_from_instance_name(component)
        by_name = {v.name.decode(): v.reference for v in execution.slave_variables(index)}
        refs[component] = (index, [by_name[n] for n in names])
    rows = []
    for k in range(int(round(t_end / STEP))):
        if not execution.step():
            raise RuntimeError(f"libcosim: step {k} failed")
        values = []
        for component in ("vehicle", "driver"):
            index, vrs = refs[component]
            values += observer.last_real_values(index, vrs)
        rows.append([(k + 1) * STEP] + values)
    return np.array(rows)


def bindings(ssp):
    """{component: [(name, value)]} from each component's .ssv parameter binding, and the SSD as fmpy reads it."""
    from fmpy.ssp.ssd import read_ssd, read_ssv

    ssd = read_ssd(ssp)
    values = {}
    for component in ssd.system.elements:
        values[component.name] = [(p.name, p.type, p.value) for binding in component.parameterBindings
                                  for p in read_ssv(ssp, resource=binding.source).parameters]
    return ssd, values


def run_fmpy_master(ssp, t_end):
    """Rows (time after the step, signals) of the SSP run with fmpy's SSD reader and FMU2Slave, stepped as
    libcosim's fixed-step algorithm steps it: parameters from the bindings, the connections passed on in
    initialization mode (twice, so that the driver's outputs see the vehicle's initial state), then at each
    communication point every FMU steps and the outputs are passed on (Jacobi)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    ssd, values = bindings(ssp)
    with tempfile.TemporaryDirectory() as tmp:
        with zipfile.ZipFile(ssp) as z:
            z.extractall(tmp)
        fmus, variables = {}, {}
        for component in ssd.system.elements:
            path = os.path.join(tmp, component.source)
            md = read_model_description(path)
            # Unzipped inside the temporary directory, so that it goes with it.
            unzipped = extract(path, unzipdir=os.path.join(tmp, component.name))
            fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                            instanceName=component.name)
            fmu.instantiate()
            fmu.setupExperiment(startTime=0.0)
            variables[component.name] = {v.name: v for v in md.modelVariables}
            for name, kind, value in values[component.name]:
                vr = [variables[component.name][name].valueReference]
                if kind == "Real":
                    fmu.setReal(vr, [float(value)])
                elif kind == "Integer":
                    fmu.setInteger(vr, [int(value)])
                else:
                    raise ValueError(f"{component.name}.{name}: parameter type {kind} not handled")
            fmus[component.name] = fmu
        connections = [(c.startElement, c.startConnector, c.endElement, c.endConnector) for c in ssd.system.connections]

        def vr(component, name):
            return variables[component][name].valueReference

        def exchange():
            outputs = [fmus[a].getReal([vr(a, ca)])[0] for a, ca, _, _ in connections]
            for (_, _, b, cb), value in zip(connections, outputs):
                fmus[b].setReal([vr(b, cb)], [value])

        for fmu in fmus.values():
            fmu.enterInitializationMode()
        exchange()
        exchange()
        for fmu in fmus.values():
            fmu.exitInitializationMode()
        rows = []
        for k in range(int(round(t_end / STEP))):
            for fmu in fmus.values():
                fmu.doStep(currentCommunicationPoint=k * STEP, communicationStepSize=STEP)
            # Recorded before the outputs are passed on, as libcosim's observers record: the driver's outputs
            # (direct feedthrough) then belong to the inputs it stepped with.
            row = [(k + 1) * STEP]
            for component, names in (("vehicle", VEHICLE), ("driver", DRIVER)):
                row += fmus[component].getReal([vr(component, n) for n in names])
            rows.append(row)
            exchange()
        for fmu in fmus.values():
            fmu.terminate()
            fmu.freeInstance()
    return np.array(rows)


def run_fmpy(ssp, t_end):
    """Rows (time after the step, signals) of fmpy's run of the SSP. simulate_ssp takes one parameter set whose
    names carry the component's name; it is built from the components' own .ssv bindings."""
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import ParameterSet, Parameter

    _, values = bindings(ssp)
    merged = ParameterSet(name="bindings")
    for component, parameters in values.items():
        for name, kind, value in parameters:
            merged.parameters.append(Parameter(name=f"{component}.{name}", type=kind, value=value))
    result = simulate_ssp(ssp, stop_time=t_end - 0.5 * STEP, step_size=STEP, parameter_set=merged)
    # simulate_ssp labels each row with the step's start; the values are those after the step.
    return np.column_stack([result["time"] + STEP] + [result[c] for c in COLUMNS])


def judge(rows, course):
    """Smallest clearance of the footprint to each lane's edges (m), exit speed, peak lateral acceleration."""
    x, y, yaw = rows[:, 1], rows[:, 2], rows[:, 3]
    clearance = [np.inf] * len(course["lanes"])
    for cx, cy in course["footprint"]:
        px = x + cx * np.cos(yaw) - cy * np.sin(yaw)
        py = y + cx * np.sin(yaw) + cy * np.cos(yaw)
        for k, lane in enumerate(course["lanes"]):
            inside = (px >= lane["from"]) & (px <= lane["to"])
            if inside.any():
                c = np.minimum(py[inside] - lane["y_min"], lane["y_max"] - py[inside]).min()
                clearance[k] = min(clearance[k], c)
    exit_lane = course["lanes"][-1]["to"]
    after = np.nonzero(x >= exit_lane)[0]
    if len(after) == 0:
        raise RuntimeError(f"the vehicle did not reach the course's exit (x = {exit_lane} m) by t = {rows[-1, 0]:.2f} s")
    exit_speed = rows[after[0], 4]
    peak_ay = np.abs(rows[:, 6]).max() / 9.81
    return clearance, exit_speed, peak_ay


def difference(a, b):
    """The largest |a - b| over time of any of the vehicle's signals, relative to that signal's peak in a (the
    driver's outputs are the vehicle's inputs: a difference there shows in the vehicle's response)."""
    assert a.shape == b.shape and np.allclose(a[:, 0], b[:, 0]), "the two runs have different time grids"
    n = 1 + len(VEHICLE)
    peak = np.abs(a[:, 1:n]).max(axis=0)
    return float((np.abs(a[:, 1:n] - b[:, 1:n]).max(axis=0) / peak).max())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ssp", default="target/ssp/DoubleLaneChange.ssp")
    parser.add_argument("--out", default="out/ssp")
    parser.add_argument("--plot", default=None, help="write a PNG of both runs against the course")
    args = parser.parse_args()
    course = read_course(args.ssp)
    t_end = stop_time(args.ssp)
    runs = {
        "libcosim": run_libcosim(args.ssp, t_end),
        "fmpy": run_fmpy_master(args.ssp, t_end),
        "fmpy.ssp": run_fmpy(args.ssp, t_end),
    }
    os.makedirs(args.out, exist_ok=True)
    passed = True
    print(f"ISO 3888-2 double lane change, entry {course['entry_speed_m_s'] * 3.6:.0f} km/h, {t_end:g} s in 10 ms steps")
    for name, rows in runs.items():
        np.savetxt(os.path.join(args.out, f"{name}.csv"), rows, delimiter=",", header="time," + ",".join(COLUMNS),
                   comments="")
        clearance, exit_speed, peak_ay = judge(rows, course)
        ok = min(clearance) >= 0.0
        passed &= ok
        lanes = ", ".join(f"{c:.3f}" for c in clearance)
        print(f"  {name:8s}: clearance per lane (1, 3, 5) {lanes} m -> {'PASS' if ok else 'FAIL'}; "
              f"exit speed {exit_speed * 3.6:.1f} km/h; peak lateral acceleration {peak_ay:.3f} g")
    for other in ("fmpy", "fmpy.ssp"):
        print(f"  libcosim vs {other}: largest difference / peak of the column: {difference(runs['libcosim'], runs[other]):.2e}")
    if args.plot:
        plot(runs, course, args.plot)
    return 0 if passed else 1


def plot(runs, course, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, 6.5), gridspec_kw={"height_ratios": [2, 1]})
    for lane in course["lanes"]:
        for y in (lane["y_min"], lane["y_max"]):
            ax1.plot([lane["from"], lane["to"]], [y, y], "o-", color="tab:orange", ms=3, lw=1)
    for (name, rows), style in zip(list(runs.items())[:2], ("-", "--")):
        ax1.plot(rows[:, 1], rows[:, 2], style, label=f"CM path ({name})")
        ax2.plot(rows[:, 0], rows[:, 9] * 1e3, style, label=f"rack ({name})")
    ax1.set_xlabel("x (m)")
    ax1.set_ylabel("y (m)")
    ax1.set_title(f"ISO 3888-2 through DoubleLaneChange.ssp at {course['entry_speed_m_s'] * 3.6:.0f} km/h: cones and CM path")
    ax1.legend()
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("rack (mm)")
    ax2.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    sys.exit(main())
