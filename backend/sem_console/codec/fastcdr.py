"""CDR -> the console's values, by Python code generated per type from cyclonedds' own type description.

cyclonedds' deserializer walks a tree of "machines" per sample and reads one value per
`struct.unpack_from`; for a 40-satellite GPSReport that and the JSON conversion after it
(`convert.to_json`) cost about a millisecond. Here the same machine tree
(`T.__idl__.v1_machine`/`v2_machine`, so the layout rules are cyclonedds' own: XCDR1 aligns 8-byte
values to 8, XCDR2 to 4 and puts a DHEADER before a sequence of structs and a presence flag
before an @optional member) is compiled once per type, encoding and byte order into a Python
function that:

- reads every run of fixed-size members with one precompiled `struct.Struct` (padding included),
  so a report of a few dozen scalars is one or two unpacks;
- for a struct of @optional members (a GPS satellite), first tries the layout with every member
  present in one unpack and checks the presence flags, and reads member by member only when one
  is absent;
- for a type of fixed-size members with @optional ones (a position report), learns the presence
  patterns of the samples it reads member by member (`PATTERNS_MAX` per encoding) and reads a
  sample of a learned pattern in one unpack, its presence flags checked;
- in JSON mode (`json`) builds `convert.to_json`'s output directly, with its checks (non-finite
  and out-of-range numbers, unknown enum ordinals, GUIDs as UUID strings, a sequence's elements up to its bound, or
  MAX_SATELLITES when it has none) inlined where the member's name and type make them known, and `convert`'s own
  functions called for the message when a check fails, so values and messages are the same;
- in sample mode (`sample`) builds the generated dataclass, equal to cyclonedds' `deserialize`.

What the generator does not cover (an XCDR1 sample of a type with @optional members, which Cyclone
neither offers nor accepts for these types, or a construct no SEM type uses) is decoded by
cyclonedds itself, so every input decodes as before. A malformed sample raises (`struct.error`,
`IndexError`, `ValueError`, `UnicodeDecodeError`); callers count it and drop it. Where cyclonedds
reads a truncated sample leniently (a GUID cut short) this decoder refuses it; wherever it
returns a value, the value is cyclonedds' (tests/unit/test_fastcdr.py pins both modes to cyclonedds on
random samples of every SEM type). `python -m sem_console.codec.fastcdr TYPE` prints the
generated source.
"""

from __future__ import annotations

import dataclasses
import functools
import logging
import re
import struct
import sys
import threading
import uuid
from collections.abc import Callable, Mapping
from typing import Any

from cyclonedds.idl import IdlStruct

from sem_console.codec import convert
from sem_console.dds.cyclone_private import enum_type, type_machine
from sem_console.dds.cyclone_private import machinery as mc
from sem_console.versions import shape
from sem_console.versions.shape import Adapter, Spec

log = logging.getLogger("sem-console.ingest")
MAX_ELEMENTS = convert.MAX_SATELLITES
_GUID_CACHE_MAX = 65_536
DICT_LITERAL_MAX = 12  # a JSON object of more members is built from a template (`_Gen.dict_of`)
_guid_text: dict[bytes, str] = {}
_guid_uuid: dict[str, uuid.UUID] = {}


def guid_text(raw: bytes) -> str:
    """A 16-byte GUID as its canonical UUID string (the same vehicles' and satellites' GUIDs recur:
    cached)."""
    s = _guid_text.get(raw)
    if s is None:
        if len(_guid_text) >= _GUID_CACHE_MAX:
            _guid_text.clear()
        s = _guid_text[raw] = str(uuid.UUID(bytes=raw))
    return s


def guid_uuid(text: str) -> uuid.UUID:
    """The UUID of a canonical UUID string from `guid_text` (cached the same way)."""
    u = _guid_uuid.get(text)
    if u is None:
        if len(_guid_uuid) >= _GUID_CACHE_MAX:
            _guid_uuid.clear()
        u = _guid_uuid[text] = uuid.UUID(text)
    return u


class Unsupported(Exception):
    """A type or encoding the generator does not cover: cyclonedds decodes it."""


class Malformed(ValueError):
    """A sample whose lengths do not fit its size."""


def _meet(a: tuple[int, int], b: tuple[int, int]) -> tuple[int, int]:
    """What is known of the position (offset mod m == r) after either of two paths."""
    m = min(a[0], b[0])
    while m > 1 and a[1] % m != b[1] % m:
        m //= 2
    return m, a[1] % m


