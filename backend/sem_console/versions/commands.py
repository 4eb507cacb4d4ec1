"""How each UMAA version commands a service: its topics, the choices its command takes, its command sample, and its
status read into the console's one command-status model (`umaa/flow.py`).

The console's commands (`console/commands.py`) and the API ask `commanding(version, service)` for the vehicle's
version, and `of_command(service, state)` for a command stored without one (the choices of the versions are
disjoint); nothing else there asks which version a vehicle speaks. `sem-check` builds and reads the same samples.

| version | service        | command topic (its status and ack topics alike)             | choices (`state`)        |
|---------|----------------|-------------------------------------------------------------|--------------------------|
| 3.0.1   | GPSFix         | UMAA::SEM::GPSFixControl::GPSFixCommand                     | (none)                   |
| 3.0.1   | InertialSensor | UMAA::SEM::InertialSensorControl::InertialSensorCommand     | OFF, ON, RESTARTING      |
| 6.0     | InertialSensor | UMAA::SEM::InertialSensorControl::InertialSensorCommandType | BEST_ALIGN, GPS_ALIGN,   |
|         |                |                                                             | INIT, SNAP_ALIGN,        |
|         |                |                                                             | STATIONARY_ALIGN,        |
|         |                |                                                             | TRANSFER_ALIGN           |

UMAA 6.0 has no GPSFix service (GPSFixControl ended with UMAA 5.2.1).
"""

from __future__ import annotations

import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState
from UMAA.Common.Measurement import DateTime

from sem_console.core.versions import UmaaVersion
from sem_console.dds.topics import AnySem, Sem60, Service
from sem_console.umaa.flow import AnyReason
from sem_console.umaa.guid import to_guid
from sem_console.versions import UMAA_3_0_1, UMAA_6_0, umaa_6_0


class Build(Protocol):
    """(source, destination, sessionID, state literal or None, time stamp (seconds, nanoseconds), the destination's
    parent as it reports it in its own `source` (UMAA 6.0's IdentifierType; None: none known)) -> the command sample."""

    def __call__(
        self,
        source: uuid.UUID,
        destination: uuid.UUID,
        session: uuid.UUID,
        state: str | None,
        stamp: tuple[int, int],
        parent: uuid.UUID | None = None,
    ) -> Any: ...


# a provider's status: (its source, the command sample, status, reason, log message, time stamp) -> the status sample
BuildStatus = Callable[[uuid.UUID, Any, Status, AnyReason, str, tuple[int, int]], Any]
# a provider's ack: (its source, the command sample, time stamp) -> the ack sample
BuildAck = Callable[[uuid.UUID, Any, tuple[int, int]], Any]


@dataclass(frozen=True)
class Commanding:
    """One version's commands of one service."""

    version: UmaaVersion
    service: Service
    command: AnySem
    status: AnySem
    ack: AnySem
    states: tuple[str, ...]  # the literals its command's `state` takes (InertialSensor); () when it takes none
    build: Build
    read_status: Callable[[Any], tuple[Status | int, AnyReason | int]]  # a status sample's status and reason
    build_status: BuildStatus
    build_ack: BuildAck
    updates: bool  # a command sent again with a newer time stamp is an update (UMAA 6.0 ICD 4.1.4.2), else a repeat
    # the status a provider's resource rejects a command after (FAILED/RESOURCE_REJECTED): 3.0.1's ICD (4.1.4.3) ties
    # no reason to a transition, so at once after ISSUED; 6.0's Figure 15 allows RESOURCE_REJECTED after COMMANDED only
    rejected_after: Status = Status.ISSUED
    # the command state machine's figure in the version's ICD (4.1): 3.0.1's Figure 4, 6.0's Figure 14
    figure: str = "Figure 4"

    def destination(self, command: Any) -> uuid.UUID:
        """The provider a command sample is addressed to (ValueError, TypeError: not a GUID)."""
        return _guid(command.destination)

    def source(self, sample: Any) -> uuid.UUID:
        """The source of a command, status or ack sample (ValueError, TypeError: not a GUID)."""
        return _guid(sample.source)

    @staticmethod
    def parent(sample: Any) -> uuid.UUID | None:
        """The parent its source says it has (UMAA 6.0's IdentifierType.parentID); None: 3.0.1's NumericGUID has none."""
        return parent_of(sample.source)


def parent_of(source: Any) -> uuid.UUID | None:
    """The `parentID` of a UMAA 6.0 IdentifierType as a UUID (the nil UUID: no parent); None for a 3.0.1 NumericGUID
    or a value that is not a GUID."""
    raw = getattr(source, "parentID", None)
    try:
        return None if raw is None else uuid.UUID(bytes=bytes(raw))
    except (TypeError, ValueError):
        return None


def _guid(raw: Any) -> uuid.UUID:
    """A NumericGUID, or the `id` of an IdentifierType (UMAA 6.0), as a UUID."""
    return uuid.UUID(bytes=bytes(getattr(raw, "id", raw)))


