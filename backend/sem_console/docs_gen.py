"""Writes the docs' generated pages. Run it after changing an option, a setting, a route or a REST model:

    .venv/bin/python -m sem_console.docs_gen

- docs/configuration.md: every option of every command that backend/pyproject.toml installs ([project.scripts]), read
  from the command's own argparse parser (the `build_parser()` beside its `main`), with the defaults and SEM_*
  environment variables of `Settings`.
- docs/rest.md: every REST route and model of the console's OpenAPI document (what `/openapi.json` serves), with the
  responses that only a console with operator tokens, with --auth-reads, or replaying a recording gives.

tests/system/test_docs.py fails while a page differs from what this writes.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import tomllib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from pydantic_core import PydanticUndefined

from sem_console.core.config import Settings

BACKEND = Path(__file__).resolve().parents[1]
PAGE = BACKEND.parent / "docs" / "configuration.md"
REST_PAGE = BACKEND.parent / "docs" / "rest.md"
FOXGLOVE_LAYOUT = BACKEND.parent / "docs" / "foxglove-layout.json"

# sem-console builds its Settings from every option it parses (cli.main: Settings(**options)), so each
# of its options is also the environment variable SEM_<NAME>. The other commands read Settings only
# for what is listed here (the default of --domain); a command not listed reads none of its options from it. A
# subcommand is listed by its full name ("sem-keys init").
SETTINGS_OPTIONS: dict[str, set[str] | None] = {
    "sem-console": None,
    "sem-sim": {"domain", "dds_security"},
    "sem-check": {"domain", "dds_security"},
    "sem-replay": {"dds_security"},
    "sem-relay": {"domain", "dds_security"},
    "sem-keys init": {"domain"},
}
# A command whose options are the fields of a settings model of its own: each option is also its environment variable
# (the model's env_prefix), and its default the model's
OWN_SETTINGS: dict[str, str] = {"sem-relay": "sem_console.relay.options:RelayOptions"}


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


def subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """A command's subcommands (`sem-keys init`, `sem-keys issue`) and their parsers; {} for a command without."""
    for action in parser._actions:  # noqa: SLF001 (argparse has no public list of a parser's actions)
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001 (nor a public class of its subcommands)
            return dict(action.choices)
    return {}


def command_section(name: str, parser: argparse.ArgumentParser, level: str = "##") -> list[str]:
    settings_names = SETTINGS_OPTIONS.get(name, set())
    fields = Settings.model_fields
    lines = [f"{level} `{name}`", ""]
    if parser.description:
        lines += [text(parser.description), ""]
    subs = subcommands(parser)
    lines += ['<div class="options" markdown>', "", "| option | environment | default | what |", "|---|---|---|---|"]
    module, _, model_name = OWN_SETTINGS.get(name, "").partition(":")
    own = getattr(importlib.import_module(module), model_name) if module else None
    for action in parser._actions:  # noqa: SLF001 (argparse has no public list of a parser's actions)
        if subs and isinstance(action, argparse._SubParsersAction):  # noqa: SLF001 (as in subcommands)
            continue  # each has a section of its own, below
        in_settings = action.dest in fields and (settings_names is None or action.dest in settings_names)
        env = f"`SEM_{action.dest.upper()}`" if in_settings else "—"
        if own is not None and action.dest in own.model_fields:
            env = f"`{own.model_config['env_prefix']}{action.dest.upper()}`"
            default = shown(own.model_fields[action.dest].default)
        elif action.required:
            default = "required"
        elif in_settings and action.default is None:
            default = shown(fields[action.dest].default)  # the parser leaves it None: Settings decides
        else:
            default = shown(action.default)
        lines.append(f"| {invocation(action)} | {env} | {default} | {text(help_of(parser, action))} |")
    lines += ["", "</div>", ""]
    for sub, sub_parser in subs.items():
        lines += command_section(f"{name} {sub}", sub_parser, level + "#")
    if SETTINGS_OPTIONS.get(name, set()) is None:
        options = {a.dest for a in parser._actions}  # noqa: SLF001 (as above)
        rest = [(k, f) for k, f in fields.items() if k not in options]
        if rest:
            lines += [
                "### Environment variables without an option",
                "",
                f"Settings of `{name}` that only the environment sets. `SEM_DDS_INTERFACE` and `SEM_DDS_PEERS` "
                "apply to every command that joins DDS; `CYCLONEDDS_URI`, when set, replaces both "
                "(see [DDS](dds.md)).",
                "",
                "| environment | default | what |",
                "|---|---|---|",
            ]
            lines += [f"| `SEM_{k.upper()}` | {shown(f.default)} | {text(f.description or '')} |" for k, f in rest]
            lines.append("")
    return lines


