#!/usr/bin/env bash
# The HIL frames of docs/results.md, "The HIL frame" (issue 36, "a bounded worst frame"): `benches/hil_frame.rs`
# on every pattern, FRAMES frames each (default 100 000, the issue's count), each pattern RUNS times (default 3;
# scripts/docs.sh --check sets 1). Prints the machine line and two markdown tables (scripts/docs.sh writes them
# into docs/results.md): the times (machine-dependent, not compared by --check) and, per kind of frame, how many
# there are and the most derivative evaluations one of them made (machine-independent: compared).
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${FRAMES:-100000}
table=$(RUNS=${RUNS:-3} cargo bench --bench hil_frame -- all "$frames" --markdown 2>/dev/null)
python3 scripts/docs_check.py machine
echo
echo "$frames frames of each pattern from t = 0; each pattern run ${RUNS:-3} times on fresh instances. The median, p99, \
p99.9 and max (µs, and % of the frame) are the first run's, as a master sees them; a frame's own cost is its least \
time over the runs (every run does the same work to the bit), the machine's noise mostly removed."
echo
echo "$table"
