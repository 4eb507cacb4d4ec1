"""Random samples of the generated UMAA types, for decoder and interoperability tests.

Every member gets a random value within its IDL type (bounds kept), and each @optional member is
present or absent at random, so a few hundred samples cover the layouts a decoder must handle.
"""

from __future__ import annotations

import enum
import random
import typing
from dataclasses import fields, is_dataclass
from typing import Any

from cyclonedds.idl import IdlEnum, IdlStruct
from cyclonedds.idl.types import ValidUnionHolder  # noqa: F401  (keeps cyclonedds.idl.types loaded)


def _meta(hint: Any) -> tuple[Any, str | None, bool]:
    """(base type, annotation text, optional) of a member's type hint."""
    optional = False
    if typing.get_origin(hint) is typing.Union:
        (hint,) = [a for a in typing.get_args(hint) if a is not type(None)]
        optional = True
    if typing.get_origin(hint) is typing.Annotated:
        args = typing.get_args(hint)
        return args[0], str(args[1]), optional
    return hint, None, optional


def random_value(hint: Any, rng: random.Random, depth: int = 0, absent: float = 0.4) -> Any:
    base, meta, _ = _meta(hint)
    if meta is not None:
        if "NumericGUID" in meta or meta.startswith("array["):
            return bytes(rng.randrange(256) for _ in range(16))
        if meta == "float64":
            return rng.choice([0.0, -1.5, rng.uniform(-1e6, 1e6), rng.uniform(-1, 1)])
        if meta == "int32":
            return rng.randrange(-(2**31), 2**31)
        if meta == "int64":  # within +-2**53: RTI's Connector carries integers through JSON doubles
            return rng.randrange(-(2**53), 2**53)
        if meta.startswith("bounded_str["):
            bound = int(meta[12:-1])
            return "".join(rng.choice("abcXYZ -_é") for _ in range(rng.randrange(0, min(bound, 40))))
        if meta.startswith("sequence["):
            inner = typing.get_args(base)[0]
            bound = int(meta[:-1].split(", ")[-1]) if ", " in meta else 6
            return [random_value(inner, rng, depth + 1, absent) for _ in range(rng.randrange(0, bound + 1))]
        raise AssertionError(f"unexpected annotation {meta}")
    if base is bool:
        return rng.random() < 0.5
    if isinstance(base, type) and issubclass(base, IdlEnum):
        return rng.choice(list(base))
    if isinstance(base, type) and issubclass(base, IdlStruct):
        return random_sample(base, rng, depth + 1, absent)
    raise AssertionError(f"unexpected member type {hint!r}")


def random_sample(cls: type, rng: random.Random, depth: int = 0, absent: float = 0.4) -> Any:
    """`absent`: the chance that each @optional member is left out."""
    hints = typing.get_type_hints(cls, include_extras=True)
    values = {}
    for f in fields(cls):
        _, _, optional = _meta(hints[f.name])
        values[f.name] = None if optional and rng.random() < absent else random_value(hints[f.name], rng, depth, absent)
    return cls(**values)


def to_plain(value: Any) -> Any:
    """A sample as plain dicts and lists (enums as ordinals, absent optionals left out), the form
    RTI's Connector reads and writes."""
    if is_dataclass(value):
        return {f.name: to_plain(getattr(value, f.name)) for f in fields(value) if getattr(value, f.name) is not None}
    if isinstance(value, enum.Enum):
        return list(type(value)).index(value)
    if isinstance(value, (bytes, bytearray)):
        return list(value)
    if isinstance(value, (list, tuple)):
        return [to_plain(v) for v in value]
    return value
