"""UMAA 6.0 reports into the console's model (the package's docstring).

- `UMAA::SEM::GPSStatus::GPSReportType` feeds the model's GPSReport: the clock and every satellite, member for member.
  A 6.0 satellite's `satelliteID` is a number; the model's `satelliteId` is the console's satellite GUID made of the
  constellation and that number (`umaa/guid.py`), so the dashboard labels it as it labels a 3.0.1 satellite (G17).
  The clock's time quality is its `timeFigureOfMerit` (a member 6.0 adds to the model); its `timeUncertainty` is null.
- `UMAA::SA::GlobalPoseStatus::GlobalPoseReportType` feeds the model's position report (GPSFixReport): its position
  (at its timeStamp), course (trueCourse) and MSL altitude (altitudeMSL); whether the position is measured
  (GPSLatLongValid: true when MEASURED or GROUND_TRUTH, false when ESTIMATED, as a 3.0.1 position from the INS); and
  the members 6.0 adds to the model (`MODEL_MEMBERS`): attitude, navigation solution, the other altitudes, depth and the
  covariances, null when the vehicle leaves them out. It reports no speed over ground, magnetic variation, velocity or
  receiver fix state: those are null.
- `UMAA::SEM::InertialSensorStatus::InertialSensorReportType` feeds the model's InertialSensorReport: its `status` (the
  stage of each kind of alignment, or a failure; literals 6.0 adds to the model's, `MODEL_LITERALS`). 6.0 reports no
  power state: `state` is null.

- Commanding (`versions/commands.py` takes it): InertialSensorCommandType built from the console's command
  (`ins_command`: source and destination as IdentifierType), and a CommandStatusType read into the model's one command
  status (`command_status`); a provider's status and ack (`ins_status`, `ins_ack`: the ack carries the whole command).

An invalid value the decoder flagged is named by the model's path ("position2DWithTime.geodeticPosition....").
"""

from __future__ import annotations

import functools
import re
import uuid
from dataclasses import dataclass
from enum import Enum
from typing import Any, get_type_hints

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.GPSConstellationEnumType import GPSConstellationEnumType as Constellation
from UMAA_6_0.Common import IdentifierType
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusEnumModule import CommandStatusEnumType as Status60
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusReasonEnumModule import CommandStatusReasonEnumType as Reason60
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as InsCmd
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorOpStatusEnumModule import InertialSensorOpStatusEnumType as OpStatus
from UMAA_6_0.Common.Measurement import DateTime
from UMAA_6_0.SA.GlobalPoseStatus import GlobalPoseReportType
from UMAA_6_0.SEM.GPSStatus import GPSClockType
from UMAA_6_0.SEM.InertialSensorControl import (
    InertialSensorCommandAckReportType,
    InertialSensorCommandStatusType,
    InertialSensorCommandType,
)

from sem_console.dds.topics import Sem60
from sem_console.umaa.flow import AnyReason, parse_reason
from sem_console.umaa.guid import satellite_guid
from sem_console.umaa.samples import make
from sem_console.versions.shape import Adapter, Lookup, Seconds, Spec, Src, Unless, apply

# The 6.0 clock member the model names differently (the 3.0.1 IDL's spelling); the one the model has and 6.0 does
# not (null: not reported; 6.0 says the time's quality as its figure of merit instead)
_CLOCK_NAMES = {"biasUncertainty": "biasUncertianty"}
_CLOCK_NOT_REPORTED = {"timeUncertainty": None}
# The 6.0 members the model has under another path, for the invalid values the decoder names (6.0's member names are
# unique across its three reports)
_PATHS = {
    "position.geodeticLatitude": "position2DWithTime.geodeticPosition.geodeticLatitude.latitude",
    "position.geodeticLongitude": "position2DWithTime.geodeticPosition.geodeticLongitude.longitude",
    "course": "trueCourse",
    "altitude": "altitudeMSL.altitude",
    "source.id": "source",
    "clock.biasUncertainty": "clock.biasUncertianty",
}
_SATELLITE_ID = re.compile(r"^(satellites\[[^\]]+\])\.satelliteID")
_POSE_ADDS = (
    "altitudeAGL",
    "altitudeASF",
    "altitudeGeodetic",
    "attitude",
    "attitudeCovariance",
    "depth",
    "navigationSolution",
    "positionCovariance",
)
MEASURED = {"MEASURED": True, "GROUND_TRUTH": True, "ESTIMATED": False}  # navigationSolution -> GPSLatLongValid

