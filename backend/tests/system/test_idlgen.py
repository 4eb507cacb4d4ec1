"""The generated Python types are built from idl/, never committed: what is built is what idlc makes of idl/ today."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from sem_console import idlgen

pytestmark = pytest.mark.process

BACKEND = Path(__file__).resolve().parents[2]


def _texts(root: Path, files: list[Path]) -> dict[Path, str]:
    return {p.relative_to(root): p.read_text() for p in files}


@pytest.mark.parametrize("package", idlgen.PACKAGES)
def test_built_types_are_fresh(tmp_path: Path, package: str) -> None:
    fresh = _texts(tmp_path, idlgen.generate_all(tmp_path)[package])
    built = _texts(BACKEND, list((BACKEND / package).rglob("*.py")))
    assert sorted(fresh) == sorted(built), "generated files differ: run `python -m sem_console.idlgen`"
    stale = [str(p) for p in fresh if fresh[p] != built[p]]
    assert not stale, f"stale generated code, run `python -m sem_console.idlgen`: {stale}"


def test_no_generated_file_is_committed() -> None:
    tracked = subprocess.run(
        ["git", "ls-files", "--", *idlgen.PACKAGES, idlgen.STAMP], cwd=BACKEND, capture_output=True, text=True, check=True
    ).stdout.split()
    assert tracked == [], f"generated files are in git (they are built by scripts/setup.sh): git rm --cached {tracked}"


def test_if_stale_regenerates_only_on_change(tmp_path: Path) -> None:
    assert idlgen.main(["--out", str(tmp_path), "--if-stale"]) == 0
    first = (tmp_path / "UMAA_6_0" / "__init__.py").stat().st_mtime_ns
    assert idlgen.up_to_date(tmp_path)
    assert idlgen.main(["--out", str(tmp_path), "--if-stale"]) == 0
    assert (tmp_path / "UMAA_6_0" / "__init__.py").stat().st_mtime_ns == first
    (tmp_path / idlgen.STAMP).write_text("an older idl/")
    assert not idlgen.up_to_date(tmp_path)


def test_patched_idlc_runs(tmp_path: Path) -> None:
    idlc = idlgen.working_idlc(tmp_path)
    _orig, libs, _plugin = idlgen._wheel_paths()
    out = subprocess.run([str(idlc), "-v"], env={"LD_LIBRARY_PATH": str(libs)}, capture_output=True, text=True)
    assert out.returncode == 0 and "11.0.1" in out.stdout + out.stderr
