"""Pins every generated type to the project's wire-layout table, tests/data/umaa-3.0.1-wire-layout.toml:
type names, member names, order and types, keys, optionals, bounds, enum literals and topic names."""

from __future__ import annotations

import importlib
import re
import tomllib
import typing
from pathlib import Path

import pytest
from cyclonedds.idl import IdlEnum, IdlStruct

from sem_console.dds.topics import Sem

LAYOUT = tomllib.loads((Path(__file__).parent / "data" / "umaa-3.0.1-wire-layout.toml").read_text())
STRUCTS = {s["name"]: s for s in LAYOUT["struct"]}
FLAGS = {"key": "k", "optional": "o", "": None}


def render(hint: typing.Any) -> tuple[str, bool]:
    """An IDL-like spelling of a generated member type, in the wire-layout table's notation, and whether it is optional."""
    optional = False
    if typing.get_origin(hint) is typing.Union:
        (hint,) = [a for a in typing.get_args(hint) if a is not type(None)]
        optional = True
    if typing.get_origin(hint) is typing.Annotated:
        base, meta = typing.get_args(hint)[0], typing.get_args(hint)[1]
        text = str(meta)
        if "NumericGUID" in text:
            return "NumericGUID", optional
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
        return hint.__name__, optional
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


def members(struct: str) -> list[tuple[str, str, str | None]]:
    """(type, name, 'k' | 'o' | None) per member of a struct, as the table has them."""
    return [(m["type"], m["name"], FLAGS[m.get("flag", "")]) for m in STRUCTS[struct]["members"]]


def gen_class(qualified: str) -> type:
    module, _, name = qualified.replace("::", ".").rpartition(".")
    return getattr(importlib.import_module(module), name)


TOPIC_TYPES = [name for name, s in STRUCTS.items() if "topic" in s]


def test_the_table_lists_every_sem_topic() -> None:
    assert len(TOPIC_TYPES) == len(Sem) == 10
    assert {STRUCTS[t]["topic"] for t in TOPIC_TYPES} == {s.spec.name for s in Sem}


@pytest.mark.parametrize("qualified", TOPIC_TYPES)
def test_topic_type_members_keys_and_names(qualified: str) -> None:
    cls = gen_class(qualified)
    assert cls.__idl_typename__.replace(".", "::") == qualified
    assert layout(cls) == members(qualified)
    specs = [s.spec for s in Sem if s.spec.type is cls]
    assert [s.name for s in specs] == [STRUCTS[qualified]["topic"]]


@pytest.mark.parametrize("name", ["GPSSatelliteType", "GPSClockType"])
def test_nested_types_all_optional(name: str) -> None:
    qualified = f"UMAA::SEM::GPSStatus::{name}"
    cls = gen_class(qualified)
    assert cls.__idl_typename__ == f"UMAA.SEM.GPSStatus.{name}"
    assert layout(cls) == members(qualified)
    assert {flag for _t, _n, flag in members(qualified)} == {"o"}


def test_enums_literal_order_and_type_names() -> None:
    assert len(LAYOUT["enums"]) == 7
    for name, literals in LAYOUT["enums"].items():
        cls = gen_class(f"UMAA::Common::MaritimeEnumeration::{name}::{name}")
        assert cls.__idl_typename__.replace(".", "::") == f"UMAA::Common::MaritimeEnumeration::{name}::{name}"
        assert [e.name for e in cls] == literals
        assert [e.value for e in cls] == list(range(len(cls)))


def test_common_types() -> None:
    common = [n for n in STRUCTS if n.startswith("UMAA::Common::Measurement::")]
    assert len(common) == 9
    for name in common:
        cls = gen_class(name)
        assert cls.__idl_typename__ == name.replace("::", ".")
        assert layout(cls) == members(name)
    assert LAYOUT["typedefs"]["NumericGUID"] == "octet[16]"
    guid = typing.get_type_hints(gen_class("UMAA::SEM::GPSFixControl::GPSFixCommandType"), include_extras=True)["source"]
    assert str(typing.get_args(guid)[1]) == "typedef[UMAA.Common.Measurement.NumericGUID, array[byte, 16]]"


def test_no_extensibility_annotation_in_idl() -> None:
    idl = Path(__file__).resolve().parents[2] / "idl"
    for f in idl.rglob("*.idl"):
        assert not re.search(r"@(final|appendable|mutable|extensibility)", f.read_text()), f
