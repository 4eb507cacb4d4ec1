"""A UMAA Service Consumer written for the tests: generated types over real DDS, no console code."""

from __future__ import annotations

import time
import uuid
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from cyclonedds.core import InstanceState
from cyclonedds.internal import InvalidSample

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.topics import Sem, Service
from sem_console.umaa.flow import CommandFlow
from sem_console.umaa.guid import from_guid, stable_guid, to_guid
from sem_console.umaa.samples import now_datetime


@dataclass
class Seen:
    """What the consumer saw of one command."""

    flow: CommandFlow = field(default_factory=CommandFlow)
    status_disposed: bool = False
    ack: Any = None
    ack_disposed: bool = False

    @property
    def statuses(self) -> list[Status]:
        return [t.status for t in self.flow.transitions]

    @property
    def reasons(self) -> list[Reason]:
        return [t.reason for t in self.flow.transitions]


class Consumer:
    def __init__(self, domain: int, name: str = "test-consumer") -> None:
        self.bus = Bus(domain)
        self.source = stable_guid(f"{name}-{domain}")
        self.readers = {sem: self.bus.reader(sem) for sem in Sem if sem.spec.cls.value != "command"}
        self.conditions = {sem: all_samples(r) for sem, r in self.readers.items()}
        self.writers = {s: self.bus.writer(s.command) for s in Service}
        self.reports: dict[Sem, dict[uuid.UUID, list[Any]]] = defaultdict(lambda: defaultdict(list))
        self.report_disposed: dict[Sem, set[uuid.UUID]] = defaultdict(set)
        self.commands: dict[uuid.UUID, Seen] = defaultdict(Seen)
        self.sent: dict[uuid.UUID, tuple[Service, Any]] = {}

    def pump(self) -> None:
        for sem, reader in self.readers.items():
            for s in reader.take(N=1000, condition=self.conditions[sem]):
                self._record(sem, s)
                if not isinstance(s, InvalidSample) and s.sample_info.instance_state != InstanceState.Alive:
                    # a dispose right after an unread sample shows only in that sample's instance state
                    self._record(sem, InvalidSample(s, s.sample_info))

    def _record(self, sem: Sem, s: Any) -> None:
        invalid = isinstance(s, InvalidSample)
        key = s.key_sample if invalid else s
        if sem.spec.cls.value == "report":
            if invalid:
                self.report_disposed[sem].add(from_guid(key.source))
            else:
                self.reports[sem][from_guid(key.source)].append(s)
            return
        seen = self.commands[from_guid(key.sessionID)]
        if sem in (Sem.GPS_FIX_COMMAND_STATUS, Sem.INS_COMMAND_STATUS):
            if invalid:
                seen.status_disposed = True
            else:
                seen.flow.observe(s.commandStatus, s.commandStatusReason, s.logMessage)
        elif invalid:
            seen.ack_disposed = True
        else:
            seen.ack = s

    def wait(self, predicate: Callable[[], bool], timeout: float = 15.0, what: str = "condition") -> None:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.pump()
            if predicate():
                return
            time.sleep(0.02)
        raise AssertionError(f"timed out waiting for {what}")

    def command(self, service: Service, destination: uuid.UUID, state: InsState | None = None, **overrides: Any) -> uuid.UUID:
        session = uuid.uuid4()
        fields: dict[str, Any] = dict(
            source=to_guid(self.source), destination=to_guid(destination), sessionID=to_guid(session), timeStamp=now_datetime()
        )
        if service is Service.INERTIAL_SENSOR:
            fields["state"] = state
        fields.update(overrides)
        sample = service.command.spec.type(**fields)
        self.sent[session] = (service, sample)
        self.writers[service].write(sample)
        return session

    def dispose(self, session: uuid.UUID) -> None:
        service, sample = self.sent[session]
        self.writers[service].dispose(sample)

    def wait_status(self, session: uuid.UUID, status: Status, timeout: float = 15.0) -> Seen:
        self.wait(lambda: status in self.commands[session].statuses, timeout, f"{status.name} for {session}")
        return self.commands[session]

    def wait_terminal(self, session: uuid.UUID, timeout: float = 15.0) -> Seen:
        self.wait(lambda: self.commands[session].flow.terminal, timeout, f"a terminal status for {session}")
        return self.commands[session]

    def latest(self, sem: Sem, source: uuid.UUID) -> Any:
        return self.reports[sem][source][-1]

    def close(self) -> None:
        self.bus.close()
