#!/usr/bin/env bash
# The FMI community's two independent checkers on our archives, target/fmu/RtVehicle.fmu (FMI 2.0 CS + ME) and
# target/fmu/RtVehicle3.fmu (FMI 3.0 CS + ME). One verdict line per check; exit 1 if any check failed.
#
#   FMUSIM=/path/to/fmusim FMUCHECK=/path/to/fmuCheck.linux64 bash scripts/fmi_checkers.sh [OUT_DIR]
#
# NOT PART OF CI. Neither tool is in a package registry that CI or the developers' machines reach: both are
# built by hand from their sources, and the tools themselves are not kept in this repository. A checker
# whose binary is not given (FMUSIM / FMUCHECK unset) is skipped with a line saying so; with neither given
# the script checks nothing and exits 0. Results, the versions used and what each checker printed:
# docs/fmi_checkers.md.
#
# The tools, as built for docs/fmi_checkers.md (Debian 12, x86_64):
# - fmusim 0.0.39, from the Reference FMUs (modelica/Reference-FMUs, BSD-2), tag v0.0.39 = commit
#   c8d4e6d90fa14be49d7622badf30e38eebea5e0a, the last release that ships fmusim (later commits remove it).
#   Built against Debian's libsundials-dev 6.4.1, libxml2-dev, libminizip-dev and zlib1g-dev instead of
#   its CMake superbuild (which downloads CVODE 7, libxml2 and zlib); fmusim's CVODE code is written for
#   SUNDIALS 7, whose only difference it meets in 6.4 is SUN_COMM_NULL (the context is created with NULL).
# - FMU Compliance Checker (modelica-tools/FMUComplianceChecker, BSD-3), commit
#   c704b983b979f57681a5322889360b7688248088 (2023-10-16, untagged; it prints its version as "Test"),
#   with FMI Library 2.0.3 (modelon-community/fmi-library, commit 4076be18d2e5506cf2d5ef4af526d93148947925,
#   the tag the checker's CMake asks for), FMIL's own third-party sources, and its tests off. FMI Library
#   2.0.3 reads FMI 1.0 and 2.0 only, so the checker runs on RtVehicle.fmu alone.
#
# The checks (docs/fmi_checkers.md says why each is as it is):
#   fmusim, on both archives: CS 0-2 s; ME 0-2 s with fmusim's explicit Euler (its default, step = the
#     output interval = DefaultExperiment stepSize 0.0083 s) and with its CVODE (BDF, rtol 1e-4); the bump
#     course in ME (road = 2, initial_speed = 2.78 m/s, 0-7 s) with Euler at a 0.5 ms output interval.
#     A run passes if fmusim exits 0, the CSV reaches the stop time, every value is finite, and: straight
#     runs hold vx = 27.7778 m/s (within 1e-6) at rest height; the bump run shows the bumps (wheel_z_fl
#     rises >= 4 cm, |pitch| >= 5 mrad) with vx within [2.5, 3.1] m/s.
#     The ME bump run with fmusim's CVODE, on both archives, is a check as well since the FMU defines time
#     events at the bump edges (c5f72b3): before them, CVODE (fmusim sets it no maximum step) stepped over
#     the bumps on the flat run-up (docs/fmi_checkers.md).
#   fmuCheck, on RtVehicle.fmu: `-k me` and `-k cs` with the checker's defaults (0-8 s from the
#     DefaultExperiment, 500 output points). A run passes if it exits 0 and its summary says the
#     simulation finished with 0 warnings and 0 errors from the FMU and from the checker. Its output CSV is
#     summarised as INFO: the checker's ME run is explicit Euler at 8 s / 500 = 16 ms, beyond the model's
#     stable Euler step (8.3 ms holds, 10 ms does not), so there roundoff grows into a wheel-hop limit cycle.
set -uo pipefail
cd "$(dirname "$0")/.."

OUT=${1:-$(mktemp -d /tmp/fmi_checkers.XXXXXX)}
mkdir -p "$OUT"
FAILED=0
FMU2=$PWD/target/fmu/RtVehicle.fmu
FMU3=$PWD/target/fmu/RtVehicle3.fmu
for f in "$FMU2" "$FMU3"; do
    [[ -f $f ]] || { echo "FAIL  missing $f (cargo run --release -p packaging)"; exit 1; }
done
# Work on copies: the archives may be rebuilt while the checks run.
cp "$FMU2" "$FMU3" "$OUT/"
FMU2=$OUT/RtVehicle.fmu
FMU3=$OUT/RtVehicle3.fmu
echo "outputs in $OUT"

verdict() { # NAME OK(0/1) DETAIL
    if [[ $2 == 0 ]]; then echo "PASS  $1: $3"; else echo "FAIL  $1: $3"; FAILED=1; fi
}

