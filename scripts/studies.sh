#!/usr/bin/env bash
# The study runner's figures (docs/studies.md, docs/studies_dlc.png): the fmpy-vs-binding comparison, runs per
# second with 1 and 2 workers, the pilot's choice against RK4 at 2 ms, the per-task overhead and the 1 000-run example
# with its pass/fail map at both. About 5 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cargo run --release -p packaging >/dev/null        # the FMUs and the SSP, for the fmpy path
cargo build --release -p rtv-study-native
.venv/bin/python scripts/study_figures.py
