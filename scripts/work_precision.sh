#!/usr/bin/env bash
# Regenerates docs/work_precision.md and docs/work_precision.png: every case of the study × RK4, AB3 and IMEX-AB3 over
# a ladder of steps, and the error-controlled DOPRI5 over a ladder of tolerances (src/studies/work_precision.rs).
# About a minute of CPU.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin rtv
docs=${RTV_DOCS:-docs} # scripts/docs.sh --check writes into a scratch folder
mkdir -p out
./target/release/rtv work-precision --out $docs/work_precision.md --csv out/work_precision.csv
.venv/bin/python scripts/plot_work_precision.py out/work_precision.csv $docs/work_precision.png
