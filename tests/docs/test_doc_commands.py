"""The documented commands run (issue 31): every command in the fenced code blocks of README.md and
docs/**/*.md, run as written from the repository's root, exits 0 (or the doc changes), and every `rtv`
subcommand the docs show refuses one bad input with a message that names the option and its range or file.

What counts as a command: a line (continuation lines ending in `\\` joined, `# comments` dropped) whose `&&`
chain has a part starting with `rtv`, `cargo run … --bin rtv --`, `cargo run … --example NAME --`,
`.venv/bin/rtv-study` or `rtv-study`, `bash scripts/…`, `python3 scripts/…` or `.venv/bin/python scripts/…`
(leading `VAR=value` assignments are its environment). Every part of such a chain runs, in order, as `&&` would.
Any other line of a shell block that starts like a command must be in OTHER_LINES with the reason it is not
run, so that no documented command goes unnoticed.

The rewrite rules (how a command is run without touching the repository):
1. Outputs go into a scratch folder, at the same relative path (an absolute one: under its file name):
   - the value of `--out`, `--csv` and `--figure`, and every argument that names a path under `docs/` or
     `out/`: `rtv stability --out docs/stability.md` writes SCRATCH/docs/stability.md, `--out jturn.csv`
     writes SCRATCH/jturn.csv;
   - a command whose default output is in the repository gets that default as an explicit option first
     (DEFAULT_OUTPUTS: `rtv kc`, `rtv calibrate`, `rtv work-precision`, `rtv-study run`), then moved as above;
   - scripts write out/ and docs/ into RTV_OUT=SCRATCH/out and RTV_DOCS=SCRATCH/docs (the scripts the docs
     show honour both).
   An argument naming a file that an earlier command of the same block wrote reads it from the scratch
   folder (`rtv check-vehicle my_car.json` after `rtv import-chrono … --out my_car.json`), and the command
   runs only where that one runs (else it is checked as in rule 4).
2. `cargo run --release --bin rtv -- ARGS` and `rtv ARGS` run target/release/rtv ARGS, built once by
   `cargo build --release --bin rtv` (the build `cargo run` would do before each).
3. A placeholder (`VEHICLE.json`, `DIR`, `my_car.json`, …) is filled from PLACEHOLDERS; one with no meaningful
   filling (a cluster's address) leaves its command not run, with the reason, its arguments still checked.
4. A command measured over SLOW_S seconds (TIMES: one run each on the 2-core machine, by
   `.venv/bin/python tests/docs/test_doc_commands.py --time`) runs only with RTV_DOCS_SLOW=1
   (`bash scripts/test.sh --slow`); without it its arguments are checked: `RTV_PARSE_ONLY=1` for rtv and
   rtv-study (parse, check, exit 0 without running), `bash -n` for a script.
After every command the repository's files (outside target/, .venv/, .git/) are as they were before it.
"""
import os
import re
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

import pytest

ROOT = Path(__file__).resolve().parents[2]
RTV = ROOT / "target" / "release" / "rtv"
DOCS = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").rglob("*.md"))]
SLOW = os.environ.get("RTV_DOCS_SLOW") == "1"
# A command above this (seconds, measured once) is in the slow set.
SLOW_S = 60.0
# The scratch folder inside a rewritten argument (replaced by the session's folder when run).
SCRATCH = "{scratch}"