def render() -> str:
    lines = [
        "# Configuration",
        "",
        "<!-- Generated by `python -m sem_console.docs_gen` from each command's argparse parser and Settings "
        "(backend/sem_console/core/config.py). Do not edit: tests/system/test_docs.py fails when this page is stale. -->",
        "",
        "Every option of every command the backend installs, as its `--help` prints it. An option with an "
        "environment variable can be set either way; the command line wins. A bad option stops the command "
        "with an error naming it and exit code 2.",
        "",
    ]
    with clean_environment():
        for name, target in commands():
            lines += command_section(name, parser_of(target.partition(":")[0]))
    return "\n".join(lines).rstrip("\n") + "\n"


# ---- the REST reference (docs/rest.md) ------------------------------------------------------
TOKENS = "docs:any-token"  # which routes need a token is all that matters here, not the token
# The consoles whose OpenAPI documents list more responses than a plain console's, in the order the page names them:
# a response a route gives only on such a console is marked with its label.
VARIANTS: tuple[tuple[str, dict[str, Any]], ...] = (
    ("with operator tokens", {"operator_tokens": TOKENS}),
    ("with --auth-reads", {"operator_tokens": TOKENS, "auth_reads": True}),
    ("in a replay", {"replay": Path("recording.mcap")}),
)
METHOD_ORDER = ("get", "post", "put", "patch", "delete")
Operation = tuple[str, str]  # (path, method)


def openapi(**settings: Any) -> dict[str, Any]:
    """The OpenAPI document a console with these settings serves (a fresh shell's environment, nothing started)."""
    from sem_console.main import create_app

    with clean_environment():
        doc: dict[str, Any] = create_app(Settings(**settings)).openapi()
    return doc


def operations(doc: dict[str, Any]) -> dict[Operation, dict[str, Any]]:
    """Every operation of the document, in the order the app registers its routes."""
    return {
        (path, method): op
        for path, item in doc["paths"].items()
        for method in sorted(item, key=METHOD_ORDER.index)
        for op in (item[method],)
    }


def md(value: str) -> str:
    """Text of the OpenAPI document (Markdown: its code spans) on one line of the page: outside code spans nothing is
    HTML, and no `|` ends a table cell."""
    parts = value.split("`")
    for i in range(0, len(parts), 2):
        parts[i] = parts[i].replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return "`".join(parts).replace("|", "\\|").replace("\n", " ").strip()


def anchor(method: str, path: str) -> str:
    """`GET /api/providers/{provider_id}` -> get-api-providers-provider_id: stable while the route is."""
    return method + "-" + "-".join(filter(None, (part.strip("{}").replace(".", "-") for part in path.split("/"))))


def model_link(ref: str) -> str:
    name = ref.rsplit("/", 1)[-1]
    return f"[`{name}`](#{name.lower()})"


def _number(value: Any) -> str:
    return str(int(value)) if isinstance(value, float) and value.is_integer() else str(value)


def _bounds(schema: dict[str, Any], low: str, high: str, unit: str = "") -> str:
    lo, hi = schema.get(low), schema.get(high)
    if lo is not None and hi is not None:
        return f"{_number(lo)} to {_number(hi)}{unit}"
    if lo is not None:
        return f"at least {_number(lo)}{unit}"
    return f"at most {_number(hi)}{unit}" if hi is not None else ""


