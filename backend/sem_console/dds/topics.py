"""Every SEM topic: its UMAA name, generated type and QoS class, in one table per UMAA version (`Sem`: 3.0.1,
`Sem60`: 6.0)."""

from __future__ import annotations

import builtins
import functools
import importlib
import typing
from dataclasses import dataclass, fields, is_dataclass
from enum import Enum
from typing import Any

from cyclonedds.core import Policy, Qos
from cyclonedds.idl import IdlStruct

from UMAA.SEM.GPSFixControl import GPSFixCommandAckReportType, GPSFixCommandStatusType, GPSFixCommandType
from UMAA.SEM.GPSFixStatus import GPSFixReportType, GPSFixStatusReportType
from UMAA.SEM.GPSStatus import GPSReportType
from UMAA.SEM.InertialSensorControl import (
    InertialSensorCommandAckReportType,
    InertialSensorCommandStatusType,
    InertialSensorCommandType,
)
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType
from UMAA_6_0.SA.GlobalPoseStatus import GlobalPoseReportType as GlobalPoseReportType60
from UMAA_6_0.SEM.GPSStatus import GPSReportType as GPSReportType60
from UMAA_6_0.SEM.InertialSensorControl import InertialSensorCommandAckReportType as InertialSensorCommandAckReportType60
from UMAA_6_0.SEM.InertialSensorControl import InertialSensorCommandStatusType as InertialSensorCommandStatusType60
from UMAA_6_0.SEM.InertialSensorControl import InertialSensorCommandType as InertialSensorCommandType60
from UMAA_6_0.SEM.InertialSensorStatus import InertialSensorReportType as InertialSensorReportType60
from UMAA_6_0_appendable.SA.GlobalPoseStatus import GlobalPoseReportType as AppendableGlobalPoseReportType60
from UMAA_appendable.SEM.GPSFixStatus import GPSFixReportType as AppendableGPSFixReportType
from UMAA_appendable.SEM.GPSStatus import GPSReportType as AppendableGPSReportType

from sem_console.dds.qos import TopicClass


@functools.cache
def has_optional(t: type) -> bool:
    """Whether a generated struct has an @optional member anywhere in its member tree."""
    for hint in typing.get_type_hints(t, include_extras=True).values():
        if typing.get_origin(hint) is typing.Union:
            return True
        while typing.get_origin(hint) is typing.Annotated or typing.get_origin(hint) is list:
            hint = typing.get_args(hint)[0]
        if isinstance(hint, type) and issubclass(hint, IdlStruct) and has_optional(hint):
            return True
    return False


@dataclass(frozen=True)
class TopicSpec:
    name: str
    type: type[IdlStruct]
    cls: TopicClass
    # The same type appendable, with the types nested in it (UMAA_appendable, UMAA_6_0_appendable, generated): what an
    # RTI Connext vehicle writes (RTI's default for IDL that does not say). The console reads such a topic with a reader
    # of each (docs/dds.md, "One reader per extensibility"). Only for the types RTI and Cyclone exchange in XCDR2.
    appendable: builtins.type[IdlStruct] | None = None  # (`type` is the field above)
    # RTI UMAAQoSLib's CommandQoS over the class's QoS (qos.umaa_command_qos): the UMAA 6.0 command, status and ack topics
    command_qos_lib: bool = False

    @property
    def xcdr2_only(self) -> bool:
        """Exchanged in XCDR2 only: the type has @optional members (see qos.representation)."""
        return has_optional(self.type)


class Sem(Enum):
    GPS_FIX_COMMAND = TopicSpec("UMAA::SEM::GPSFixControl::GPSFixCommand", GPSFixCommandType, TopicClass.COMMAND)
    GPS_FIX_COMMAND_STATUS = TopicSpec(
        "UMAA::SEM::GPSFixControl::GPSFixCommandStatus", GPSFixCommandStatusType, TopicClass.STATUS
    )
    GPS_FIX_COMMAND_ACK = TopicSpec(
        "UMAA::SEM::GPSFixControl::GPSFixCommandAckReport", GPSFixCommandAckReportType, TopicClass.STATUS
    )
    GPS_FIX_REPORT = TopicSpec(
        "UMAA::SEM::GPSFixStatus::GPSFixReport", GPSFixReportType, TopicClass.REPORT, AppendableGPSFixReportType
    )
    GPS_FIX_STATUS_REPORT = TopicSpec("UMAA::SEM::GPSFixStatus::GPSFixStatusReport", GPSFixStatusReportType, TopicClass.REPORT)
    GPS_REPORT = TopicSpec("UMAA::SEM::GPSStatus::GPSReport", GPSReportType, TopicClass.REPORT, AppendableGPSReportType)
    INS_COMMAND = TopicSpec(
        "UMAA::SEM::InertialSensorControl::InertialSensorCommand", InertialSensorCommandType, TopicClass.COMMAND
    )
    INS_COMMAND_STATUS = TopicSpec(
        "UMAA::SEM::InertialSensorControl::InertialSensorCommandStatus", InertialSensorCommandStatusType, TopicClass.STATUS
    )
    INS_COMMAND_ACK = TopicSpec(
        "UMAA::SEM::InertialSensorControl::InertialSensorCommandAckReport", InertialSensorCommandAckReportType, TopicClass.STATUS
    )
    INS_REPORT = TopicSpec("UMAA::SEM::InertialSensorStatus::InertialSensorReport", InertialSensorReportType, TopicClass.REPORT)

    @property
    def spec(self) -> TopicSpec:
        return self.value


