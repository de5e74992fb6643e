#!/usr/bin/env bash
# Runs the four standard manoeuvres (rtv manoeuvre), prints their metrics, writes out/<manoeuvre>.csv and
# docs/manoeuvres.png. About 10 s.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cargo build --release --bin rtv
mkdir -p out
for m in step-steer sine-with-dwell steady-state fishhook double-lane-change; do
    ./target/release/rtv manoeuvre "$m" --out "out/$m.csv"
done
.venv/bin/python scripts/plot_manoeuvres.py out