MODEL_MEMBERS: dict[str, dict[str, Any]] = {
    "GPSFixReportType": {n: h for n, h in get_type_hints(GlobalPoseReportType, include_extras=True).items() if n in _POSE_ADDS},
    "GPSClockType": {"timeFigureOfMerit": get_type_hints(GPSClockType, include_extras=True)["timeFigureOfMerit"]},
}
"""The members 6.0 adds to the console's model, by the model's struct: optional there (absent from a 3.0.1 vehicle's
report, null when a 6.0 vehicle leaves an optional member out)."""
MODEL_LITERALS: dict[str, type[Enum]] = {"InertialSensorOpStatusEnumType": OpStatus}
"""The literals 6.0 adds to an enumeration of the model, by its name: the model's INS status is either version's."""


def model_path(path: str) -> str:
    """The model's path of a wire report's member, as an invalid value is named ("course" -> "trueCourse")."""
    return _SATELLITE_ID.sub(r"\1.satelliteId", _PATHS.get(path, path))


def _renamed(invalid: list[str]) -> list[str]:
    """The decoder's invalid-value messages ("path: why") with each path the model's."""
    out = []
    for message in invalid:
        path, sep, why = message.partition(": ")
        out.append(model_path(path) + sep + why)
    return out


@functools.cache
def _satellite_id(number: Any, constellation: Any) -> str | None:
    """The console's GUID for a 6.0 satellite: its constellation and its number (None when either is not usable).
    Cached: a receiver sees a few dozen satellites, reported every second."""
    if (
        not isinstance(number, float | int)
        or not float(number).is_integer()
        or not isinstance(constellation, str)
        or constellation not in Constellation.__members__
    ):
        return None
    try:
        return str(uuid.UUID(bytes=bytes(satellite_guid(Constellation[constellation], int(number)))))
    except ValueError:  # out of 1..255
        return None


def gps_report(report: dict[str, Any], invalid: list[str]) -> tuple[dict[str, Any], list[str]]:
    """A 6.0 GPSReportType (its JSON and invalid values, `codec`) as the model's GPSReport. Each satellite (its JSON,
    fresh from the decoder) is made the model's in place: satelliteID as satelliteId; a number no satellite has (not a
    whole number 1..255) is null and listed in `invalid`, as the decoder lists a value a sensor cannot mean."""
    clock = report.get("clock") or {}
    unnamed: list[str] = []
    satellites = report.get("satellites") or []
    for i, sat in enumerate(satellites):  # a loop, not a call per satellite: a report has dozens, every second
        number, constellation = sat.pop("satelliteID", None), sat.get("constellationType")
        sat["satelliteId"] = sid = _satellite_id(number, constellation)
        if sid is None and number is not None and constellation is not None:
            unnamed.append(f"satellites[{i}].satelliteId: {number!r} is no satellite number (a whole number 1..255)")
    return {
        "clock": {**{_CLOCK_NAMES.get(k, k): v for k, v in clock.items()}, **_CLOCK_NOT_REPORTED},
        "numberSatellitesInView": report.get("numberSatellitesInView"),
        "satellites": satellites,
        "source": source_of(report),
        "timeStamp": report.get("timeStamp"),
    }, (_renamed(invalid) if invalid else invalid) + unnamed


GLOBAL_POSE: Spec = {
    "altitudeMSL": Unless("altitude", {"altitude": Src("altitude")}),
    "GPSFixCommandStatus": None,
    "GPSLatLongValid": Lookup("navigationSolution", MEASURED),
    "magneticVariation": None,
    "position2DWithTime": {
        "geodeticPosition": {
            "geodeticLatitude": {"latitude": Src("position.geodeticLatitude")},
            "geodeticLongitude": {"longitude": Src("position.geodeticLongitude")},
        },
        "timeAtPosition": Seconds("timeStamp"),
    },
    "SOG": None,
    "trueCourse": Src("course"),
    "velocity": None,
    "source": Src("source.id"),
    "timeStamp": Src("timeStamp"),
    **{name: Src(name) for name in _POSE_ADDS},
}
"""A 6.0 GlobalPoseReportType as the model's position report (GPSFixReport)."""
INS_REPORT: Spec = {"state": None, "status": Src("status"), "source": Src("source.id"), "timeStamp": Src("timeStamp")}
"""A 6.0 InertialSensorReportType as the model's InertialSensorReport: its status; no power state (null)."""


