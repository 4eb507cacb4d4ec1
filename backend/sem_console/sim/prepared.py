"""A report written from prepared bytes: cyclonedds serialises a sample member by member in Python (about a
millisecond for a 32-satellite GPSReport), which at a thousand vehicles was most of `sem-sim`'s CPU.

A `Layout` is one type's serialised form for one shape: the lengths of its sequences and strings, which @optional
members are present, and its strings. cyclonedds serialises a sample of that shape once; every value member (a number,
an enumeration, a boolean, a GUID) is then found in those bytes by serialising it twice with two probe values and
seeing which bytes change. A sample of the same shape is then its values packed by one `struct.Struct` between the
constant bytes (headers, lengths, presence flags, padding), the same bytes cyclonedds would write
(tests/unit/test_prepared.py pins them on random samples of every report type of both UMAA versions). The shape is
checked by generated code before every use: a sample of another shape gets a layout of its own (a few per type:
the vehicles of a simulator share them), and one no layout can hold (a member no layout reads) is serialised by
cyclonedds as before.
"""

from __future__ import annotations

import copy
import struct
import time
from collections.abc import Callable
from typing import Any

from cyclonedds.core import DDSException
from cyclonedds.pub import DataWriter

from sem_console.dds.cyclone_private import enum_type, type_machine, write_cdr, write_flush, writer_version_2
from sem_console.dds.cyclone_private import machinery as mc

LAYOUTS_MAX = 16  # per writer: the shapes its samples come in (GPSFixStatusReport: 0..11 carrier-to-noise values)


class Unsupported(Exception):
    """A member the layout cannot write; the sample is serialised by cyclonedds."""


class _Leaf:
    """One value member: the expression reading it from the sample, its struct code, and its two probe values."""

    def __init__(self, expr: str, code: str, probes: tuple[Any, Any], setter: Callable[[Any, Any], None], value: Any) -> None:
        self.expr, self.code, self.probes, self.set, self.value = expr, code, probes, setter, value
        self.offset = -1


def _number_probes(code: str) -> tuple[Any, Any]:
    """Two values of a struct code whose packed bytes differ in every byte."""
    size = struct.calcsize(code)
    return struct.unpack(code, b"\x11" * size)[0], struct.unpack(code, b"\x22" * size)[0]


def _setter(parent: Callable[[Any], Any], name: str | int) -> Callable[[Any, Any], None]:
    if isinstance(name, int):
        return lambda s, v: parent(s).__setitem__(name, v)
    return lambda s, v: setattr(parent(s), name, v)


def _getter(parent: Callable[[Any], Any], name: str | int) -> Callable[[Any], Any]:
    if isinstance(name, int):
        return lambda s: parent(s)[name]
    return lambda s: getattr(parent(s), name)


