#!/usr/bin/env bash
# Runs the four standard manoeuvres (rtv manoeuvre), prints their metrics, writes out/<manoeuvre>.csv and
# docs/manoeuvres.png. About 10 s. RTV_OUT and RTV_DOCS move out/ and docs/ (tests/docs runs this command
# into a scratch folder).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null
cargo build --release --bin rtv
out="${RTV_OUT:-out}"
docs="${RTV_DOCS:-docs}"
mkdir -p "$out" "$docs"
for m in step-steer sine-with-dwell steady-state fishhook double-lane-change; do
    ./target/release/rtv manoeuvre "$m" --out "$out/$m.csv"
done
.venv/bin/python scripts/plot_manoeuvres.py "$out" "$docs/manoeuvres.png"
