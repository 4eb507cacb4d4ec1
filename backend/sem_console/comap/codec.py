"""IMC packets and payloads, driven by the table in messages.py.

Packet (IMC 5.x): a 20-byte header

    sync u16 (0xFE55) | mgid u16 | size u16 (payload bytes) | timestamp fp64 (s since epoch)
    | src u16 | src_ent u8 | dst u16 | dst_ent u8

then the payload, then a u16 CRC over header and payload. The CRC is IMC's CRC-16-IBM: polynomial
0x8005 in its reflected form 0xA001 (bits in from the least significant end), initial value 0, no
final xor (the "CRC-16/ARC" of the CRC catalogues; crc("123456789") == 0xBB3D). Byte order is the
sender's: a sync that reads 0x55FE in little-endian means the whole packet, CRC included, is
big-endian. We send little-endian.

Decoding never trusts a count or a size: a count that needs more bytes than remain, a payload that
is not exactly `size` bytes long, an unknown id and a wrong CRC all raise ImcError (with a `kind`
for the counters); nothing else escapes.
"""

from __future__ import annotations

import struct
import time
from dataclasses import dataclass, field
from typing import Any

from sem_console.comap.messages import BY_ID, BY_NAME, GROUPS, FieldType

SYNC = 0xFE55
NONE_ID = 0xFFFF
BROADCAST = 0xFFFF
BROADCAST_ENT = 0xFF
HEADER = struct.Struct("<HHHdHBHB")  # 20 bytes
HEADER_SIZE = 20
MAX_PAYLOAD = 0xFFFF
SCALARS = {"u8": "B", "u16": "H", "fp32": "f", "fp64": "d"}


class ImcError(ValueError):
    """A packet or payload we cannot read; kind is one of the counters' names."""

    def __init__(self, kind: str, detail: str) -> None:
        super().__init__(f"{kind}: {detail}")
        self.kind = kind


@dataclass
class Message:
    """A decoded message: its abbreviation (name) and its fields by name (nested messages are Messages)."""

    name: str
    fields: dict[str, Any] = field(default_factory=dict)

    def __getitem__(self, key: str) -> Any:
        return self.fields[key]

    @property
    def id(self) -> int:
        return BY_NAME[self.name].id


def msg(name: str, **fields: Any) -> Message:
    if name not in BY_NAME:
        raise KeyError(f"no message {name!r} in the table")
    return Message(name, fields)


@dataclass
class Header:
    mgid: int
    size: int
    timestamp: float
    src: int
    src_ent: int
    dst: int
    dst_ent: int
    big_endian: bool = False


def crc16(data: bytes, crc: int = 0) -> int:
    """IMC's CRC-16-IBM (reflected 0xA001, init 0)."""
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


# ---- encoding ------------------------------------------------------------------------------


def _encode_value(ftype: FieldType, value: Any, out: bytearray) -> None:
    if isinstance(ftype, str):
        out += struct.pack("<" + SCALARS[ftype], value)
        return
    kind, group = ftype
    if kind == "list":
        items = list(value or [])
        out += struct.pack("<H", len(items))
        for item in items:
            _encode_inline(group, item, out)
    else:
        if value is None:
            out += struct.pack("<H", NONE_ID)
        else:
            _encode_inline(group, value, out)


def _encode_inline(group: str, m: Message, out: bytearray) -> None:
    if m.name not in GROUPS[group]:
        raise ValueError(f"{m.name} is not a {group}")
    out += struct.pack("<H", m.id)
    encode_payload(m, out)


def encode_payload(m: Message, out: bytearray | None = None) -> bytearray:
    out = bytearray() if out is None else out
    for name, ftype in BY_NAME[m.name].fields:
        _encode_value(ftype, m.fields[name], out)
    return out


def encode_packet(
    m: Message,
    src: int,
    dst: int = BROADCAST,
    *,
    src_ent: int = 0xFF,
    dst_ent: int = BROADCAST_ENT,
    timestamp: float | None = None,
) -> bytes:
    """A whole little-endian IMC packet carrying m."""
    payload = encode_payload(m)
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(f"{m.name} payload of {len(payload)} bytes does not fit an IMC packet")
    head = HEADER.pack(SYNC, m.id, len(payload), time.time() if timestamp is None else timestamp, src, src_ent, dst, dst_ent)
    body = head + payload
    return bytes(body + struct.pack("<H", crc16(body)))


