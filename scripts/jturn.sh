#!/usr/bin/env bash
# The J-turn through the FMU: set up (apt libclang, .venv), package target/fmu/RtVehicle.fmu, simulate it
# with fmpy (0-8 s, 100 km/h, speed hold), write out/jturn.csv and out/jturn.png, print a summary. RTV_OUT moves
# out/ (tests/docs runs this command into a scratch folder); arguments go to scripts/run_jturn_fmu.py.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run --release -p packaging
.venv/bin/python scripts/run_jturn_fmu.py --out "${RTV_OUT:-out}" "$@"
