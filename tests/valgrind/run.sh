#!/usr/bin/env bash
# valgrind memcheck over the FMU's whole lifecycle (tests/valgrind/lifecycle.c) on the packaged binary
# (target/fmu/RtVehicle.fmu: build it with `cargo run --release -p packaging`). Fails on any memory error
# and on any definitely, indirectly or possibly lost byte. "Still reachable" blocks are not counted: they
# are the Rust runtime's and the C library's own process-lifetime allocations, which exist whether or not the
# FMU leaks (the driver's own report shows 0 lost; a leak of the FMU, such as a state left alive at
# fmi2FreeInstance before issue 7, shows as "definitely lost").
set -euo pipefail
cd "$(dirname "$0")/../.."
work=target/valgrind
rm -rf "$work" && mkdir -p "$work/fmu"
python3 -c "import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])" target/fmu/RtVehicle.fmu "$work/fmu"
cc -O1 -g -Wall -Wextra -o "$work/lifecycle" tests/valgrind/lifecycle.c -ldl
resources="file://$(pwd)/$work/fmu/resources"
# Not `set -e` here: the summary is printed whatever the outcome, a failing run's above all.
status=0
valgrind --error-exitcode=1 --leak-check=full --show-leak-kinds=definite,indirect,possible \
    --errors-for-leak-kinds=definite,indirect,possible --log-file="$work/memcheck.log" \
    "$work/lifecycle" "$work/fmu/binaries/linux64/RtVehicle.so" "$resources" || status=$?
grep -E "Process terminating|All heap blocks were freed|ERROR SUMMARY|definitely lost:|indirectly lost:|possibly lost:|still reachable:|in use at exit" \
    "$work/memcheck.log" | sed 's/^==[0-9]*== */memcheck: /'
if [ "$status" -ne 0 ]; then
    echo "memcheck FAILED (exit status $status): $work/memcheck.log"
fi
exit $status
