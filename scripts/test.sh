#!/usr/bin/env bash
# Runs every test: the install logic (libclang detection), Rust (unit, integration, doc), Python (fmpy on
# the packaged FMU, the study runner on Dask, its glibc floor, a fuzz test of the C API, the documented
# commands), the docs' figures regenerated and compared (scripts/docs.sh --check) and a valgrind memcheck of the
# lifecycle.
# `--slow` also runs the documented commands that take over a minute (tests/docs; without it their arguments
# are checked) and the benchmarks, so that they cannot rot: hil_frame through its docs generator (the HIL frames
# of docs/results.md regenerated and compared), the criterion benches once each (criterion's --test mode).
set -euo pipefail
cd "$(dirname "$0")/.."
slow=0
for a in "$@"; do
    case "$a" in
        --slow) slow=1 ;;
        *) echo "usage: bash scripts/test.sh [--slow]" >&2; exit 2 ;;
    esac
done
bash scripts/setup.sh
bash scripts/test_libclang.sh
cargo test --workspace --release
# The options table's own proof: a setting declared in the model description alone (feature `test-option`)
# reaches the FMU, the CLI, the validation, the defaults, the FMI 3.0 description and docs/fmu.md.
cargo test --release --features test-option --lib fmi::option_tests
cargo test --release --features test-option --bin rtv
cargo run --release -p packaging
cargo build --release -p rtv-study-native
RTV_DOCS_SLOW=$slow .venv/bin/python -m pytest -q tests/fmu tests/study tests/docs
# Every figure of README.md and docs/ that does not depend on the machine, regenerated into a scratch folder and
# compared with the committed docs (issue 31; docs/results.md, "How the figures are checked").
bash scripts/docs.sh --check
if [ $slow = 1 ]; then
    bash scripts/docs.sh --check hil_frame
    cargo bench --bench evaluation --bench acceleration -- --test
fi
# setup.sh installs valgrind; a machine without it (not set up by this project) skips the memcheck, saying so.
if command -v valgrind >/dev/null 2>&1; then
    bash tests/valgrind/run.sh
else
    echo "valgrind not installed: memcheck skipped"
fi