def _float_fails(v: str, name: str) -> str:
    """The condition (Python source) under which `convert` flags the float in variable `v` of member `name`."""
    lo_hi = convert.RANGES.get(name)
    if lo_hi:  # NaN fails the comparison too
        return f"not ({lo_hi[0]!r} <= {v} <= {lo_hi[1]!r})"
    return f"{v} - {v}"  # nan for NaN and infinities, 0.0 (false) for every finite value


def _bad_enum(enum: type, v: int, path: str, invalid: list[str]) -> None:
    invalid.append(convert.unknown_ordinal(enum, v, path))


def _too_many(n: int, path: str, invalid: list[str], limit: int = MAX_ELEMENTS) -> None:
    invalid.append(convert.too_many(n, path, limit))


class _Gen:
    """Generates one function `decode(b)` for one type, encoding version, byte order and mode."""

    def __init__(self, v2: bool, little: bool, json: bool, rename: Callable[[str], str] | None = None) -> None:
        self.v2, self.json = v2, json
        self.rename = rename  # a member's path as the JSON's reader names it (a version's model, `shape`)
        self.trees: dict[str, dict[str, str]] = {}  # a struct's JSON expression -> its members' expressions
        self.endian = "<" if little else ">"
        self.amax = 4 if v2 else 8
        self.lines: list[str] = []
        self.indent = 1
        self.ns: dict[str, Any] = {
            "_value": convert._value,  # noqa: SLF001
            "_bad_enum": _bad_enum,
            "_too_many": _too_many,
            "guid_text": guid_text,
            "_guids": _guid_text,
            "unpack_from": struct.unpack_from,
            "Malformed": Malformed,
            "error": struct.error,
        }
        self.k = 0
        self.run: list[tuple[str, str | None]] = []  # pending fixed-size reads: (struct code, variable or None for padding)
        self.checks: list[str] = []  # statements to emit once the pending run is read
        self.pure: dict[str, str] = {}  # a variable -> the statement that only computes it (dropped when unused)
        self.unpacks: list[tuple[str, list[tuple[str, str | None]]]] = []  # (its Struct's name, its run): `drop_unused`
        self.absent: set[str] = set()  # with a pattern: the presence flags of the members it says are absent
        self.enum_names: dict[str, tuple[str, ...]] = {}  # JSON mode: a variable holding an enum's name (or None)
        self.pattern: list[bool] | None = None  # the presence of each @optional member, in order: no branch on them
        self.expect: list[str] = []  # with a pattern: the conditions its presence flags meet
        self.record = False  # the presence flags read go to the list `fl` (what `TypeDecoder` learns patterns from)
        self.phase = (self.amax, 0)  # (m, r): the position after the header is r modulo m

    # ---- plumbing --------------------------------------------------------------------------
    def var(self, prefix: str = "v") -> str:
        self.k += 1
        return f"{prefix}{self.k}"

    def const(self, obj: Any, prefix: str = "C") -> str:
        name = self.var(prefix)
        self.ns[name] = obj
        return name

    def emit(self, line: str) -> None:
        self.lines.append("    " * self.indent + line)

    def align_code(self, a: int) -> str:
        # offsets count from the end of the 4-byte encapsulation header
        return f"p += -p & {a - 1}" if a <= 4 else f"p += (4 - p) & {a - 1}"

    def align(self, a: int) -> None:
        a = min(a, self.amax)
        if a <= 1:
            return
        m, r = self.phase
        if a <= m:
            pad = -r % a
            if pad:
                self.run.append(("x" * pad, None))
                self.phase = (m, (r + pad) % m)
        else:
            self.flush()
            self.emit(self.align_code(a))
            self.phase = (a, 0)

    def advance(self, size: int) -> None:
        m, r = self.phase
        self.phase = (m, (r + size) % m)

    def fixed(self, code: str, size: int, alignment: int) -> str:
        self.align(alignment)
        v = self.var()
        self.run.append((code, v))
        self.advance(size)
        return v

    def flush(self) -> None:
        if self.run:
            fmt = self.endian + "".join(c for c, _ in self.run)
            names = [v for _, v in self.run if v]
            s = struct.Struct(fmt)
            if fmt[1:] == "B" and names:  # a presence flag alone: indexing is cheaper than an unpack
                self.emit(f"{names[0]} = b[p]")
            elif names:
                self.emit(self.unpack(self.run, "p"))
            self.emit(f"p += {s.size}")
            self.run = []
        for line in self.checks:
            self.emit(line)
        self.checks = []

    def block(self, header: str, body: Callable[[], str | None]) -> tuple[str | None, tuple[int, int]]:
        """`header:` then what `body` emits, flushed; returns body's result and the phase after it."""
        self.emit(header)
        self.indent += 1
        out = body()
        self.flush()
        if self.lines[-1].rstrip().endswith(":"):
            self.emit("pass")
        self.indent -= 1
        return out, self.phase

    def dict_of(self, items: list[tuple[str, str]]) -> str:
        """A dict of these names and expressions: a literal, or, one of many names, a copy of its template (None
        throughout) with the other values set, which costs a third as much to build."""
        if len(items) <= DICT_LITERAL_MAX:
            return "{" + ", ".join(f"{n!r}: {e}" for n, e in items) + "}"
        d = self.var("d")
        self.emit(f"{d} = {self.const(dict.fromkeys(n for n, _ in items), 'D')}.copy()")
        for n, e in items:
            if e != "None":
                self.emit(f"{d}[{n!r}] = {e}")
        return d

    def unpack(self, run: list[tuple[str, str | None]], at: str) -> str:
        """The statement that reads `run` (struct codes and variables, None for padding) at offset `at` in one unpack;
        a read nothing uses becomes padding (`drop_unused`)."""
        name = self.const(struct.Struct(self.endian + "".join(c for c, _ in run)), "S")
        self.unpacks.append((name, list(run)))
        return self._unpack_line(name, run, at)

    @staticmethod
    def _unpack_line(name: str, run: list[tuple[str, str | None]], at: str) -> str:
        names = [v for _, v in run if v]
        return f"{', '.join(names)}, = {name}.unpack_from(b, {at})" if names else f"{name}.unpack_from(b, {at})"

    def merge_absent(self) -> None:
        """With a pattern: each run of adjacent presence flags of absent members read as one unsigned integer (or a
        few), one zero test for them all instead of one per flag."""
        out: list[tuple[str, str | None]] = []
        i = 0
        while i < len(self.run):
            j = i
            while j < len(self.run) and self.run[j][1] in self.absent:
                j += 1
            if j == i:
                out.append(self.run[i])
                i += 1
                continue
            for _, v in self.run[i:j]:
                self.expect.remove(f"not {v}")
            n = j - i
            for size, code in ((8, "Q"), (4, "I"), (2, "H"), (1, "B")):
                while n >= size:
                    v = self.var()
                    out.append((code, v))
                    self.expect.append(f"not {v}")
                    n -= size
            i = j
        self.run = out

    def lookup(self, table: Mapping[Any, Any], expr: str) -> str:
        """`table.get(expr)`: of an enum's name (or None), a subscript of the table made whole over them, cheaper."""
        names = self.enum_names.get(expr)
        if names is None:
            return f"{self.const(table)}.get({expr})"
        return f"{self.const({**{n: table.get(n) for n in names}, None: None})}[{expr}]"

    def drop_unused(self, expr: str) -> None:
        """Drop the statements that only compute a value nothing reads (a member the version's model leaves out,
        such as an identifier's parentID), and read such a value as padding: no object is made for it."""
        used = set(
            re.findall(
                r"\b[a-z]\d+\b", expr + "\n" + "\n".join(line for line in self.lines if line.strip() not in self.pure.values())
            )
        )
        unused = {line for v, line in self.pure.items() if v not in used}
        self.lines = [line for line in self.lines if line.strip() not in unused]
        lines = {self._unpack_line(name, run, at): (name, run, at) for name, run in self.unpacks for at in ("p", "4")}
        used = set(re.findall(r"\b[a-z]\d+\b", expr + "\n" + "\n".join(line for line in self.lines if line.strip() not in lines)))
        for k, line in enumerate(self.lines):
            found = lines.get(line.strip())
            if found is None:
                continue
            name, run, at = found
            if all(v is None or v in used for _, v in run):
                continue
            kept = [(c, v) if v is None or v in used else (f"{struct.calcsize(self.endian + c)}x", None) for c, v in run]
            self.ns[name] = struct.Struct(self.endian + "".join(c for c, _ in kept))
            self.lines[k] = line[: len(line) - len(line.lstrip())] + self._unpack_line(name, kept, at)

    # ---- values ----------------------------------------------------------------------------
    def value(self, mach: Any, path: str, name: str, enum_member: bool = False) -> str:
        """Emit the reads of one value; returns the expression of its decoded value (valid once flushed).
        `path` is the body of an f-string naming the value (as convert.to_json names it)."""
        if self.rename is not None:
            path = self.rename(path)
        if isinstance(mach, mc.InstanceMachine):
            return self.value(type_machine(mach.type, mach.use_version_2), path, name, enum_member)
        if isinstance(mach, mc.StructMachine):
            if self.v2 and self.pattern is None and self._speculable(mach):
                return self.speculative(mach, path)
            return self.struct(mach, path)
        if isinstance(mach, mc.PrimitiveMachine):
            v = self.fixed(mach.code, mach.size, mach.alignment)
            if self.json:
                if mach.code in "fd":
                    self.checks.append(f'if {_float_fails(v, name)}: {v} = _value({v}, f"{path}", inv, {name!r})')
                elif mach.code != "?" and name in convert.RANGES:
                    lo, hi = convert.RANGES[name]
                    self.checks.append(f'if not ({lo!r} <= {v} <= {hi!r}): _value({v}, f"{path}", inv, {name!r})')
            return v
        if isinstance(mach, (mc.EnumMachine, mc.BitBoundEnumMachine)):
            code, size = ("I", 4) if isinstance(mach, mc.EnumMachine) else (mach.code, mach.size)
            v = self.fixed(code, size, mach.alignment)
            out = self.var()
            members = {m.value: m for m in enum_type(mach)}  # what Enum(v) looks up (aliases are not members)
            if not self.json:
                self.checks.append(f"{out} = {self.const(members, 'E')}.get({v}, {v})")
            elif enum_member:
                names = {value: m.name for value, m in members.items()}
                self.checks.append(f"{out} = {self.const(names, 'N')}.get({v})")
                self.checks.append(f'if {out} is None: _bad_enum({self.const(mach.enum, "T")}, {v}, f"{path}", inv)')
                self.enum_names[out] = tuple(names.values())
            else:  # an enum not declared as a struct member's type: convert gives the name or the number as it is
                names = {value: m.name for value, m in members.items()}
                self.checks.append(f"{out} = {self.const(names, 'N')}.get({v}, {v})")
            return out
        if isinstance(mach, mc.ByteArrayMachine):
            v = self.fixed(f"{mach.size}s", mach.size, 1)
            if not self.json:
                return v
            if name in convert.GUID_MEMBERS and mach.size == 16:
                out = self.var()
                self.pure[out] = f"{out} = _guids.get({v}) or guid_text({v})"
                self.checks.append(self.pure[out])
                return out
            return self.generic(v, path)
        if isinstance(mach, mc.OptionalMachine):
            return self.optional(mach, path, name, enum_member)
        if isinstance(mach, mc.StringMachine):
            return self.string()
        if isinstance(mach, mc.PlainCdrV2SequenceOfPrimitiveMachine):
            return self.primitive_sequence(mach, path, name)
        if isinstance(mach, mc.SequenceMachine):
            return self.sequence(mach, path, name)
        if isinstance(mach, mc.PlainCdrV2ArrayOfPrimitiveMachine):
            self.align(mach.alignment)
            self.flush()
            v = self.var()
            self.emit(f"{v} = list(unpack_from({self.endian + mach.code!r}, b, p))")
            self.emit(f"p += {mach.size}")
            self.advance(mach.size)
            return self.generic(v, path) if self.json else v
        raise Unsupported(type(mach).__name__)

    def generic(self, v: str, path: str) -> str:
        """JSON of a value decoded as a sample, by convert itself (what no check above specialises)."""
        out = self.var()
        self.checks.append(f'{out} = _value({v}, f"{path}", inv)')
        return out

    def struct(self, mach: Any, path: str) -> str:
        cls = mach.type
        names = [f.name for f in dataclasses.fields(cls)]
        if list(mach.members_machines) != names:
            raise Unsupported(f"{cls.__name__}: members not in field order")
        enums = convert._enum_members(cls) if self.json else {}  # noqa: SLF001
        exprs = [self.value(mm, f"{path}.{n}" if path else n, n, n in enums) for n, mm in mach.members_machines.items()]
        if self.json:
            expr = "{" + ", ".join(f"{n!r}: {e}" for n, e in zip(names, exprs, strict=True)) + "}"
            self.trees[expr] = dict(zip(names, exprs, strict=True))
            return expr
        return f"{self.const(cls, 'T')}({', '.join(exprs)})"

    def optional(self, mach: Any, path: str, name: str, enum_member: bool) -> str:
        if not mach.use_version_2:
            raise Unsupported("an XCDR1 @optional member")
        flag = self.fixed("B", 1, 1)
        if self.pattern is not None:
            if not self.pattern:
                raise Unsupported("a presence pattern too short")
            here = self.pattern.pop(0)
            self.expect.append(flag if here else f"not {flag}")
            if not here:
                self.absent.add(flag)
            return self.value(mach.submachine, path, name, enum_member) if here else "None"
        self.flush()
        if self.record:
            self.emit(f"fl.append({flag})")
        out = self.var()
        before = self.phase

        def present() -> None:
            e = self.value(mach.submachine, path, name, enum_member)
            self.flush()
            self.emit(f"{out} = {e}")

        _, after = self.block(f"if {flag}:", present)
        self.emit("else:")
        self.emit(f"    {out} = None")
        self.phase = _meet(before, after)
        return out

    def string(self) -> str:
        n = self.fixed("I", 4, 4)
        self.flush()
        v = self.var()
        # as cyclonedds: n - 1 bytes of UTF-8 and a terminator it does not check (n == 0: nothing)
        self.emit(f"if {n} and p + {n} > len(b): raise Malformed('a string past the end')")
        self.emit(f"{v} = b[p:p + {n} - 1].decode()")
        self.emit(f"p += {n}")
        self.phase = (1, 0)
        return v

    def primitive_sequence(self, mach: Any, path: str, name: str) -> str:
        n = self.fixed("I", 4, 4)
        self.flush()
        v = self.var()
        a = min(mach.alignment, self.amax)
        after_count = self.phase
        self.emit(f"if {n}:")
        m, r = self.phase
        if a > m:
            self.emit("    " + self.align_code(a))
        elif -r % a:
            self.emit(f"    p += {-r % a}")
        self.emit(f"    {v} = list(unpack_from({self.endian!r} + str({n}) + {mach.code!r}, b, p))")
        self.emit(f"    p += {n} * {mach.size}")
        self.emit("else:")
        self.emit(f"    {v} = []")
        present = (a, 0) if a > 1 and mach.size % a == 0 else (1, 0)
        self.phase = _meet(after_count, present)
        if not self.json:
            return v
        if mach.code in "fd" and name not in convert.RANGES:
            limit = mach.max_length or MAX_ELEMENTS
            self.emit(f"if {n} > {limit}: _too_many({n}, f\"{path}\", inv, {limit}); del {v}[{limit}:]")
            self.emit(f"if sum({v}) * 0.0: {v} = [_value(x, f\"{path}[{{j}}]\", inv) for j, x in enumerate({v})]")
            return v
        out = self.var()
        self.emit(f'{out} = _value({v}, f"{path}", inv)')
        return out

    def sequence(self, mach: Any, path: str, name: str) -> str:
        dheader = self.fixed("I", 4, 4) if mach.add_size_header else None
        n = self.fixed("I", 4, 4)
        self.flush()
        lst, i, end = self.var("l"), self.var("i"), self.var("e")
        limit = mach.maxlen or MAX_ELEMENTS  # a bounded sequence keeps its bound (UMAA 6.0's satellites: 300)
        if dheader:
            self.emit(f"{end} = p - 4 + {dheader}")
        # every element takes at least one byte: a count past the end is refused before the loop
        self.emit(f"if {n} > len(b) - p: raise Malformed('a sequence longer than the sample')")
        self.emit(f"{lst} = []")
        json = self.json
        if json:
            keep = self.var("k")
            self.emit(f"if {n} > {limit}: _too_many({n}, f\"{path}\", inv, {limit})")
            self.emit(f"{keep} = inv")
        before = self.phase
        start = before
        for _ in range(4):  # the phase at the top of the loop: what holds for the first and every later turn
            mark, k0 = len(self.lines), self.k
            self.phase = start

            def body() -> None:
                if json:
                    self.emit(f"if {i} == {limit}: inv = []  # elements past the limit are dropped, unflagged")
                e = self.element(mach.submachine, f"{path}[{{{i}}}]", name)
                self.flush()
                self.emit(f"{lst}.append({e})")

            _, after = self.block(f"for {i} in range({n}):", body)
            if _meet(start, after) == start:
                break
            del self.lines[mark:]
            self.k = k0
            start = _meet(start, after)
        else:
            raise Unsupported("no stable phase for a sequence")
        if json:
            self.emit(f"inv = {keep}")
            self.emit(f"del {lst}[{limit}:]")
        if dheader:
            self.emit(f"p = {end}")
            self.phase = (1, 0)
        else:
            self.phase = _meet(before, after)
        return lst

    def element(self, mach: Any, path: str, name: str) -> str:
        """One element of a sequence (JSON: a struct or string as to_json converts it, anything else by convert)."""
        target = mach
        while isinstance(target, mc.InstanceMachine):
            target = type_machine(target.type, target.use_version_2)
        if self.json and not isinstance(target, (mc.StructMachine, mc.StringMachine)):
            return self._generic_element(mach, path, name)
        return self.value(mach, path, name)

    def _generic_element(self, mach: Any, path: str, name: str) -> str:
        """An element that is not a struct: decoded as a sample, converted by convert (as to_json would)."""
        self.json = False
        try:
            v = self.value(mach, path, name)
        finally:
            self.json = True
        return self.generic(v, path)

    def _speculable(self, mach: Any) -> bool:
        """A struct of @optional fixed-size scalars (and fixed-size non-optional ones)."""
        ms = list(mach.members_machines.values())
        return any(isinstance(m, mc.OptionalMachine) for m in ms) and all(
            isinstance(
                m.submachine if isinstance(m, mc.OptionalMachine) else m,
                (mc.PrimitiveMachine, mc.EnumMachine, mc.BitBoundEnumMachine, mc.ByteArrayMachine),
            )
            for m in ms
        )

    def speculative(self, mach: Any, path: str) -> str:
        """A struct of @optional members (XCDR2) read first as if every member were present, in one unpack
        (one Struct per phase of the start, mod 4), kept if every presence flag says so; otherwise (or
        with too few bytes left for that layout) read member by member."""
        self.flush()
        out = self.var()
        start_phase = self.phase
        # the fast layout, per possible start phase
        variants = []
        for r0 in range(4):
            save_run, save_phase = self.run, self.phase
            self.run, self.phase = [], (4, r0)
            flags: list[str] = []
            checks_before = self.checks
            self.checks = []
            lines_mark = len(self.lines)
            exprs = []
            names = [f.name for f in dataclasses.fields(mach.type)]
            enums = convert._enum_members(mach.type) if self.json else {}  # noqa: SLF001
            for n, mm in mach.members_machines.items():
                sub = f"{path}.{n}" if path else n
                if isinstance(mm, mc.OptionalMachine):
                    flags.append(self.fixed("B", 1, 1))
                    mm = mm.submachine
                exprs.append(self.value(mm, sub, n, n in enums))
            fmt = self.endian + "".join(c for c, _ in self.run)
            variants.append((struct.Struct(fmt), [v for _, v in self.run if v], flags, self.checks, exprs, names))
            assert len(self.lines) == lines_mark
            self.run, self.phase, self.checks = save_run, save_phase, checks_before
        m0, r0 = start_phase
        phases = [r0 % 4] if m0 >= 4 else list(range(4))
        structs = [variants[r][0] if r in phases else None for r in range(4)]
        self.emit(f"{out} = None")
        sel = self.var("s")
        if len(phases) == 1:
            self.emit(f"{sel} = {self.const(structs[phases[0]], 'S')}")
        else:
            self.emit(f"{sel} = {self.const(tuple(structs), 'S')}[(p - 4) & 3]")
        self.emit(f"if p + {sel}.size <= len(b):")
        self.indent += 1
        for idx, r in enumerate(phases):
            s, names_, flags, checks, exprs, fields_ = variants[r]
            if len(phases) > 1:
                self.emit(("if" if idx == 0 else "elif") + f" {sel} is {self.const(s, 'S')}:")
                self.indent += 1
            self.emit(f"{', '.join(names_)}, = {sel}.unpack_from(b, p)")
            self.emit(f"if {' and '.join(flags)}:")
            self.indent += 1
            self.emit(f"p += {s.size}")
            if self.record:
                self.emit(f"fl += {(True,) * len(flags)!r}")
            for c in checks:
                self.emit(c)
            if self.json:
                self.emit(f"{out} = {{{', '.join(f'{n!r}: {e}' for n, e in zip(fields_, exprs, strict=True))}}}")
            else:
                self.emit(f"{out} = {self.const(mach.type, 'T')}({', '.join(exprs)})")
            self.indent -= 1
            if len(phases) > 1:
                self.indent -= 1
        self.indent -= 1
        # otherwise (a member absent, or too few bytes left for all present): member by member

        def slow() -> None:
            e = self.struct(mach, path)
            self.flush()
            self.emit(f"{out} = {e}")

        self.phase = start_phase
        self.block(f"if {out} is None:", slow)
        self.phase = (1, 0)  # the end depends on which members were present
        return out


