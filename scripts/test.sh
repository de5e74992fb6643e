#!/usr/bin/env bash
# Runs every test: the install logic (libclang detection), Rust (unit, integration, doc), Python (fmpy on
# the packaged FMU, the study runner on Dask, its glibc floor, a fuzz test of the C API) and a valgrind memcheck of the lifecycle.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/test_libclang.sh
cargo test --workspace --release
cargo run --release -p packaging
cargo build --release -p rtv-study-native
.venv/bin/python -m pytest -q tests/fmu tests/study
# setup.sh installs valgrind; a machine without it (not set up by this project) skips the memcheck, saying so.
if command -v valgrind >/dev/null 2>&1; then
    bash tests/valgrind/run.sh
else
    echo "valgrind not installed: memcheck skipped"
fi
