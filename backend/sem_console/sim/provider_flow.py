"""The provider side of the UMAA command flow (ICD 4.1) for one simulated vehicle.

Every status it publishes goes through a `umaa.flow.CommandFlow`, the same Figure 4 the
console checks, so a step the figure does not allow is logged as the violation it is (only
the `skip-commanded` fault makes one, on purpose).

A command comes with its version's commanding (`versions/commands.py`: its status and ack samples and topics); what
an inertial sensor command does to the vehicle's INS is its version's `InsEffects` (`Ins301` here, UMAA 6.0's
alignments in `umaa_6_0.py`). A version whose commands can be updated (UMAA 6.0 ICD 4.1.4.2) starts a command again,
ISSUED/UPDATED, when it comes again with a newer time stamp.
"""

from __future__ import annotations

import logging
import uuid
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Protocol

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType as FixState
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState

from sem_console.dds.topics import Sem, Service
from sem_console.sim.journal import Journal
from sem_console.sim.models import SUBMERGED_DEPTH_M
from sem_console.sim.options import SimOptions
from sem_console.sim.reports import Out, Sensors
from sem_console.umaa.flow import SUCCESS_NEXT, TERMINAL, UPDATED, AnyReason, CommandFlow, Transition
from sem_console.umaa.guid import from_guid
from sem_console.umaa.samples import datetime_to_float, now_datetime
from sem_console.versions.commands import Commanding

log = logging.getLogger("sem-sim")

MAX_TOMBSTONES = 10_000


class InsEffects(Protocol):
    """What an inertial sensor command of a version does to the vehicle's INS (`sensors.ins`, or its 6.0 alignment)."""

    def start(self, sensors: Sensors, command: Any, t: float) -> None:
        """EXECUTING: start the commanded state (`t`: the sensors' time)."""

    def done(self, sensors: Sensors, command: Any, t: float) -> bool:
        """The commanded state is reached."""

    def fail(self, sensors: Sensors, command: Any, t: float) -> None:
        """The `fail-midway` fault: what the INS reports as the command fails."""

    def stop(self, sensors: Sensors, command: Any, t: float) -> None:
        """The command is canceled: the INS stays where it is."""


class Ins301:
    """UMAA 3.0.1: the INS switched OFF, ON (aligning again from off) or RESTARTING (`models.Ins`)."""

    def start(self, sensors: Sensors, command: Any, t: float) -> None:
        target = command.state
        if target is InsState.ON and sensors.ins.state is InsState.ON:
            return  # already on: nothing to do but report it
        sensors.ins.set(target, t)

    def done(self, sensors: Sensors, command: Any, t: float) -> bool:
        if command.state is InsState.OFF:
            return sensors.ins.state is InsState.OFF
        return sensors.ins.state is InsState.ON and sensors.ins.status(t).name == "OPERATIONAL"

    def fail(self, sensors: Sensors, command: Any, t: float) -> None:
        """Nothing to show: the 3.0.1 report has no failed alignment."""

    def stop(self, sensors: Sensors, command: Any, t: float) -> None:
        """The power state commanded stays."""


@dataclass
class Execution:
    """One command as the provider runs it."""

    commanding: Commanding  # its version's: the status and ack samples and topics
    command: Any
    received: float
    flow: CommandFlow = field(default_factory=CommandFlow)
    next_at: float = 0.0  # when the next flow step is due
    orphan_since: float | None = None
    reached: bool = False  # the commanded state was reached and reported
    ended: bool = False  # status and ack disposed

    def __post_init__(self) -> None:
        self.flow.figure = self.commanding.figure  # its violations name its version's figure (6.0: Figure 14)

    @property
    def service(self) -> Service:
        return self.commanding.service

    @property
    def session(self) -> uuid.UUID:
        return from_guid(self.command.sessionID)

    @property
    def status(self) -> Status | None:
        return self.flow.status