# Check one fmusim CSV: KIND = straight | bump | info, STOP = the stop time. Prints a summary; exit 0 = pass.
check_csv() {
    python3 - "$1" "$2" "$3" <<'EOF'
import csv, math, sys
path, kind, stop = sys.argv[1], sys.argv[2], float(sys.argv[3])
try:
    rows = list(csv.reader(open(path)))
    head, data = rows[0], [[float(v) for v in r] for r in rows[1:]]
except Exception as e:  # no file, no rows, a non-number
    print(f"unreadable output {path}: {e}"); sys.exit(1)
col = lambda n: [r[head.index(n)] for r in data]
bad = sum(not math.isfinite(v) for r in data for v in r)
vx, z, wz, pitch = col("vx"), col("z"), col("wheel_z_fl"), col("pitch")
rise, pmax = max(wz) - wz[0], max(map(abs, pitch))
msg = (f"{len(data)} rows to t = {data[-1][0]:g} s, {bad} non-finite, vx [{min(vx):.6g}, {max(vx):.6g}] m/s, "
       f"z [{min(z):.5f}, {max(z):.5f}] m, wheel_z_fl rise {rise * 1e3:.1f} mm, |pitch| max {pmax * 1e3:.2f} mrad")
ok = bad == 0 and abs(data[-1][0] - stop) < 1e-6
if kind == "straight":
    ok = ok and all(abs(v - 27.7778) < 1e-6 for v in vx) and max(z) - min(z) < 1e-6
elif kind == "bump":
    ok = ok and rise >= 0.04 and pmax >= 5e-3 and 2.5 <= min(vx) and max(vx) <= 3.1
elif kind == "info":
    msg += "; bumps " + ("seen" if rise >= 0.04 else "NOT seen (stepped over)")
elif kind == "straight-info":
    msg += "; straight running " + ("held" if all(abs(v - 27.7778) < 1e-6 for v in vx) else
                                    "NOT held (explicit Euler beyond its stable step)")
print(msg)
sys.exit(0 if ok else 1)
EOF
}

# fmusim NAME KIND STOP FMU ARGS...: run it, check its CSV, print the verdict.
run_fmusim() {
    local name=$1 kind=$2 stop=$3 fmu=$4; shift 4
    local log=$OUT/$name.log csv=$OUT/$name.csv
    if ! "$FMUSIM" --stop-time "$stop" --output-file "$csv" --logging-on --log-file "$log" "$@" "$fmu" \
        >"$OUT/$name.out" 2>&1; then
        verdict "fmusim $name" 1 "fmusim exited non-zero: $( { tail -n 3 "$OUT/$name.out"; tail -n 3 "$log"; } 2>/dev/null | tr '\n' ' ')"
        return
    fi
    local summary rc
    summary=$(check_csv "$csv" "$kind" "$stop"); rc=$?
    if grep -qiE '^\[(warning|error|fatal|discard)' "$log"; then
        summary="$summary; FMU logged: $(grep -iE '^\[(warning|error|fatal|discard)' "$log" | head -2 | tr '\n' ' ')"
        rc=1
    fi
    if [[ $kind == info ]]; then echo "INFO  fmusim $name: $summary"; else verdict "fmusim $name" "$rc" "$summary"; fi
}

if [[ -z ${FMUSIM:-} ]]; then
    echo "SKIP  fmusim: FMUSIM is not set (the path to a built fmusim)"
elif [[ ! -x $FMUSIM ]]; then
    verdict "fmusim" 1 "FMUSIM=$FMUSIM is not an executable"
else
    echo "fmusim: $("$FMUSIM" --version 2>&1 | head -1)"
    BUMP=(--start-value road 2 --start-value initial_speed 2.78)
    run_fmusim cs3       straight 2 "$FMU3" --interface-type cs
    run_fmusim me3_euler straight 2 "$FMU3" --interface-type me --solver euler
    run_fmusim me3_cvode straight 2 "$FMU3" --interface-type me --solver cvode
    run_fmusim cs2       straight 2 "$FMU2" --interface-type cs
    run_fmusim me2_euler straight 2 "$FMU2" --interface-type me --solver euler
    run_fmusim me2_cvode straight 2 "$FMU2" --interface-type me --solver cvode
    run_fmusim me3_bump_euler bump 7 "$FMU3" --interface-type me --solver euler --output-interval 0.0005 "${BUMP[@]}"
    run_fmusim me2_bump_euler bump 7 "$FMU2" --interface-type me --solver euler --output-interval 0.0005 "${BUMP[@]}"
    run_fmusim me3_bump_cvode bump 7 "$FMU3" --interface-type me --solver cvode "${BUMP[@]}"
    run_fmusim me2_bump_cvode bump 7 "$FMU2" --interface-type me --solver cvode "${BUMP[@]}"
fi

if [[ -z ${FMUCHECK:-} ]]; then
    echo "SKIP  fmuCheck: FMUCHECK is not set (the path to a built fmuCheck.linux64)"
elif [[ ! -x $FMUCHECK ]]; then
    verdict "fmuCheck" 1 "FMUCHECK=$FMUCHECK is not an executable"
else
    for k in me cs; do
        log=$OUT/fmucheck_$k.log
        "$FMUCHECK" -k "$k" -l 4 -e "$log" -o "$OUT/fmucheck_$k.csv" "$FMU2" >"$OUT/fmucheck_$k.out" 2>&1
        rc=$?
        fmu_n=$(grep -A1 '^FMU reported:' "$log" | sed -n 's/^\s*\([0-9]*\) warning(s) and error(s)/\1/p')
        chk_w=$(sed -n 's/^\s*\([0-9]*\) Warning(s)/\1/p' "$log")
        chk_e=$(sed -n 's/^\s*\([0-9]*\) Error(s)/\1/p' "$log")
        finished=$(grep -o 'Simulation finished successfully at time [0-9.e+-]*' "$log")
        ok=1
        [[ $rc == 0 && $fmu_n == 0 && $chk_w == 0 && $chk_e == 0 && -n $finished ]] && ok=0
        verdict "fmuCheck -k $k RtVehicle.fmu" "$ok" \
            "exit $rc, FMU reported ${fmu_n:-?} warnings/errors, checker ${chk_w:-?} warnings ${chk_e:-?} errors, ${finished:-simulation did not finish}"
        [[ -s $OUT/fmucheck_$k.csv ]] &&
            echo "INFO  fmuCheck -k $k output: $(check_csv "$OUT/fmucheck_$k.csv" straight-info 8)"
    done
fi

exit "$FAILED"
