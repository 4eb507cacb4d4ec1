"""UMAA 6.0 reports into the console's model (the package's docstring).

- `UMAA::SEM::GPSStatus::GPSReportType` feeds the model's GPSReport: the clock and every satellite, member for member.
  A 6.0 satellite's `satelliteID` is a number; the model's `satelliteId` is the console's satellite GUID made of the
  constellation and that number (`umaa/guid.py`), so the dashboard labels it as it labels a 3.0.1 satellite (G17).
  The clock's `timeFigureOfMerit` has no member in the model yet and is left out; its `timeUncertainty` is null.
- `UMAA::SA::GlobalPoseStatus::GlobalPoseReportType` and `UMAA::SEM::InertialSensorStatus::InertialSensorReportType`
  count for the vehicle's link (their samples, their instances) under their own topic names; their position and
  alignment stage have no place in the model yet (`model` None).
- Commanding (`versions/commands.py` takes it): InertialSensorCommandType built from the console's command
  (`ins_command`: source and destination as IdentifierType), and a CommandStatusType read into the model's one command
  status (`command_status`); a provider's status and ack (`ins_status`, `ins_ack`: the ack carries the whole command).
"""

from __future__ import annotations

import functools
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum
from typing import Any

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.GPSConstellationEnumType import GPSConstellationEnumType as Constellation
from UMAA_6_0.Common import IdentifierType
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusEnumModule import CommandStatusEnumType as Status60
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusReasonEnumModule import CommandStatusReasonEnumType as Reason60
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as InsCmd
from UMAA_6_0.Common.Measurement import DateTime
from UMAA_6_0.SEM.InertialSensorControl import (
    InertialSensorCommandAckReportType,
    InertialSensorCommandStatusType,
    InertialSensorCommandType,
)

from sem_console.dds.topics import Sem60
from sem_console.umaa.flow import AnyReason, parse_reason
from sem_console.umaa.guid import satellite_guid
from sem_console.umaa.samples import make

# The 6.0 clock member the model names differently (the 3.0.1 IDL's spelling); the one the model has and 6.0 does
# not (null: not reported; 6.0 reports the time's quality as a figure of merit instead, which the model lacks)
_CLOCK_NAMES = {"biasUncertainty": "biasUncertianty"}
_CLOCK_LEFT_OUT = {"timeFigureOfMerit"}
_CLOCK_NOT_REPORTED = {"timeUncertainty": None}


@functools.cache
def _satellite_id(number: Any, constellation: Any) -> str | None:
    """The console's GUID for a 6.0 satellite: its constellation and its number (None when either is not usable).
    Cached: a receiver sees a few dozen satellites, reported every second."""
    if not isinstance(number, float | int) or not float(number).is_integer() or not isinstance(constellation, str) \
            or constellation not in Constellation.__members__:
        return None
    try:
        return str(uuid.UUID(bytes=bytes(satellite_guid(Constellation[constellation], int(number)))))
    except ValueError:  # out of 1..255
        return None


def _satellite(s: dict[str, Any]) -> dict[str, Any]:
    """A 6.0 satellite (its JSON, fresh from the decoder) made the model's in place: satelliteID as satelliteId."""
    s["satelliteId"] = _satellite_id(s.pop("satelliteID", None), s.get("constellationType"))
    return s


def gps_report(report: dict[str, Any]) -> dict[str, Any]:
    """A 6.0 GPSReportType (its JSON, `codec`) as the model's GPSReport."""
    clock = report.get("clock") or {}
    return {
        "clock": {**{_CLOCK_NAMES.get(k, k): v for k, v in clock.items() if k not in _CLOCK_LEFT_OUT}, **_CLOCK_NOT_REPORTED},
        "numberSatellitesInView": report.get("numberSatellitesInView"),
        "satellites": [_satellite(s) for s in report.get("satellites") or []],
        "source": source_of(report),
        "timeStamp": report.get("timeStamp"),
    }


def source_of(report: dict[str, Any]) -> str | None:
    """The vehicle a 6.0 sample comes from: the `id` of its `source` (UMAA::Common::IdentifierType)."""
    source = report.get("source")
    return source.get("id") if isinstance(source, dict) else None


@dataclass(frozen=True)
class Report:
    """What the console makes of one 6.0 report topic."""

    topic: str  # the topic the vehicle's link health counts it under: the model's topic when it feeds one
    model: Callable[[dict[str, Any]], dict[str, Any]] | None  # its JSON as the model's report; None: health only


REPORTS: dict[Sem60, Report] = {
    Sem60.GPS_REPORT: Report("GPSReport", gps_report),
    Sem60.GLOBAL_POSE_REPORT: Report("GlobalPoseReportType", None),
    Sem60.INS_REPORT: Report("InertialSensorReportType", None),
}


# ---- commanding: InertialSensorControl (UMAA 6.0 SEM ICD 4.1) -------------------------------------------------------
NIL_GUID = bytes(16)  # a parentID: the console and the simulated vehicles have no parent


def identifier(guid: uuid.UUID) -> IdentifierType:
    """A vehicle's or a console's UMAA::Common::IdentifierType: its GUID as `id`, no parent."""
    return make(IdentifierType, id=list(guid.bytes), parentID=list(NIL_GUID))


INS_COMMAND_STATES: tuple[str, ...] = tuple(InsCmd.__members__)  # BEST_ALIGN, GPS_ALIGN, INIT, SNAP_ALIGN, ...


def ins_command(source: uuid.UUID, destination: uuid.UUID, session: uuid.UUID, state: str | None,
                stamp: tuple[int, int]) -> InertialSensorCommandType:
    """An InertialSensorCommandType of the console (`source`) to a vehicle (`destination`); `state` a literal of
    INS_COMMAND_STATES (KeyError otherwise)."""
    return make(InertialSensorCommandType, state=InsCmd[state or ""],
                timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]), source=identifier(source),
                sessionID=list(session.bytes), destination=identifier(destination))


def command_status(sample: Any) -> tuple[Status | int, AnyReason | int]:
    """A CommandStatusType's status and reason in the model (`umaa/flow.py`): the same literals, by name (6.0's
    enumerations are alphabetical, 3.0.1's are not), UPDATED the model's own; an ordinal neither has stays a number."""
    status, reason = sample.commandStatus, sample.commandStatusReason
    return (Status[status.name] if isinstance(status, Enum) else status,
            (parse_reason(reason.name) if isinstance(reason, Enum) else reason))


def ins_status(source: uuid.UUID, command: Any, status: Status, reason: AnyReason, message: str,
               stamp: tuple[int, int]) -> InertialSensorCommandStatusType:
    """A provider's InertialSensorCommandStatusType for `command` (its InertialSensorCommandType): the model's status
    and reason as 6.0's literals of the same names."""
    return make(InertialSensorCommandStatusType,
                timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]), source=identifier(source),
                sessionID=command.sessionID, commandStatus=Status60[status.name], commandStatusReason=Reason60[reason.name],
                logMessage=message[:4095])


def ins_ack(source: uuid.UUID, command: Any, stamp: tuple[int, int]) -> InertialSensorCommandAckReportType:
    """A provider's InertialSensorCommandAckReportType: the command it executes, whole."""
    return InertialSensorCommandAckReportType(command=command, timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]),
                                              source=identifier(source), sessionID=command.sessionID)
