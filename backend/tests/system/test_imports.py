"""The backend's import graph keeps the contracts of backend/pyproject.toml ([tool.importlinter]): each room imports only
rooms below it, only the layers above `api` import it, no package has an import cycle between its modules or
subpackages, sem-check and the API's contract do not take the wire codec from console/, and the codec imports none of
its users. Imports under `if TYPE_CHECKING:` count: a cycle the interpreter never runs is still one a reader has to
untangle.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import pytest

pytestmark = pytest.mark.process

BACKEND = Path(__file__).resolve().parents[2]
LINT_IMPORTS = Path(sys.executable).parent / "lint-imports"


def options() -> dict[str, Any]:
    found: dict[str, Any] = tomllib.loads((BACKEND / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    return found


def lint_imports(cwd: Path, **env: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [str(LINT_IMPORTS), "--no-cache", "--no-logo"],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, **env},
    )


def test_the_import_contracts_are_kept() -> None:
    run = lint_imports(BACKEND)
    assert run.returncode == 0, run.stdout + run.stderr
    assert f"Contracts: {len(options()['contracts'])} kept, 0 broken." in run.stdout, run.stdout


def test_a_cycle_through_type_checking_imports_breaks_the_contracts(tmp_path: Path) -> None:
    """The project's own options (every [tool.importlinter] option but the package and its contracts) over a package
    whose one cycle is hidden under `if TYPE_CHECKING:`: the acyclic contract is broken and names the import."""
    package = tmp_path / "house"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "service.py").write_text("from house.sources import open_source\n")
    (package / "sources.py").write_text(
        "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n"
        "    from house.service import Console\n\ndef open_source() -> None: ...\n"
    )
    lines = ["[tool.importlinter]", 'root_package = "house"']
    lines += [
        f"{key} = {json.dumps(value)}"
        for key, value in options().items()
        if key not in ("root_package", "root_packages", "contracts")
    ]
    lines += ["", "[[tool.importlinter.contracts]]", 'name = "no cycles"', 'type = "acyclic_siblings"', 'ancestors = ["house"]']
    (tmp_path / "pyproject.toml").write_text("\n".join(lines) + "\n")
    run = lint_imports(tmp_path, PYTHONPATH=str(tmp_path))
    assert run.returncode == 1, run.stdout + run.stderr
    assert ".sources -> .service" in run.stdout, run.stdout


# What each command loads as it starts: every test, vehicle and CI job starts these processes, so a heavy library
# imported where it is not needed is paid on every start (sem-sim took 1 CPU-second, 0.4 without the database's
# modules and shapely)
@pytest.mark.parametrize(
    "module, not_loaded",
    [
        ("sem_console.sim.sem_sim", ["sqlalchemy", "sqlmodel", "alembic", "shapely", "numpy", "fastapi"]),
        ("sem_console.check.cli", ["sqlalchemy", "sqlmodel", "alembic", "shapely", "numpy", "fastapi"]),
        ("sem_console.relay.cli", ["sqlalchemy", "sqlmodel", "alembic", "shapely", "numpy", "fastapi"]),
        ("sem_console.keys.cli", ["sqlalchemy", "sqlmodel", "alembic", "shapely", "numpy", "fastapi", "zenoh"]),
        ("sem_console.main", ["shapely", "numpy", "aspn23", "foxglove"]),  # CoMap's geometry and the ASPN encoder: on first use
    ],
)
def test_a_command_starts_without_the_libraries_it_does_not_use(module: str, not_loaded: list[str]) -> None:
    run = subprocess.run(
        [sys.executable, "-c", f"import sys, {module}; print(' '.join(sorted(sys.modules)))"],
        cwd=BACKEND,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 0, run.stderr
    loaded = set(run.stdout.split())
    assert [m for m in not_loaded if m in loaded] == []
