#!/usr/bin/env bash
# The HMMWV's two tires side by side (docs/tire_magic_formula.md, its figures): steady-state curves of the
# STI tire and of the Magic Formula of resources/tires/HMMWV_Pac02Tire.tir (`rtv tire`), the steady-state
# cornering manoeuvre (understeer gradient), and a J-turn at one rack amplitude with each tire.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo build --release --bin rtv
rtv=./target/release/rtv
tir=resources/tires/HMMWV_Pac02Tire.tir
out=out/tire_comparison
mkdir -p "$out"
for fz in 3000 6300 9500; do
    for sweep in alpha kappa combined; do
        $rtv tire --fz $fz --sweep $sweep --out $out/sti_${sweep}_$fz.csv
        $rtv tire --tir $tir --fz $fz --sweep $sweep --out $out/mf_${sweep}_$fz.csv
    done
done
$rtv manoeuvre steady-state --out $out/sti_steady.csv 2>&1 | grep -v triangle > $out/sti_steady.txt
$rtv manoeuvre steady-state --tire $tir --out $out/mf_steady.csv 2>&1 | grep -v triangle > $out/mf_steady.txt
# One amplitude for both: the STI tire's calibrated 0.4 g J-turn (resources/calibration.json).
amp=$(.venv/bin/python -c "import json; print(json.load(open('resources/calibration.json'))['jturn_amplitude_m'])")
$rtv scene jturn --amplitude $amp --out $out/sti_jturn.csv 2>&1 | grep -v triangle
$rtv scene jturn --amplitude $amp --tire $tir --out $out/mf_jturn.csv 2>&1 | grep -v triangle
.venv/bin/python scripts/plot_tire_comparison.py $out $amp ${RTV_DOCS:-docs} # scripts/docs.sh --check writes into a scratch folder
