#!/usr/bin/env bash
# Instructions per evaluation, per tire evaluation and per IMEX-AB3 step, counted by valgrind callgrind over the
# measured loop alone (`--toggle-collect='*measured*'`: the examples' set-up is not counted), divided by the
# loop's length. Deterministic for a given build. Prints the Markdown table of docs/results.md, "Instructions"
# (scripts/docs.sh writes it there). The examples' headers say what each loop does.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --example evaluation_instructions --example tire_instructions --example imex_step_instructions \
    2>/dev/null
# count N PROGRAM ARGS...: instructions of the measured loop over N, to the nearest unit. The programs run from a
# folder whose path has a fixed length, in an empty environment: valgrind puts the program's absolute path and
# the environment on the client's stack, and the stack's alignment changes the count (the HMMWV's evaluation
# read 35 231 and 35 267 for the same binary, run from two checkouts). So fixed, the same build gives the same
# count to the instruction, wherever the repository is.
ex=$(mktemp -d /tmp/rtv_instructions.XXXXXX)
trap 'rm -rf "$ex"' EXIT
cp target/release/examples/{evaluation_instructions,tire_instructions,imex_step_instructions} "$ex/"
vg=$(command -v valgrind)
count() {
    local n=$1 total
    shift
    total=$(env -i "$vg" --tool=callgrind --collect-atstart=no --toggle-collect='*measured*' \
        --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | sed -nE 's/^==[0-9]+== Collected : ([0-9]+)$/\1/p')
    echo $(((total + n / 2) / n))
}
group() { sed -E ':a;s/([0-9])([0-9]{3})($| )/\1 \2\3/;ta'; } # 35231 -> 35 231
ratio() { python3 -c "import sys; print(f'{$1 / $2:.3f}')"; } # 3 decimals: a step of 8e-4, below the counts' 3e-3 check
pac02=resources/tires/HMMWV_Pac02Tire.tir
mf61=resources/tires/mf61_example.tir
hmmwv=$(count 2000 $ex/evaluation_instructions 2000)
macpherson=$(count 2000 $ex/evaluation_instructions 2000 resources/vehicles/generic_macpherson.json)
wishbone=$(count 2000 $ex/evaluation_instructions 2000 resources/vehicles/generic_double_wishbone.json)
single=$(count 2000 $ex/evaluation_instructions 2000 resources/vehicles/rtv_single_wishbone.json)
solid=$(count 2000 $ex/evaluation_instructions 2000 resources/vehicles/rtv_hmmwv_solid_rear.json)
solid_axles=$(count 2000 $ex/evaluation_instructions 2000 resources/vehicles/rtv_hmmwv_solid_axles.json)
on_pac02=$(count 2000 $ex/evaluation_instructions 2000 - $pac02)
sti=$(count 20000 $ex/tire_instructions sti 20000)
tire_pac02=$(count 20000 $ex/tire_instructions $pac02 20000)
tire_mf61=$(count 20000 $ex/tire_instructions $mf61 20000)
imex=$(count 2000 $ex/imex_step_instructions 2000)
echo "Counted by $(valgrind --version) on the baseline x86-64 code (valgrind runs it: \`src/simd.rs\`), built by"
echo "$(rustc --version | cut -d' ' -f1-2); the loops are in \`examples/\`, run by \`scripts/instructions.sh\` with a fixed"
echo "stack layout (the stack's alignment moves the counts by up to 0.3 %: the script says why)."
echo
echo "| what | instructions | against (a ratio of instructions) |"
echo "|---|---|---|"
echo "| one synthesis evaluation at the J-turn's state at 4 s, HMMWV (\`evaluation_instructions 2000\`) | $(group <<<"$hmmwv") | |"
echo "| the same, Chrono's MacPherson import (\`... 2000 resources/vehicles/generic_macpherson.json\`) | $(group <<<"$macpherson") | $(ratio "$macpherson" "$hmmwv") × the HMMWV's |"
echo "| the same, Chrono's double-wishbone import (\`... 2000 resources/vehicles/generic_double_wishbone.json\`) | $(group <<<"$wishbone") | $(ratio "$wishbone" "$hmmwv") × the HMMWV's |"
echo "| the same, the single-wishbone vehicle (\`... 2000 resources/vehicles/rtv_single_wishbone.json\`) | $(group <<<"$single") | $(ratio "$single" "$hmmwv") × the HMMWV's |"
echo "| the same, the HMMWV with a three-link solid rear axle (\`... 2000 resources/vehicles/rtv_hmmwv_solid_rear.json\`) | $(group <<<"$solid") | $(ratio "$solid" "$hmmwv") × the HMMWV's |"
echo "| the same, the HMMWV on solid axles, the front one steered (\`... 2000 resources/vehicles/rtv_hmmwv_solid_axles.json\`) | $(group <<<"$solid_axles") | $(ratio "$solid_axles" "$hmmwv") × the HMMWV's |"
echo "| the same, the HMMWV on its Magic Formula tire (\`... 2000 - $pac02\`) | $(group <<<"$on_pac02") | $(ratio "$on_pac02" "$hmmwv") × the HMMWV's on STI |"
echo "| one tire force evaluation (forces, moments, rolling resistance), STI (\`tire_instructions sti 20000\`) | $(group <<<"$sti") | |"
echo "| the same, the Magic Formula of PAC2002 \`$pac02\` | $(group <<<"$tire_pac02") | $(ratio "$tire_pac02" "$sti") × STI |"
echo "| the same, the Magic Formula of MF 6.1 \`$mf61\` | $(group <<<"$tire_mf61") | $(ratio "$tire_mf61" "$sti") × STI |"
echo "| one IMEX-AB3 step at a given J, steady cornering from the J-turn's state at 4 s (\`imex_step_instructions 2000\`) | $(group <<<"$imex") | $(ratio "$imex" "$hmmwv") × an evaluation |"
