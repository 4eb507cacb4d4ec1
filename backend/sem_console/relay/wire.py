"""What a relay puts on Zenoh: key `sem/<relay>/<domain>/<vehicle>/<topic>` (`<relay>`: the vehicles' relay's name, the
key space Zenoh's access control gives it), the payload the sample's CDR with its encapsulation
header (a dispose's or unregistration's: the instance's key CDR), and an attachment saying which of the three it is
and the sample's source timestamp."""

from __future__ import annotations

import struct
import uuid
from dataclasses import dataclass
from enum import IntEnum

PREFIX = "sem"
_ATTACHMENT = struct.Struct("<BBq")  # format version, kind, source timestamp (ns since the epoch)
FORMAT = 1


class Kind(IntEnum):
    SAMPLE = 0
    DISPOSE = 1  # the instance was disposed (a cancel, a cleanup, a report's end)
    UNREGISTER = 2  # the instance lost its last writer


def key(relay: str, domain: int, vehicle: uuid.UUID, topic: str) -> str:
    return f"{PREFIX}/{relay}/{domain}/{vehicle}/{topic}"


@dataclass(frozen=True)
class Address:
    relay: str  # the vehicles' relay the vehicle is heard through
    domain: int
    vehicle: uuid.UUID
    topic: str


def parse_key(text: str) -> Address | None:
    """The parts of a relay's key, or None for a key that is not one."""
    parts = text.split("/", 4)
    if len(parts) != 5 or parts[0] != PREFIX or not parts[2].isdigit():
        return None
    try:
        return Address(parts[1], int(parts[2]), uuid.UUID(parts[3]), parts[4])
    except ValueError:
        return None


def attachment(kind: Kind, source_ns: int) -> bytes:
    return _ATTACHMENT.pack(FORMAT, kind, source_ns)


def read_attachment(data: bytes | None) -> tuple[Kind, int] | None:
    """(kind, source timestamp), or None for an attachment of another format."""
    if data is None or len(data) != _ATTACHMENT.size:
        return None
    version, kind, ts = _ATTACHMENT.unpack(data)
    if version != FORMAT or kind not in Kind._value2member_map_:
        return None
    return Kind(kind), ts