def kind(schema: dict[str, Any]) -> str:
    """A schema as the page writes its type: `integer (1 to 1000)`, `list of [Command](#command)`, `"ON" or "OFF"`."""
    if "$ref" in schema:
        return model_link(schema["$ref"])
    if "const" in schema:
        return f"`{json.dumps(schema['const'])}`"
    if "enum" in schema:
        return " or ".join(f"`{json.dumps(v)}`" for v in schema["enum"])
    for key in ("oneOf", "anyOf"):
        if key in schema:
            return " or ".join(kind(s) for s in schema[key])
    t = schema.get("type", "any")
    notes = []
    if t == "array":
        if "prefixItems" in schema:
            return "[" + ", ".join(kind(s) for s in schema["prefixItems"]) + "]"
        text = f"list of {kind(schema.get('items', {}))}"
        notes.append(_bounds(schema, "minItems", "maxItems", " items"))
    elif t == "object":
        values = schema.get("additionalProperties")
        if not isinstance(values, dict):
            return "object"
        text = f"map of {kind(schema.get('propertyNames', {'type': 'string'}))} to {kind(values)}"
    else:
        text = str(t)
        notes.append(schema.get("format", ""))
        notes.append(_bounds(schema, "minimum", "maximum"))
        notes.append(_bounds(schema, "minLength", "maxLength", " characters"))
        if "exclusiveMinimum" in schema:
            notes.append(f"over {_number(schema['exclusiveMinimum'])}")
        if "pattern" in schema:
            notes.append(f"`{schema['pattern']}`")
    notes = [n for n in notes if n]
    return f"{text} ({', '.join(notes)})" if notes else text


def default_of(schema: dict[str, Any], required: bool) -> str:
    if required:
        return "required"
    return f"`{json.dumps(schema['default'])}`" if "default" in schema else "—"


def conditional(
    base: dict[Operation, dict[str, Any]], variants: list[tuple[str, dict[str, Any]]]
) -> dict[Operation, dict[str, tuple[str, dict[str, Any]]]]:
    """Per operation, each response only a variant console gives: status -> (the variant's label, the response)."""
    out: dict[Operation, dict[str, tuple[str, dict[str, Any]]]] = {}
    for label, doc in variants:
        for key, op in operations(doc).items():
            extra = out.setdefault(key, {})
            for code, response in op.get("responses", {}).items():
                if code not in base.get(key, {}).get("responses", {}) and code not in extra:
                    extra[code] = (label, response)
    return out


