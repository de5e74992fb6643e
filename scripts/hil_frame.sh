#!/usr/bin/env bash
# The HIL frames of docs/results.md, "The HIL frame" (issue 36, "a bounded worst frame"): `benches/hil_frame.rs`
# on every pattern, FRAMES frames each (default 100 000, the issue's count), each pattern RUNS times (default 3;
# scripts/docs.sh --check sets 1). Prints the machine line and two markdown tables (scripts/docs.sh writes them
# into docs/results.md): the times (machine-dependent, not compared by --check) and, per kind of frame, how many
# there are and the most derivative evaluations one of them made (machine-independent: compared); and a third,
# each pattern's instructions per frame, counted by valgrind callgrind (compared to 3e-3, as every callgrind count).
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${FRAMES:-100000}
table=$(RUNS=${RUNS:-3} cargo bench --bench hil_frame -- all "$frames" --markdown 2>/dev/null)
# Instructions per frame: the whole process's callgrind totals of one run of 4 000 and of 2 000 frames, differenced
# (the set-up and the warm-up cancel), over 2 000: frames 2 001-4 000 of a run. The binary runs from a folder whose
# path has a fixed length, in an empty environment (scripts/instructions.sh says why).
bin=$(cargo bench --bench hil_frame --no-run 2>&1 | sed -nE 's/^ *Executable .*\((.*)\)$/\1/p')
ex=$(mktemp -d /tmp/rtv_hil_frame.XXXXXX)
trap 'rm -rf "$ex"' EXIT
cp "$bin" "$ex/hil_frame"
vg=$(command -v valgrind)
total() {
    env -i RUNS=1 "$vg" --tool=callgrind --callgrind-out-file=/dev/null "$ex/hil_frame" "$1" "$2" 2>&1 >/dev/null |
        sed -nE 's/^==[0-9]+== Collected : ([0-9]+)$/\1/p'
}
group() { sed -E ':a;s/([0-9])([0-9]{3})($| )/\1 \2\3/;ta'; } # 163763 -> 163 763
python3 scripts/docs_check.py machine
echo
echo "$frames frames of each pattern from t = 0; each pattern run ${RUNS:-3} times on fresh instances. The median, p99, \
p99.9 and max (µs, and % of the frame) are the first run's, as a master sees them; a frame's own cost is its least \
time over the runs (every run does the same work to the bit), the machine's noise mostly removed."
echo
echo "$table"
echo
echo "Instructions per frame: \`valgrind --tool=callgrind\` totals of one run (\`RUNS=1 <hil_frame bench binary> PATTERN\`)"
echo "of 4 000 frames and of 2 000, differenced, over 2 000 (frames 2 001-4 000: after the J-turn's ramp, the brake's"
echo "onset and the bumps; the step checks among them); counted by $(valgrind --version)."
echo
echo "| pattern | instructions per frame |"
echo "|---|---|"
# The patterns, in the bench's order: the first column of its table.
sed -nE 's/^\| ([^|]+[^ |]) \| (1 ms|8.33 ms).*/\1/p' <<<"$table" | while read -r pattern; do
    per_frame=$((($(total "$pattern" 4000) - $(total "$pattern" 2000) + 1000) / 2000))
    echo "| $pattern | $(group <<<"$per_frame") |"
done
