"""The schemas of a recording's channels.

A SEM topic's schema is OMG IDL (MCAP schema encoding `omgidl`): the text of the topic type's
file in its UMAA version's IDL (`idl/` for 3.0.1, `idl/umaa-6.0/` for 6.0) and of every file it includes,
in dependency order (an included file before
the file that includes it, each once), with the preprocessor lines (`#include`, the include
guards) left out, so the text stands alone. The files' modules are merged: each module is
opened once and holds the declarations of every file in it, in that order (plain
concatenation reopens `module UMAA` once per file, which is valid IDL too, but Cyclone's idlc
Python backend crashes on a reopened module that adds a submodule). Each struct is marked
`@final`: that is how the console's types are built (`idlgen` runs idlc with `-x final`) and
so how their CDR is laid out on the wire; a channel of samples an appendable writer sent (an RTI
vehicle's GPSReport and GPSFixReport, delimited XCDR2) has the same IDL with each struct
`@appendable` (`idl_text(name, extensibility="appendable")`), which is how those samples are laid
out. UMAA's enums stay in modules of their own name, which is valid OMG IDL.

`idl/` is part of the installed package: `sem_console/recording/idl` links to it in the
repository, and the package data takes the files into a wheel (the console's image copies it).
"""

from __future__ import annotations

import functools
import re
from pathlib import Path
from typing import Literal

from cyclonedds.idl import IdlStruct

from sem_console.dds.topics import AnySem, Sem60
from sem_console.versions import UMAA_3_0_1, UMAA_6_0, UmaaVersion

IDL_DIR = Path(__file__).resolve().parent / "idl"
# Each UMAA version's IDL: 3.0.1 in idl/ itself, 6.0 in its own folder (the layout `idlgen` generates the types from)
IDL_DIRS: dict[UmaaVersion, Path] = {UMAA_3_0_1: IDL_DIR, UMAA_6_0: IDL_DIR / "umaa-6.0"}
SCHEMA_ENCODING = "omgidl"
MESSAGE_ENCODING = "cdr"
_INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]([^">]+)[">]', re.MULTILINE)
_STRUCT = re.compile(r"^(\s*)struct\s", re.MULTILINE)


def type_name(dtype: type[IdlStruct]) -> str:
    """The fully qualified UMAA type name of a generated type, e.g. UMAA::SEM::GPSStatus::GPSReportType."""
    return dtype.__idl_typename__.replace(".", "::")


def version_of(sem: AnySem) -> UmaaVersion:
    """The UMAA version of a SEM topic: its table (`dds/topics.py`)."""
    return UMAA_6_0 if isinstance(sem, Sem60) else UMAA_3_0_1


def topic_idl(sem: AnySem, extensibility: Literal["final", "appendable"] = "final") -> str:
    """The schema text of a SEM topic's channel: its type's IDL from its version's folder."""
    return idl_text(type_name(sem.spec.type), IDL_DIRS[version_of(sem)], extensibility)


def _file_of(name: str) -> str:
    return name.replace("::", "/") + ".idl"


def _files_in_order(root: str, idl_dir: Path) -> list[str]:
    """`root` and every file it includes, each after the files it includes (depth first)."""
    order: list[str] = []

    def visit(rel: str, stack: tuple[str, ...]) -> None:
        if rel in order:
            return
        if rel in stack:
            raise ValueError(f"include cycle: {' -> '.join((*stack, rel))}")
        path = idl_dir / rel
        if not path.is_file():
            raise FileNotFoundError(f"IDL file {rel} not found under {idl_dir}")
        for inc in _INCLUDE.findall(path.read_text()):
            visit(inc, (*stack, rel))
        order.append(rel)

    visit(root, ())
    return order


def _standalone(text: str, extensibility: str) -> str:
    lines = [ln for ln in text.splitlines() if not ln.lstrip().startswith("#")]
    return _STRUCT.sub(lambda m: f"{m.group(1)}@{extensibility}\n{m.group(1)}struct ", "\n".join(lines))


_MODULE = re.compile(r"module\s+(\w+)\s*\{")
_CLOSE = re.compile(r"\s*;")


class _Module:
    def __init__(self) -> None:
        self.items: list[str | tuple[str, _Module]] = []  # declarations (text) and submodules, in order
        self.children: dict[str, _Module] = {}

    def child(self, name: str) -> _Module:
        if name not in self.children:
            self.children[name] = _Module()
            self.items.append((name, self.children[name]))
        return self.children[name]

    def render(self, depth: int = 0) -> str:
        out = []
        for item in self.items:
            if isinstance(item, str):
                out.append(item)
            else:
                out.append(f"module {item[0]} {{\n{item[1].render(depth + 1)}}};\n")
        return "".join(out)


def _merge(text: str, into: _Module, note: str) -> str:
    """Add the declarations of `text` to the module tree `into`; the comment `note` goes before the
    first declaration. Returns the note when it was not used (no declaration at this level)."""
    pos, buf = 0, []
    while pos < len(text):
        if text.startswith("//", pos):
            end = text.find("\n", pos)
            end = len(text) if end < 0 else end + 1
            buf.append(text[pos:end])
            pos = end
            continue
        m = _MODULE.match(text, pos)
        if m is None or (pos > 0 and (text[pos - 1].isalnum() or text[pos - 1] == "_")):
            buf.append(text[pos])
            pos += 1
            continue
        note = _flush(buf, into, note)
        depth, i = 1, m.end()
        while depth:  # the module's closing brace (IDL declarations nest braces, comments hold none here)
            if i >= len(text):
                raise ValueError("unbalanced braces in IDL")
            depth += {"{": 1, "}": -1}.get(text[i], 0)
            i += 1
        note = _merge(text[m.end() : i - 1], into.child(m.group(1)), note)
        close = _CLOSE.match(text, i)
        pos = close.end() if close else i
    return _flush(buf, into, note)


def _flush(buf: list[str], into: _Module, note: str) -> str:
    chunk = "".join(buf).strip("\n")
    buf.clear()
    if not chunk.strip():
        return note
    if chunk.lstrip().startswith("//") and "\n" not in chunk.strip():  # a lone comment: keep it with the note
        return f"{note}{chunk.strip()}\n"
    into.items.append(f"{note}{chunk}\n")
    return ""


@functools.cache
def idl_text(name: str, idl_dir: Path = IDL_DIR, extensibility: Literal["final", "appendable"] = "final") -> str:
    """The self-contained IDL of the type `name` (fully qualified), as a recording's schema holds it, every struct
    of the given extensibility."""
    root = _Module()
    for rel in _files_in_order(_file_of(name), idl_dir):
        _merge(_standalone((idl_dir / rel).read_text(), extensibility), root, f"// {rel}\n")
    return root.render()