def _flat(mach: Any) -> bool:
    """A type of fixed-size members only (through @optional members and nested structs): with its members' presence
    known, one `struct.Struct` reads all of it."""
    if isinstance(mach, mc.InstanceMachine):
        return _flat(type_machine(mach.type, mach.use_version_2))
    if isinstance(mach, mc.StructMachine):
        return all(_flat(m) for m in mach.members_machines.values())
    if isinstance(mach, mc.OptionalMachine):
        return _flat(mach.submachine)
    return isinstance(mach, (mc.PrimitiveMachine, mc.EnumMachine, mc.BitBoundEnumMachine, mc.ByteArrayMachine))


def _has_optional(mach: Any) -> bool:
    if isinstance(mach, mc.InstanceMachine):
        return _has_optional(type_machine(mach.type, mach.use_version_2))
    if isinstance(mach, mc.StructMachine):
        return any(_has_optional(m) for m in mach.members_machines.values())
    return isinstance(mach, mc.OptionalMachine)


def learnable(cls: type[IdlStruct], v2: bool, json: bool) -> bool:
    """Whether `TypeDecoder` learns the presence patterns of `cls`'s samples (XCDR2, JSON mode): a type of fixed-size
    members with @optional ones, which a known pattern reads in one unpack."""
    top = type_machine(cls, v2)
    return v2 and json and _flat(top) and _has_optional(top)