class _Walk:
    """The members of one sample, through its type's machine tree: value members and the shape's guards."""

    def __init__(self) -> None:
        self.leaves: list[_Leaf] = []
        self.guards: list[str] = []
        self.consts: dict[str, Any] = {}
        self.binds: list[str] = []  # a struct's or a sequence's local name, read once: `a3 = a1.satellites`

    def bind(self, expr: str) -> str:
        """A local name for `expr`, read once before the guards (a sample of another shape raises there, as a guard)."""
        if expr.isidentifier():
            return expr
        name = f"a{len(self.binds)}"
        self.binds.append(f"{name} = {expr}")
        return name

    def const(self, value: Any) -> str:
        name = f"K{len(self.consts)}"
        self.consts[name] = value
        return name

    def member(self, m: Any, expr: str, value: Any, get: Callable[[Any], Any], name: str | int) -> None:
        here = _getter(get, name)
        path = f"{expr}[{name}]" if isinstance(name, int) else f"{expr}.{name}"
        self.walk(m, path, value, here, _setter(get, name))

    def walk(self, m: Any, expr: str, value: Any, get: Callable[[Any], Any], put: Callable[[Any, Any], None]) -> None:
        if isinstance(m, mc.InstanceMachine):
            m = type_machine(m.type, m.use_version_2)
        if isinstance(m, mc.OptionalMachine):
            self.guards.append(f"{expr} is None" if value is None else f"{expr} is not None")
            if value is not None:
                self.walk(m.submachine, expr, value, get, put)
        elif isinstance(m, mc.StructMachine):
            if not hasattr(value, "__dataclass_fields__"):
                raise Unsupported(f"{expr}: not a struct")
            expr = self.bind(expr)
            for name, sub in m.members_machines.items():
                self.member(sub, expr, getattr(value, name), get, name)
        elif isinstance(m, mc.PrimitiveMachine):
            if m.code == "?":
                self.guards.append(f"{expr}.__class__ is bool")  # '?' would pack any object by its truth
                self.leaves.append(_Leaf(expr, "?", (False, True), put, value))
            else:
                self.leaves.append(_Leaf(expr, m.code, _number_probes(m.code), put, value))
        elif isinstance(m, (mc.EnumMachine, mc.BitBoundEnumMachine)):
            members = list(enum_type(m))
            if len(members) < 2:
                raise Unsupported(f"{expr}: an enumeration of one literal")
            code = m.code if isinstance(m, mc.BitBoundEnumMachine) else "I"
            self.guards.append(f"{expr}.__class__ is {self.const(type(members[0]))}")  # so its _value_ is its number
            self.leaves.append(_Leaf(f"{expr}._value_", code, (members[0], members[1]), put, value))
        elif isinstance(m, mc.ByteArrayMachine):
            self.guards.append(f"len({expr}) == {m.size}")
            self.leaves.append(_Leaf(f"bytes({expr})", f"{m.size}s", (b"\x11" * m.size, b"\x22" * m.size), put, value))
        elif isinstance(m, mc.StringMachine):
            self.guards.append(f"{expr} == {self.const(value)}")
        elif isinstance(m, (mc.SequenceMachine, mc.PlainCdrV2SequenceOfPrimitiveMachine)):
            expr = self.bind(expr)
            self.guards.append(f"len({expr}) == {len(value)}")
            for i, item in enumerate(value):
                if isinstance(m, mc.SequenceMachine):
                    self.member(m.submachine, expr, item, get, i)
                else:
                    self.leaves.append(_Leaf(f"{expr}[{i}]", m.code, _number_probes(m.code), _setter(get, i), item))
        else:
            raise Unsupported(f"{expr}: {type(m).__name__}")


