"""The provider side of the UMAA command flow (ICD 4.1) for one simulated vehicle.

Every status it publishes goes through a `umaa.flow.CommandFlow`, the same Figure 4 the
console checks, so a step the figure does not allow is logged as the violation it is (only
the `skip-commanded` fault makes one, on purpose).
"""

from __future__ import annotations

import logging
import uuid
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType as FixState
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

from sem_console.dds.topics import Sem, Service
from sem_console.sim.journal import Journal
from sem_console.sim.models import SUBMERGED_DEPTH_M
from sem_console.sim.options import SimOptions
from sem_console.sim.reports import Out, Sensors
from sem_console.umaa.flow import SUCCESS_NEXT, TERMINAL, CommandFlow, Transition
from sem_console.umaa.guid import from_guid
from sem_console.umaa.samples import now_datetime

log = logging.getLogger("sem-sim")

MAX_TOMBSTONES = 10_000


@dataclass
class Execution:
    """One command as the provider runs it."""

    service: Service
    command: Any
    received: float
    flow: CommandFlow = field(default_factory=CommandFlow)
    next_at: float = 0.0  # when the next flow step is due
    orphan_since: float | None = None
    reached: bool = False  # the commanded state was reached and reported
    ended: bool = False  # status and ack disposed

    @property
    def session(self) -> uuid.UUID:
        return from_guid(self.command.sessionID)

    @property
    def status(self) -> Status | None:
        return self.flow.status