def _command_3_0_1(service: Service) -> Build:
    def build(
        source: uuid.UUID,
        destination: uuid.UUID,
        session: uuid.UUID,
        state: str | None,
        stamp: tuple[int, int],
        parent: uuid.UUID | None = None,
    ) -> Any:  # 3.0.1's destination is a NumericGUID
        values: dict[str, Any] = dict(
            source=to_guid(source),
            destination=to_guid(destination),
            sessionID=to_guid(session),
            timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]),
        )
        if service is Service.INERTIAL_SENSOR:
            values["state"] = InsState[state or ""]
        return service.command.spec.type(**values)

    return build


def _status_3_0_1(sample: Any) -> tuple[Status | int, AnyReason | int]:
    return sample.commandStatus, sample.commandStatusReason


def _build_status_3_0_1(service: Service) -> BuildStatus:
    def build(source: uuid.UUID, command: Any, status: Status, reason: AnyReason, message: str, stamp: tuple[int, int]) -> Any:
        if not isinstance(reason, Reason):
            raise ValueError(f"UMAA 3.0.1 has no reason {reason.name}")
        status_type: Callable[..., Any] = service.status.spec.type  # a generated struct takes its members as keywords
        return status_type(
            source=to_guid(source),
            commandStatus=status,
            commandStatusReason=reason,
            logMessage=message[:4095],
            sessionID=command.sessionID,
            timeStamp=DateTime(seconds=stamp[0], nanoseconds=stamp[1]),
        )

    return build


def _build_ack_3_0_1(service: Service) -> BuildAck:
    def build(source: uuid.UUID, command: Any, _stamp: tuple[int, int]) -> Any:
        ack_type: Callable[..., Any] = service.ack.spec.type  # as above
        if service is Service.GPS_FIX:
            return ack_type(source=to_guid(source), sessionID=command.sessionID)
        return ack_type(state=command.state, source=to_guid(source), sessionID=command.sessionID)

    return build


COMMANDING: dict[tuple[UmaaVersion, Service], Commanding] = {
    **{
        (UMAA_3_0_1, s): Commanding(
            UMAA_3_0_1,
            s,
            s.command,
            s.status,
            s.ack,
            tuple(InsState.__members__) if s is Service.INERTIAL_SENSOR else (),
            _command_3_0_1(s),
            _status_3_0_1,
            _build_status_3_0_1(s),
            _build_ack_3_0_1(s),
            False,
        )
        for s in Service
    },
    (UMAA_6_0, Service.INERTIAL_SENSOR): Commanding(
        UMAA_6_0,
        Service.INERTIAL_SENSOR,
        Sem60.INS_COMMAND,
        Sem60.INS_COMMAND_STATUS,
        Sem60.INS_COMMAND_ACK,
        umaa_6_0.INS_COMMAND_STATES,
        umaa_6_0.ins_command,
        umaa_6_0.command_status,
        umaa_6_0.ins_status,
        umaa_6_0.ins_ack,
        True,
        Status.COMMANDED,
        "Figure 14",
    ),
}
SERVICE_NAMES = {Service.GPS_FIX: "GPS fix", Service.INERTIAL_SENSOR: "inertial sensor"}


def commanding(version: UmaaVersion, service: Service) -> Commanding | None:
    """How a vehicle of `version` is commanded for `service`; None: its version has no such service."""
    return COMMANDING.get((version, service))


def of_command(service: Service, state: str | None) -> Commanding:
    """The commanding a stored command was issued with: the version whose choices have its state (GPSFix: 3.0.1's)."""
    for c in COMMANDING.values():
        if c.service is service and (state in c.states if c.states else state is None):
            return c
    raise ValueError(f"no UMAA version commands {service.value} with {state!r}")


def refusal(version: UmaaVersion, service: Service, state: str | None, vehicle: str) -> str | None:
    """Why a command cannot go to a vehicle of `version`, in one line naming its version and its choices; None when
    it can."""
    c = commanding(version, service)
    if c is None:
        return f"{vehicle} speaks UMAA {version}, which has no {SERVICE_NAMES[service]} service ({service.value}Control)"
    if state is None or state in c.states:
        return None
    other = next((o.version for o in COMMANDING.values() if o.service is service and state in o.states), None)
    what = f"{state} is a UMAA {other} state" if other else f"{state} is no state"
    return f"{vehicle} speaks UMAA {version}: its {SERVICE_NAMES[service]} takes {', '.join(c.states)}; {what}"


# the topics commands are written on, and statuses and acks read from, with the service and reader they belong to
COMMAND_TOPICS = [c.command for c in COMMANDING.values()]
STATUS_TOPICS = {c.status: c for c in COMMANDING.values()}
ACK_TOPICS = {c.ack: c for c in COMMANDING.values()}