def generate(
    cls: type[IdlStruct],
    v2: bool,
    little: bool,
    json: bool,
    spec: Spec = None,
    rename: Callable[[str], str] | None = None,
    patterns: tuple[tuple[bool, ...], ...] = (),
    learn: Callable[[list[int]], None] | None = None,
) -> tuple[str, dict[str, Any]]:
    """The source of `decode(b)` for `cls` and the names it uses. With a `spec` (JSON mode) it returns the JSON of a
    version's model (`versions/shape.py`), an invalid value named by `rename` of its path. Each of `patterns` (the
    presence of every @optional member, in the order they are read) is tried first: one unpack, its presence flags
    checked; a sample of none of them is read member by member, its presence flags given to `learn` when set."""
    g = _Gen(v2, little, json, rename if json and spec is not None else None)
    top = type_machine(cls, v2)

    def returned(expr: str) -> str:
        if json and spec is not None:

            def member(path: str, top: str = expr) -> str:
                for part in path.split("."):
                    top = g.trees[top][part]
                return top

            expr = shape.source(spec, member, g.const, g.dict_of, g.lookup)
        return f"return {expr}, inv" if json else f"return {expr}"

    body: list[str] = []
    for pattern in patterns:
        g.pattern, g.expect, g.phase = list(pattern), [], (g.amax, 0)
        expr = g.value(top, "", "")
        if g.pattern or g.lines:
            raise Unsupported("a presence pattern that does not fit the type")
        g.merge_absent()
        g.emit("try:")
        g.emit(f"    {g.unpack(g.run, '4')}")
        g.emit("except error:")
        g.emit("    pass")
        g.emit("else:")
        g.emit(f"    if {' and '.join(g.expect) or 'True'}:")
        g.indent += 2
        for line in g.checks:
            g.emit(line)
        g.emit(returned(expr))
        g.indent -= 2
        g.run, g.checks, g.pattern = [], [], None
        body += g.lines
        g.lines = []
    g.phase, g.record = (g.amax, 0), learn is not None
    if learn is not None:
        g.ns["_learn"] = learn
        g.emit("fl = []")
    expr = g.value(top, "", "")
    g.flush()
    if learn is not None:
        g.emit("_learn(fl)")
    g.lines = body + g.lines
    tail = returned(expr)
    g.drop_unused(tail)
    head = ["def decode(b):", "    p = 4"] + (["    inv = []"] if json else [])
    return "\n".join(head + g.lines + ["    " + tail]) + "\n", g.ns


