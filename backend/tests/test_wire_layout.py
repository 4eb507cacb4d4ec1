"""Pins every generated type to ../shared/spec/umaa-3.0.1-wire-layout.md, read from the file itself."""

from __future__ import annotations

import importlib
import os
import re
import typing
from pathlib import Path

import pytest
from cyclonedds.idl import IdlEnum, IdlStruct

from sem_console.dds.topics import Sem

NAME = "umaa-3.0.1-wire-layout.md"


def _find_spec() -> Path:
    """SEM_SPEC_DIR, else shared/spec beside the repository clone (../shared/spec from the repo root)."""
    if os.environ.get("SEM_SPEC_DIR"):
        return Path(os.environ["SEM_SPEC_DIR"]) / NAME
    for parent in Path(__file__).resolve().parents:
        if (parent / "shared" / "spec" / NAME).exists():
            return parent / "shared" / "spec" / NAME
    raise FileNotFoundError(f"{NAME} not found: put shared/ beside the repository or set SEM_SPEC_DIR")


SPEC = _find_spec()
TEXT = SPEC.read_text()
MEMBER = re.compile(r"^(?P<type>.+?) (?P<name>\w+)(?: \((?P<flag>[ko])\))?$")


def render(hint: typing.Any) -> tuple[str, bool]:
    """An IDL-like spelling of a generated member type, in the wire-layout file's notation, and whether it is optional."""
    optional = False
    if typing.get_origin(hint) is typing.Union:
        (hint,) = [a for a in typing.get_args(hint) if a is not type(None)]
        optional = True
    if typing.get_origin(hint) is typing.Annotated:
        base, meta = typing.get_args(hint)[0], typing.get_args(hint)[1]
        text = str(meta)
        if "NumericGUID" in text:
            return "G", optional
        simple = {"float64": "double", "int32": "long", "int64": "long long"}
        if text in simple:
            return simple[text], optional
        if text.startswith("bounded_str["):
            return f"string<{text[12:-1]}>", optional
        if text.startswith("sequence["):
            inner = typing.get_args(base)[0]
            elem = render(inner)[0]
            bound = text[:-1].split(", ")[-1] if ", " in text else None
            return (f"sequence<{elem},{bound}>" if bound else f"sequence<{elem}>"), optional
        raise AssertionError(f"unexpected annotation {text}")
    if hint is bool:
        return "boolean", optional
    if isinstance(hint, type) and issubclass(hint, (IdlStruct, IdlEnum)):
        return ("DT" if hint.__name__ == "DateTime" else hint.__name__), optional
    raise AssertionError(f"unexpected member type {hint!r}")


def layout(cls: type) -> list[tuple[str, str, str | None]]:
    """(type, name, 'k' | 'o' | None) per member, in the generated order."""
    hints = typing.get_type_hints(cls, include_extras=True)
    keys = {n for n, a in getattr(cls, "__idl_field_annotations__", {}).items() if a.get("key")}
    out = []
    for name in cls.__annotations__:
        t, optional = render(hints[name])
        out.append((t, name, "k" if name in keys else "o" if optional else None))
    return out


def parse_members(text: str, default_flag: str | None = None) -> list[tuple[str, str, str | None]]:
    out = []
    for part in text.strip().rstrip(".").split("; "):
        part = re.sub(r"\s*\(0\.\.999999999\)|\s*\(unbounded\)|\s*\(sic:.*?\)", "", part.replace("`", "").strip())
        part = part.replace("@optional ", "(o)")
        flag = default_flag
        if part.startswith("(o)"):
            part, flag = part[3:], "o"
        m = MEMBER.match(part)
        assert m, f"cannot read member {part!r}"
        out.append((m["type"].replace(" ", "") if m["type"].startswith("sequence") else m["type"], m["name"], m["flag"] or flag))
    return out


def gen_class(qualified: str) -> type:
    module, _, name = qualified.replace("::", ".").rpartition(".")
    return getattr(importlib.import_module(module), name)


def topic_rows() -> list[tuple[str, str, str]]:
    rows = re.findall(r"^\| `(UMAA::SEM::[\w:]+)` \((?:topic )?`…::(\w+)`\) \| (.+) \|$", TEXT, re.M)
    assert len(rows) == 10, "the wire-layout file lists ten topic types"
    return rows


@pytest.mark.parametrize("qualified,topic,members", topic_rows(), ids=lambda v: v if "::" in str(v) else None)
def test_topic_type_members_keys_and_names(qualified: str, topic: str, members: str) -> None:
    cls = gen_class(qualified)
    assert cls.__idl_typename__.replace(".", "::") == qualified
    if members.startswith("same members as "):
        members = dict((q.split("::")[-1], m) for q, _t, m in topic_rows())[members.split()[-1]]
    assert layout(cls) == parse_members(members)
    namespace = qualified.rsplit("::", 1)[0]
    specs = [s.spec for s in Sem if s.spec.type is cls]
    assert [s.name for s in specs] == [f"{namespace}::{topic}"]


@pytest.mark.parametrize("name", ["GPSSatelliteType", "GPSClockType"])
def test_nested_types_all_optional(name: str) -> None:
    text = re.search(rf"^- `{name}`: (.+?)(?=\n- |\n\n)", TEXT, re.M | re.S)[1].replace("\n", " ")  # type: ignore[index]
    text = re.sub(r"\s+", " ", text)
    cls = gen_class(f"UMAA::SEM::GPSStatus::{name}")
    assert cls.__idl_typename__ == f"UMAA.SEM.GPSStatus.{name}"
    assert layout(cls) == parse_members(text, default_flag="o")


def test_enums_literal_order_and_type_names() -> None:
    rows = re.findall(r"^\| (\w+EnumType) \| ([A-Z_0-9, ]+) \|$", TEXT, re.M)
    assert len(rows) == 7
    for name, literals in rows:
        cls = gen_class(f"UMAA::Common::MaritimeEnumeration::{name}::{name}")
        assert cls.__idl_typename__.replace(".", "::") == f"UMAA::Common::MaritimeEnumeration::{name}::{name}"
        assert [e.name for e in cls] == [x.strip() for x in literals.split(",")]
        assert [e.value for e in cls] == list(range(len(cls)))


def test_common_types() -> None:
    rows = re.findall(r"^\| (\w+) \| struct \{ (.+) \}.*\|$", TEXT, re.M)
    assert len(rows) == 9
    for name, members in rows:
        cls = gen_class(f"UMAA::Common::Measurement::{name}")
        assert cls.__idl_typename__ == f"UMAA.Common.Measurement.{name}"
        assert layout(cls) == parse_members(members)
    guid = typing.get_type_hints(gen_class("UMAA::SEM::GPSFixControl::GPSFixCommandType"), include_extras=True)["source"]
    assert str(typing.get_args(guid)[1]) == "typedef[UMAA.Common.Measurement.NumericGUID, array[byte, 16]]"


def test_no_extensibility_annotation_in_idl() -> None:
    idl = Path(__file__).resolve().parents[2] / "idl"
    for f in idl.rglob("*.idl"):
        assert not re.search(r"@(final|appendable|mutable|extensibility)", f.read_text()), f