# Seconds each documented command took (wall), one run each on the 2-core machine (AMD EPYC, 2 vCPUs) while
# other engineers' builds kept its load average at 7-10: an idle machine takes about half (the CPU seconds
# were 0.4-0.7 of these). Keyed by the command's text as the doc writes it (comments dropped); a command the
# docs write twice has its longer time (the first study run runs 1 000 runs, the next ones resume). Measured
# by `.venv/bin/python tests/docs/test_doc_commands.py --time`, after `bash scripts/test.sh`'s builds; the scenes,
# ride, calibrate, kc and manoeuvres again once the automatic internal step had come.
TIMES = {
    "bash scripts/jturn.sh": 14.8,
    "bash scripts/setup.sh && cargo build --release -p rtv-study-native": 2.8,
    "bash scripts/setup.sh": 2.7,
    ".venv/bin/rtv-study run examples/studies/dlc_speed_damper.toml": 211.8,
    ".venv/bin/rtv-study describe double-lane-change": 1.3,
    "cargo run --release --bin rtv -- scene jturn --out jturn.csv": 0.4,
    "cargo run --release --bin rtv -- scene jturn --integrator ab3 --slip steady --out jturn_ab3.csv": 0.4,
    "cargo run --release --bin rtv -- kinematics --axle front --out front.csv": 0.0,
    "cargo run --release --bin rtv -- steering --out steering.csv": 0.0,
    "cargo run --release --bin rtv -- kc --vehicle-file resources/vehicles/generic_macpherson.json": 4.5,
    "cargo run --release --bin rtv -- scene sine --tolerance 1e-4 --output-interval 0.04": 0.0,
    "cargo run --release --bin rtv -- scene sine --integrator imex-ab3 --step 0.008333333333333333 "
    "--output-interval 0.008333333333333333": 0.1,
    "cargo run --release --bin rtv -- scene jturn --road-file resources/roads/test_track.xodr --end 5 --out track.csv": 0.9,
    "cargo run --release --bin rtv -- scene bump --contact envelope --out bump.csv": 0.4,
    "cargo run --release --bin rtv -- calibrate": 31.8,
    "cargo run --release --bin rtv -- scene bump --bump-height 0.2 --initial-speed 16.67 --out big_bump.csv": 0.5,
    "cargo run --release --bin rtv -- scene jturn --amplitude 0 --speed coast --initial-speed 16.67 --brake 4000 "
    "--out stop.csv": 0.8,
    "cargo run --release --bin rtv -- stability --out docs/stability.md": 77.8,
    "cargo run --release --bin rtv -- work-precision": 68.4,
    "cargo run --release --bin rtv -- linearize --ay 2 --out linear.md": 0.1,
    "cargo run --release --bin rtv -- check-vehicle resources/vehicles/generic_macpherson.json": 0.0,
    "cargo run --release --bin rtv -- import-chrono VEHICLE.json --data-dir DIR --out my_car.json": 0.0,
    "bash scripts/manoeuvres.sh": 8.9,
    "cargo run --release --bin rtv -- import-chrono data/chrono/generic/vehicle/Vehicle_MacPhersonStruts.json "
    "--data-dir data/chrono --out my_car.json": 0.0,
    "cargo run --release --bin rtv -- check-vehicle my_car.json": 0.0,
    "cargo run --release --bin rtv -- import-chrono --all data/chrono": 0.2,
    "cargo run --release --bin rtv -- kc --vehicle-file my_car.json --out docs/kc/my_car.md": 5.6,
    "cargo run --release --bin rtv -- scene jturn --vehicle-file my_car.json --out jturn.csv": 0.6,
    "cargo run --release --bin rtv -- stability --vehicle-file my_car.json --out stability.md": 114.4,
    "cargo run --release --bin rtv -- tire --tire-file my_tire.tir --fz 5000 --sweep combined --out curves.csv": 0.0,
    "cargo run --release --bin rtv -- scene jturn --tire-file my_tire.tir --out jturn.csv": 4.4,
    "cargo run --release --bin rtv -- scene bump --road-file my_road.crg --contact envelope --step 0.001 --out run.csv": 1.7,
    "cargo run --release --bin rtv -- scene sine --road-file iso8608:C:42 --out run.csv": 1.7,
    "cargo run --release --bin rtv -- scene jturn --friction 0.5 --out run.csv": 1.2,
    "cargo run --release --bin rtv -- ride halfround --height 8": 15.9,
    "cargo run --release --bin rtv -- ride rms --course resources/roads/detrended_rms_course_1in.crg": 59.1,
    # Mostly the example's build: the tests' build of the library carries their test support, the example's
    # not, and the library is a cdylib (one file), so each build replaces the other's.
    "cargo run --release --example tire_curves -- out/tire_curves.csv": 119.0,
    ".venv/bin/python scripts/plot_tire_curves.py out/tire_curves.csv docs/tire_curves.png": 2.3,
    "cargo run --release --bin rtv -- import-chrono path/to/data/vehicle/my_car/Vehicle.json "
    "--data-dir path/to/data/vehicle --out my_car.json": 0.0,
    "rtv import-chrono data/chrono/generic/vehicle/Vehicle_MacPhersonStruts.json --data-dir data/chrono "
    "--out resources/vehicles/generic_macpherson.json": 0.0,
    "rtv import-chrono data/chrono/generic/vehicle/Vehicle_DoubleWishbones.json --data-dir data/chrono "
    "--out resources/vehicles/generic_double_wishbone.json": 0.0,
    "rtv import-chrono data/single_wishbone/Vehicle_SingleWishbones.json --data-dir data/chrono "
    "--tire-file data/chrono/generic/tire/Generic_Pac02Tire.tir --out resources/vehicles/rtv_single_wishbone.json": 0.0,
}

