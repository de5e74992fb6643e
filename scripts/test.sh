#!/usr/bin/env bash
# Runs every test: Rust (unit, integration, doc) and Python (fmpy on the packaged FMU).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/test_libclang.sh
cargo test --workspace --release
if [ -d tests/fmu ] && ls tests/fmu/test_*.py >/dev/null 2>&1; then
    cargo run --release -p packaging
    .venv/bin/python -m pytest -q tests/fmu
fi
