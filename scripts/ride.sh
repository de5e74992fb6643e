#!/usr/bin/env bash
# The NRMM ride tests of the HMMWV (docs/ride.md): `rtv ride halfround` over the shipped half-round obstacle
# files and `rtv ride rms` over the detrended RMS courses (resources/roads/, Project Chrono, BSD-3).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin rtv
rtv=./target/release/rtv
docs=${RTV_DOCS:-docs} # scripts/docs.sh --check writes into a scratch folder
out=$docs/ride.md
{
    echo "# Ride tests (NRMM): the HMMWV"
    echo
    echo "Written by \`bash scripts/ride.sh\` (each table is \`rtv ride ...\` as headed); do not edit by hand. The"
    echo "method, the filters and what the model cannot do are in docs/roads.md, \"Ride tests\"."
    echo
    echo "![ride curves](ride.png)"
    for h in 4 8 10 12 16 20; do
        echo
        echo "## Half-round obstacle, $h in: \`rtv ride halfround --height $h\`"
        echo
        $rtv ride halfround --height $h 2>/dev/null
    done
    for c in 1 2 4; do
        echo
        echo "## RMS course, $c in: \`rtv ride rms --course resources/roads/detrended_rms_course_${c}in.crg\`"
        echo
        $rtv ride rms --course resources/roads/detrended_rms_course_${c}in.crg 2>/dev/null
    done
} > $out
bash scripts/setup.sh > /dev/null
.venv/bin/python scripts/plot_ride.py $out $docs/ride.png
echo "wrote $out and $docs/ride.png"