def _named_after_type(t: type[IdlStruct], cls: TopicClass, appendable: type[IdlStruct] | None = None) -> TopicSpec:
    """A UMAA 6.0 topic: named after its type's full name (UMAA::SEM::GPSStatus::GPSReportType)."""
    return TopicSpec(str(t.__idl_typename__).replace(".", "::"), t, cls, appendable, command_qos_lib=cls is not TopicClass.REPORT)


class Sem60(Enum):
    """The UMAA 6.0 topics the console serves (tests/data/umaa-6.0-wire-layout.toml)."""

    GPS_REPORT = _named_after_type(GPSReportType60, TopicClass.REPORT)
    GLOBAL_POSE_REPORT = _named_after_type(GlobalPoseReportType60, TopicClass.REPORT, AppendableGlobalPoseReportType60)
    INS_REPORT = _named_after_type(InertialSensorReportType60, TopicClass.REPORT)
    INS_COMMAND = _named_after_type(InertialSensorCommandType60, TopicClass.COMMAND)
    INS_COMMAND_STATUS = _named_after_type(InertialSensorCommandStatusType60, TopicClass.STATUS)
    INS_COMMAND_ACK = _named_after_type(InertialSensorCommandAckReportType60, TopicClass.STATUS)

    @property
    def spec(self) -> TopicSpec:
        return self.value


AnySem = Sem | Sem60


class Service(str, Enum):
    """The two commandable SEM services and their command, status and ack topics."""

    GPS_FIX = "GPSFix"
    INERTIAL_SENSOR = "InertialSensor"

    @property
    def command(self) -> Sem:
        return Sem.GPS_FIX_COMMAND if self is Service.GPS_FIX else Sem.INS_COMMAND

    @property
    def status(self) -> Sem:
        return Sem.GPS_FIX_COMMAND_STATUS if self is Service.GPS_FIX else Sem.INS_COMMAND_STATUS

    @property
    def ack(self) -> Sem:
        return Sem.GPS_FIX_COMMAND_ACK if self is Service.GPS_FIX else Sem.INS_COMMAND_ACK


_D_CDR2 = (0x08, 0x09)  # the second byte of the delimited XCDR2 encapsulation ids, big and little endian


def delimited(data: bytes) -> bool:
    """Whether serialised CDR says delimited XCDR2 (D_CDR2, DDS-XTypes 7.6.3.1.2) in its encapsulation header: what
    a writer of an appendable type sends, so a sample of a topic's appendable copy (TopicSpec.appendable)."""
    return len(data) > 1 and data[0] == 0 and data[1] in _D_CDR2


def _appendable_class(cls: type) -> Any:
    """The class of the same name in the appendable copy of its package (UMAA_appendable, UMAA_6_0_appendable:
    sem_console.idlgen writes it at the same module path)."""
    package, rest = cls.__module__.split(".", 1)
    return getattr(importlib.import_module(f"{package}_appendable.{rest}"), cls.__name__)


def to_appendable(value: Any) -> Any:
    """A sample of a topic's final type as its appendable copy (TopicSpec.appendable), member for member: what
    `sem-sim --gps-extensibility appendable` writes. cyclonedds serialises a member by the class its annotation names,
    so the nested structs and enums become the copy's too."""
    if is_dataclass(value) and not isinstance(value, type):
        return _appendable_class(type(value))(**{f.name: to_appendable(getattr(value, f.name)) for f in fields(value)})
    if isinstance(value, Enum):
        return _appendable_class(type(value))[value.name]
    if isinstance(value, list):
        return [to_appendable(v) for v in value]
    return value


def final_type_qos(sem: AnySem) -> Qos:
    """What a reader of a topic's final type adds when the topic also has an appendable copy: it validates the
    writer's type (`force_type_validation`), so a writer that sends no type information (RTI on the recipe) is
    refused, not matched by name and misread; that writer is read by a reader of the appendable copy."""
    if sem.spec.appendable is None:
        return Qos()
    return Qos(Policy.TypeConsistency.AllowTypeCoercion(force_type_validation=True))
