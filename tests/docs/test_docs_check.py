"""scripts/docs_check.py, the comparison of `bash scripts/docs.sh --check`: what it compares and what it skips
(docs/results.md, "How the figures are checked"), and the generated blocks it fills."""
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import docs_check  # noqa: E402

DOC = """\
# A generated doc

Machine-dependent figures (times and real-time factors) measured on AMD EPYC, 2 cores available, 2026-11-27.
The whole study took 47 s of CPU.

| setting | error | evaluations | CPU ms | instructions (whole process) |
|---|---|---|---|---|
| RK4 h = 2 ms | 9.01e-8 | 17680 | 111.9 | 702 200 038 |

Written by `rtv kc --out docs/kc/hmmwv.md`, generated at commit `23c59fb`.
"""


def compare(tmp_path, new_text, old_text=DOC, scratch=None):
    old, new = tmp_path / "old.md", tmp_path / "new.md"
    old.write_text(old_text)
    new.write_text(new_text)
    return docs_check.compare("docs/x.md", str(old), str(new), scratch)


def test_the_same_doc_passes(tmp_path):
    assert compare(tmp_path, DOC) == 0


@pytest.mark.parametrize("old, new", [
    ("| 9.01e-8 |", "| 9.02e-8 |"),  # an error
    ("| 17680 |", "| 17681 |"),  # a count
    ("# A generated doc", "# A generated report"),  # words
])
def test_a_deterministic_difference_fails_naming_the_doc_and_line(tmp_path, capsys, old, new):
    assert compare(tmp_path, DOC.replace(old, new)) == 1
    out = capsys.readouterr().out
    line = next(i + 1 for i, l in enumerate(DOC.splitlines()) if old in l)
    assert f"docs/x.md:{line}: differs" in out and new.strip("| ") in out


@pytest.mark.parametrize("old, new", [
    ("| 111.9 |", "| 98.0 |"),  # a column headed "CPU ..."
    ("took 47 s of CPU", "took 52 s of CPU"),  # a line naming CPU time
    ("AMD EPYC, 2 cores available, 2026-11-27", "Intel Xeon, 8 cores available, 2027-01-02"),  # the machine line
    ("commit `23c59fb`", "commit `0a1b2c3d`"),
])
def test_machine_dependent_figures_are_not_compared(tmp_path, old, new):
    assert compare(tmp_path, DOC.replace(old, new)) == 0


def test_a_line_naming_cpu_still_compares_its_words(tmp_path):
    assert compare(tmp_path, DOC.replace("took 47 s of CPU", "took 47 s of GPU and CPU")) == 1


def test_callgrind_counts_compare_to_3e3(tmp_path):
    assert compare(tmp_path, DOC.replace("702 200 038", "702 920 038")) == 0  # 1.02e-3: CI's build of one commit
    assert compare(tmp_path, DOC.replace("702 200 038", "704 400 038")) == 1  # 3.1e-3


def test_a_missing_or_extra_line_fails(tmp_path, capsys):
    assert compare(tmp_path, DOC.replace("The whole study took 47 s of CPU.\n", "")) == 1
    assert "docs/x.md:4: differs" in capsys.readouterr().out
    assert compare(tmp_path, DOC + "| extra row |\n") == 1


def test_the_scratch_folder_is_removed_from_the_regenerated_text(tmp_path):
    regenerated = DOC.replace("--out docs/kc/hmmwv.md", "--out /tmp/rtv_docs_check.ab12/docs/kc/hmmwv.md")
    assert compare(tmp_path, regenerated, scratch="/tmp/rtv_docs_check.ab12") == 0
    assert compare(tmp_path, regenerated) == 1


def test_fill_replaces_a_block_and_refuses_a_missing_one(tmp_path):
    doc = tmp_path / "doc.md"
    doc.write_text("before\n<!-- costs: begin (written by `x`) -->\nold\n<!-- costs: end -->\nafter\n")
    docs_check.fill(str(doc), "costs", "new 1\nnew 2\n")
    assert doc.read_text() == "before\n<!-- costs: begin (written by `x`) -->\nnew 1\nnew 2\n<!-- costs: end -->\nafter\n"
    run = subprocess.run([sys.executable, str(ROOT / "scripts" / "docs_check.py"), "fill", str(doc), "other"],
                         input="x", capture_output=True, text=True)
    assert run.returncode != 0 and "no generated block 'other'" in run.stderr


def test_every_block_in_the_docs_has_its_end_and_a_generator():
    """docs.sh fills these blocks; a block without its end, or one no generator writes, would go stale."""
    docs_sh = (ROOT / "scripts" / "docs.sh").read_text() + (ROOT / "scripts" / "study_figures.py").read_text()
    for path in [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        text = path.read_text()
        for line in text.splitlines():
            if line.startswith("<!-- ") and ": begin" in line:
                name = line[5:line.index(": begin")]
                assert f"<!-- {name}: end -->" in text, f"{path}: block {name} has no end"
                assert name in docs_sh, f"{path}: no generator writes block {name}"
