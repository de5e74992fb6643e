#!/usr/bin/env python3
"""The helpers of scripts/docs.sh (standard library only).

  docs_check.py machine                   the line that names the machine and date of machine-dependent figures
  docs_check.py fill DOC NAME < TEXT      replace the generated block NAME of DOC with TEXT
  docs_check.py compare NAME OLD NEW [DIR]
                                          compare a committed doc (OLD) with its regeneration (NEW), naming
                                          NAME and the line of each difference; exit 1 if any. DIR/ is removed
                                          from NEW's text first (the scratch folder it was written in, which
                                          the commands that wrote it name in their "Written by" lines)

A generated block in a hand-written doc sits between the lines

  <!-- NAME: begin (written by `COMMAND`) -->
  <!-- NAME: end -->

The comparison skips machine-dependent figures by one rule (docs/results.md, "How the figures are checked"):
- In a Markdown table, a column whose header names a time or a rate of one (it contains "CPU", "wall", "µs",
  "real time" or "per second") is not compared.
- Outside tables, the numbers of a line that contains one of those words are not compared, and a line that
  contains "machine-dependent" (the line naming the machine and date) is not compared at all.
- A column of callgrind counts (its header contains "instructions" or "(whole process)") is compared to 3e-3
  relative: the build's directory and machine move them (measured on one commit: one evaluation 35 301
  instructions built here, 35 337 in CI's fresh clone, 1.02e-3; earlier 35 321 against 35 333; a whole bump
  run 808.92 M against 808.77 M, 1.9e-4), the stack's alignment moved them by up to 0.3 % before
  scripts/instructions.sh fixed it, and a process's start-up varies by a few dozen instructions between runs.
  A column of ratios of such counts (its header contains "ratio") is compared to twice that, each of its two
  counts moving by up to 3e-3, and to 1e-3 more for its printed rounding (three decimals): measured, the solid
  rear axle's evaluation 31 329 instructions here and 31 401 in CI's fresh clone (2.3e-3), its ratio to the
  HMMWV's 0.885 against 0.888 (3.4e-3).
- A commit id ("commit `0123abc`") is not compared.
- A round-off figure, a number in scientific notation below 1e-12 (4.4e-16, -9.7e-15, 1.5e-13), is compared
  only as such: its digits move with numpy's release and the order of floating-point operations (measured: the
  same commit's docs/kc/chrono_check.md gave 4.4e-16 and 3.6e-16, 9.7e-15 and 9.5e-15, with numpy 2.4.6
  against the release of its last generation), while a figure that leaves round-off still differs. 1e-12 is
  the Newton tolerance of the kinematic solves, rtv's and the Chrono check's: below it a difference of two
  solved positions is the solvers' noise (the single wishbone's steer against travel, 1.5e-13 deg in
  docs/kc/chrono_check.md, is Chrono's re-implementation's own, a numpy solve).
Everything else must be equal, character for character.
"""
import difflib
import os
import platform
import re
import sys
import time

MACHINE_WORDS = re.compile(r"CPU|wall|µs|real time|per second")
NUMBER = re.compile(r"[-+−]?\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?")
COMMIT = re.compile(r"commit `[0-9a-f]{7,40}`")
ROUNDOFF = re.compile(r"[-+−]?\d(?:\.\d+)?e-(?:1[3-9]|[2-9]\d|[1-9]\d\d)\b")
CALLGRIND_TOLERANCE = 3e-3
# A ratio of two counts is printed to three decimals: each side rounded by up to 5e-4.
RATIO_ROUNDING = 1e-3


def machine():
    model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo") if line.startswith("model name")),
                 platform.processor() or "unknown CPU")
    return (f"Machine-dependent figures (times and real-time factors) measured on {model}, "
            f"{len(os.sched_getaffinity(0))} cores available, Linux {platform.release()}, "
            f"{time.strftime('%Y-%m-%d', time.gmtime())}; the other figures do not depend on the machine.")


