"""The committed Python types are what idlc makes of idl/ today."""

from __future__ import annotations

from pathlib import Path

from sem_console import idlgen

BACKEND = Path(__file__).resolve().parents[1]


def test_generated_types_are_fresh(tmp_path: Path) -> None:
    written = idlgen.generate(tmp_path)
    fresh = {p.relative_to(tmp_path): p.read_text() for p in written}
    committed = {p.relative_to(BACKEND): p.read_text() for p in (BACKEND / "UMAA").rglob("*.py")}
    assert sorted(fresh) == sorted(committed), "generated files differ: run `python -m sem_console.idlgen`"
    stale = [str(p) for p in fresh if fresh[p] != committed[p]]
    assert not stale, f"stale generated code, run `python -m sem_console.idlgen`: {stale}"


def test_appendable_copies_are_fresh(tmp_path: Path) -> None:
    written = idlgen.generate_appendable(tmp_path)
    fresh = {p.relative_to(tmp_path): p.read_text() for p in written}
    committed = {p.relative_to(BACKEND): p.read_text() for p in (BACKEND / idlgen.APPENDABLE).rglob("*.py")}
    assert fresh == committed, "stale appendable copies: run `python -m sem_console.idlgen`"


def test_patched_idlc_runs(tmp_path: Path) -> None:
    import subprocess
    idlc = idlgen.working_idlc(tmp_path)
    _orig, libs, _plugin = idlgen._wheel_paths()
    out = subprocess.run([str(idlc), "-v"], env={"LD_LIBRARY_PATH": str(libs)}, capture_output=True, text=True)
    assert out.returncode == 0 and "11.0.1" in out.stdout + out.stderr
