"""JAUS over JUDP (AS5669A): the transport header, our field-type table, and the records we write.

JUDP datagram, little-endian: the version byte 0x02, then one or more messages one after the other (AS5669A lets a
sender pack several into one datagram; we send one). Each message (offsets from its start):

    byte 0       message type / header-compression flags, 0
    bytes 1-2    size u16: the whole message, this header included (14 + message id + body)
    byte 3       flags: priority bits 0-1, broadcast bits 2-3, ack/nak bits 4-5, packet flags bits 6-7
    bytes 4-7    destination id; bytes 8-11 source id (each: component u8, node u8, subsystem u16)
    12-13        message id u16, then the body, then a sequence number u16

A record's presence vector has bit i set when its i-th optional field is present (from bit 0).
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass
from typing import NamedTuple

VERSION = 2
HEADER = struct.Struct("<BBHBBBHBBH")  # version .. source id
MESSAGE_ID = struct.Struct("<H")
SEQUENCE = struct.Struct("<H")
OVERHEAD = 14  # size = OVERHEAD + 2 (message id) + body
MIN_PACKET = HEADER.size + MESSAGE_ID.size + SEQUENCE.size

QUERY_NAVIGATION = 0x2421
REPORT_NAVIGATION = 0x4421
QUERY_COMMS_LOST_CONFIGURATION = 0x2C03
REPORT_COMMS_LOST_CONFIGURATION = 0x4C03


@dataclass(frozen=True)
class FieldType:
    """An unsigned integer of `bits`; scaled when `lo`/`hi` are given: value = raw * (hi - lo) / (2**bits - 1) + lo."""

    bits: int
    lo: float | None = None
    hi: float | None = None

    @property
    def code(self) -> str:
        return {8: "B", 16: "H", 32: "I"}[self.bits]

    def raw(self, value: float) -> int | None:
        """The integer for `value`, or None when it is outside the type's range (the field is then not sent)."""
        top = (1 << self.bits) - 1  # an int (2**n is typed as int | float)
        if self.lo is None or self.hi is None:
            v = int(value)
            return v if 0 <= v <= top else None
        if not math.isfinite(value) or not self.lo <= value <= self.hi:
            return None
        return round((value - self.lo) / (self.hi - self.lo) * top)

    def value(self, raw: int) -> float:
        if self.lo is None or self.hi is None:
            return float(raw)
        return raw * (self.hi - self.lo) / ((1 << self.bits) - 1) + self.lo


U32, U16 = 32, 16
# The one table of field types the spec leaves blank (our choice, README "Gateways"). A field not in it is never sent.
FIELD_TYPES: dict[str, FieldType] = {
    "TimeSeconds": FieldType(U32),
    "TimeNanoSeconds": FieldType(U32),
    "Latitude": FieldType(U32, -90.0, 90.0),
    "Longitude": FieldType(U32, -180.0, 180.0),
    "AltitudeAGL": FieldType(U32, -10_000.0, 35_000.0),
    "AltitudeMSL": FieldType(U32, -10_000.0, 35_000.0),
    "AltitudeASF": FieldType(U32, -10_000.0, 35_000.0),
    "Depth": FieldType(U32, -10_000.0, 35_000.0),
    "XYPositionRMS": FieldType(U32, 0.0, 100.0),
    "ZPositionRMS": FieldType(U32, 0.0, 100.0),
    "Roll": FieldType(U16, -math.pi, math.pi),
    "Pitch": FieldType(U16, -math.pi, math.pi),
    "Heading": FieldType(U16, -math.pi, math.pi),
    "Course": FieldType(U16, -math.pi, math.pi),
    "Velocity_N": FieldType(U32, -327.68, 327.68),
    "Velocity_E": FieldType(U32, -327.68, 327.68),
    "Velocity_D": FieldType(U32, -327.68, 327.68),
    "SpeedOverGround": FieldType(U16, 0.0, 327.67),
}