def _applied(spec: Spec) -> Adapter:
    """The adapter of a report said by `spec`, for its JSON as cyclonedds decodes it."""

    def adapt(report: dict[str, Any], invalid: list[str]) -> tuple[dict[str, Any], list[str]]:
        return apply(spec, report), _renamed(invalid) if invalid else invalid

    return adapt


def source_of(report: dict[str, Any]) -> str | None:
    """The vehicle a 6.0 sample comes from: the `id` of its `source` (UMAA::Common::IdentifierType)."""
    source = report.get("source")
    return source.get("id") if isinstance(source, dict) else None


@dataclass(frozen=True)
class Report:
    """What the console makes of one 6.0 report topic."""

    topic: str  # the model's report topic it feeds (the vehicle's link health counts it under that name)
    model: Adapter  # its JSON and invalid values as the model's
    spec: Spec = None  # the same as data, when it can be said so: the generated decoder returns the model's JSON


REPORTS: dict[Sem60, Report] = {
    Sem60.GPS_REPORT: Report("GPSReport", gps_report),
    Sem60.GLOBAL_POSE_REPORT: Report("GPSFixReport", _applied(GLOBAL_POSE), GLOBAL_POSE),
    Sem60.INS_REPORT: Report("InertialSensorReport", _applied(INS_REPORT), INS_REPORT),
}


# ---- commanding: InertialSensorControl (UMAA 6.0 SEM ICD 4.1) -------------------------------------------------------
NIL_GUID = bytes(16)  # a parentID: the console and the simulated vehicles have no parent (ICD 6.0 5.2.9, Table 24)


def identifier(guid: uuid.UUID, parent: uuid.UUID | None = None) -> IdentifierType:
    """A vehicle's or a console's UMAA::Common::IdentifierType: its GUID as `id`, its parent's as `parentID` (the nil
    UUID when it has none: the root of its tree, ICD 6.0 5.2.9)."""
    return make(IdentifierType, id=list(guid.bytes), parentID=list(parent.bytes if parent is not None else NIL_GUID))


INS_COMMAND_STATES: tuple[str, ...] = tuple(InsCmd.__members__)  # BEST_ALIGN, GPS_ALIGN, INIT, SNAP_ALIGN, ...


def ins_command(
    source: uuid.UUID,
    destination: uuid.UUID,
    session: uuid.UUID,
    state: str | None,
    stamp: tuple[int, int],
    parent: uuid.UUID | None = None,
) -> InertialSensorCommandType:
    """An InertialSensorCommandType of the console (`source`) to a vehicle (`destination`, whose identifier has the
    `parent` it reports in its own source: a command's destination is the provider's identifier, ICD 6.0 4.1 and 5.2.9);
    `state` a literal of INS_COMMAND_STATES (KeyError otherwise)."""
    return make(
        InertialSensorCommandType,
        state=InsCmd[state or ""],
        timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]),
        source=identifier(source),
        sessionID=list(session.bytes),
        destination=identifier(destination, parent),
    )


def command_status(sample: Any) -> tuple[Status | int, AnyReason | int]:
    """A CommandStatusType's status and reason in the model (`umaa/flow.py`): the same literals, by name (6.0's
    enumerations are alphabetical, 3.0.1's are not), UPDATED the model's own; an ordinal neither has stays a number."""
    status, reason = sample.commandStatus, sample.commandStatusReason
    return (
        Status[status.name] if isinstance(status, Enum) else status,
        (parse_reason(reason.name) if isinstance(reason, Enum) else reason),
    )


def ins_status(
    source: uuid.UUID, command: Any, status: Status, reason: AnyReason, message: str, stamp: tuple[int, int]
) -> InertialSensorCommandStatusType:
    """A provider's InertialSensorCommandStatusType for `command` (its InertialSensorCommandType): the model's status
    and reason as 6.0's literals of the same names."""
    return make(
        InertialSensorCommandStatusType,
        timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]),
        source=identifier(source),
        sessionID=command.sessionID,
        commandStatus=Status60[status.name],
        commandStatusReason=Reason60[reason.name],
        logMessage=message[:4095],
    )


def ins_ack(source: uuid.UUID, command: Any, stamp: tuple[int, int]) -> InertialSensorCommandAckReportType:
    """A provider's InertialSensorCommandAckReportType: the command it executes, whole."""
    return InertialSensorCommandAckReportType(
        command=command,
        timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]),
        source=identifier(source),
        sessionID=command.sessionID,
    )
