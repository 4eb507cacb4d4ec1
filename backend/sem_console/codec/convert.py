"""Generated UMAA samples -> JSON that mirrors the IDL member for member.

ICD attribute names, nested structs kept, enums as literal names, absent optionals as
null, NumericGUID as a canonical UUID string. Values a sensor cannot mean (NaN,
latitude 200, 10,000 satellites, an unknown enum ordinal) become null or stay as sent
and are listed in `invalid` as "path: why", so a display can flag them.
"""

from __future__ import annotations

import math
import typing
import uuid
from dataclasses import fields, is_dataclass
from enum import Enum
from functools import cache
from typing import Any

MAX_SATELLITES = 256  # the elements kept of an unbounded sequence (UMAA 3.0.1's satellites); a bounded one keeps its bound

# member name -> (min, max) for values whose range the ICD fixes
RANGES: dict[str, tuple[float, float]] = {
    "latitude": (-90.0, 90.0),
    "longitude": (-180.0, 180.0),
    "geodeticLatitude": (-90.0, 90.0),  # UMAA 6.0's GeoPosition2D
    "geodeticLongitude": (-180.0, 180.0),
    "azimuth": (-math.pi, 2 * math.pi),  # Angle is -pi..pi; some receivers send 0..2pi
    "elevation": (-math.pi / 2, math.pi / 2),
    "trueCourse": (0.0, 2 * math.pi),
    "course": (-2 * math.pi, 2 * math.pi),  # UMAA 6.0's GlobalPoseReportType: CourseTrueNorth (SA ICD 6.0)
    "magneticVariation": (-math.pi, math.pi),
    "SOG": (0.0, 200.0),
    "antennaCarrierNoiseDensity": (0.0, 1_000_000.0),
    "basebandCarrierNoiseDensity": (0.0, 1_000_000.0),
    "nanoseconds": (0, 999_999_999),
    "altitude": (-10_000.0, 700_000.0),
    "downSpeed": (-10_000.0, 10_000.0),
    "eastSpeed": (-10_000.0, 10_000.0),
    "northSpeed": (-10_000.0, 10_000.0),
}
GUID_MEMBERS = {"source", "destination", "sessionID", "satelliteId", "id", "parentID"}  # id, parentID: UMAA 6.0's IdentifierType


def to_json(sample: Any) -> tuple[dict[str, Any], list[str]]:
    invalid: list[str] = []
    return _value(sample, "", invalid), invalid


@cache
def bounds(cls: type) -> dict[str, int]:
    """The bound of each bounded sequence member of a generated struct (UMAA 6.0's satellites: 300)."""
    out = {}
    for name, hint in typing.get_type_hints(cls, include_extras=True).items():
        for a in typing.get_args(hint):
            if isinstance(getattr(a, "max_length", None), int):
                out[name] = a.max_length
    return out


@cache
def _enum_members(cls: type) -> dict[str, type]:
    """Members of a generated struct whose declared type is an enum."""
    out = {}
    for name, hint in typing.get_type_hints(cls, include_extras=True).items():
        args = typing.get_args(hint) if typing.get_origin(hint) is typing.Union else (hint,)
        for a in args:
            if isinstance(a, type) and issubclass(a, Enum):
                out[name] = a
    return out


def _value(v: Any, path: str, invalid: list[str], name: str | None = None, limit: int = MAX_SATELLITES) -> Any:
    """`v` as JSON, an invalid value listed by `path`; its range is its member's, `name` (the wire type's member, which
    a version's model may name otherwise in `path`), else the last member of `path`; a sequence keeps `limit` elements
    (its member's bound, or MAX_SATELLITES)."""
    name = name or path.rsplit(".", 1)[-1].split("[")[0]
    if v is None:
        return None
    if isinstance(v, Enum):
        return v.name
    if is_dataclass(v) and not isinstance(v, type):  # a sample (not a class)
        enums, bound = _enum_members(type(v)), bounds(type(v))
        out: dict[str, Any] = {}
        for f in fields(v):
            member, sub = getattr(v, f.name), f"{path}.{f.name}" if path else f.name
            if f.name in enums and member is not None and not isinstance(member, Enum):
                invalid.append(unknown_ordinal(enums[f.name], member, sub))
                out[f.name] = None
            else:
                out[f.name] = _value(member, sub, invalid, None, bound.get(f.name, MAX_SATELLITES))
        return out
    if name in GUID_MEMBERS and isinstance(v, (bytes, bytearray, list, tuple)):
        raw = bytes(v)
        if len(raw) != 16:
            invalid.append(f"{path}: GUID of {len(raw)} bytes")
            return None
        return str(uuid.UUID(bytes=raw))
    if isinstance(v, bool):
        return v
    if isinstance(v, float):
        if not math.isfinite(v):
            invalid.append(f"{path}: {v} is not a number")
            return None
        _check_range(name, v, path, invalid)
        return v
    if isinstance(v, int):
        if name in RANGES:
            _check_range(name, v, path, invalid)
        return v
    if isinstance(v, str):
        return v
    if isinstance(v, (list, tuple)):
        if len(v) > limit:
            invalid.append(too_many(len(v), path, limit))
            v = v[:limit]
        return [_value(x, f"{path}[{i}]", invalid) for i, x in enumerate(v)]
    invalid.append(f"{path}: unreadable value {type(v).__name__}")
    return None


def unknown_ordinal(enum: type, value: Any, path: str) -> str:
    return f"{path}: unknown {enum.__name__} ordinal {value!r}"


def too_many(n: int, path: str, limit: int = MAX_SATELLITES) -> str:
    return f"{path}: {n} elements, more than {limit}; the first {limit} kept"


def _check_range(name: str, v: float, path: str, invalid: list[str]) -> None:
    lo_hi = RANGES.get(name)
    if lo_hi and not lo_hi[0] <= v <= lo_hi[1]:
        invalid.append(f"{path}: {v} outside {lo_hi[0]:g}..{lo_hi[1]:g}")