# Documented commands known to fail, each with the message it fails with and what will make it pass: reported
# as expected failures (pytest's strict xfail: once it passes, the test fails until its line here is removed).
# Empty since the automatic internal step (the README's two bump commands failed with step-size instability).
EXPECTED_TO_FAIL = {
}

# Placeholders of the docs and what fills them here; None with a reason: the command is not run.
PLACEHOLDERS = {
    "VEHICLE.json": "data/chrono/generic/vehicle/Vehicle_MacPhersonStruts.json",
    "DIR": "data/chrono",
    "path/to/data/vehicle/my_car/Vehicle.json": "data/chrono/generic/vehicle/Vehicle_DoubleWishbones.json",
    "path/to/data/vehicle": "data/chrono",
    # "your car" where no command of the block wrote it: a shipped import.
    "my_car.json": "resources/vehicles/generic_macpherson.json",
    "my_tire.tir": "resources/tires/HMMWV_Pac02Tire.tir",
    "my_road.crg": "resources/roads/halfround_4in.crg",
    "my_study.toml": "examples/studies/dlc_speed_damper.toml",
    "tcp://HOST:8786": (None, "a Dask cluster's scheduler: there is none here (the same study runs on the embedded "
                              "LocalCluster in the lines above it); its arguments are checked"),
    "/path/to/fmusim": (None, "fmusim and the FMU Compliance Checker are in no package registry CI reaches "
                              "(docs/fmi_checkers.md: run by hand); the script is checked with bash -n"),
    "/path/to/fmuCheck.linux64": (None, "as /path/to/fmusim"),
    "[OUT_DIR]": (None, "as /path/to/fmusim"),
}

# Lines of shell blocks that start like a command but are not of the forms above: why each is not run.
OTHER_LINES = {
    "cargo run --release -p packaging": "the FMU's packaging: scripts/test.sh runs it before the Python tests",
    ".venv/bin/python -m pytest -q tests/fmu": "the FMU tests: scripts/test.sh runs them",
    "cargo build --release -p rtv-study-native": "a build: scripts/test.sh builds it before the Python tests",
    "cargo test --lib integrate -- --nocapture": "Rust tests: scripts/test.sh runs the workspace's",
    "cargo test --test integrators": "Rust tests: scripts/test.sh runs the workspace's",
    "cargo test --release --test work_precision": "Rust tests: scripts/test.sh runs the workspace's",
    "cargo test --release --test allocation": "Rust tests: scripts/test.sh runs the workspace's",
    "cargo test --release --test stability": "Rust tests: scripts/test.sh runs the workspace's",
}
# bash scripts/test.sh is this test's own runner: running it here would recurse.
NOT_RUN = {"bash scripts/test.sh": "it runs this test (scripts/test.sh → pytest tests/docs): it would recurse"}

