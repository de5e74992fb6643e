#!/usr/bin/env bash
# The cost of each scene's 8 s run with and without leaving out what it does not need (docs/results.md,
# "What the options leave out"): derivative evaluations (the CLI's summary line), the instructions of the
# whole process (valgrind callgrind's total) and its CPU time (user + system, median of RUNS runs, default
# 11); both include the set-up and the CSV writing. The binary runs from a folder whose path has a fixed
# length, and callgrind in an empty environment (scripts/instructions.sh says why); a whole process's count
# still varies by a few thousand instructions between runs. Prints the machine line and markdown rows (scripts/docs.sh writes them into
# docs/results.md; the CPU columns are machine-dependent).
# SCENES="jturn sine" picks scenes; KEEP_ALL=0 leaves out the --keep-all rows; further arguments go to every
# run (e.g. --slip steady --speed coast).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin rtv 2>/dev/null
runs=${RUNS:-11}
out=$(mktemp -d /tmp/rtv_pruning.XXXXXX)
trap 'rm -rf "$out"' EXIT
cp target/release/rtv "$out/rtv"
rtv=$out/rtv
group() { sed -E ':a;s/([0-9])([0-9]{3})($| )/\1 \2\3/;ta'; } # 1234567 -> 1 234 567
row() { # scene, label, extra options...
    local scene=$1 label=$2
    shift 2
    summary=$($rtv scene "$scene" "$@" --out "$out/run.csv" 2>&1 | grep " evaluations")
    evals=$(sed -E 's/.*, ([0-9]+) evaluations.*/\1/' <<<"$summary")
    simulated=$(sed -E 's/^[^:]*: ([0-9.]+) s simulated.*/\1/' <<<"$summary")
    # CPU time of the whole process (user + system, from getrusage: less disturbed than the wall clock by
    # other jobs on the machine), median of the runs; and the real-time factor it gives.
    read -r cpu factor < <(python3 - "$runs" "$simulated" "$rtv" scene "$scene" "$@" --out "$out/run.csv" <<'PY'
import resource, statistics, subprocess, sys
def used():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime
times = []
for _ in range(int(sys.argv[1])):
    before = used()
    subprocess.run(sys.argv[3:], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    times.append(used() - before)
t = statistics.median(times)
print(f"{t:.3f} {float(sys.argv[2]) / t:.0f}")
PY
)
    instr=$(env -i "$(command -v valgrind)" --tool=callgrind --callgrind-out-file="$out/cg.out" $rtv scene "$scene" "$@" \
        --out "$out/run.csv" 2>&1 >/dev/null | sed -nE 's/^==[0-9]+== Collected : ([0-9]+)$/\1/p')
    columns=$(head -1 "$out/run.csv" | tr , '\n' | wc -l)
    echo "| $scene | $label | $evals | $(group <<<"$instr") | $(group <<<"$((instr / evals))") | $columns | ${cpu} s | ${factor} |"
}
python3 scripts/docs_check.py machine
echo
echo "CPU: user + system time of the whole process, the median of $runs runs; real time ×: the simulated time over it."
echo
echo "| scene | run | evaluations | instructions (whole process) | per evaluation (whole process) | CSV columns | CPU | real time × |"
echo "|---|---|---|---|---|---|---|---|"
for scene in ${SCENES:-bump jturn sine}; do
    row "$scene" "as declared" "${@}"
    [ "${KEEP_ALL:-1}" = 0 ] || row "$scene" "--keep-all" --keep-all "${@}"
done
