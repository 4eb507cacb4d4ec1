"""Small helpers to build and read generated UMAA samples."""

from __future__ import annotations

import functools
import time
from dataclasses import fields
from typing import TYPE_CHECKING, Any, TypeVar

from UMAA.Common.Measurement import DateTime

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

T = TypeVar("T", bound="DataclassInstance")  # the generated structs are dataclasses


@functools.cache
def _members(cls: type[DataclassInstance]) -> tuple[str, ...]:
    return tuple(f.name for f in fields(cls))


def make(cls: type[T], **values: Any) -> T:
    """Construct a generated struct; members not given are None (for @optional members). A name that is not a member
    is a TypeError."""
    members = _members(cls)
    if len(values) == len(members):  # every member given (the simulator's reports, a thousand vehicles' a second)
        return cls(**values)
    unknown = values.keys() - set(members)
    if unknown:
        raise TypeError(f"{cls.__name__} has no member {', '.join(sorted(unknown))}")
    return cls(**{name: values.get(name) for name in members})


def now_datetime(t: float | None = None) -> DateTime:
    t = time.time() if t is None else t
    seconds = int(t)
    return DateTime(seconds=seconds, nanoseconds=min(int((t - seconds) * 1e9), 999_999_999))


def datetime_to_float(dt: DateTime) -> float:
    return dt.seconds + dt.nanoseconds / 1e9