class ProviderFlow:
    """The commands one vehicle runs: start, steps, effects on its sensors, cancel, cleanup."""

    def __init__(
        self,
        opts: SimOptions,
        number: int,
        guid: uuid.UUID,
        faults: set[str],
        sensors: Sensors,
        journal: Journal,
        write: Out,
        dispose: Out,
        ins: InsEffects | None = None,
    ) -> None:
        self.opts, self.number, self.guid, self.faults, self.sensors = opts, number, guid, faults, sensors
        self.journal, self.write, self.dispose = journal, write, dispose
        self.ins: InsEffects = ins or Ins301()
        self.executions: dict[tuple[Service, uuid.UUID], Execution] = {}
        self.ended: OrderedDict[tuple[Service, uuid.UUID], None] = OrderedDict()  # tombstones of ended commands

    def step_delay(self) -> float:
        d = self.opts.scaled(self.opts.step_seconds)
        return d * self.opts.slow_factor if "slow" in self.faults else d

    def on_command(self, commanding: Commanding, cmd: Any, now: float, startup: bool, last_status: Status | None) -> None:
        key = (commanding.service, from_guid(cmd.sessionID))
        ex = self.executions.get(key)
        if ex is not None:
            ex.orphan_since = None  # a writer is back for this command: it is not orphaned
            if commanding.updates and _stamp(cmd) > _stamp(ex.command) and "no-answer" not in self.faults:
                self.update(ex, cmd, now)
            return  # otherwise a repeat of a known command changes nothing
        if key in self.ended:
            return  # canceled or cleaned up before: a republished sample must not start it again
        ex = Execution(commanding, cmd, received=now)
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
            self.write(ex.commanding.ack, self.ack_sample(ex))  # the ack died with the previous process
            log.info("vehicle %d resumes %s %s from %s", self.number, ex.service.value, ex.session, last.name)
            ex.next_at = now
            if last is Status.EXECUTING:
                self.start_effect(ex, now)
        else:
            self.publish_status(ex, Status.FAILED, Reason.SERVICE_FAILED, "provider restarted and does not resume commands")

    def accept(self, ex: Execution, now: float) -> None:
        """Command Start Sequence: ISSUED; then, for a valid command it will run, the ack."""
        self.publish_status(ex, Status.ISSUED, Reason.SUCCEEDED, "command received")
        self.validate_and_ack(ex, now)

    def validate_and_ack(self, ex: Execution, now: float) -> None:
        """After ISSUED: a command it will not run FAILED, one it will run acknowledged (its ack) and stepped on."""
        error = self.validate(ex)
        if error:
            self.publish_status(ex, Status.FAILED, Reason.VALIDATION_FAILED, error)
            return
        if self.reject(ex):
            return
        for other in self.executions.values():  # a newer command of a service supersedes the running one
            if other is not ex and other.service is ex.service and other.status not in TERMINAL and other.status is not None:
                self.publish_status(other, Status.FAILED, Reason.INTERRUPTED, f"superseded by command {ex.session}")
        self.write(ex.commanding.ack, self.ack_sample(ex))
        ex.next_at = now + self.step_delay()

    def reject(self, ex: Execution) -> bool:
        """The `reject` fault: the resource rejects the command, FAILED/RESOURCE_REJECTED, after the status its version
        allows that reason after (`Commanding.rejected_after`: 3.0.1 ISSUED, 6.0 COMMANDED)."""
        if "reject" not in self.faults or ex.status is not ex.commanding.rejected_after:
            return False
        self.publish_status(ex, Status.FAILED, Reason.RESOURCE_REJECTED, "resource rejected the command (injected fault)")
        return True

    def update(self, ex: Execution, cmd: Any, now: float) -> None:
        """Updating a Command (UMAA 6.0 ICD 4.1.4.2): a running command sent again with a newer time stamp starts over,
        ISSUED/UPDATED, as a new command (its timeout too); a finished one ignores it."""
        if ex.status is None or ex.status in TERMINAL:
            return
        if ex.status is Status.EXECUTING and ex.service is Service.INERTIAL_SENSOR:
            self.ins.stop(self.sensors, ex.command, self.sensors.t(now))
        ex.command, ex.received, ex.reached = cmd, now, False
        self.publish_status(ex, Status.ISSUED, UPDATED, "command updated: started over")
        self.validate_and_ack(ex, now)

    def validate(self, ex: Execution) -> str | None:
        ts = ex.command.timeStamp
        if not 0 <= ts.nanoseconds <= 999_999_999 or ts.seconds < 0:
            return f"timeStamp out of range ({ts.seconds} s, {ts.nanoseconds} ns)"
        state = getattr(ex.command, "state", None)
        if ex.service is Service.INERTIAL_SENSOR and getattr(state, "name", None) not in ex.commanding.states:
            return f"unknown inertial sensor state {state!r}"
        return None

    def ack_sample(self, ex: Execution) -> Any:
        stamp = now_datetime()
        return ex.commanding.build_ack(self.guid, ex.command, (stamp.seconds, stamp.nanoseconds))

    def status_sample(self, ex: Execution, status: Status, reason: AnyReason, message: str) -> Any:
        stamp = now_datetime()
        return ex.commanding.build_status(self.guid, ex.command, status, reason, message, (stamp.seconds, stamp.nanoseconds))

    def publish_status(self, ex: Execution, status: Status, reason: AnyReason, message: str) -> None:
        t = ex.flow.observe(status, reason, message)
        if t is not None and t.violation and "skip-commanded" not in self.faults:
            log.warning("vehicle %d %s %s: publishing a violation: %s", self.number, ex.service.value, ex.session, t.violation)
        self.journal.set(self.guid, ex.service, ex.session, status)
        self.write(ex.commanding.status, self.status_sample(ex, status, reason, message))
        log.info("vehicle %d %s %s -> %s/%s %s", self.number, ex.service.value, ex.session, status.name, reason.name, message)

    def start_effect(self, ex: Execution, now: float) -> None:
        s = self.sensors
        if ex.service is Service.GPS_FIX:
            s.surfacing = True
            s.fix_state = FixState.INITIATING
        else:
            self.ins.start(s, ex.command, s.t(now))

    def effect_done(self, ex: Execution, now: float) -> bool:
        s = self.sensors
        if ex.service is Service.GPS_FIX:
            if s.fix_state is FixState.INITIATING and s.depth > SUBMERGED_DEPTH_M / 2:
                s.fix_state = FixState.PERFORMING
            if s.fix_valid:
                s.fix_state = FixState.STABLE
            return s.fix_valid
        return self.ins.done(s, ex.command, s.t(now))

    def advance(self, ex: Execution, now: float) -> None:
        if ex.status in TERMINAL or ex.status is None or now < ex.next_at or "no-answer" in self.faults:
            return
        if self.reject(ex):
            return
        step = SUCCESS_NEXT[ex.status]
        if step is Status.COMMANDED:
            if "skip-commanded" in self.faults:  # break the state machine on purpose
                log.warning(
                    "vehicle %d %s %s: skipping COMMANDED (injected fault), a breach of the %s state machine (%s)",
                    self.number,
                    ex.service.value,
                    ex.session,
                    ex.commanding.version,
                    ex.flow.figure,
                )
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
            if ex.service is Service.INERTIAL_SENSOR:
                self.ins.fail(s, ex.command, s.t(now))
                s.report_now(Sem.INS_REPORT)
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
            elif ex.status is Status.EXECUTING:
                self.ins.stop(self.sensors, ex.command, self.sensors.t(now))
            self.publish_status(ex, Status.CANCELED, Reason.CANCELED, "canceled by the consumer")
        if ex.status is not None:
            self.dispose(ex.commanding.status, self.status_sample(ex, ex.status, Reason.SUCCEEDED, ""))
            self.dispose(ex.commanding.ack, self.ack_sample(ex))
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


def _stamp(command: Any) -> float:
    """A command's time stamp, in seconds."""
    try:
        return datetime_to_float(command.timeStamp)
    except (AttributeError, TypeError):
        return 0.0
