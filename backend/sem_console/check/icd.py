"""What the checker knows of ICD 3.0.1 and the UMAA 3.0.1 IDL, as data: the SEM services, their
topics, the section and table of each, and each topic type's name, members and keys. The
types come from the generated code (`backend/UMAA`), the one translation of the IDL in `idl/`.

`Version` gathers what a run asks of the UMAA version it tests: this module's `V3_0_1`, and
`umaa_6_0.V6_0` (UMAA 6.0)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields

from cyclonedds.core import Qos

from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import AnySem, Sem


@dataclass(frozen=True)
class ServiceDef:
    name: str  # the ICD's service name
    section: str  # its ICD section and operations table
    topics: tuple[AnySem, ...]


SERVICES = (
    ServiceDef("GPSFixControl", "ICD 5.1.1, Table 6", (Sem.GPS_FIX_COMMAND, Sem.GPS_FIX_COMMAND_STATUS, Sem.GPS_FIX_COMMAND_ACK)),
    ServiceDef("GPSFixStatus", "ICD 5.1.2, Table 10", (Sem.GPS_FIX_REPORT, Sem.GPS_FIX_STATUS_REPORT)),
    ServiceDef("GPSStatus", "ICD 5.1.3, Table 13", (Sem.GPS_REPORT,)),
    ServiceDef("InertialSensorControl", "ICD 5.1.4, Table 15", (Sem.INS_COMMAND, Sem.INS_COMMAND_STATUS, Sem.INS_COMMAND_ACK)),
    ServiceDef("InertialSensorStatus", "ICD 5.1.5, Table 19", (Sem.INS_REPORT,)),
)
SERVICE_OF = {sem: s for s in SERVICES for sem in s.topics}

# Each topic's operation section and message table.
TOPIC_REF: dict[AnySem, str] = {
    Sem.GPS_FIX_COMMAND_ACK: "ICD 5.1.1.1, Table 7",
    Sem.GPS_FIX_COMMAND_STATUS: "ICD 5.1.1.2, Table 8",
    Sem.GPS_FIX_COMMAND: "ICD 5.1.1.3, Table 9",
    Sem.GPS_FIX_REPORT: "ICD 5.1.2.1, Table 11",
    Sem.GPS_FIX_STATUS_REPORT: "ICD 5.1.2.2, Table 12",
    Sem.GPS_REPORT: "ICD 5.1.3.1, Table 14",
    Sem.INS_COMMAND_ACK: "ICD 5.1.4.1, Table 16",
    Sem.INS_COMMAND_STATUS: "ICD 5.1.4.2, Table 17",
    Sem.INS_COMMAND: "ICD 5.1.4.3, Table 18",
    Sem.INS_REPORT: "ICD 5.1.5.1, Table 20",
}


def short(sem: AnySem) -> str:
    """The ICD's topic name without its namespace: GPSFixReport."""
    return sem.spec.name.rsplit("::", 1)[-1]


def type_name(sem: AnySem) -> str:
    """The topic type's fully qualified IDL name: UMAA::SEM::GPSFixStatus::GPSFixReportType."""
    return sem.spec.type.__idl_typename__.replace(".", "::")


def members(t: type) -> list[str]:
    return [f.name for f in fields(t)]


def keys(t: type) -> set[str]:
    return {name for name, a in getattr(t, "__idl_field_annotations__", {}).items() if a.get("key")}


def key_ref(sem: AnySem) -> str:
    """Where the ICD marks the topic's key members (with *)."""
    if sem.spec.cls is TopicClass.COMMAND:
        return "ICD 5.2.2, Table 22 (UMAACommand)"
    if sem.spec.cls is TopicClass.STATUS:
        return "ICD 5.2.4, Table 24 (UMAACommandStatusBase)"
    return "ICD 5.2.3, Table 23 (UMAAStatus)"


# Where the ICD has each step of the command flow (section 4.1), by what the command tests cite
FLOW_REFS_3_0_1 = {
    "flow": "ICD 4.1, Figure 4",
    "figure": "Figure 4",
    "every": "ICD 4.1.4",
    "start": "ICD 4.1.4 step 3",
    "ack": "ICD 4.1.4.1 step 1",
    "commanded": "ICD 4.1.4.1 step 2",
    "executing": "ICD 4.1.4.1 step 3",
    "complete": "ICD 4.1.4.2",
    "failed": "ICD 4.1.4.3",
    "cancel": "ICD 4.1.4.4",
    "cancel figure": "Figure 14",
    "cleanup": "ICD 4.1.5, Figure 15",
    "subscribe": "ICD 4.1.2.1",
    "destination": "ICD 4.1",
    "ins ack": "ICD 5.1.4.1, Table 16",
    "ins report": "ICD 5.1.4.3 and 5.1.5.1",
}


@dataclass(frozen=True)
class Version:
    """What a run asks of the UMAA version it tests."""

    name: str  # "3.0.1", "6.0"
    idl: str  # how reasons name its IDL: "UMAA 3.0.1 IDL"
    services: tuple[ServiceDef, ...]
    topic_ref: Mapping[AnySem, str]
    key_ref: Callable[[AnySem], str]
    reports: tuple[AnySem, ...]
    flow: Mapping[str, str]  # FLOW_REFS_3_0_1's keys
    enum_ref: str  # where the ICD lists the enum literals
    types_ref: str  # its table of type definitions (ranges)
    # the QoS of a provider's endpoint against the version's QoS reference (reader: a command reader); None: the
    # project's profile, whose differences fail as `profile` (discovery.py)
    qos_reference: Callable[[AnySem, Qos, bool], list[str]] | None = None
    value_checks: Mapping[AnySem, Callable[..., list[str | None]]] = field(default_factory=dict)
    # a decoder's finding (codec/convert.py) with the section of its rule, None to drop it; None: reports.py's 3.0.1 one
    decoder_finding: Callable[[str], str | None] | None = None
    timing: Mapping[str, str] | None = None  # the timing test's references (reports.TIMING_REFS's keys); None: 3.0.1's

    @property
    def service_of(self) -> dict[AnySem, ServiceDef]:
        return {sem: s for s in self.services for sem in s.topics}


V3_0_1 = Version(
    "3.0.1",
    "UMAA 3.0.1 IDL",
    SERVICES,
    TOPIC_REF,
    key_ref,
    tuple(sem for s in SERVICES for sem in s.topics if sem.spec.cls is TopicClass.REPORT),
    FLOW_REFS_3_0_1,
    "ICD 5.3",
    "ICD 5.4, Table 45",
)
