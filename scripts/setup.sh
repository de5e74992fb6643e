#!/usr/bin/env bash
# Installs what the build and the tests need on a fresh Debian machine (idempotent):
# libclang for fmi-sys's bindgen, and a Python venv (.venv) with fmpy, numpy, matplotlib, pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! ls /usr/lib/llvm-*/lib/libclang*.so* >/dev/null 2>&1 && ! ldconfig -p 2>/dev/null | grep -q libclang; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq libclang-dev >/dev/null
fi
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -c "import fmpy, numpy, matplotlib, pytest" 2>/dev/null || \
    .venv/bin/pip install -q fmpy numpy matplotlib pytest