_FALLBACK: Any = object()
PATTERNS_MAX = 4
"""The presence patterns a decoder learns per encoding (a fleet's vehicles leave out a few sets of members)."""


class TypeDecoder:
    """The generated decoders of one type, built on first use per encoding, byte order and mode."""

    def __init__(
        self, cls: type[IdlStruct], spec: Spec = None, rename: Callable[[str], str] | None = None, adapt: Adapter | None = None
    ) -> None:
        self.cls = cls
        # a version's report as its model (`versions/`): `spec` for the generated code, `adapt` for cyclonedds' JSON
        self.spec, self.rename, self.adapt = spec, rename, adapt
        self._fns: dict[tuple[bool, bool, bool], Any] = {}
        self._patterns: dict[tuple[bool, bool, bool], tuple[tuple[bool, ...], ...]] = {}
        self._lock = threading.Lock()

    def _fn(self, data: bytes, json: bool) -> Any:
        kind = data[1]
        key = (3 < kind < 128, bool(kind & 1), json)  # as cyclonedds reads the encapsulation header
        fn = self._fns.get(key)
        if fn is None:
            with self._lock:
                fn = self._fns.get(key)
                if fn is None:
                    fn = self._fns[key] = self._build(*key)
        return fn

    @property
    def patterns(self) -> dict[tuple[bool, bool, bool], tuple[tuple[bool, ...], ...]]:
        """The presence patterns learned, by (XCDR2, little-endian, JSON mode)."""
        return dict(self._patterns)

    def _learn(self, key: tuple[bool, bool, bool], flags: list[int]) -> None:
        """A sample read member by member had these presence flags: its pattern is tried first from now on."""
        pattern = tuple(bool(f) for f in flags)
        with self._lock:
            patterns = self._patterns.get(key, ())
            if pattern not in patterns and len(patterns) < PATTERNS_MAX:
                self._patterns[key] = (*patterns, pattern)
                self._fns[key] = self._build(*key)

    def _build(self, v2: bool, little: bool, json: bool) -> Any:
        name = f"{self.cls.__name__} {'xcdr2' if v2 else 'xcdr1'} {'le' if little else 'be'}{' json' if json else ''}"
        try:
            key = (v2, little, json)
            patterns = self._patterns.get(key, ())
            learn = None
            if len(patterns) < PATTERNS_MAX and learnable(self.cls, v2, json):
                learn = functools.partial(self._learn, key)
            source, ns = generate(self.cls, v2, little, json, self.spec, self.rename, patterns, learn)
            exec(compile(source, f"<fastcdr {name}>", "exec"), ns)  # our own generated source
            return ns["decode"]
        except Unsupported:
            return _FALLBACK
        except Exception:  # a generator bug must not lose samples: cyclonedds decodes them, slower
            log.exception("no generated decoder for %s; cyclonedds decodes it", name)
            return _FALLBACK

    def json(self, data: bytes) -> tuple[dict[str, Any], list[str]]:
        """`convert.to_json(cls.deserialize(data))`, faster."""
        fn = self._fn(data, True)
        if fn is _FALLBACK:
            decoded_by_cyclonedds = convert.to_json(self.cls.deserialize(data))
            return decoded_by_cyclonedds if self.adapt is None else self.adapt(*decoded_by_cyclonedds)
        decoded: tuple[dict[str, Any], list[str]] = fn(data)  # the generated decode(b), JSON mode
        return decoded

    def sample(self, data: bytes) -> Any:
        """`cls.deserialize(data)`, faster."""
        fn = self._fn(data, False)
        if fn is _FALLBACK:
            return self.cls.deserialize(data)
        return fn(data)


_decoders: dict[tuple[type[IdlStruct], int], TypeDecoder] = {}


def decoder(
    cls: type[IdlStruct], spec: Spec = None, rename: Callable[[str], str] | None = None, adapt: Adapter | None = None
) -> TypeDecoder:
    """The decoders of `cls`; with a `spec` (and its `rename` and `adapt`, `TypeDecoder`), of its JSON as a version's
    model."""
    key = (cls, id(spec))
    d = _decoders.get(key)
    if d is None:
        d = _decoders.setdefault(key, TypeDecoder(cls, spec, rename, adapt))
    return d


if __name__ == "__main__":
    from sem_console.dds.topics import Sem

    wanted = sys.argv[1] if len(sys.argv) > 1 else "GPSReportType"
    for sem in Sem:
        if sem.spec.type.__name__ == wanted:
            for v2 in (False, True):
                try:
                    print(generate(sem.spec.type, v2, True, "--sample" not in sys.argv)[0])
                except Unsupported as e:
                    print(f"# {'XCDR2' if v2 else 'XCDR1'}: not generated ({e}); cyclonedds decodes it\n")
