"""The backend's runtime import graph: no cycles, and the lower rooms never import the API.

Built with `ast` over every module of `sem_console`, without importing any of them: imports at module level and inside
functions count (both run), imports under `if TYPE_CHECKING:` do not (they never run).
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import sem_console

PACKAGE = Path(sem_console.__file__).parent
ROOT = "sem_console"
# The rooms allowed to import sem_console.api: the API itself and the top-level modules that assemble the console (main),
# start it (cli) and export its published schemas (schema_export).
API_USERS = ("sem_console.api", "sem_console.main", "sem_console.cli", "sem_console.schema_export")


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _runtime_imports(tree: ast.AST) -> Iterator[ast.Import | ast.ImportFrom]:
    """Every import statement that can run: all of them but those under `if TYPE_CHECKING:` (its else branch runs)."""
    if isinstance(tree, (ast.Import, ast.ImportFrom)):
        yield tree
        return
    if isinstance(tree, ast.If) and _is_type_checking(tree.test):
        children: list[ast.AST] = list(tree.orelse)
    else:
        children = list(ast.iter_child_nodes(tree))
    for child in children:
        yield from _runtime_imports(child)


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    """The absolute module an ImportFrom names (relative imports resolved against `module`)."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join([*base, node.module] if node.module else base)


def import_graph() -> dict[str, set[str]]:
    """module -> the sem_console modules it imports at run time."""
    modules = _modules()
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        targets: set[str] = set()
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in _runtime_imports(tree):
            if isinstance(node, ast.Import):
                targets.update(alias.name for alias in node.names)
                continue
            base = _resolve(name, path.name == "__init__.py", node)
            for alias in node.names:
                # `from pkg import mod` imports the submodule; `from mod import name` imports mod
                sub = f"{base}.{alias.name}"
                targets.add(sub if sub in modules else base)
        graph[name] = {t for t in targets if t in modules and t != name}
    return graph


def find_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), each as a sorted list."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return cycles


def _in(module: str, room: str) -> bool:
    return module == room or module.startswith(room + ".")


def test_graph_sees_the_package() -> None:
    graph = import_graph()
    # a sample of known edges: the walk finds module-level, function-level and `from pkg import module` imports
    assert "sem_console.core.config" in graph["sem_console.main"]
    assert "sem_console.main" in graph["sem_console.cli"]  # inside main(), at function level
    assert "sem_console.api.audit" in graph["sem_console.api.guard"]  # `from sem_console.api import audit`
    assert len(graph) > 50


def test_type_checking_imports_do_not_count() -> None:
    tree = ast.parse(
        "from typing import TYPE_CHECKING\n"
        "if TYPE_CHECKING:\n    import a\nelse:\n    import b\n"
        "def f():\n    import c\n"
    )
    names = {alias.name for node in _runtime_imports(tree) for alias in node.names}
    assert names == {"TYPE_CHECKING", "b", "c"}


def test_cycle_finder() -> None:
    assert find_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert find_cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycles() -> None:
    cycles = find_cycles(import_graph())
    assert cycles == [], "import cycles in sem_console (runtime imports):\n" + "\n".join(" <-> ".join(c) for c in cycles)


def room(module: str) -> str:
    """A module's room: its sub-package of sem_console (sem_console.console), or itself at the top (sem_console.main)."""
    return ".".join(module.split(".")[:2])


def test_no_cycles_between_rooms() -> None:
    """Data flows one way between rooms too: no room imports a room that imports it back, through any modules
    (sim and comap, console and api were such pairs)."""
    rooms: dict[str, set[str]] = {}
    for module, targets in import_graph().items():
        rooms.setdefault(room(module), set()).update(room(t) for t in targets if room(t) != room(module))
    cycles = find_cycles(rooms)
    assert cycles == [], "rooms that import each other:\n" + "\n".join(" <-> ".join(c) for c in cycles)


def test_lower_rooms_do_not_import_the_api() -> None:
    offenders = sorted(
        f"{module} imports {target}"
        for module, targets in import_graph().items()
        if not any(_in(module, room) for room in API_USERS)
        for target in targets
        if _in(target, "sem_console.api")
    )
    assert offenders == []


def test_the_codec_is_below_its_users() -> None:
    """The wire codec (codec/) is shared by the console, sem-check, the API and the benchmarks: it imports none of
    them, and sem-check reaches the decoder without importing the console."""
    users = ("sem_console.console", "sem_console.check", "sem_console.api", "sem_console.recording")
    graph = import_graph()
    offenders = sorted(
        f"{module} imports {target}"
        for module, targets in graph.items()
        if _in(module, "sem_console.codec")
        for target in targets
        if any(_in(target, user) for user in users)
    )
    offenders += sorted(
        f"{module} imports {target}"
        for module, targets in graph.items()
        if _in(module, "sem_console.check")
        for target in targets
        if _in(target, "sem_console.console")
    )
    assert offenders == []
    assert "sem_console.codec.decode" in graph["sem_console.check.observe"]
