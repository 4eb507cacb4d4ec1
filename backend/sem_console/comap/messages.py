"""The CoMap message table: the one declarative description of every message layout we speak.

Written from the CoMap message definitions (IMC 5.x, sync 0xFE55). Each message is an IMC id, an
abbreviation and its fields in wire order; a field is (name, type) where type is one of

- "u8", "u16", "fp32", "fp64": little- or big-endian as the packet says (IMC uint8_t, uint16_t, fp32_t, fp64_t);
- ("list", GROUP): IMC message-list: u16 count, then each element as its u16 id and its payload;
- ("msg", GROUP): IMC inline message: u16 id then its payload, or the id 0xFFFF for none (None).

GROUP names the ids an element may have (a message group, or one message). `codec.py` walks this
table to encode and to decode; there is no hand-written encoder or decoder for any message.

| id   | abbrev                | payload (bytes) | fields |
|------|-----------------------|-----------------|--------|
| 604  | MapPoint              | 20   | lat fp64 rad, lon fp64 rad, alt fp32 m |
| 3001 | WorldModel            | 4+   | geo_features list<GeoFeature>, cov_states list<CoverageState> |
| 3002 | GeoFeature            | 4+   | feature_id u16, points list<MapPoint> (1 point, 2 line, 3+ polygon) |
| 3003 | CoverageState         | 3    | feature_id u16, state u8 (COV: 1 COMPLETED, 2 PARTIAL, 3 NONE) |
| 3004 | TaskAdmin             | 5+   | tid u16, op u8 (TAOP: 1 ACCEPT .. 6 STATUS_REQUEST), arg msg<TaskAdminArgs> |
| 3005 | SynchAdmin            | 1    | op u8 (SYNCOP: 1 HOLD, 2 RESUME, 3 INTERRUPT) |
| 3006 | VehicleCapabilities   | 2+   | capabilities list<VehicleCapability> |
| 3010 | CapabilityAreaSurvey  | 17   | sensor u8, resolution fp32 px/m², res_bathym_factor fp32, cov_rate fp32 m²/s,
|      |                       |      | cov_bathym_factor fp32 |
| 3011 | CapabilityPointSurvey | 9    | sensor u8, resolution fp32 px/m², duration fp32 s |
| 3012 | CapabilityMove        | 4    | speed fp32 m/s |
| 3101 | SurveyTask            | 17   | task_id u16, feature_id u16, sensor u8, resolution fp32 px/m²,
|      |                       |      | deadline fp64 s since epoch |
| 3102 | MoveTask              | 32   | task_id u16, destination msg<MapPoint>, deadline fp64 s since epoch |
| 3103 | TaskStatus            | 5    | task_id u16, status u8 (SSTATUS: 1 COMPLETED, 2 IN_PROGRESS, 3 ERROR, 4 ASSIGNED),
|      |                       |      | progress u8 %, quality u8 % |
| 3104 | SynchTask             | 14   | task_id u16, feature_id u16, time_window u16 s, deadline fp64 s since epoch |

The definitions name a sensor type enum without listing its values; the project numbers it as
SENSOR below (0 ANY: the task takes whatever sensor the vehicle has).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

FieldType = str | tuple[str, str]


@dataclass(frozen=True)
class Layout:
    id: int
    name: str
    fields: tuple[tuple[str, FieldType], ...]


class Coverage(IntEnum):
    COMPLETED = 1
    PARTIAL = 2
    NONE = 3


class TaskOp(IntEnum):
    ACCEPT = 1
    REJECT = 2
    ASSIGN = 3
    UNASSIGN = 4
    STATUS = 5
    STATUS_REQUEST = 6


class SynchOp(IntEnum):
    HOLD = 1
    RESUME = 2
    INTERRUPT = 3


class TaskStatusEnum(IntEnum):
    COMPLETED = 1
    IN_PROGRESS = 2
    ERROR = 3
    ASSIGNED = 4


class Sensor(IntEnum):
    """Not enumerated by the CoMap definitions: the project's own numbering."""

    ANY = 0
    SIDESCAN = 1
    MULTIBEAM = 2
    CAMERA = 3
    MAGNETOMETER = 4


LAYOUTS: tuple[Layout, ...] = (
    Layout(604, "MapPoint", (("lat", "fp64"), ("lon", "fp64"), ("alt", "fp32"))),
    Layout(3001, "WorldModel", (("geo_features", ("list", "GeoFeature")), ("cov_states", ("list", "CoverageState")))),
    Layout(3002, "GeoFeature", (("feature_id", "u16"), ("points", ("list", "MapPoint")))),
    Layout(3003, "CoverageState", (("feature_id", "u16"), ("state", "u8"))),
    Layout(3004, "TaskAdmin", (("tid", "u16"), ("op", "u8"), ("arg", ("msg", "TaskAdminArgs")))),
    Layout(3005, "SynchAdmin", (("op", "u8"),)),
    Layout(3006, "VehicleCapabilities", (("capabilities", ("list", "VehicleCapability")),)),
    Layout(
        3010,
        "CapabilityAreaSurvey",
        (
            ("sensor", "u8"),
            ("resolution", "fp32"),
            ("res_bathym_factor", "fp32"),
            ("cov_rate", "fp32"),
            ("cov_bathym_factor", "fp32"),
        ),
    ),
    Layout(3011, "CapabilityPointSurvey", (("sensor", "u8"), ("resolution", "fp32"), ("duration", "fp32"))),
    Layout(3012, "CapabilityMove", (("speed", "fp32"),)),
    Layout(
        3101,
        "SurveyTask",
        (("task_id", "u16"), ("feature_id", "u16"), ("sensor", "u8"), ("resolution", "fp32"), ("deadline", "fp64")),
    ),
    Layout(3102, "MoveTask", (("task_id", "u16"), ("destination", ("msg", "MapPoint")), ("deadline", "fp64"))),
    Layout(3103, "TaskStatus", (("task_id", "u16"), ("status", "u8"), ("progress", "u8"), ("quality", "u8"))),
    Layout(3104, "SynchTask", (("task_id", "u16"), ("feature_id", "u16"), ("time_window", "u16"), ("deadline", "fp64"))),
)

BY_ID: dict[int, Layout] = {m.id: m for m in LAYOUTS}
BY_NAME: dict[str, Layout] = {m.name: m for m in LAYOUTS}

# Message groups: the messages an inline message or a message-list element may be.
GROUPS: dict[str, frozenset[str]] = {
    "TaskAdminArgs": frozenset({"SurveyTask", "MoveTask", "TaskStatus", "SynchTask"}),
    "VehicleCapability": frozenset({"CapabilityAreaSurvey", "CapabilityPointSurvey", "CapabilityMove"}),
    **{m.name: frozenset({m.name}) for m in LAYOUTS},
}
