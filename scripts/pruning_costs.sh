#!/usr/bin/env bash
# The cost of each scene's 8 s run with and without leaving out what it does not need (docs/results.md,
# "What the options leave out"): derivative evaluations (the CLI's summary line), the CPU time of the whole
# process (median of 11 runs) and its instructions (valgrind callgrind's total); both include the set-up and
# the CSV writing. Prints markdown rows.
# SCENES="jturn sine" picks scenes; further arguments go to every run (e.g. --slip steady --speed coast).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin rtv 2>/dev/null
rtv=./target/release/rtv
out=${TMPDIR:-/tmp}/rtv_pruning
mkdir -p "$out"
row() { # scene, label, extra options...
    local scene=$1 label=$2
    shift 2
    evals=$($rtv scene "$scene" "$@" --out "$out/run.csv" 2>&1 | grep " evaluations" \
        | sed -E 's/.*, ([0-9]+) evaluations.*/\1/')
    # CPU time of the whole process (user + system, from getrusage: less disturbed than the wall clock by
    # other jobs on the machine), median of 11 runs.
    cpu=$(python3 - "$rtv" scene "$scene" "$@" --out "$out/run.csv" <<'PY'
import resource, statistics, subprocess, sys
def used():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime
times = []
for _ in range(11):
    before = used()
    subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    times.append(used() - before)
print(f"{statistics.median(times):.3f}")
PY
)
    valgrind --tool=callgrind --callgrind-out-file="$out/cg.out" $rtv scene "$scene" "$@" --out "$out/run.csv" \
        >/dev/null 2>&1
    instr=$(callgrind_annotate "$out/cg.out" 2>/dev/null | grep "PROGRAM TOTALS" | sed -E 's/^ *([0-9,]+).*/\1/' | tr -d ,)
    columns=$(head -1 "$out/run.csv" | tr , '\n' | wc -l)
    echo "| $scene | $label | $evals | ${cpu} s | $(echo "$instr" | sed -E ':a;s/([0-9])([0-9]{3})($|,)/\1,\2\3/;ta') | $((instr / evals)) | $columns |"
}
echo "| scene | run | evaluations | CPU (process, median of 11) | instructions (whole process) | per evaluation | CSV columns |"
echo "|---|---|---|---|---|---|---|"
for scene in ${SCENES:-bump jturn sine}; do
    row "$scene" "as declared" "${@}"
    row "$scene" "--keep-all" --keep-all "${@}"
done