def fill(doc, name, text):
    begin = re.compile(r"^<!-- " + re.escape(name) + r": begin.*-->$", re.M)
    end = "<!-- " + name + ": end -->"
    src = open(doc).read()
    b = begin.search(src)
    e = src.find(end, b.end()) if b else -1
    if not b or e < 0:
        sys.exit(f"{doc}: no generated block '{name}' (lines '<!-- {name}: begin ... -->' and '{end}')")
    open(doc, "w").write(src[: b.end()] + "\n" + text.rstrip("\n") + "\n" + src[e:])


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def numbers(text):
    text = re.sub(r"(?<=\d) (?=\d{3}\b)", "", text)  # 212 061 957: one number
    return [float(n.replace(",", "").replace("−", "-")) for n in NUMBER.findall(text)]


def masked(lines):
    """Each line as (text to compare exactly, numbers to compare to a tolerance)."""
    out, header = [], None
    for line in lines:
        line = ROUNDOFF.sub("(round-off)", COMMIT.sub("commit `…`", line))
        if line.lstrip().startswith("|"):
            row = cells(line)
            if header is None:
                header = row
            elif not all(set(c) <= set("-: ") for c in row):
                fuzzy = []
                for i, h in enumerate(header[: len(row)]):
                    if MACHINE_WORDS.search(h):
                        row[i] = "…"
                    elif "(whole process)" in h or "instructions" in h:
                        ratio = "ratio" in h
                        tolerance = (2 * CALLGRIND_TOLERANCE, RATIO_ROUNDING) if ratio else (CALLGRIND_TOLERANCE, 0.0)
                        fuzzy += [(n, tolerance) for n in numbers(row[i])]
                        row[i] = NUMBER.sub("#", row[i])
                out.append(("| " + " | ".join(row) + " |", fuzzy))
                continue
            out.append((line, []))
            continue
        header = None
        if "machine-dependent" in line.lower():
            out.append(("…", []))
        elif MACHINE_WORDS.search(line):
            out.append((NUMBER.sub("#", line), []))
        else:
            out.append((line, []))
    return out


def compare(name, old_path, new_path, scratch=None):
    old, new = open(old_path).read().splitlines(), open(new_path).read()
    new = (new.replace(scratch.rstrip("/") + "/", "") if scratch else new).splitlines()
    a, b = masked(old), masked(new)
    close = lambda na, nb: len(na) == len(nb) and all(
        abs(x - y) <= rel * max(abs(x), abs(y)) + absolute for (x, (rel, absolute)), (y, _) in zip(na, nb))
    bad = []
    matcher = difflib.SequenceMatcher(None, [t for t, _ in a], [t for t, _ in b], autojunk=False)
    for op, i1, i2, j1, j2 in matcher.get_opcodes():
        if op == "equal":
            bad += [f"{name}:{i + 1}: differs beyond 3e-3 in a callgrind count (6e-3 in a ratio of two)\n"
                    f"  committed:   {old[i]}\n  regenerated: {new[j]}"
                    for i, j in zip(range(i1, i2), range(j1, j2)) if not close(a[i][1], b[j][1])]
            continue
        for k in range(max(i2 - i1, j2 - j1)):
            i, j = i1 + k, j1 + k
            line = i + 1 if i < i2 else i1 + 1
            committed = old[i] if i < i2 else "(no line)"
            regenerated = new[j] if j < j2 else "(no line)"
            bad.append(f"{name}:{line}: differs\n  committed:   {committed}\n  regenerated: {regenerated}")
    for message in bad[:20]:
        print(message)
    if len(bad) > 20:
        print(f"{name}: {len(bad) - 20} more differing lines")
    return 1 if bad else 0


def main(argv):
    if argv[:1] == ["machine"]:
        print(machine())
    elif argv[:1] == ["fill"] and len(argv) == 3:
        fill(argv[1], argv[2], sys.stdin.read())
    elif argv[:1] == ["compare"] and len(argv) in (4, 5):
        return compare(*argv[1:])
    else:
        sys.exit(__doc__)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
