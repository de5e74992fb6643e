#!/usr/bin/env bash
# The HMMWV's linear model (rtv linearize): docs/linear.md at 100 km/h straight running, and the root locus
# against speed, docs/linear_root_locus.png (eigenvalues at 10..40 m/s, out/linear_sweep.csv). About 2 s.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x .venv/bin/python ] || bash scripts/setup.sh
cargo build --release --bin rtv
rtv=./target/release/rtv
docs=${RTV_DOCS:-docs} # scripts/docs.sh --check writes into a scratch folder
mkdir -p out
$rtv linearize --iso4138 on --figure linear_root_locus.png --out $docs/linear.md > /dev/null 2> >(grep -v 'triangle inequality' >&2)
$rtv linearize --sweep-speeds 10:40:2 --csv out/linear_sweep.csv 2> >(grep -v 'triangle inequality' >&2)
.venv/bin/python scripts/plot_linear.py out/linear_sweep.csv $docs/linear_root_locus.png