class ProviderFlow:
    """The commands one vehicle runs: start, steps, effects on its sensors, cancel, cleanup."""

    def __init__(self, opts: SimOptions, number: int, guid: uuid.UUID, faults: set[str], sensors: Sensors,
                 journal: Journal, write: Out, dispose: Out) -> None:
        self.opts, self.number, self.guid, self.faults, self.sensors = opts, number, guid, faults, sensors
        self.journal, self.write, self.dispose = journal, write, dispose
        self.source = sensors.source
        self.executions: dict[tuple[Service, uuid.UUID], Execution] = {}
        self.ended: OrderedDict[tuple[Service, uuid.UUID], None] = OrderedDict()  # tombstones of ended commands

    def step_delay(self) -> float:
        d = self.opts.scaled(self.opts.step_seconds)
        return d * self.opts.slow_factor if "slow" in self.faults else d

    def on_command(self, service: Service, cmd: Any, now: float, startup: bool, last_status: Status | None) -> None:
        key = (service, from_guid(cmd.sessionID))
        ex = self.executions.get(key)
        if ex is not None:
            ex.orphan_since = None  # a writer is back for this command: it is not orphaned
            return  # commands are immutable: a repeat of a known command changes nothing
        if key in self.ended:
            return  # canceled or cleaned up before: a republished sample must not start it again
        ex = Execution(service, cmd, received=now)
        self.executions[key] = ex
        if "no-answer" in self.faults:
            return
        if startup and last_status is not None:
            self.recover(ex, last_status, now)
        else:
            self.accept(ex, now)

    def recover(self, ex: Execution, last: Status, now: float) -> None:
        """Provider Startup Sequence for a command this provider had already answered (ICD 4.1.2.1)."""
        ex.flow.transitions.append(Transition(last, Reason.SUCCEEDED, "from the journal"))  # where it stood
        if last in TERMINAL:
            return  # finished: wait for the consumer's cleanup
        if self.opts.on_startup == "resume":
            self.write(ex.service.ack, self.ack_sample(ex))  # the ack died with the previous process
            log.info("vehicle %d resumes %s %s from %s", self.number, ex.service.value, ex.session, last.name)
            ex.next_at = now
            if last is Status.EXECUTING:
                self.start_effect(ex, now)
        else:
            self.publish_status(ex, Status.FAILED, Reason.SERVICE_FAILED, "provider restarted and does not resume commands")

    def accept(self, ex: Execution, now: float) -> None:
        """Command Start Sequence: ISSUED; then, for a valid command it will run, the ack."""
        self.publish_status(ex, Status.ISSUED, Reason.SUCCEEDED, "command received")
        error = self.validate(ex)
        if error:
            self.publish_status(ex, Status.FAILED, Reason.VALIDATION_FAILED, error)
            return
        if "reject" in self.faults:
            self.publish_status(ex, Status.FAILED, Reason.RESOURCE_REJECTED, "resource rejected the command (injected fault)")
            return
        for other in self.executions.values():  # a newer command of a service supersedes the running one
            if other is not ex and other.service is ex.service and other.status not in TERMINAL and other.status is not None:
                self.publish_status(other, Status.FAILED, Reason.INTERRUPTED, f"superseded by command {ex.session}")
        self.write(ex.service.ack, self.ack_sample(ex))
        ex.next_at = now + self.step_delay()

    def validate(self, ex: Execution) -> str | None:
        ts = ex.command.timeStamp
        if not 0 <= ts.nanoseconds <= 999_999_999 or ts.seconds < 0:
            return f"timeStamp out of range ({ts.seconds} s, {ts.nanoseconds} ns)"
        if ex.service is Service.INERTIAL_SENSOR and not isinstance(ex.command.state, InsState):
            return f"unknown inertial sensor state {ex.command.state!r}"
        return None

    def ack_sample(self, ex: Execution) -> Any:
        ack: Callable[..., Any] = ex.service.ack.spec.type  # a generated struct takes its members as keywords
        if ex.service is Service.GPS_FIX:
            return ack(source=self.source, sessionID=ex.command.sessionID)
        return ack(state=ex.command.state, source=self.source, sessionID=ex.command.sessionID)

    def status_sample(self, ex: Execution, status: Status, reason: Reason, message: str) -> Any:
        status_type: Callable[..., Any] = ex.service.status.spec.type  # as above
        return status_type(source=self.source, commandStatus=status, commandStatusReason=reason,
                                           logMessage=message[:4095], sessionID=ex.command.sessionID, timeStamp=now_datetime())

    def publish_status(self, ex: Execution, status: Status, reason: Reason, message: str) -> None:
        t = ex.flow.observe(status, reason, message)
        if t is not None and t.violation and "skip-commanded" not in self.faults:
            log.warning(
                "vehicle %d %s %s: publishing a Figure 4 violation: %s", self.number, ex.service.value, ex.session, t.violation
            )
        self.journal.set(self.guid, ex.service, ex.session, status)
        self.write(ex.service.status, self.status_sample(ex, status, reason, message))
        log.info("vehicle %d %s %s -> %s/%s %s", self.number, ex.service.value, ex.session, status.name, reason.name, message)

    def start_effect(self, ex: Execution, now: float) -> None:
        s = self.sensors
        if ex.service is Service.GPS_FIX:
            s.surfacing = True
            s.fix_state = FixState.INITIATING
        else:
            target = ex.command.state
            if target is InsState.ON and s.ins.state is InsState.ON:
                return  # already on: nothing to do but report it
            s.ins.set(target, s.t(now))

    def effect_done(self, ex: Execution, now: float) -> bool:
        s = self.sensors
        if ex.service is Service.GPS_FIX:
            if s.fix_state is FixState.INITIATING and s.depth > SUBMERGED_DEPTH_M / 2:
                s.fix_state = FixState.PERFORMING
            if s.fix_valid:
                s.fix_state = FixState.STABLE
            return s.fix_valid
        target = ex.command.state
        if target is InsState.OFF:
            return s.ins.state is InsState.OFF
        status = s.ins.status(s.t(now))
        return s.ins.state is InsState.ON and status.name == "OPERATIONAL"

    def advance(self, ex: Execution, now: float) -> None:
        if ex.status in TERMINAL or ex.status is None or now < ex.next_at or "no-answer" in self.faults:
            return
        step = SUCCESS_NEXT[ex.status]
        if step is Status.COMMANDED:
            if "skip-commanded" in self.faults:  # break Figure 4 on purpose
                self.publish_status(ex, Status.EXECUTING, Reason.SUCCEEDED, "executing (COMMANDED skipped: injected fault)")
                self.start_effect(ex, now)
            else:
                self.publish_status(ex, Status.COMMANDED, Reason.SUCCEEDED, "validated and commanded")
            ex.next_at = now + self.step_delay()
        elif step is Status.EXECUTING:
            self.publish_status(ex, Status.EXECUTING, Reason.SUCCEEDED, "executing")
            self.start_effect(ex, now)
            ex.next_at = now + self.step_delay()
        elif step is Status.COMPLETED:
            self.execute(ex, now)

    def execute(self, ex: Execution, now: float) -> None:
        """EXECUTING: fail on a timeout or a fault, complete once the effect is reached and reported."""
        s = self.sensors
        half = self.opts.scaled(self.opts.surface_seconds if ex.service is Service.GPS_FIX else self.opts.align_seconds) / 2
        if now - ex.received >= self.opts.scaled(self.opts.command_timeout):
            s.surfacing = False
            self.publish_status(ex, Status.FAILED, Reason.TIMEOUT, "the command did not finish in time")
        elif ex.service is Service.INERTIAL_SENSOR and s.ins.failed and ex.command.state is not InsState.OFF:
            self.publish_status(ex, Status.FAILED, Reason.RESOURCE_FAILED, "inertial sensor failure")
        elif "fail-midway" in self.faults and now - ex.received >= half:
            s.surfacing = False
            self.publish_status(ex, Status.FAILED, Reason.RESOURCE_FAILED, "resource failed during execution (injected fault)")
        elif self.effect_done(ex, now) and ("slow" not in self.faults or now >= ex.next_at):
            if not ex.reached:  # report the reached state first; COMPLETED follows on the next tick
                ex.reached = True
                s.report_now(Sem.GPS_FIX_REPORT if ex.service is Service.GPS_FIX else Sem.INS_REPORT)
            else:
                self.publish_status(ex, Status.COMPLETED, Reason.SUCCEEDED, "completed")

    def end(self, ex: Execution, now: float) -> None:
        """The consumer disposed the command (or it lost every writer): cancel or clean up."""
        if ex.ended:
            return
        if ex.status is not None and ex.status not in TERMINAL and "no-answer" not in self.faults:
            if ex.service is Service.GPS_FIX:
                self.sensors.surfacing = False  # stays where it is
            self.publish_status(ex, Status.CANCELED, Reason.CANCELED, "canceled by the consumer")
        if ex.status is not None:
            self.dispose(ex.service.status, self.status_sample(ex, ex.status, Reason.SUCCEEDED, ""))
            self.dispose(ex.service.ack, self.ack_sample(ex))
        ex.ended = True
        key = (ex.service, ex.session)
        del self.executions[key]
        self.ended[key] = None
        while len(self.ended) > MAX_TOMBSTONES:
            self.ended.popitem(last=False)
        self.journal.drop(self.guid, ex.service, ex.session)

    def step(self, now: float) -> None:
        for ex in list(self.executions.values()):
            if ex.orphan_since is not None and now - ex.orphan_since >= self.opts.orphan_grace:
                self.end(ex, now)
            else:
                self.advance(ex, now)

    def shutdown(self) -> None:
        """Provider Shutdown Sequence, for the commands: fail what is incomplete."""
        for ex in list(self.executions.values()):
            if ex.status is not None and ex.status not in TERMINAL:
                self.publish_status(ex, Status.FAILED, Reason.SERVICE_FAILED, "provider shutting down")
