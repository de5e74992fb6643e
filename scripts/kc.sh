#!/usr/bin/env bash
# Writes the K&C report of every shipped vehicle into docs/kc/: the built-in HMMWV (resources/hmmwv.json)
# and each resources/vehicles/*.json; each report's CSVs and PNGs beside it (docs/kc/README.md). Prints each report
# written, relative to docs/ (scripts/docs.sh compares those).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x .venv/bin/python ] || bash scripts/setup.sh >&2
cargo build --release --bin rtv >&2
rtv=./target/release/rtv
# Chrono's TMeasy tire files are JSON too ("Type": "Tire"); they ship beside the vehicles that name them.
is_tire_file() { grep -Eq '"Type"[[:space:]]*:[[:space:]]*"Tire"' "$1"; }
docs=${RTV_DOCS:-docs} # scripts/docs.sh --check writes into a scratch folder
mkdir -p $docs/kc
$rtv kc --out $docs/kc/hmmwv.md 2> >(grep -v 'triangle inequality' >&2)
echo kc/hmmwv.md
for f in resources/vehicles/*.json; do
    [ -e "$f" ] || continue
    is_tire_file "$f" && continue # a TMeasy tire shipped beside its vehicle (the MAN 5t's)
    name=$(basename "$f" .json)
    $rtv kc --vehicle-file "$f" --out "$docs/kc/$name.md" 2> >(grep -v 'triangle inequality' >&2)
    echo "kc/$name.md"
done