# ---- decoding ------------------------------------------------------------------------------


class _Reader:
    def __init__(self, data: bytes | memoryview, end: str) -> None:
        self.data, self.pos, self.end = memoryview(data), 0, end

    def take(self, fmt: str) -> Any:
        s = struct.Struct(self.end + fmt)
        if self.pos + s.size > len(self.data):
            raise ImcError("truncated", f"needs {s.size} bytes at offset {self.pos}, has {len(self.data) - self.pos}")
        (v,) = s.unpack_from(self.data, self.pos)
        self.pos += s.size
        return v

    def remaining(self) -> int:
        return len(self.data) - self.pos


def _decode_value(ftype: FieldType, r: _Reader, depth: int) -> Any:
    if isinstance(ftype, str):
        return r.take(SCALARS[ftype])
    kind, group = ftype
    if kind == "list":
        count = r.take("H")
        if count * 2 > r.remaining():  # every element has at least its u16 id
            raise ImcError("bad_size", f"a list of {count} elements in {r.remaining()} bytes")
        return [_decode_inline(group, r, depth, allow_none=False) for _ in range(count)]
    return _decode_inline(group, r, depth, allow_none=True)


def _decode_inline(group: str, r: _Reader, depth: int, *, allow_none: bool) -> Message | None:
    mid = r.take("H")
    if mid == NONE_ID and allow_none:
        return None
    layout = BY_ID.get(mid)
    if layout is None:
        raise ImcError("unknown_id", f"inline message id {mid}")
    if layout.name not in GROUPS[group]:
        raise ImcError("bad_message", f"{layout.name} where a {group} belongs")
    return _decode_fields(layout.name, r, depth + 1)


def _decode_fields(name: str, r: _Reader, depth: int) -> Message:
    if depth > 8:
        raise ImcError("bad_message", "messages nested too deep")
    return Message(name, {fname: _decode_value(ftype, r, depth) for fname, ftype in BY_NAME[name].fields})


def decode_payload(mgid: int, payload: bytes | memoryview, big_endian: bool = False) -> Message:
    """The message of id mgid from exactly these payload bytes."""
    layout = BY_ID.get(mgid)
    if layout is None:
        raise ImcError("unknown_id", f"message id {mgid}")
    r = _Reader(payload, ">" if big_endian else "<")
    m = _decode_fields(layout.name, r, 0)
    if r.remaining():
        raise ImcError("bad_size", f"{layout.name}: {r.remaining()} bytes beyond its fields")
    return m


def decode_packet(data: bytes) -> tuple[Header, Message]:
    """Header and message of one datagram; ImcError for anything wrong with it."""
    if len(data) < HEADER_SIZE + 2:
        raise ImcError("truncated", f"{len(data)} bytes is shorter than a header and CRC")
    (sync,) = struct.unpack_from("<H", data)
    if sync == SYNC:
        end = "<"
    elif sync == 0x55FE:
        end = ">"
    else:
        raise ImcError("bad_sync", f"sync 0x{sync:04X}")
    sync, mgid, size, ts, src, src_ent, dst, dst_ent = struct.unpack_from(end + "HHHdHBHB", data)
    if HEADER_SIZE + size + 2 != len(data):
        raise ImcError("bad_size", f"header says {size} payload bytes, the datagram has {len(data) - HEADER_SIZE - 2}")
    (crc,) = struct.unpack_from(end + "H", data, HEADER_SIZE + size)
    if crc != crc16(data[: HEADER_SIZE + size]):
        raise ImcError("bad_crc", f"CRC 0x{crc:04X}, computed 0x{crc16(data[: HEADER_SIZE + size]):04X}")
    header = Header(mgid, size, ts, src, src_ent, dst, dst_ent, big_endian=end == ">")
    return header, decode_payload(mgid, memoryview(data)[HEADER_SIZE : HEADER_SIZE + size], end == ">")
