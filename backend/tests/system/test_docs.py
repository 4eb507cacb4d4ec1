"""The docs: the generated configuration page is current and names every option each command's
`--help` prints; the generated REST reference is current and has every route and the responses of a console with
tokens or replaying; the README stays short and its links lead somewhere."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from sem_console import docs_gen

ROOT = Path(__file__).resolve().parents[3]
README_MAX_BYTES = 15 * 1024


def test_configuration_page_is_what_the_generator_writes_now() -> None:
    assert docs_gen.PAGE.read_text(encoding="utf-8") == docs_gen.render(), (
        "docs/configuration.md is stale: run .venv/bin/python -m sem_console.docs_gen"
    )


def test_rest_reference_is_what_the_generator_writes_now() -> None:
    assert docs_gen.REST_PAGE.read_text(encoding="utf-8") == docs_gen.render_rest(), (
        "docs/rest.md is stale: run .venv/bin/python -m sem_console.docs_gen"
    )


def test_foxglove_layout_is_what_the_generator_writes_now() -> None:
    assert docs_gen.FOXGLOVE_LAYOUT.read_text(encoding="utf-8") == docs_gen.foxglove_layout(), (
        "docs/foxglove-layout.json is stale: run .venv/bin/python -m sem_console.docs_gen"
    )


def _route_section(page: str, method: str, path: str) -> str:
    start = page.index(f"### `{method} {path}`")
    return page[start : page.index("\n### ", start + 1)]


def test_rest_reference_has_every_route_with_what_only_some_consoles_answer() -> None:
    page = docs_gen.render_rest()
    ops = docs_gen.operations(docs_gen.openapi())
    common = docs_gen.common_responses(ops)
    assert set(common) == {"403", "413", "422"}  # listed once, under "Every route"
    for (path, method), op in ops.items():
        section = _route_section(page, method.upper(), path)
        assert f"**{op['summary']}.**" in section
        for code, response in op["responses"].items():
            assert f"\n| {code} |" in section or common.get(code) == response, (method, path, code)
    # a command route: a token's refusals only with operator tokens, 409 only in a replay (the plain document has none)
    recording = _route_section(page, "POST", "/api/recordings")
    assert "| 401 | *with operator tokens:* no operator token" in recording
    assert "| 409 | *in a replay:* read-only" in recording
    # a read: a token's refusals only with --auth-reads; health never asks one
    assert "| 401 | *with --auth-reads:* " in _route_section(page, "GET", "/api/providers")
    assert "| 401 |" not in _route_section(page, "GET", "/api/health")
    # the request body's model is linked and has its fields
    assert "Request body: [`InertialSensorRequest`](#inertialsensorrequest)." in _route_section(
        page, "POST", "/api/providers/{provider_id}/inertial-sensor"
    )
    assert (
        "| `state` | `\"OFF\"` or `\"ON\"` or `\"RESTARTING\"` or `\"BEST_ALIGN\"` or `\"GPS_ALIGN\"` or `\"INIT\"` or "
        "`\"SNAP_ALIGN\"` or `\"STATIONARY_ALIGN\"` or `\"TRANSFER_ALIGN\"` | required | a state of the vehicle's UMAA" in page
    )


def help_options(text: str) -> list[str]:
    """The option strings of an argparse --help: each entry line starts with two spaces and a dash
    (`  -h, --help ...`, `  --port PORT ...`)."""
    found = []
    for line in text.splitlines():
        if line.startswith("  -"):
            invocation = re.split(r"\s{2,}", line.strip())[0]
            found += [part.split()[0] for part in invocation.split(", ")]
    return found


def documented_options(page: str, command: str) -> set[str]:
    """The options in the first column of the command's table on the configuration page (a subcommand's, `sem-keys
    init`, under its own heading)."""
    start = re.search(rf"^#+ `{re.escape(command)}`$", page, re.MULTILINE)
    assert start is not None, command
    end = re.compile(r"^#", re.MULTILINE).search(page, start.end())
    rows = [line for line in page[start.end() : end.start() if end else None].splitlines() if line.startswith("| `")]
    return {option for row in rows for option in row.split("`")[1].split(", ")}


def invocations() -> list[tuple[str, str, list[str]]]:
    """(command as the page names it, entry point, arguments before --help): each command, or each of its
    subcommands when it has them (sem-keys init, sem-keys issue)."""
    out = []
    for command, target in docs_gen.commands():
        subs = docs_gen.subcommands(docs_gen.parser_of(target.partition(":")[0]))
        out += [(f"{command} {sub}", target, [sub]) for sub in subs] or [(command, target, [])]
    return out


@pytest.mark.parametrize("command, target, before", invocations())
def test_every_option_of_help_is_on_the_configuration_page(command: str, target: str, before: list[str]) -> None:
    module, _, function = target.partition(":")
    # the entry point pyproject.toml installs as the console script, run as that script does
    run = subprocess.run(
        [sys.executable, "-c", f"import sys; from {module} import {function} as main; sys.exit(main())", *before, "--help"],
        capture_output=True,
        text=True,
        timeout=60,
        check=True,
    )
    options = help_options(run.stdout)
    assert "--help" in options and len(options) > 2, run.stdout
    missing = set(options) - documented_options(docs_gen.PAGE.read_text(encoding="utf-8"), command)
    assert not missing, f"{command} options not in docs/configuration.md: {sorted(missing)}"


def test_readme_is_short_and_its_links_resolve() -> None:
    readme = ROOT / "README.md"
    assert readme.stat().st_size <= README_MAX_BYTES, f"README.md is {readme.stat().st_size} bytes: move detail to docs/"
    text = readme.read_text(encoding="utf-8")
    links = re.findall(r"\]\(([^)\s]+)\)", text)
    assert any(link.startswith("docs/") for link in links)
    broken = [link for link in links if not re.match(r"[a-z]+:", link) and not (ROOT / link.partition("#")[0]).exists()]
    assert not broken, f"README.md links to missing files: {broken}"


def _figures() -> object:
    import importlib.util

    spec = importlib.util.spec_from_file_location("bench_figures", ROOT / "bench" / "figures.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_benchmark_page_shows_each_figure_of_the_json_beside_its_target(tmp_path: Path) -> None:
    figures: Any = _figures()
    (tmp_path / "latency.json").write_text(
        json.dumps(
            {
                "bench": "latency",
                "cores": 2,
                "date": "2026-11-25T18:00:00Z",
                "machine": {
                    "cores": 2,
                    "cpu": "Xeon",
                    "memoryGiB": 23.5,
                    "os": "Linux",
                    "python": "3.11.7",
                    "cyclonedds": "11.0.1",
                    "loadAverage1m": 1.5,
                },
                "targets": [
                    {"name": "overhead p50", "value": 0.8, "unit": "ms", "target": "< 1", "holds": True},
                    {"name": "overhead p99", "value": 7.5, "unit": "ms", "target": "< 5", "holds": False},
                ],
                "runs": [{"window_ms": 5, "p50_ms": 1.9}],
            }
        )
    )
    page = figures.render(tmp_path)
    assert "measured 2026-11-25T18:00:00Z on Xeon, 2 cores" in page and "load average 1.5" in page
    assert "| overhead p50 | 0.8 ms | < 1 ms | holds |" in page
    assert "| overhead p99 | 7.5 ms | < 5 ms | **missed** |" in page
    assert "| 5 | 1.9 |" in page  # a list of rows becomes a table
    # the page the docs build renders carries the marker the hook replaces
    assert figures.MARKER in (ROOT / "docs" / "benchmarks.md").read_text(encoding="utf-8")


def test_a_broken_benchmark_result_is_one_line_naming_the_file(tmp_path: Path) -> None:
    figures: Any = _figures()
    (tmp_path / "ingest.json").write_text('{"bench": "ingest", ')
    with pytest.raises(SystemExit, match=r"ingest\.json is not JSON .*run its benchmark again"):
        figures.render(tmp_path)
    assert "No benchmark has been run" in figures.render(tmp_path / "none")