# A command that writes into the repository by default gets its default as an explicit option (then moved into
# the scratch folder by the output rule): (tool, subcommand) -> the options, from the command's arguments.
DEFAULT_OUTPUTS = {
    ("rtv", "kc"): lambda a: ["--out", f"docs/kc/{PurePosixPath(option(a, '--vehicle') or 'hmmwv').stem}.md"],
    ("rtv", "calibrate"): lambda a: ["--out", "resources/calibration.json"],
    ("rtv", "work-precision"): lambda a: ["--out", "docs/work_precision.md", "--csv", "out/work_precision.csv"],
    ("study", "run"): lambda a: ["--out", f"studies/{PurePosixPath(a[1]).stem}"],
}
OUTPUT_OPTIONS = ("--out", "--csv", "--figure")

# One bad input per rtv subcommand the docs show (and those they run through scripts): the arguments and the
# patterns its message must contain (the option and its range, or the file). Each also runs with
# RTV_PARSE_ONLY=1, which must refuse it the same way.
BAD_INPUTS = [
    (["scene", "jturn", "--friction", "3"], [r"--road-friction", r"outside \[0\.05, 2\]"]),
    (["scene", "jturn", "--vehicle", "missing.json"], [r"--vehicle", r"missing\.json"]),
    (["scene", "jturn", "--road", "missing.crg"], [r"--road", r"missing\.crg"]),
    (["kinematics", "--axle", "front", "--increment", "0"], [r"--increment > 0"]),
    (["steering", "--from", "-1"], [r"--from", r"beyond the steering limit ±[0-9.]+ m"]),
    (["kc", "--steering-points", "4"], [r"--steering-points", r"odd whole number from 3 to 10001"]),
    (["calibrate", "--vehicle", "missing.json"], [r"--vehicle", r"missing\.json"]),
    (["stability", "--threads", "0"], [r"--threads", r"1\.\.=64"]),
    (["work-precision", "--cases", "slalom"], [r"--cases", r"'slalom' is not one of jturn"]),
    (["linearize", "--speed", "0"], [r"--speed 0", r"must be in \(1, [0-9.]+\] m/s"]),
    (["check-vehicle", "missing.json"], [r"missing\.json: cannot read"]),
    (["import-chrono", "missing.json", "--data-dir", "data/chrono", "--out", f"{SCRATCH}/x.json"],
     [r"missing\.json: cannot read"]),
    (["import-chrono", "data/chrono/generic/vehicle/Vehicle_MacPhersonStruts.json", "--data-dir", "nowhere",
      "--out", f"{SCRATCH}/x.json"], [r"nowhere/generic/chassis/Chassis\.json does not exist", r"--data-dir"]),
    (["tire", "--fz", "0", "--sweep", "alpha"], [r"--fz", r"\(0, 1e6\] N"]),
    (["tire", "--tir", "missing.tir", "--fz", "5000", "--sweep", "alpha"], [r"--tir", r"missing\.tir"]),
    (["ride", "halfround", "--height", "7"], [r"--height 7", r"halfround_7in\.crg"]),
    (["ride", "rms", "--course", "missing.crg"], [r"--course", r"missing\.crg"]),
    (["manoeuvre", "step-steer", "--initial-speed", "0"], [r"--initial-speed", r"\(1, [0-9.]+\] m/s"]),
    (["road", "--road", "missing.crg"], [r"--road", r"missing\.crg"]),
]


def option(args, name):
    """The value of `name` in an argument list, or None."""
    return args[args.index(name) + 1] if name in args[:-1] else None


# ---- finding the commands -------------------------------------------------------------------------------

