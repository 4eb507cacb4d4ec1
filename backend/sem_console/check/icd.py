"""What the checker knows of ICD 3.0.1 and the UMAA 3.0.1 IDL, as data: the SEM services, their
topics, the section and table of each, and each topic type's name, members and keys. The
types come from the generated code (`backend/UMAA`), the one translation of the IDL in `idl/`."""

from __future__ import annotations

from dataclasses import dataclass, fields

from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import Sem


@dataclass(frozen=True)
class ServiceDef:
    name: str  # the ICD's service name
    section: str  # its ICD section and operations table
    topics: tuple[Sem, ...]


SERVICES = (
    ServiceDef("GPSFixControl", "ICD 5.1.1, Table 6", (Sem.GPS_FIX_COMMAND, Sem.GPS_FIX_COMMAND_STATUS, Sem.GPS_FIX_COMMAND_ACK)),
    ServiceDef("GPSFixStatus", "ICD 5.1.2, Table 10", (Sem.GPS_FIX_REPORT, Sem.GPS_FIX_STATUS_REPORT)),
    ServiceDef("GPSStatus", "ICD 5.1.3, Table 13", (Sem.GPS_REPORT,)),
    ServiceDef("InertialSensorControl", "ICD 5.1.4, Table 15",
               (Sem.INS_COMMAND, Sem.INS_COMMAND_STATUS, Sem.INS_COMMAND_ACK)),
    ServiceDef("InertialSensorStatus", "ICD 5.1.5, Table 19", (Sem.INS_REPORT,)),
)
SERVICE_OF = {sem: s for s in SERVICES for sem in s.topics}

# Each topic's operation section and message table.
TOPIC_REF = {
    Sem.GPS_FIX_COMMAND_ACK: "ICD 5.1.1.1, Table 7", Sem.GPS_FIX_COMMAND_STATUS: "ICD 5.1.1.2, Table 8",
    Sem.GPS_FIX_COMMAND: "ICD 5.1.1.3, Table 9", Sem.GPS_FIX_REPORT: "ICD 5.1.2.1, Table 11",
    Sem.GPS_FIX_STATUS_REPORT: "ICD 5.1.2.2, Table 12", Sem.GPS_REPORT: "ICD 5.1.3.1, Table 14",
    Sem.INS_COMMAND_ACK: "ICD 5.1.4.1, Table 16", Sem.INS_COMMAND_STATUS: "ICD 5.1.4.2, Table 17",
    Sem.INS_COMMAND: "ICD 5.1.4.3, Table 18", Sem.INS_REPORT: "ICD 5.1.5.1, Table 20",
}


def short(sem: Sem) -> str:
    """The ICD's topic name without its namespace: GPSFixReport."""
    return sem.spec.name.rsplit("::", 1)[-1]


def type_name(sem: Sem) -> str:
    """The topic type's fully qualified IDL name: UMAA::SEM::GPSFixStatus::GPSFixReportType."""
    return sem.spec.type.__idl_typename__.replace(".", "::")


def members(t: type) -> list[str]:
    return [f.name for f in fields(t)]


def keys(t: type) -> set[str]:
    return {name for name, a in getattr(t, "__idl_field_annotations__", {}).items() if a.get("key")}


def key_ref(sem: Sem) -> str:
    """Where the ICD marks the topic's key members (with *)."""
    if sem.spec.cls is TopicClass.COMMAND:
        return "ICD 5.2.2, Table 22 (UMAACommand)"
    if sem.spec.cls is TopicClass.STATUS:
        return "ICD 5.2.4, Table 24 (UMAACommandStatusBase)"
    return "ICD 5.2.3, Table 23 (UMAAStatus)"
