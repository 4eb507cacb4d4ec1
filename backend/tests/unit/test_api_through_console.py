"""The API goes through the console's own methods (console/service.py, "what the API asks of the console"), never
past them into its parts: no `console.alarms.open`, no `console.store.audit(...)`, no `recorder = console.recorder`."""

from __future__ import annotations

import ast
from pathlib import Path

import sem_console.api

API = Path(sem_console.api.__file__).parent
VALUES = frozenset({"id", "station"})  # plain values of the console a route may read


def reaches(source: str) -> list[tuple[int, str]]:
    """(line, `console.<attr>...`) of every use of the console that is not a call of its method or one of VALUES."""
    tree = ast.parse(source)
    called = {id(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    found = []
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "console"):
            continue
        if id(node) in called or node.attr in VALUES:
            continue
        found.append((node.lineno, f"console.{node.attr}"))
    return found


def test_the_scan_finds_each_kind_of_reach() -> None:
    assert reaches("console.alarms.active()") == [(1, "console.alarms")]
    assert reaches("x = console.store.held") == [(1, "console.store")]
    assert reaches("recorder = console.recorder") == [(1, "console.recorder")]
    assert reaches("f(console.hub)") == [(1, "console.hub")]
    assert reaches("console.active_alarms()\nconsole.station\nconsole.id\nconsole.recording().status()") == []


def test_no_route_reaches_into_the_console() -> None:
    files = sorted(API.rglob("*.py"))
    assert any(f.parent.name == "routes" for f in files)
    found = [f"{f.relative_to(API.parent)}:{line}: {what}" for f in files for line, what in reaches(f.read_text())]
    assert not found, "call a method of Console (console/service.py) instead:\n" + "\n".join(found)
