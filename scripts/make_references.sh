#!/usr/bin/env bash
# Regenerates tests/reference/{bump,jturn,sine}.csv: conventional formulation, RK4 at 0.1 ms, 0.01 s output
# interval (docs/physics.md §9.12), every channel (--keep-all), and shows convergence against RK4 at 0.05 ms (tests/reference/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bin rtv
refs=${RTV_REFERENCES:-tests/reference} # scripts/docs.sh --check writes into a scratch folder
mkdir -p "$refs" out/reference
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
for scene in bump jturn sine; do
    ./target/release/rtv scene "$scene" --formulation conventional --integrator rk4 --step 0.0001 --keep-all \
        --out "$refs/$scene.csv" 2>&1 | grep -v triangle
    ./target/release/rtv scene "$scene" --formulation conventional --integrator rk4 --step 0.00005 --keep-all \
        --out "out/reference/${scene}_half.csv" 2>&1 | grep -v triangle
done
python3 scripts/convergence.py "$commit" "$refs" out/reference > "$refs/README.md"
cat "$refs/README.md"