FENCE = re.compile(r"^\s*(```|~~~)\s*([\w+-]*)")
SHELL_LANGUAGES = {"sh", "bash", "shell", "console", ""}
# First words of a line that reads as a command (a line of output in an untagged block does not start so).
COMMAND_WORDS = {"rtv", "rtv-study", "cargo", "bash", "sh", "python", "python3", "valgrind", "pytest", "pip"}
ENV_ASSIGNMENT = re.compile(r"^[A-Z_][A-Z0-9_]*=")


@dataclass
class Part:
    kind: str  # rtv | study | script | python | example | cargo
    env: dict
    argv: list  # as run, SCRATCH in its outputs
    doc_args: list  # as the doc writes them


@dataclass
class Command:
    doc: str
    line: int
    text: str
    parts: list = field(default_factory=list)
    not_run: str = None  # the reason, when not run
    after: list = field(default_factory=list)  # the commands of its block that write what it reads

    @property
    def id(self):
        return f"{self.doc}:{self.line}"


def fenced_blocks(doc):
    """(language, [(line number, text)]) of each fenced block of a Markdown file."""
    blocks, current = [], None
    for n, text in enumerate((ROOT / doc).read_text().splitlines(), 1):
        fence = FENCE.match(text)
        if fence and current is None:
            current = (fence.group(2).lower(), [])
        elif fence:
            blocks.append(current)
            current = None
        elif current is not None:
            current[1].append((n, text))
    return blocks


def logical_lines(body):
    """Continuation lines (ending in a backslash) joined: (first line's number, text without its comment)."""
    lines, start, joined = [], None, ""
    for n, text in body:
        start = n if start is None else start
        if text.rstrip().endswith("\\"):
            joined += text.rstrip()[:-1] + " "
            continue
        lines.append((start, re.sub(r"(^|\s)#.*$", "", joined + text).strip()))
        start, joined = None, ""
    return [(n, t) for n, t in lines if t]


def tokens(text):
    """A line's words as the shell splits them (`&&` one word); a line of output may not parse: its words."""
    lexer = shlex.shlex(text, posix=True, punctuation_chars=True)
    lexer.whitespace_split = True
    lexer.commenters = ""
    try:
        return list(lexer)
    except ValueError:  # an unbalanced quote: not a command
        return text.split()


def chain(words):
    """A command's `&&` parts, each (environment assignments, words)."""
    parts, current = [], []
    for w in words + ["&&"]:
        if w == "&&":
            env = {}
            while current and ENV_ASSIGNMENT.match(current[0]):
                key, _, value = current.pop(0).partition("=")
                env[key] = value
            parts.append((env, current))
            current = []
        else:
            current.append(w)
    return parts


def classify(words):
    """(kind, the words rewrite() reads: the arguments after rtv, rtv-study or bash, else the whole line) of a
    documented form, or None."""
    if not words:
        return None
    if words[0] == "rtv":
        return "rtv", words[1:]
    if words[0] == "cargo" and words[1:2] == ["run"] and "--" in words:
        head, args = words[: words.index("--")], words[words.index("--") + 1:]
        if option(head, "--bin") == "rtv":
            return "rtv", args
        if option(head, "--example"):
            return "example", words
    if words[0] in ("rtv-study", ".venv/bin/rtv-study"):
        return "study", words[1:]
    if words[0] == "bash" and words[1:2] and words[1].startswith("scripts/"):
        return "script", words[1:]
    if words[0] in ("python3", ".venv/bin/python") and words[1:2] and words[1].startswith("scripts/"):
        return "python", words
    return None


def looks_like_a_command(words):
    first = next((w for w in words if not ENV_ASSIGNMENT.match(w)), "")
    return first in COMMAND_WORDS or first.startswith(("./", ".venv/", "scripts/", "target/"))


def to_scratch(path):
    p = PurePosixPath(path)
    return f"{SCRATCH}/{p.name if p.is_absolute() else p}"