# ReportNavigation's records: presence-vector width (bits) and optional fields in order (bit 0 first)
GLOBAL_POSE = (
    16,
    (
        "Latitude",
        "Longitude",
        "AltitudeAGL",
        "AltitudeMSL",
        "AltitudeASF",
        "Depth",
        "XYPositionRMS",
        "ZPositionRMS",
        "Roll",
        "Pitch",
        "Heading",
        "Attitude_RMS",
        "Course",
        "TimeSeconds",
        "TimeNanoSeconds",
    ),
)
LOCAL_POSE = (
    16,
    (
        "X",
        "Y",
        "AltitudeAGL",
        "AltitudeMSL",
        "AltitudeASF",
        "Depth",
        "ZLocal",
        "XYPositionRMS",
        "ZPositionRMS",
        "Roll",
        "Pitch",
        "Heading",
        "Attitude_RMS",
        "Course",
        "TimeSeconds",
        "TimeNanoSeconds",
    ),
)
VELOCITY_NED = (8, ("Velocity_N", "Velocity_E", "Velocity_D"))
VELOCITY_STATE = (
    16,
    (
        "Velocity_RMS",
        "RollRate",
        "PitchRate",
        "YawRate",
        "Rate_RMS",
        "SpeedOverGround",
        "SpeedRelativeToMedium",
        "RotationsPerMinute",
        "IndicatedSpeed",
        "TimeSeconds",
        "TimeNanoSeconds",
    ),
)
ACCELERATION_STATE = (
    16,
    (
        "Acceleration_X",
        "Acceleration_Y",
        "Acceleration_Z",
        "Acceleration_RMS",
        "RollAcceleration",
        "PitchAcceleration",
        "YawAcceleration",
        "RotationalAcceleration_RMS",
        "TimeSeconds",
        "TimeNanoSeconds",
    ),
)
VELOCITY_NED_TAG = 2  # VelocityVar: 0 VelocityVehicleXYZRec, 1 VelocityLocalXYZRec, 2 VelocityNEDRec
COMMS_LOST_POLICIES = {"STOP_MISSION": 0, "CONTINUE_MISSION": 1}  # CommsLostPolicyVar tags we report


class JausId(NamedTuple):
    subsystem: int
    node: int
    component: int

    def __str__(self) -> str:
        return f"{self.subsystem}.{self.node}.{self.component}"


class Malformed(ValueError):
    """A datagram that is not one well-formed JUDP message; the reason names a counter."""


class Packet(NamedTuple):
    flags: int
    destination: JausId
    source: JausId
    message_id: int
    body: bytes
    sequence: int


def parse(data: bytes) -> list[Packet]:
    """Every message of a datagram, in order; Malformed when any of them is (its framing then cannot be trusted)."""
    if len(data) < MIN_PACKET:
        raise Malformed("short")
    if data[0] != VERSION:
        raise Malformed("wrong version")
    out, at = [], 1
    while at < len(data):
        if len(data) - at < MIN_PACKET - 1:
            raise Malformed("short")
        _, kind, size, flags, dc, dn, ds, sc, sn, ss = HEADER.unpack_from(data, at - 1)  # the version byte is skipped
        if kind != 0:
            raise Malformed("header compression")
        if not MIN_PACKET - 1 <= size <= len(data) - at:
            raise Malformed("wrong size")
        if flags >> 6:
            raise Malformed("multi-packet")
        end = at + size
        (message_id,) = MESSAGE_ID.unpack_from(data, at - 1 + HEADER.size)
        body = data[at - 1 + HEADER.size + MESSAGE_ID.size : end - SEQUENCE.size]
        (sequence,) = SEQUENCE.unpack_from(data, end - SEQUENCE.size)
        out.append(Packet(flags, JausId(ds, dn, dc), JausId(ss, sn, sc), message_id, body, sequence))
        at = end
    return out


def packet(flags: int, destination: JausId, source: JausId, message_id: int, body: bytes, sequence: int) -> bytes:
    size = OVERHEAD + MESSAGE_ID.size + len(body)
    return (
        HEADER.pack(
            VERSION,
            0,
            size,
            flags,
            destination.component,
            destination.node,
            destination.subsystem,
            source.component,
            source.node,
            source.subsystem,
        )
        + MESSAGE_ID.pack(message_id)
        + body
        + SEQUENCE.pack(sequence & 0xFFFF)
    )


def record(layout: tuple[int, tuple[str, ...]], asked: int, values: dict[str, float]) -> bytes:
    """A record with the fields both `asked` for (presence bits) and present in `values` whose type the table gives."""
    width, names = layout
    present = 0
    fields = b""
    for bit, name in enumerate(names):
        ftype = FIELD_TYPES.get(name)
        if not asked >> bit & 1 or ftype is None or values.get(name) is None:
            continue
        raw = ftype.raw(values[name])
        if raw is None:
            continue
        present |= 1 << bit
        fields += struct.pack("<" + ftype.code, raw)
    return struct.pack("<B" if width == 8 else "<H", present) + fields
