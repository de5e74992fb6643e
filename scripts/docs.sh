#!/usr/bin/env bash
# Every generated doc and figure of README.md and docs/, from one run; or, with --check, the deterministic ones
# regenerated into a scratch folder and compared with the committed docs.
#
#   bash scripts/docs.sh [NAME...]            regenerate (all, or the generators named), in place
#   bash scripts/docs.sh --check [NAME...]    regenerate the checked ones (or those named) into a scratch folder; exit 1, naming
#                                             the doc and the line, if a figure differs (scripts/test.sh runs it)
#   bash scripts/docs.sh --list               the generators: name, checked or not, what each writes and how
#
# A figure lives in one doc, written by the command that measures it; other docs link to it. The whole docs
# below are written by their commands; a figure block inside a hand-written doc sits between
# `<!-- NAME: begin (written by ...) -->` and `<!-- NAME: end -->` and is replaced by its command's output
# (scripts/docs_check.py fill).
#
# Checked: every figure that does not depend on the machine (counts, errors, orders, pass/fail tables,
# instruction counts). Not compared, by one rule (scripts/docs_check.py; docs/results.md, "How the figures are
# checked"): table columns whose header names a time or a rate of one ("CPU", "wall", "µs", "real time", "per
# second"), the numbers of other lines that name one, the line naming the machine and date (it contains
# "machine-dependent"), commit ids; callgrind counts ("instructions" and "(whole process)" columns) to 3e-3.
# Not checked at all: the PNG figures (drawn from the same runs; matplotlib's bytes vary with its version), and
# the generators marked "write only" in --list: their figures are times (studies), need the packaged FMUs
# (ssp, studies) or are figures only (plots, manoeuvres). The five stability suites are written here but not
# checked: each takes 1-2 min on 2 cores, over --check's budget of about 10 min in CI (issue 31).
# Marked "slow" in --list: checked only when named (`bash scripts/docs.sh --check hil_frame`, which
# `scripts/test.sh --slow` runs): a benchmark's build and run, which `scripts/test.sh` without --slow does not pay.
set -euo pipefail
cd "$(dirname "$0")/.."

