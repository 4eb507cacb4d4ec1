"""NumericGUID <-> uuid.UUID, stable GUIDs, and the satelliteId convention.

satelliteId layout (RFC 4122 variant, version 5, so it is a valid UMAA GUID):
bytes 0..13 are fixed (taken from uuid5(NAMESPACE_URL, "urn:sem-console:gnss-satellite")),
byte 14 is the GPSConstellationEnumType ordinal and byte 15 the PRN or slot number.
A display that sees that prefix labels the satellite as a letter plus the PRN
(G12, E07, R05, C21, S133, J02, I04); any other GUID is shown as a short hex id.
"""

from __future__ import annotations

import uuid
from collections.abc import Sequence

from UMAA.Common.MaritimeEnumeration.GPSConstellationEnumType import GPSConstellationEnumType as Constellation

SAT_PREFIX = uuid.uuid5(uuid.NAMESPACE_URL, "urn:sem-console:gnss-satellite").bytes[:14]
SAT_LETTER = {
    Constellation.GPS: "G",
    Constellation.GALILEO: "E",
    Constellation.GLONASS: "R",
    Constellation.BEIDOU: "C",
    Constellation.SBAS: "S",
    Constellation.QZSS: "J",
    Constellation.IRNSS: "I",
    Constellation.UNKNOWN: "U",
}


def to_guid(u: uuid.UUID) -> list[int]:
    return list(u.bytes)


def from_guid(g: Sequence[int] | bytes) -> uuid.UUID:
    return uuid.UUID(bytes=bytes(g))


def stable_guid(name: str) -> uuid.UUID:
    """A GUID that is the same every run for the same name (RFC 4122 version 5)."""
    return uuid.uuid5(uuid.NAMESPACE_URL, f"urn:sem-console:{name}")


def satellite_guid(constellation: Constellation, prn: int) -> list[int]:
    if not 0 < prn < 256:
        raise ValueError(f"PRN {prn} out of 1..255")
    return list(SAT_PREFIX + bytes([int(constellation.value), prn]))


def satellite_label(g: Sequence[int] | bytes | None) -> str | None:
    if g is None:
        return None
    raw = bytes(g)
    if len(raw) == 16 and raw[:14] == SAT_PREFIX:
        try:
            return f"{SAT_LETTER[Constellation(raw[14])]}{raw[15]:02d}"
        except ValueError:
            pass
    return raw.hex()[:8]
