"""JSON Schema of the JSON form of UMAA samples, derived from the generated IDL types.

So that the dashboard's report types come from the IDL too, and never from a second,
hand-written copy: enums are their literal names, GUIDs UUID strings, every member may
be null (an optional that is absent, or a value flagged invalid, see convert.py).
"""

from __future__ import annotations

import typing
from enum import Enum
from typing import Any

from cyclonedds.idl import IdlStruct

from sem_console.codec.convert import GUID_MEMBERS
from sem_console.versions import umaa_6_0


def _schema(hint: Any, name: str, defs: dict[str, Any]) -> dict[str, Any]:
    if typing.get_origin(hint) is typing.Union:
        (hint,) = [a for a in typing.get_args(hint) if a is not type(None)]
    if typing.get_origin(hint) is typing.Annotated:
        base, meta = typing.get_args(hint)[0], str(typing.get_args(hint)[1])
        if name in GUID_MEMBERS or "NumericGUID" in meta:
            return {"type": "string", "format": "uuid"}
        if meta.startswith("sequence["):
            return {"type": "array", "items": _schema(typing.get_args(base)[0], "", defs)}
        if meta.startswith("bounded_str["):
            return {"type": "string"}
        if meta in ("float32", "float64"):
            return {"type": "number"}
        return {"type": "integer"}
    if hint is bool:
        return {"type": "boolean"}
    if hint is str:
        return {"type": "string"}
    if isinstance(hint, type) and issubclass(hint, Enum):
        defs.setdefault(hint.__name__, {"type": "string", "enum": [e.name for e in hint]})
        return {"$ref": f"#/$defs/{hint.__name__}"}
    if isinstance(hint, type) and issubclass(hint, IdlStruct):
        struct_schema(hint, defs)
        return {"$ref": f"#/$defs/{hint.__name__}"}
    raise TypeError(f"no JSON schema for {hint!r}")


def struct_schema(cls: type[IdlStruct], defs: dict[str, Any]) -> None:
    if cls.__name__ in defs:
        return
    defs[cls.__name__] = {}  # placeholder against recursion
    hints = typing.get_type_hints(cls, include_extras=True)
    props = {n: {"anyOf": [_schema(h, n, defs), {"type": "null"}]} for n, h in hints.items()}
    defs[cls.__name__] = {
        "type": "object",
        "title": cls.__name__,
        "description": f"JSON form of {cls.__idl_typename__.replace('.', '::')}",
        "properties": props,
        "required": list(hints),
        "additionalProperties": False,
    }


def report_schemas() -> dict[str, Any]:
    """$defs for the four report types of the console's model (and everything they use), keyed by IDL type name: the
    UMAA 3.0.1 types, with the members and literals UMAA 6.0 adds to the model (`versions/umaa_6_0.py`), a member
    optional (absent from a 3.0.1 vehicle's report)."""
    from sem_console.codec.decode import REPORT_TOPICS

    defs: dict[str, Any] = {}
    for sem in REPORT_TOPICS:
        struct_schema(sem.spec.type, defs)
    for struct, members in umaa_6_0.MODEL_MEMBERS.items():
        defs[struct]["properties"].update({n: {"anyOf": [_schema(h, n, defs), {"type": "null"}]} for n, h in members.items()})
        defs[struct]["description"] += " (and the members UMAA 6.0 adds, absent from a UMAA 3.0.1 vehicle's report)"
    for enum, added in umaa_6_0.MODEL_LITERALS.items():
        literals = defs[enum]["enum"]
        literals.extend(e.name for e in added if e.name not in literals)
    return defs