# name | checked (check), checked only when named (slow) or not (write) | what it writes | the command (as the docs name it)
GENERATORS="\
plots|write|docs/kinematics.png, docs/scene_*.png, docs/tire_curves.png|bash scripts/plots.sh
linear|check|docs/linear.md, docs/linear_root_locus.png|bash scripts/linear.sh
kc|check|docs/kc/*.md with their CSVs and PNGs|bash scripts/kc.sh
chrono_check|check|docs/kc/chrono_check.md, docs/kc/chrono_check_{macpherson,single_wishbone}.png|.venv/bin/python scripts/chrono_kinematics_check.py
ride|check|docs/ride.md, docs/ride.png|bash scripts/ride.sh
tire_comparison|check|docs/tire_magic_formula.md (above its hand-written section), docs/tire_mf_*.png|bash scripts/tire_comparison.sh
work_precision|check|docs/work_precision.md, docs/work_precision.png|bash scripts/work_precision.sh
chrono_compare|check|docs/vehicle_file.md, section \"How close an import is to its source\"|cargo run --release --bin rtv -- chrono-compare
catalogue|check|docs/vehicle_file.md, block \"catalogue\" (a Chrono data folder, one line per vehicle)|cargo run --release --bin rtv -- import-chrono --all data/chrono
hop_resolution|check|docs/hop_resolution_{rk4,imex,stiff_rk4,stiff_imex}.md (compiled into the library)|cargo run --release --example hop_resolution -- ... (each doc's first line)
references|check|tests/reference/README.md and the reference traces tests/reference/*.csv|bash scripts/make_references.sh
instructions|check|docs/results.md, block \"instructions\"|bash scripts/instructions.sh
fmu_parameters|check|docs/fmu.md, block \"real-parameters\" (the options table of the model description)|cargo run --release --bin rtv -- options
scene_costs|check|docs/results.md, blocks \"scene-costs\", \"scene-costs-steady\", \"scene-costs-imex\"|bash scripts/pruning_costs.sh (with the options each block names)
hil_frame|slow|docs/results.md, block \"hil-frame\" (the HIL frames' times and worst frames)|bash scripts/hil_frame.sh
manoeuvres|write|docs/manoeuvres.png|bash scripts/manoeuvres.sh
ssp|write|docs/ssp_dlc.png|bash scripts/ssp.sh
studies|write|docs/studies.md, block \"figures\"; docs/studies_dlc.png|bash scripts/studies.sh
stability|write|docs/stability.md, docs/stability_pac02.md, docs/stability_{generic_macpherson,generic_double_wishbone,rtv_single_wishbone,rtv_hmmwv_solid_rear,rtv_hmmwv_solid_axles,uaz469,vw_microbus,audi,man_5t}.md|cargo run --release --bin rtv -- stability ... (each doc's first line)"

mode=write
names=()
for a in "$@"; do
    case $a in
        --check) mode=check ;;
        --list)
            echo "$GENERATORS" | awk -F'|' '{ printf "%-16s %-6s %s\n%23s%s\n", $1, $2, $3, "", $4 }'
            exit 0
            ;;
        -*) echo "unknown option $a (--check, --list)" >&2; exit 2 ;;
        *) names+=("$a") ;;
    esac
done
all=$(echo "$GENERATORS" | cut -d'|' -f1)
for n in "${names[@]}"; do
    grep -qx "$n" <<<"$all" || { echo "no generator '$n' (bash scripts/docs.sh --list)" >&2; exit 2; }
done
if [ ${#names[@]} -eq 0 ]; then
    if [ $mode = check ]; then
        mapfile -t names < <(echo "$GENERATORS" | awk -F'|' '$2 == "check" { print $1 }')
    else
        mapfile -t names <<<"$all"
    fi
fi

bash scripts/setup.sh >/dev/null
cargo build --release --bin rtv --examples 2>&1 | grep -E "^(error|warning: unused)" || true
[ -x target/release/rtv ] || { echo "cargo build failed" >&2; exit 1; }
rtv=./target/release/rtv

if [ $mode = check ]; then
    scratch=$(mktemp -d "${TMPDIR:-/tmp}/rtv_docs_check.XXXXXX")
    trap 'rm -rf "$scratch"' EXIT
    cp -a docs "$scratch/docs" # the hand-written docs whose blocks are replaced, and tire_magic_formula.md's kept part
    mkdir -p "$scratch/tests/reference"
    export RTV_DOCS=$scratch/docs RTV_REFERENCES=$scratch/tests/reference RUNS=1
else
    export RTV_DOCS=docs RTV_REFERENCES=tests/reference
fi
docs=$RTV_DOCS

# A block of a hand-written doc: block DOC NAME COMMAND... writes COMMAND's output between the block's markers.
block() {
    local doc=$1 name=$2 text
    shift 2
    text=$("$@")
    python3 scripts/docs_check.py fill "$docs/$doc" "$name" <<<"$text"
}

# Each generator: run_NAME writes into $docs (docs/, or the scratch copy) and echoes the docs to compare,
# as paths relative to docs/ (or tests/reference/README.md).
run_plots() { bash scripts/plots.sh >/dev/null; }
run_linear() { bash scripts/linear.sh >/dev/null; echo linear.md; }
run_kc() { bash scripts/kc.sh; } # it prints the reports it wrote, relative to docs/
run_chrono_check() {
    .venv/bin/python scripts/chrono_kinematics_check.py --out "$docs/kc/chrono_check.md" \
        --plot "$docs/kc/chrono_check_macpherson.png" >/dev/null
    echo kc/chrono_check.md
}
run_ride() { bash scripts/ride.sh >/dev/null; echo ride.md; }
run_tire_comparison() { bash scripts/tire_comparison.sh >/dev/null; echo tire_magic_formula.md; }
run_work_precision() { bash scripts/work_precision.sh >/dev/null; echo work_precision.md; }
run_chrono_compare() { $rtv chrono-compare --doc "$docs/vehicle_file.md" >/dev/null; echo vehicle_file.md; }
run_catalogue() { block vehicle_file.md catalogue $rtv import-chrono --all data/chrono; echo vehicle_file.md; }
run_hop_resolution() {
    local vehicles="resources/hmmwv.json resources/vehicles/generic_macpherson.json resources/vehicles/generic_double_wishbone.json"
    ./target/release/examples/hop_resolution rk4 $vehicles >"$docs/hop_resolution_rk4.md"
    ./target/release/examples/hop_resolution imex-ab3 $vehicles >"$docs/hop_resolution_imex.md"
    ./target/release/examples/hop_resolution rk4 --stiff >"$docs/hop_resolution_stiff_rk4.md"
    ./target/release/examples/hop_resolution imex-ab3 --stiff >"$docs/hop_resolution_stiff_imex.md"
    printf '%s\n' hop_resolution_rk4.md hop_resolution_imex.md hop_resolution_stiff_rk4.md hop_resolution_stiff_imex.md
}
run_references() { bash scripts/make_references.sh >/dev/null; echo ../tests/reference/README.md; }
run_fmu_parameters() { block fmu.md real-parameters $rtv options; echo fmu.md; }
run_instructions() { block results.md instructions bash scripts/instructions.sh; echo results.md; }
run_scene_costs() {
    block results.md scene-costs bash scripts/pruning_costs.sh
    block results.md scene-costs-steady env SCENES="jturn sine" bash scripts/pruning_costs.sh --slip steady --speed coast
    block results.md scene-costs-imex env SCENES="jturn sine" KEEP_ALL=0 bash scripts/pruning_costs.sh \
        --integrator imex-ab3 --step 0.008333333333333333 --output-interval 0.1
    echo results.md
}
run_hil_frame() { block results.md hil-frame bash scripts/hil_frame.sh; echo results.md; }
run_manoeuvres() { bash scripts/manoeuvres.sh >/dev/null; }
run_ssp() { bash scripts/ssp.sh >/dev/null; }
run_studies() { bash scripts/studies.sh >/dev/null; }
run_stability() {
    $rtv stability --out "$docs/stability.md" >/dev/null
    $rtv stability --tire-file resources/tires/HMMWV_Pac02Tire.tir --out "$docs/stability_pac02.md" >/dev/null
    for v in generic_macpherson generic_double_wishbone rtv_single_wishbone rtv_hmmwv_solid_rear rtv_hmmwv_solid_axles uaz469 vw_microbus audi man_5t; do
        $rtv stability --vehicle-file "resources/vehicles/$v.json" --out "$docs/stability_$v.md" >/dev/null
    done
    printf '%s\n' stability.md stability_pac02.md stability_generic_macpherson.md stability_generic_double_wishbone.md \
        stability_rtv_single_wishbone.md stability_rtv_hmmwv_solid_rear.md stability_rtv_hmmwv_solid_axles.md \
        stability_uaz469.md stability_vw_microbus.md stability_audi.md stability_man_5t.md
}

failed=()
started=$SECONDS
for n in "${names[@]}"; do
    t0=$SECONDS
    log=$(mktemp "${TMPDIR:-/tmp}/rtv_docs_$n.XXXXXX")
    touch "$log.stamp"
    # In a subshell with -e of its own: a function called as an `if` condition would run with -e off.
    set +e
    (set -e; "run_$n") >"$log.docs" 2>"$log"
    rc=$?
    set -e
    if [ $rc != 0 ]; then
        echo "FAIL  $n: its command failed (exit $rc; $log: $(tail -n 3 "$log" | tr '\n' ' '))"
        failed+=("$n")
        continue
    fi
    if [ $mode = check ]; then
        ok=1
        while read -r d; do
            [ -n "$d" ] || continue
            committed=docs/$d new=$docs/$d
            if [ ! "$new" -nt "$log.stamp" ]; then
                echo "FAIL  $n: it did not write docs/$d"
                ok=0
            elif ! python3 scripts/docs_check.py compare "$(realpath -m --relative-to=. "$committed")" "$committed" "$new" "$scratch"; then
                ok=0
            fi
        done <"$log.docs"
        [ $ok = 1 ] && echo "ok    $n ($((SECONDS - t0)) s)" || failed+=("$n")
    else
        echo "wrote $n ($((SECONDS - t0)) s)"
    fi
    rm -f "$log" "$log.docs" "$log.stamp"
done
echo "scripts/docs.sh $([ $mode = check ] && echo --check): ${#names[@]} generators in $((SECONDS - started)) s"
if [ ${#failed[@]} -gt 0 ]; then
    echo "differs or failed: ${failed[*]}$([ $mode = check ] && echo " (regenerate with: bash scripts/docs.sh ${failed[*]})")"
    exit 1
fi
