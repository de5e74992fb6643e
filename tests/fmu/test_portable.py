"""The packaged linux64 binary loads on old Linux: it requires no glibc symbol version newer than 2.17.

The dynamic loader refuses a library whose version requirements (ELF section .gnu.version_r, what
`objdump -p` lists as "Version References") name a GLIBC_x.y the system's libc does not define, weak symbols
included. So the check reads that section with pyelftools rather than trusting a list of symbols.
"""

import io
import re
import shutil
import subprocess
import zipfile

import pytest
from elftools.elf.elffile import ELFFile

GLIBC_FLOOR = (2, 17)  # manylinux2014; Rust's standard library supports glibc 2.17
SO_NAME = "binaries/linux64/RtVehicle.so"


def glibc_version(name):
    """'GLIBC_2.3.4' -> (2, 3, 4); None for anything else (GCC_3.0, GLIBC_PRIVATE, ...)."""
    m = re.fullmatch(r"GLIBC_(\d+(?:\.\d+)*)", name)
    return tuple(int(x) for x in m.group(1).split(".")) if m else None


def highest_glibc(names):
    """The highest GLIBC_ version among version names, compared numerically (2.3.4 < 2.17), or None."""
    versions = [v for v in map(glibc_version, names) if v is not None]
    return max(versions) if versions else None


def version_requirements(elf_bytes):
    """{library: [version names]} from the ELF's .gnu.version_r section."""
    elf = ELFFile(io.BytesIO(elf_bytes))
    section = elf.get_section_by_name(".gnu.version_r")
    if section is None:
        return {}
    return {verneed.name: [aux.name for aux in auxs] for verneed, auxs in section.iter_versions()}


def fmt(v):
    return ".".join(map(str, v))


# ---- the parser on known lists: the check must be able to fail ------------------------------------


def test_version_parser_on_known_lists():
    assert glibc_version("GLIBC_2.2.5") == (2, 2, 5)
    assert glibc_version("GLIBC_PRIVATE") is None
    assert glibc_version("GCC_3.0") is None
    # What Debian 12's native build of this library requires (objdump -T): 2.35 (hypot), above the floor.
    debian12 = ["GLIBC_2.2.5", "GLIBC_2.3", "GLIBC_2.3.4", "GLIBC_2.14", "GLIBC_2.17", "GLIBC_2.18",
                "GLIBC_2.28", "GLIBC_2.30", "GLIBC_2.33", "GLIBC_2.34", "GLIBC_2.35", "GCC_3.0"]
    assert highest_glibc(debian12) == (2, 35) > GLIBC_FLOOR
    # Numeric, not lexicographic: "2.3.4" > "2.17" as strings.
    assert highest_glibc(["GLIBC_2.3.4", "GLIBC_2.17", "GLIBC_2.2.5"]) == (2, 17) <= GLIBC_FLOOR
    assert highest_glibc(["GLIBC_2.9", "GLIBC_2.10"]) == (2, 10)
    assert highest_glibc(["GCC_3.0"]) is None


# ---- the packaged binary ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def linux64_so(fmu_path):
    with zipfile.ZipFile(fmu_path) as z:
        return z.read(SO_NAME)


def test_packaged_binary_is_x86_64(linux64_so):
    elf = ELFFile(io.BytesIO(linux64_so))
    assert elf.elfclass == 64 and elf["e_machine"] == "EM_X86_64"


def test_packaged_binary_needs_glibc_2_17_at_most(linux64_so):
    reqs = version_requirements(linux64_so)
    names = [n for ns in reqs.values() for n in ns]
    highest = highest_glibc(names)
    assert highest is not None, f"no GLIBC_ version requirement found in {SO_NAME}: {reqs}"
    too_new = sorted({n for n in names if (glibc_version(n) or (0,)) > GLIBC_FLOOR})
    assert highest <= GLIBC_FLOOR, (
        f"{SO_NAME} needs glibc {fmt(highest)} > {fmt(GLIBC_FLOOR)} ({', '.join(too_new)}): "
        "package with `cargo run --release -p packaging` (cargo zigbuild, target x86_64-unknown-linux-gnu.2.17)")
    assert "GLIBC_PRIVATE" not in names


@pytest.mark.skipif(shutil.which("objdump") is None, reason="objdump (binutils) not installed")
def test_reader_agrees_with_objdump(linux64_so, tmp_path):
    """pyelftools' reading of the version requirements is what binutils sees."""
    so = tmp_path / "RtVehicle.so"
    so.write_bytes(linux64_so)
    out = subprocess.run(["objdump", "-T", str(so)], capture_output=True, text=True, check=True).stdout
    from_objdump = set(re.findall(r"\bGLIBC_[0-9.]*[0-9]\b", out))
    from_elf = {n for ns in version_requirements(linux64_so).values() for n in ns if n.startswith("GLIBC_")}
    assert from_objdump <= from_elf
    assert highest_glibc(from_objdump) == highest_glibc(from_elf)