def common_responses(ops: dict[Operation, dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """The responses every route gives, each as most routes describe it: the page lists them once, and at a route only
    where it says more."""
    out: dict[str, dict[str, Any]] = {}
    for code in set.intersection(*(set(op["responses"]) for op in ops.values())):
        told = [json.dumps(op["responses"][code], sort_keys=True) for op in ops.values()]
        out[code] = json.loads(max(told, key=told.count))
    return dict(sorted(out.items()))


def body_kind(response: dict[str, Any]) -> str:
    content = response.get("content", {})
    if not content:
        return "—"
    return " or ".join(kind(c.get("schema", {})) if media == "application/json" else f"`{media}`" for media, c in content.items())


def response_rows(responses: dict[str, tuple[str, dict[str, Any]]]) -> list[str]:
    rows = ["| status | what | body |", "|---|---|---|"]
    for code in sorted(responses):
        label, r = responses[code]
        what = md(r.get("description", ""))
        rows.append(f"| {code} | {f'*{label}:* ' if label else ''}{what} | {body_kind(r)} |")
    return rows


def operation_section(path: str, method: str, op: dict[str, Any], responses: dict[str, tuple[str, dict[str, Any]]]) -> list[str]:
    lines = [
        f"### `{method.upper()} {path}` {{#{anchor(method, path)}}}",
        "",
        f"**{md(op.get('summary', ''))}.**" + (f" {md(op['description'])}" if op.get("description") else ""),
        "",
    ]
    params = op.get("parameters", [])
    if params:
        lines += ["| parameter | in | type | default | what |", "|---|---|---|---|---|"]
        lines += [
            f"| `{p['name']}` | {p['in']} | {kind(p.get('schema', {}))} | "
            f"{default_of(p.get('schema', {}), p.get('required', False))} | {md(p.get('description', '—'))} |"
            for p in params
        ]
        lines.append("")
    body = op.get("requestBody")
    if body is not None:
        lines += [f"Request body: {body_kind(body)}.", ""]
    return [*lines, *response_rows(responses), ""]


def model_section(name: str, schema: dict[str, Any]) -> list[str]:
    lines = [f"### `{name}` {{#{name.lower()}}}", ""]
    if schema.get("description"):
        lines += [md(schema["description"]), ""]
    fields = schema.get("properties", {})
    if not fields:
        return [*lines, "No fields: `{}`." if schema.get("type") == "object" else f"{kind(schema)}.", ""]
    required = set(schema.get("required", ()))
    lines += ["| field | type | default | what |", "|---|---|---|---|"]
    lines += [
        f"| `{field}` | {kind(s)} | {default_of(s, field in required)} | {md(s.get('description', ''))} |"
        for field, s in fields.items()
    ]
    return [*lines, ""]


def render_rest() -> str:
    doc = openapi()
    ops = operations(doc)
    extra = conditional(ops, [(label, openapi(**settings)) for label, settings in VARIANTS])
    common = common_responses(ops)
    lines = [
        "# REST reference",
        "",
        "<!-- Generated by `python -m sem_console.docs_gen` from the console's OpenAPI document (the routes of "
        "backend/sem_console/api/routes/ and the models of api/schemas.py). Do not edit: tests/system/test_docs.py fails "
        "when this page is stale. -->",
        "",
        "Every REST route of the console and every model it takes or answers, as its OpenAPI document says "
        "(served at `/openapi.json`). What the routes have in common (times, exports, errors, tokens) and the "
        "WebSocket are on the [API](api.md) page. A response marked *with operator tokens*, *with --auth-reads* "
        "or *in a replay* is given only by a console started so.",
        "",
        "## Every route",
        "",
        "Besides its own responses, every route may answer:",
        "",
        *response_rows({code: ("", r) for code, r in common.items()}),
        "",
    ]
    tags: dict[str, list[Operation]] = {}
    for key, op in ops.items():
        tags.setdefault(op.get("tags", ["other"])[0], []).append(key)
    lines += ["| route | summary |", "|---|---|"]
    lines += [
        f"| [`{m.upper()} {p}`](#{anchor(m, p)}) | {md(ops[(p, m)].get('summary', ''))} |"
        for keys in tags.values()
        for p, m in keys
    ]
    lines.append("")
    for tag, keys in tags.items():
        lines += [f"## {tag[:1].upper()}{tag[1:]}", ""]
        for path, method in keys:
            op = ops[(path, method)]
            own = {code: ("", r) for code, r in op.get("responses", {}).items() if common.get(code) != r}
            lines += operation_section(path, method, op, {**own, **extra.get((path, method), {})})
    lines += ["## Models", ""]
    for name, schema in sorted(doc.get("components", {}).get("schemas", {}).items()):
        lines += model_section(name, schema)
    return "\n".join(lines).rstrip("\n") + "\n"


def foxglove_layout() -> str:
    from sem_console.gateways.foxglove.layout import layout

    return layout()


PAGES: dict[Path, Callable[[], str]] = {PAGE: render, REST_PAGE: render_rest, FOXGLOVE_LAYOUT: foxglove_layout}


def main() -> int:
    for page, write in PAGES.items():
        page.write_text(write(), encoding="utf-8")
        print(f"wrote {page}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
