"""Samples -> JSON, including values no sensor can mean, decoded from the bytes a peer could send."""

from __future__ import annotations

import math

from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as Op
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as Ins
from UMAA.Common.Measurement import DateTime
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from sem_console.codec.convert import to_json


def test_unknown_enum_ordinal_from_the_wire_is_flagged() -> None:
    sample = InertialSensorReportType(state=Ins.ON, status=Op.INIT, source=bytes(range(16)), timeStamp=DateTime(1, 2))
    raw = bytearray(sample.serialize())
    raw[4] = 99  # the state member's ordinal, as another vendor's writer could send it
    decoded = InertialSensorReportType.deserialize(bytes(raw))  # what the console's reader hands over
    report, invalid = to_json(decoded)
    assert report["state"] is None and report["status"] == "INIT"
    assert invalid == ["state: unknown InertialSensorStateEnumType ordinal 99"]
    assert report["source"] == "00010203-0405-0607-0809-0a0b0c0d0e0f"


def test_nan_and_out_of_range() -> None:
    sample = InertialSensorReportType(state=Ins.ON, status=Op.INIT, source=bytes(range(16)), timeStamp=DateTime(1, 2_000_000_000))
    _report, invalid = to_json(sample)
    assert invalid == ["timeStamp.nanoseconds: 2000000000 outside 0..1e+09"]
    from sem_console.codec.convert import _value

    bad: list[str] = []
    assert _value(math.inf, "SOG", bad) is None and bad == ["SOG: inf is not a number"]