def rewrite(kind, args, files, command):
    """The arguments as run (rules 1 and 3) and the reason it is not run, if a placeholder has no filling.
    `files`: the scratch files of the block so far (their names as the doc writes them) and the command that
    wrote each; a command that reads one runs after that command (`command.after`)."""
    if kind in ("rtv", "study") and args:
        add = DEFAULT_OUTPUTS.get((kind, args[0]))
        if add and not any(o in args for o in OUTPUT_OPTIONS):
            args = args + add(args)
    out, not_run = [], None
    for i, a in enumerate(args):
        if kind in ("rtv", "study") and i > 0 and args[i - 1] in OUTPUT_OPTIONS:
            files[a] = command
            out.append(to_scratch(a))
        elif a.startswith(("docs/", "out/")) or a in files:
            # A path under docs/ or out/ named first is written there (the example's out/tire_curves.csv).
            if a in files and files[a] is not command:
                command.after.append(files[a])
            files.setdefault(a, command)
            out.append(to_scratch(a))
        else:
            a, reason = fill(a)
            out.append(a)
            not_run = not_run or reason
    return out, not_run


def fill(word):
    """A placeholder's filling (the word itself if it is none), and the reason not to run if it has none."""
    filling = PLACEHOLDERS.get(word, word)
    return (word, f"{word}: {filling[1]}") if isinstance(filling, tuple) else (filling, None)


def documented_commands():
    """Every documented command, in the docs' order, and the command-like lines of no documented form."""
    commands, others = [], []
    for doc in DOCS:
        for language, body in fenced_blocks(doc):
            if language not in SHELL_LANGUAGES:
                continue
            files = {}
            for n, text in logical_lines(body):
                words = tokens(text)
                parts = chain(words)
                text = " ".join(words)
                if not any(classify(w) for _, w in parts):
                    if looks_like_a_command(words):
                        others.append((f"{doc}:{n}", text))
                    continue
                c = Command(doc, n, text, not_run=NOT_RUN.get(text))
                for env, w in parts:
                    kind, args = classify(w) or ("cargo" if w[:1] == ["cargo"] else "unknown", w)
                    reason = None
                    for key, value in env.items():
                        env[key], why = fill(value)
                        reason = reason or why
                    args, why = rewrite(kind, args, files, c)
                    c.not_run = c.not_run or reason or why
                    argv = [str(RTV)] + args if kind == "rtv" else (
                        [".venv/bin/rtv-study"] + args if kind == "study" else (
                            ["bash"] + args if kind == "script" else args))
                    c.parts.append(Part(kind, env, argv, w))
                commands.append(c)
    return commands, others


COMMANDS, OTHERS = documented_commands()


# ---- running them -------------------------------------------------------------------------------------

EXCLUDED = {"target", ".venv", ".git", "__pycache__", ".pytest_cache"}


def repository_files():
    """(size, mtime) of every file of the repository but the build, the venv and caches."""
    files = {}
    for folder, subfolders, names in os.walk(ROOT):
        subfolders[:] = [d for d in subfolders if d not in EXCLUDED and not d.endswith(".egg-info")]
        for name in names:
            path = os.path.join(folder, name)
            st = os.lstat(path)
            files[os.path.relpath(path, ROOT)] = (st.st_size, st.st_mtime_ns)
    return files


def changed(before, after):
    return sorted(p for p in before.keys() | after.keys() if before.get(p) != after.get(p))


def materialize(argv, scratch):
    """SCRATCH replaced by the folder; the parents of scratch paths made (as docs/ and out/ exist in a checkout)."""
    out = []
    for a in argv:
        if SCRATCH in a:
            a = a.replace(SCRATCH, str(scratch))
            Path(a).parent.mkdir(parents=True, exist_ok=True)
        out.append(a)
    return out


def environment(scratch, part, parse_only=False):
    env = {k: v for k, v in os.environ.items() if k != "RTV_PARSE_ONLY"}
    env.update(part.env, RTV_OUT=str(scratch / "out"), RTV_DOCS=str(scratch / "docs"))
    if parse_only:
        env["RTV_PARSE_ONLY"] = "1"
    return env


