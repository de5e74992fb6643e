#!/usr/bin/env bash
# Regenerates the figures under docs/: kinematic curves, the three scenes (default configuration), and
# the tire curves (paper Fig. 3).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo build --release --bin rtv --example tire_curves
mkdir -p out/plots
rtv=./target/release/rtv
$rtv kinematics --axle front --out out/plots/kin_front.csv
$rtv kinematics --axle rear --out out/plots/kin_rear.csv
$rtv steering --out out/plots/steering.csv
.venv/bin/python scripts/plot_kinematics.py out/plots/kin_front.csv out/plots/kin_rear.csv out/plots/steering.csv docs/kinematics.png
for s in bump jturn sine; do $rtv scene $s --out out/plots/$s.csv 2>&1 | grep -v triangle; done
.venv/bin/python scripts/plot_scenes.py out/plots
./target/release/examples/tire_curves out/plots/tire_curves.csv > /dev/null
.venv/bin/python scripts/plot_tire_curves.py out/plots/tire_curves.csv docs/tire_curves.png
ls -la docs/*.png
