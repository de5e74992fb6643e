#!/usr/bin/env bash
# The ISO 3888-2 double lane change as a system of FMUs: builds the FMUs and target/ssp/DoubleLaneChange.ssp,
# runs it in libcosim and in fmpy (scripts/run_ssp.py), prints the pass/fail metrics and the importers'
# agreement, and writes out/ssp/*.csv and docs/ssp_dlc.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo run --release -p packaging
.venv/bin/python scripts/run_ssp.py --ssp target/ssp/DoubleLaneChange.ssp --out out/ssp --plot docs/ssp_dlc.png
