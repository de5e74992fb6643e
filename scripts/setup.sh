#!/usr/bin/env bash
# Installs what the build and the tests need on a fresh Debian machine (idempotent, quiet when all is there):
# libclang for fmi-sys's bindgen, valgrind for the memcheck run, and a Python venv (.venv) with fmpy, numpy,
# matplotlib, pytest, pyelftools (the GLIBC check), libcosimpy (libcosim, the second importer of the SSP) and
# cargo-zigbuild + ziglang (the portable linux64 FMU binary).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/libclang.sh
apt_packages=()
# Judge by the files bindgen can load (libclang-cpp.so.N, present on Debian 12 images, is not one).
# bindgen also needs clang's builtin headers (stddef.h) in the library's resource directory: libclang1-N
# without libclang-common-N-dev has the library and not them.
mapfile -t libclang_files < <(libclang_candidates)
if ! libclang_present "${libclang_files[@]}" >/dev/null \
    || ! compgen -G "/usr/lib/llvm-*/lib/clang/*/include/stddef.h" >/dev/null; then
    apt_packages+=(libclang-dev)
fi
command -v valgrind >/dev/null 2>&1 || apt_packages+=(valgrind)
if [ ${#apt_packages[@]} -gt 0 ]; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${apt_packages[@]}" >/dev/null
fi
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
# packaging/ runs .venv/bin/cargo-zigbuild, which finds zig as `python -m ziglang` in the same venv. Both are
# pinned to the pair the portable build was tested with (zig's command line and paths change between releases).
{ .venv/bin/python -c "import fmpy, numpy, matplotlib, pytest, elftools, ziglang, libcosimpy" 2>/dev/null \
    && [ -x .venv/bin/cargo-zigbuild ]; } || \
    .venv/bin/pip install -q fmpy numpy matplotlib pytest pyelftools libcosimpy==0.0.6 cargo-zigbuild==0.24.0 ziglang==0.17.1
# The study runner (python/rtv_study, docs/studies.md): Dask distributed, pyarrow and tqdm, pinned to the
# versions it was tested with; the package itself installed editable (its `rtv-study` command in .venv/bin).
.venv/bin/python -c "import dask.distributed, pyarrow, tqdm, rtv_study" 2>/dev/null || \
    .venv/bin/pip install -q "dask[distributed]==2026.8.0" pyarrow==26.0.1 tqdm==4.70.1 -e python
