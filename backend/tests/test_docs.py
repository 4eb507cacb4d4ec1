"""The docs: the generated configuration page is current and names every option each command's
`--help` prints; the README stays short and its links lead somewhere."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from sem_console import docs_gen

ROOT = Path(__file__).resolve().parents[2]
README_MAX_BYTES = 15 * 1024


def test_configuration_page_is_what_the_generator_writes_now() -> None:
    assert docs_gen.PAGE.read_text(encoding="utf-8") == docs_gen.render(), (
        "docs/configuration.md is stale: run .venv/bin/python -m sem_console.docs_gen")


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
    """The options in the first column of the command's table on the configuration page."""
    start = page.index(f"## `{command}`")
    end = page.find("\n## ", start + 1)
    rows = [line for line in page[start:end if end >= 0 else None].splitlines() if line.startswith("| `")]
    return {option for row in rows for option in row.split("`")[1].split(", ")}


@pytest.mark.parametrize("command, target", docs_gen.commands())
def test_every_option_of_help_is_on_the_configuration_page(command: str, target: str) -> None:
    module, _, function = target.partition(":")
    # the entry point pyproject.toml installs as the console script, run as that script does
    run = subprocess.run([sys.executable, "-c", f"import sys; from {module} import {function} as main; sys.exit(main())",
                          "--help"], capture_output=True, text=True, timeout=60, check=True)
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
    broken = [link for link in links if not re.match(r"[a-z]+:", link)
              and not (ROOT / link.partition("#")[0]).exists()]
    assert not broken, f"README.md links to missing files: {broken}"