class Layout:
    """One shape of one type, prepared from a sample of it (the module's docstring)."""

    def __init__(self, sample: Any, version_2: bool | None) -> None:
        template = _serialise(sample, version_2)
        v2 = template[1] >= 6  # the encapsulation identifier: 0..3 XCDR1, 6.. XCDR2
        little = bool(template[1] & 1)
        endian = "<" if little else ">"
        w = _Walk()
        w.walk(type_machine(type(sample), v2), "s", sample, lambda s: s, lambda s, v: None)
        # where each value member lies: every one set to its first probe, then to its second, and the bytes that
        # changed, member after member in the order cyclonedds writes them (the walk's)
        probe = copy.deepcopy(sample)
        serialised = []
        for k in (0, 1):
            for leaf in w.leaves:
                leaf.set(probe, leaf.probes[k])
            serialised.append(_serialise(probe, version_2))
        ba, bb = serialised
        if len(ba) != len(template) or len(bb) != len(template):
            raise Unsupported("the probes change the sample's length")
        changed = [i for i in range(len(ba)) if ba[i] != bb[i]]
        at = 0
        for leaf in w.leaves:
            pa = struct.pack(endian + leaf.code, _raw(leaf.probes[0]))
            pb = struct.pack(endian + leaf.code, _raw(leaf.probes[1]))
            if at >= len(changed):
                raise Unsupported(f"{leaf.expr}: not found in the serialised sample")
            leaf.offset = changed[at] - next(i for i in range(len(pa)) if pa[i] != pb[i])
            while at < len(changed) and changed[at] < leaf.offset + len(pa):
                at += 1
        fmt, gaps, at = [endian], [], 0
        for leaf in w.leaves:
            if leaf.offset < at:
                raise Unsupported(f"{leaf.expr}: overlaps the member before it")
            fmt += [f"{leaf.offset - at}s", leaf.code]
            gaps.append(template[at : leaf.offset])
            at = leaf.offset + struct.calcsize(endian + leaf.code)
        fmt.append(f"{len(template) - at}s")
        gaps.append(template[at:])
        self.struct = struct.Struct("".join(fmt))
        self._args: list[Any] = [None] * (2 * len(w.leaves) + 1)
        self._args[0::2] = gaps
        guards = " and ".join(w.guards) or "True"
        values = ", ".join(leaf.expr for leaf in w.leaves)
        lines = ["def values(s):", *(f"    {b}" for b in w.binds), f"    if not ({guards}):", "        return None"]
        source = "\n".join([*lines, f"    return ({values}{',' if w.leaves else ''})", ""])
        ns: dict[str, Any] = dict(w.consts)
        exec(compile(source, f"<layout of {type(sample).__name__}>", "exec"), ns)
        self.values: Callable[[Any], tuple[Any, ...] | None] = ns["values"]
        self.size = len(template)
        if self.encode(sample) != template or self.encode(probe) != bb:
            raise Unsupported(f"{type(sample).__name__}: the layout does not give cyclonedds' bytes")

    def encode(self, sample: Any) -> bytes | None:
        """The sample's serialised bytes; None when it is not of this layout's shape."""
        try:
            values = self.values(sample)
        except (AttributeError, TypeError, IndexError):
            return None
        if values is None:
            return None
        args = self._args
        args[1::2] = values
        try:
            return self.struct.pack(*args)
        except struct.error:  # a value out of its member's range: cyclonedds says what
            return None


def _raw(v: Any) -> Any:
    return v.value if hasattr(v, "value") else v


def _serialise(sample: Any, version_2: bool | None) -> bytes:
    data: bytes = sample.serialize(use_version_2=version_2)
    return data.ljust((len(data) + 3) & ~3, b"\0")  # as DataWriter.write pads it


class PreparedWriter:
    """A DataWriter whose samples are written from prepared layouts (the module's docstring)."""

    def __init__(self, writer: DataWriter[Any]) -> None:
        self.writer = writer
        self.version_2 = writer_version_2(writer)
        self.layouts: list[Layout] = []
        self.unprepared: set[type] = set()  # types whose layout failed: written by cyclonedds

    def encode(self, sample: Any) -> bytes:
        """The bytes `DataWriter.write` would write for `sample`."""
        for layout in self.layouts:
            data = layout.encode(sample)
            if data is not None:
                return data
        if type(sample) not in self.unprepared:
            try:
                layout = Layout(sample, self.version_2)
            except Unsupported:
                self.unprepared.add(type(sample))
            else:
                data = layout.encode(sample)
                if data is not None:
                    self.layouts = [layout, *self.layouts[: LAYOUTS_MAX - 1]]
                    return data
        return _serialise(sample, self.version_2)

    def write(self, sample: Any) -> None:
        if not isinstance(sample, self.writer.data_type):
            raise TypeError(f"{sample} is not of type {self.writer.data_type}")
        ret = write_cdr(self.writer, self.encode(sample), time.time_ns())
        if ret < 0:
            raise DDSException(ret, f"Occurred while writing sample in {self.writer!r}")

    def dispose(self, sample: Any) -> None:
        self.writer.dispose(sample)

    def flush(self) -> None:
        """Send what a batching writer (`Bus.writer(batching=True)`) holds."""
        ret = write_flush(self.writer)
        if ret < 0:
            raise DDSException(ret, f"Occurred while flushing {self.writer!r}")
