"""A UMAA SEM Service Provider for the sem-check tests, written from ICD 3.0.1 section 4.1 (not from `sem-sim`): it
serves GPSFixControl, InertialSensorControl and InertialSensorStatus on a participant of its own, and can break the
ICD in one of `BREACHES` at a time.

Per command addressed to it (ICD 4.1: `destination`): ISSUED (4.1.4 step 3); a step later, as it starts processing
it, the ack (4.1.4.1 step 1) and COMMANDED, then EXECUTING a step after (4.1.4.1 steps 2 and 3); COMPLETED `execute`
seconds later (4.1.4.2); an InertialSensor command's state shows in the InertialSensorReport from EXECUTING (a restart
as RESTARTING, then ON). The consumer's dispose before the end cancels it: CANCELED/CANCELED, then its status and ack
disposed (4.1.4.4), or, a provider whose commands cannot be canceled (`cancelable=False`), runs it on to COMPLETED and
then disposes them (4.1.4.4); after the end it cleans up: status and ack disposed (4.1.5). `step` is the time between
ISSUED, COMMANDED and EXECUTING. A provider that rejects an InertialSensor command for the state the sensor is in
(`reject_same_state=True`) answers it ISSUED, then FAILED/RESOURCE_REJECTED (4.1.4.3: a provider may reject a command).

The breaches, each one an ICD rule a vehicle was seen to break:
- `ignore-cancel`: a dispose before the end is ignored; the command runs to COMPLETED and its status and ack are
  never disposed (4.1.4.4 wants them disposed either way);
- `silent-same-state`: an InertialSensor command for the state the sensor is in gets no status at all (4.1: the
  provider responds to every command addressed to it);
- `answer-any-destination`: commands addressed to any GUID are run as its own (4.1: `destination`);
- `fail-after-cleanup`: a moment after disposing a finished command's status and ack it publishes FAILED/TIMEOUT for
  it (Figure 4: nothing follows COMPLETED).
"""

from __future__ import annotations

import threading
import time
import uuid
from dataclasses import dataclass, field
from typing import Any

from cyclonedds.core import InstanceState

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as OpStatus
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

from sem_console.dds.bus import Bus
from sem_console.dds.topics import Sem, Service
from sem_console.umaa.guid import from_guid, to_guid
from sem_console.umaa.samples import now_datetime

BREACHES = ("ignore-cancel", "silent-same-state", "answer-any-destination", "fail-after-cleanup")
REPORT_PERIOD = 0.1  # s between InertialSensorReports
LATE = 0.2  # s after the cleanup that `fail-after-cleanup` publishes FAILED


@dataclass
class Command:
    service: Service
    sample: Any
    due: list[tuple[float, Status]]  # the statuses still to publish, and when
    status: Status = Status.ISSUED
    disposed_early: bool = False  # the consumer disposed it before COMPLETED, and it was not canceled
    acked: bool = False  # its ack was published: it started processing it
    late: list[float] = field(default_factory=list)  # when to publish FAILED after the cleanup