def run(argv, env, timeout):
    started = time.monotonic()
    p = subprocess.run(argv, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
    return p, time.monotonic() - started


def tail(text, lines=15):
    return "\n".join(text.strip().splitlines()[-lines:])


def check_arguments(part, scratch):
    """Rule 4 without running: the part's arguments parsed and checked, or its script's syntax."""
    argv = materialize(part.argv, scratch)
    if part.kind in ("rtv", "study"):
        p, _ = run(argv, environment(scratch, part, parse_only=True), timeout=120)
        said = p.stderr if part.kind == "rtv" else p.stdout
        assert p.returncode == 0 and "(RTV_PARSE_ONLY=1)" in said, \
            f"`{shlex.join(argv)}` with RTV_PARSE_ONLY=1: exit {p.returncode}\n{tail(p.stderr)}"
    elif part.kind == "script":
        script = ROOT / argv[1]
        assert script.is_file(), f"{argv[1]} does not exist"
        p, _ = run(["bash", "-n", str(script)], os.environ, timeout=60)
        assert p.returncode == 0, f"bash -n {argv[1]}: {p.stderr}"
    elif part.kind == "python":
        script = ROOT / argv[1]
        assert script.is_file(), f"{argv[1]} does not exist"
        compile(script.read_text(), str(script), "exec")
    elif part.kind == "example":
        assert (ROOT / "examples" / f"{option(argv, '--example')}.rs").is_file()


@pytest.fixture(scope="session")
def scratch(tmp_path_factory):
    return tmp_path_factory.mktemp("documented_commands")


@pytest.fixture(scope="session")
def rtv_built():
    p = subprocess.run(["cargo", "build", "--release", "--bin", "rtv"], cwd=ROOT, capture_output=True, text=True)
    assert p.returncode == 0, tail(p.stderr)


def test_every_documented_command_is_known():
    """A new command in the docs is timed into TIMES (or is not run, with its reason); a line of no documented
    form is in OTHER_LINES; entries no doc has any more are removed."""
    texts = {c.text for c in COMMANDS}
    untimed = [f"{c.id}: {c.text}" for c in COMMANDS if c.text not in TIMES and not c.not_run]
    assert not untimed, "not in TIMES (measure with `.venv/bin/python tests/docs/test_doc_commands.py --time`):\n" \
        + "\n".join(untimed)
    unknown = [f"{where}: {text}" for where, text in OTHERS if text not in OTHER_LINES]
    assert not unknown, "command lines of no documented form: add them to OTHER_LINES with a reason\n" \
        + "\n".join(unknown)
    unsupported = [f"{c.id}: {c.text}" for c in COMMANDS for p in c.parts if p.kind == "unknown"]
    assert not unsupported, "chains with a part this test cannot run:\n" + "\n".join(unsupported)
    stale = [t for t in [*TIMES, *EXPECTED_TO_FAIL, *NOT_RUN] if t not in texts] \
        + [t for t in OTHER_LINES if t not in {text for _, text in OTHERS}]
    assert not stale, "no doc has these any more:\n" + "\n".join(stale)


def params():
    running = set()
    for c in COMMANDS:
        # A command that reads what a command not run here wrote is checked, not run.
        runs = not c.not_run and (SLOW or TIMES.get(c.text, 0.0) <= SLOW_S) and all(a.id in running for a in c.after)
        if runs:
            running.add(c.id)
        marks = []
        if runs and c.text in EXPECTED_TO_FAIL:
            marks.append(pytest.mark.xfail(strict=True, reason=EXPECTED_TO_FAIL[c.text]))
        yield pytest.param(c, runs, marks=marks, id=c.id)


PASSED = set()  # the commands run and passed in this session, by id


@pytest.mark.parametrize("command,runs", list(params()))
def test_documented_command(command, runs, scratch, rtv_built):
    waits_for = [a.id for a in command.after if a.id not in PASSED]
    if runs and waits_for:  # deselected, or failed (reported there)
        pytest.skip(f"reads what {', '.join(waits_for)} writes, which did not run and pass in this session")
    if not runs:
        for part in command.parts:
            check_arguments(part, scratch)
        if command.not_run:
            pytest.skip(f"not run: {command.not_run}")
        return  # slow: its arguments checked; RTV_DOCS_SLOW=1 runs it
    timeout = 5 * TIMES.get(command.text, 60.0) + 120
    for part in command.parts:
        argv = materialize(part.argv, scratch)
        before = repository_files()
        p, _ = run(argv, environment(scratch, part), timeout)
        assert p.returncode == 0, \
            f"{command.id}: `{command.text}` exited {p.returncode} (ran `{shlex.join(argv)}`)\n{tail(p.stderr)}"
        touched = changed(before, repository_files())
        assert not touched, f"{command.id}: `{shlex.join(argv)}` changed the repository: {touched}"
    PASSED.add(command.id)


def documented_subcommands():
    return sorted({p.doc_args[p.doc_args.index("--") + 1] if "--" in p.doc_args else p.doc_args[1]
                   for c in COMMANDS for p in c.parts if p.kind == "rtv"})


def test_every_documented_subcommand_has_a_bad_input():
    missing = set(documented_subcommands()) - {args[0] for args, _ in BAD_INPUTS}
    assert not missing, f"no bad input in BAD_INPUTS for: {sorted(missing)}"


@pytest.mark.parametrize("parse_only", [False, True], ids=["run", "parse-only"])
@pytest.mark.parametrize("args,patterns", BAD_INPUTS, ids=[" ".join(a[:3]) for a, _ in BAD_INPUTS])
def test_bad_input_is_refused_naming_the_option(args, patterns, parse_only, scratch, rtv_built):
    argv = materialize([str(RTV)] + args, scratch)
    env = {k: v for k, v in os.environ.items() if k != "RTV_PARSE_ONLY"}
    if parse_only:
        env["RTV_PARSE_ONLY"] = "1"
    before = repository_files()
    p, _ = run(argv, env, timeout=120)
    assert p.returncode != 0, f"`{shlex.join(argv)}` exited 0"
    message = [line for line in p.stderr.splitlines() if not line.startswith(("warning:", "usage:", " "))]
    for pattern in patterns:
        assert any(re.search(pattern, line) for line in message), f"no /{pattern}/ in {message}"
    assert not changed(before, repository_files())


# ---- measuring them -------------------------------------------------------------------------------------

def measure(substring=""):
    """Runs every documented command once (the slow ones too), printing its seconds as TIMES lines (with the
    CPU seconds of its processes and the load average before it: a loaded machine stretches wall time)."""
    import resource
    import tempfile

    subprocess.run(["cargo", "build", "--release", "--bin", "rtv"], cwd=ROOT, check=True)
    with tempfile.TemporaryDirectory(prefix="rtv-docs-") as folder:
        for c in COMMANDS:
            if c.not_run or substring not in c.text:
                continue
            load = os.getloadavg()[0]
            cpu = resource.getrusage(resource.RUSAGE_CHILDREN)
            total, code = 0.0, 0
            for part in c.parts:
                p, seconds = run(materialize(part.argv, Path(folder)), environment(Path(folder), part), None)
                total, code = total + seconds, p.returncode
                if code:
                    break
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = after.ru_utime + after.ru_stime - cpu.ru_utime - cpu.ru_stime
            print(f"    {c.text!r}: {total:.1f},  # {c.id}: CPU {cpu:.1f} s, load {load:.1f}"
                  f"{f', exit {code}' if code else ''}", flush=True)


if __name__ == "__main__":
    if sys.argv[1:2] != ["--time"]:
        sys.exit("usage: .venv/bin/python tests/docs/test_doc_commands.py --time [SUBSTRING]")
    measure(sys.argv[2] if len(sys.argv) > 2 else "")
