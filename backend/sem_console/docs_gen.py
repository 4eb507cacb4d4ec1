"""Writes the docs' configuration page (docs/configuration.md): every option of every command that
backend/pyproject.toml installs ([project.scripts]), read from the command's own argparse parser
(the `build_parser()` beside its `main`), with the defaults and SEM_* environment variables of
`Settings`. Run it after changing an option or a setting:

    .venv/bin/python -m sem_console.docs_gen

tests/test_docs.py fails while the page differs from what this writes.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import tomllib
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from pydantic_core import PydanticUndefined

from sem_console.core.config import Settings

BACKEND = Path(__file__).resolve().parents[1]
PAGE = BACKEND.parent / "docs" / "configuration.md"

# sem-console builds its Settings from every option it parses (cli.main: Settings(**options)), so each
# of its options is also the environment variable SEM_<NAME>. The other commands read Settings only
# for what is listed here (the default of --domain); a command not listed reads none of its options from it.
SETTINGS_OPTIONS: dict[str, set[str] | None] = {"sem-console": None, "sem-sim": {"domain"}, "sem-check": {"domain"}}


def commands() -> list[tuple[str, str]]:
    """(command, entry point "module:function") for each console script of the backend, in pyproject.toml's order."""
    project = tomllib.loads((BACKEND / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    return list(project.get("scripts", {}).items())


@contextmanager
def clean_environment() -> Iterator[None]:
    """Defaults as a fresh shell sees them: a parser may take a default from SEM_* (sem-sim's --domain)."""
    saved = {k: v for k, v in os.environ.items() if k.startswith("SEM_") or k == "CYCLONEDDS_URI"}
    for k in saved:
        del os.environ[k]
    try:
        yield
    finally:
        os.environ.update(saved)


def parser_of(module: str) -> argparse.ArgumentParser:
    build = getattr(importlib.import_module(module), "build_parser", None)
    if build is None:
        raise SystemExit(f"{module} has no build_parser(): the configuration page reads each command's parser from it")
    parser = build()
    assert isinstance(parser, argparse.ArgumentParser)
    return parser


def text(value: str) -> str:
    """Plain text in a Markdown table cell: nothing in it is markup or HTML."""
    for ch in "\\`*_[]|":
        value = value.replace(ch, "\\" + ch)
    return value.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace("\n", " ")


def shown(value: Any) -> str:
    if value is None or value is PydanticUndefined or value == argparse.SUPPRESS or value in ("", [], ()):
        return "—"
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    if isinstance(value, (list, tuple)):
        return f"`{','.join(map(str, value))}`"
    return f"`{value}`"


def invocation(action: argparse.Action) -> str:
    """The option as --help writes it, less a value name that only repeats the option's:
    `--port`, `--record DIR`, `--jaus-port [N]`, `--log-level {debug,info}`."""
    if action.choices is not None:
        metavar = "{" + ",".join(map(str, action.choices)) + "}"
    else:
        metavar = str(action.metavar or (action.dest.upper() if action.option_strings else action.dest))
    if not action.option_strings:
        return f"`{metavar}`"
    flags = f"`{', '.join(action.option_strings)}`"
    if action.nargs == 0 or (action.metavar is None and action.choices is None and action.nargs is None):
        return flags  # a flag, or a value named after the option itself (--port PORT): the name adds nothing
    # two code spans: a narrow column breaks between the option and its value, never inside either
    return f"{flags} `[{metavar}]`" if action.nargs == "?" else f"{flags} `{metavar}`"


def help_of(parser: argparse.ArgumentParser, action: argparse.Action) -> str:
    """The help text with its %(default)s and the like filled in, as argparse prints it."""
    if not action.help:
        return ""
    params = {k: v for k, v in vars(action).items() if v is not argparse.SUPPRESS}
    params["prog"] = parser.prog
    if params.get("choices") is not None:
        params["choices"] = ", ".join(map(str, params["choices"]))
    return action.help % params


def command_section(name: str, parser: argparse.ArgumentParser) -> list[str]:
    settings_names = SETTINGS_OPTIONS.get(name, set())
    fields = Settings.model_fields
    lines = [f"## `{name}`", ""]
    if parser.description:
        lines += [text(parser.description), ""]
    lines += ['<div class="options" markdown>', "", "| option | environment | default | what |", "|---|---|---|---|"]
    for action in parser._actions:  # noqa: SLF001 (argparse has no public list of a parser's actions)
        in_settings = action.dest in fields and (settings_names is None or action.dest in settings_names)
        env = f"`SEM_{action.dest.upper()}`" if in_settings else "—"
        if action.required:
            default = "required"
        elif in_settings and action.default is None:
            default = shown(fields[action.dest].default)  # the parser leaves it None: Settings decides
        else:
            default = shown(action.default)
        lines.append(f"| {invocation(action)} | {env} | {default} | {text(help_of(parser, action))} |")
    lines += ["", "</div>", ""]
    if SETTINGS_OPTIONS.get(name, set()) is None:
        options = {a.dest for a in parser._actions}  # noqa: SLF001 (as above)
        rest = [(k, f) for k, f in fields.items() if k not in options]
        if rest:
            lines += ["### Environment variables without an option", "",
                      f"Settings of `{name}` that only the environment sets. `SEM_DDS_INTERFACE` and `SEM_DDS_PEERS` "
                      "apply to every command that joins DDS; `CYCLONEDDS_URI`, when set, replaces both "
                      "(see [DDS](dds.md)).", "",
                      "| environment | default | what |", "|---|---|---|"]
            lines += [f"| `SEM_{k.upper()}` | {shown(f.default)} | {text(f.description or '')} |" for k, f in rest]
            lines.append("")
    return lines


def render() -> str:
    lines = ["# Configuration", "",
             "<!-- Generated by `python -m sem_console.docs_gen` from each command's argparse parser and Settings "
             "(backend/sem_console/core/config.py). Do not edit: tests/test_docs.py fails when this page is stale. -->",
             "",
             "Every option of every command the backend installs, as its `--help` prints it. An option with an "
             "environment variable can be set either way; the command line wins. A bad option stops the command "
             "with an error naming it and exit code 2.", ""]
    with clean_environment():
        for name, target in commands():
            lines += command_section(name, parser_of(target.partition(":")[0]))
    return "\n".join(lines).rstrip("\n") + "\n"


def main() -> int:
    PAGE.write_text(render(), encoding="utf-8")
    print(f"wrote {PAGE}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
