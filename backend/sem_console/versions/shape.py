"""A version's report as the console's model, said once as data: a `Spec`, the model's report member for member, each
member taken from the wire report's JSON (`Src`), looked up in a table (`Lookup`), a time stamp in seconds (`Seconds`),
null unless a member is present (`Unless`), or null (None).

One spec, two readings that give the same JSON: `apply` builds the model's report from the wire report's JSON (what a
sample cyclonedds decodes takes), and `source` writes it as the Python expression the generated decoder returns
(`codec/fastcdr.py`), so a report the generated code decodes is the model's as it is read, with no second pass.
`tests/test_umaa_versions.py` holds them to the same JSON.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Src:
    """The wire report's member at `path` (dotted), a value or a whole struct."""

    path: str


@dataclass(frozen=True)
class Lookup:
    """The wire report's member at `path` looked up in `table` (None when it is not there)."""

    path: str
    table: Mapping[Any, Any]


@dataclass(frozen=True)
class Seconds:
    """The wire report's DateTime at `path` as seconds since the epoch."""

    path: str


@dataclass(frozen=True)
class Unless:
    """None when the wire report's member at `path` is absent (null), else `then`."""

    path: str
    then: Spec


Spec = Src | Lookup | Seconds | Unless | dict[str, "Spec"] | None
Adapter = Callable[[dict[str, Any], list[str]], tuple[dict[str, Any], list[str]]]
"""A version's report (its JSON and invalid values, as `codec` decodes them) as the model's."""


def _at(report: Any, path: str) -> Any:
    for part in path.split("."):
        report = report.get(part) if isinstance(report, dict) else None
    return report


def apply(spec: Spec, report: dict[str, Any]) -> Any:
    """The model's value that `spec` says, from the wire report's JSON."""
    if spec is None:
        return None
    if isinstance(spec, dict):
        return {name: apply(s, report) for name, s in spec.items()}
    if isinstance(spec, Src):
        return _at(report, spec.path)
    if isinstance(spec, Lookup):
        value = _at(report, spec.path)
        return spec.table.get(value) if isinstance(value, str | int | float | bool) else None
    if isinstance(spec, Seconds):
        seconds, nanoseconds = _at(report, f"{spec.path}.seconds"), _at(report, f"{spec.path}.nanoseconds")
        return None if seconds is None or nanoseconds is None else seconds + nanoseconds / 1e9
    return None if _at(report, spec.path) is None else apply(spec.then, report)


def source(
    spec: Spec,
    member: Callable[[str], str],
    const: Callable[[Any], str],
    build: Callable[[list[tuple[str, str]]], str] | None = None,
    lookup: Callable[[Mapping[Any, Any], str], str] | None = None,
) -> str:
    """The Python expression of the model's value that `spec` says: `member(path)` is the expression of the wire
    report's member at `path` in the generated decoder, `const(obj)` the name of a constant it holds, `build(items)`
    (when given) the expression of a dict of those names and expressions (a dict literal otherwise), `lookup(table,
    expr)` (when given) that of `table.get(expr)`."""
    if spec is None:
        return "None"
    if isinstance(spec, dict):
        items = [(name, source(s, member, const, build, lookup)) for name, s in spec.items()]
        return build(items) if build is not None else "{" + ", ".join(f"{n!r}: {e}" for n, e in items) + "}"
    if isinstance(spec, Src):
        return member(spec.path)
    if isinstance(spec, Lookup):
        expr = member(spec.path)
        return lookup(spec.table, expr) if lookup is not None else f"{const(spec.table)}.get({expr})"
    if isinstance(spec, Seconds):
        return f"({member(f'{spec.path}.seconds')} + {member(f'{spec.path}.nanoseconds')} / 1e9)"
    present = member(spec.path)
    if present == "None":
        return "None"
    return f"(None if {present} is None else {source(spec.then, member, const, None, lookup)})"