class IcdProvider:
    def __init__(
        self,
        domain: int,
        breach: str | None = None,
        execute: float = 0.4,
        step: float = 0.05,
        cancelable: bool = True,
        reject_same_state: bool = False,
    ) -> None:
        assert breach is None or breach in BREACHES, breach
        self.breach, self.execute, self.step, self.cancelable = breach, execute, step, cancelable
        self.reject_same_state = reject_same_state
        self.bus = Bus(domain)
        self.guid = uuid.uuid4()
        self.status = {s: self.bus.writer(s.status) for s in Service}
        self.ack = {s: self.bus.writer(s.ack) for s in Service}
        self.report = self.bus.writer(Sem.INS_REPORT)
        self.readers = {s: self.bus.reader(s.command) for s in Service}
        self.state = InsState.ON
        self.sessions: dict[int, uuid.UUID] = {}  # command instance handle -> its session
        self.running: dict[uuid.UUID, Command] = {}
        self.cleaned: dict[uuid.UUID, Command] = {}  # fail-after-cleanup: commands to fail after their cleanup
        self.reported_at = 0.0
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.loop, daemon=True)
        self.thread.start()

    def close(self) -> None:
        self.stop.set()
        self.thread.join()
        self.bus.close()

    def loop(self) -> None:
        while not self.stop.is_set():
            now = time.monotonic()
            for service, reader in self.readers.items():
                for s in reader.take(N=16):
                    self.on_sample(service, s, now)
            for session, cmd in list(self.running.items()):
                while cmd.due and cmd.due[0][0] <= now:
                    self.publish(cmd, cmd.due.pop(0)[1])
                if cmd.status is Status.COMPLETED and cmd.disposed_early:
                    if self.breach == "ignore-cancel":
                        del self.running[session]  # its status and ack stay on the bus
                    else:
                        self.end(session, cmd, now)  # it could not be canceled: COMPLETED, then disposed (4.1.4.4)
            for session, cmd in list(self.cleaned.items()):
                if cmd.late[0] <= now:
                    self.status[cmd.service].write(self.status_sample(cmd, Status.FAILED, Reason.TIMEOUT))
                    del self.cleaned[session]
            if now - self.reported_at >= REPORT_PERIOD:
                self.publish_report(now)
            time.sleep(0.01)

    def on_sample(self, service: Service, s: Any, now: float) -> None:
        info = s.sample_info
        if info.valid_data and info.instance_handle not in self.sessions:
            self.start(service, s, info.instance_handle, now)
        session = self.sessions.get(info.instance_handle)
        cmd = self.running.get(session) if session is not None else None
        if info.instance_state == InstanceState.NotAliveDisposed and session is not None and cmd is not None:
            self.end(session, cmd, now)

    def start(self, service: Service, s: Any, handle: int, now: float) -> None:
        if from_guid(s.destination) != self.guid and self.breach != "answer-any-destination":
            return
        same = service is Service.INERTIAL_SENSOR and s.state == self.state
        if same and self.breach == "silent-same-state":
            return
        session = from_guid(s.sessionID)
        self.sessions[handle] = session
        cmd = Command(
            service,
            s,
            [
                (now + self.step, Status.COMMANDED),
                (now + 2 * self.step, Status.EXECUTING),
                (now + 2 * self.step + self.execute, Status.COMPLETED),
            ],
        )
        if same and self.reject_same_state:
            cmd.due = [(now + self.step, Status.FAILED)]
        self.running[session] = cmd
        self.status[service].write(self.status_sample(cmd, Status.ISSUED, Reason.SUCCEEDED))

    def end(self, session: uuid.UUID, cmd: Command, now: float) -> None:
        """The consumer disposed the command: cancel it (ICD 4.1.4.4), or clean it up (ICD 4.1.5)."""
        if cmd.status not in (Status.COMPLETED, Status.FAILED):
            if self.breach == "ignore-cancel" or not self.cancelable:
                cmd.disposed_early = True
                return
            cmd.due.clear()
            self.publish(cmd, Status.CANCELED)
        self.status[cmd.service].dispose(self.status_sample(cmd, cmd.status, Reason.SUCCEEDED))
        if cmd.acked:
            self.ack[cmd.service].dispose(self.ack_sample(cmd))
        del self.running[session]
        if self.breach == "fail-after-cleanup" and cmd.status is Status.COMPLETED:
            cmd.late.append(now + LATE)
            self.cleaned[session] = cmd

    def publish(self, cmd: Command, status: Status) -> None:
        if status is Status.COMMANDED:
            self.ack[cmd.service].write(self.ack_sample(cmd))
            cmd.acked = True
        cmd.status = status
        reason = {Status.CANCELED: Reason.CANCELED, Status.FAILED: Reason.RESOURCE_REJECTED}.get(status, Reason.SUCCEEDED)
        if cmd.service is Service.INERTIAL_SENSOR and status is Status.EXECUTING:
            self.set_state(cmd.sample.state)
        if cmd.service is Service.INERTIAL_SENSOR and status is Status.COMPLETED and self.state is InsState.RESTARTING:
            self.set_state(InsState.ON)
        self.status[cmd.service].write(self.status_sample(cmd, status, reason))

    def set_state(self, state: InsState) -> None:
        self.state = state
        self.publish_report(time.monotonic())

    def publish_report(self, now: float) -> None:
        self.reported_at = now
        status = OpStatus.INIT if self.state is InsState.RESTARTING else OpStatus.OPERATIONAL
        self.report.write(
            Sem.INS_REPORT.spec.type(state=self.state, status=status, source=to_guid(self.guid), timeStamp=now_datetime())
        )

    def status_sample(self, cmd: Command, status: Status, reason: Reason) -> Any:
        return cmd.service.status.spec.type(
            source=to_guid(self.guid),
            sessionID=cmd.sample.sessionID,
            commandStatus=status,
            commandStatusReason=reason,
            logMessage="",
            timeStamp=now_datetime(),
        )

    def ack_sample(self, cmd: Command) -> Any:
        if cmd.service is Service.GPS_FIX:
            return Sem.GPS_FIX_COMMAND_ACK.spec.type(source=to_guid(self.guid), sessionID=cmd.sample.sessionID)
        return Sem.INS_COMMAND_ACK.spec.type(state=cmd.sample.state, source=to_guid(self.guid), sessionID=cmd.sample.sessionID)
