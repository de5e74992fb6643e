#!/usr/bin/env bash
# Tests scripts/libclang.sh (setup.sh's decision whether to apt-get install libclang-dev) on fixed layouts,
# so that it is checked on a machine that has libclang too. Run by scripts/test.sh.
set -uo pipefail
cd "$(dirname "$0")/.."
source scripts/libclang.sh
passed=0 failed=0

expect() { # expect present|missing DESCRIPTION PATH...
    local want=$1 what=$2 got
    shift 2
    got=$(libclang_present "$@")
    if [ "$got" = "$want" ]; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
        echo "FAIL: $what: got $got, want $want (paths: $*)"
    fi
}

# This Debian 12 image without libclang-dev/libclang1-14: only the C++ library and static archives remain.
# The old `ldconfig -p | grep libclang` said "present" here and bindgen then panicked.
expect missing "Debian 12 image, libclang-cpp only" \
    /usr/lib/x86_64-linux-gnu/libclang-cpp.so.14 /usr/lib/llvm-14/lib/libclang-cpp.so.14 \
    /usr/lib/llvm-14/lib/libclangBasic.a /usr/lib/llvm-14/lib/libclang-cpp.so
expect missing "nothing at all"
expect missing "compiler-rt libraries are not libclang" /usr/lib/llvm-14/lib/clang/14.0.6/lib/linux/libclang_rt.asan-x86_64.so
# What libclang1-14 / libclang-14-dev / libclang-dev install, one at a time (clang-sys loads any of them).
expect present "libclang1-14: versioned soname" /usr/lib/x86_64-linux-gnu/libclang-14.so.1
expect present "libclang1-14: llvm dir" /usr/lib/llvm-14/lib/libclang.so.1
expect present "libclang-14-dev: libclang-14.so" /usr/lib/x86_64-linux-gnu/libclang-14.so
expect present "libclang-dev: libclang.so" /usr/lib/llvm-14/lib/libclang.so
expect present "full version in the name" /usr/lib/llvm-14/lib/libclang-14.0.6.so
expect present "libclang after libclang-cpp" /usr/lib/x86_64-linux-gnu/libclang-cpp.so.14 /usr/lib/x86_64-linux-gnu/libclang-14.so.13

# libclang_candidates lists what clang-sys would look at: with LIBCLANG_PATH it searches only there.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
touch "$tmp/libclang-cpp.so.14" "$tmp/libclangAST.a"
expect missing "LIBCLANG_PATH dir with libclang-cpp only" $(LIBCLANG_PATH=$tmp libclang_candidates)
touch "$tmp/libclang-14.so.1"
expect present "LIBCLANG_PATH dir with libclang-14.so.1" $(LIBCLANG_PATH=$tmp libclang_candidates)

echo "libclang: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
