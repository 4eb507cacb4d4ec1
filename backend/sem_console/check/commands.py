"""Command tests (`--commands` only): the checker is a UMAA Service Consumer and runs commands
through the ICD 4.1 flow, each status sequence followed by the console's Figure 4 monitor
(`umaa.flow.CommandFlow`).

- `commands.GPSFix.complete`: ISSUED -> COMMANDED -> EXECUTING -> COMPLETED, each step within the
  stated time, with the ack report (ICD 4.1.4, 4.1.4.1, 4.1.4.2) and, when the provider serves
  GPSFixReport, a valid position reported by then;
- `commands.GPSFix.cancel`: disposed while EXECUTING -> CANCELED, or COMPLETED for a command that
  cannot be canceled, then status and ack disposed (ICD 4.1.4.4, Figure 14). A command that
  completes before the checker could dispose it is followed by a second, disposed at its first
  status; each is disposed and its status and ack must go (ICD 4.1.5);
- `commands.InertialSensor.OFF|ON|RESTARTING`: each through the flow, the InertialSensorReport
  following the commanded state; `commands.InertialSensor.same`: a command for the state the
  sensor is in, answered through the flow to COMPLETED or, rejected, FAILED (ICD 4.1: the provider
  responds to every command; 4.1.4.3);
- `commands.<Service>.cleanup`: after the consumer disposes a finished command the provider
  disposes its status and ack (ICD 4.1.5, Figure 15);
- `commands.<Service>.destination`: a command addressed to another GUID, sent before the service's
  other commands, gets no status or ack from the provider (ICD 4.1: `destination`).

A UMAA 6.0 provider's InertialSensor is tested with the 6.0 commands (`inertial_sensor_6_0`: each
InertialSensorCmdEnumType command, a cancel, an update, the same alignment again, the cleanup and another
destination), each failure naming its ICD 6.0 section; its samples are built by `umaa_6_0.py`.

Any status sequence that breaks Figure 4 fails its test, quoting the transition, also when it comes
after the test (after the cleanup: every command to the provider is watched until --step-time after its dispose);
a command with no status within the answer time fails as unanswered, with the time waited, and the
service's next commands are skipped. Every command is disposed before the checker leaves (ICD 4.1.6.2).
"""

from __future__ import annotations

import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TextIO, cast

from cyclonedds.pub import DataWriter

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as InsState
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as InsCmd

from sem_console.check import icd, umaa_6_0
from sem_console.check.observe import Observer, StatusSeen
from sem_console.check.results import Case, Outcome, Progress, Stopped, Timer
from sem_console.core.versions import UmaaVersion
from sem_console.dds.bus import wait_for_acks
from sem_console.dds.topics import AnySem, Sem, Sem60, Service
from sem_console.umaa.flow import SUCCESS_NEXT, UPDATED, CommandFlow, name
from sem_console.umaa.samples import now_datetime
from sem_console.versions.commands import Commanding, commanding, parent_of


@dataclass
class CommandLimits:
    answer: float  # s from sending to the first status (ISSUED)
    step: float  # s for each later step: COMMANDED, EXECUTING, the ack, CANCELED after a dispose, the cleanup disposes
    execute: float  # s from EXECUTING to a terminal status


SHORT = {Service.GPS_FIX: "GPSFix", Service.INERTIAL_SENSOR: "InertialSensor"}
LEFT = "the provider has left the domain: none of its DDS endpoints remain (stopped, or off the network)"
GPS_NAMES = [f"commands.GPSFix.{t}" for t in ("complete", "cancel", "cleanup", "destination")]
INS_NAMES = [f"commands.InertialSensor.{t}" for t in ("OFF", "ON", "RESTARTING", "same", "cleanup", "destination")]
INS_NAMES_6_0 = [
    f"commands.InertialSensor.{t if isinstance(t, str) else t.name}" for t in (*umaa_6_0.TESTS, "cleanup", "destination")
]
ACTIVE = frozenset({Status.ISSUED, Status.COMMANDED, Status.EXECUTING})
SETTLED = {"RESTARTING": "ON"}  # the state an inertial sensor reporting this one ends in

# Where the ICD has the provider take a step of the successful path after ISSUED (Version.flow's keys)
STEP_REF: dict[Status | None, str] = {Status.COMMANDED: "commanded", Status.EXECUTING: "executing"}
DESTINATION_REF = (
    ": a command's destination directs it at one Service Provider, which responds to the commands addressed to its ID"
)


def names(version: icd.Version = icd.V3_0_1) -> list[str]:
    """The command tests of a UMAA version."""
    return INS_NAMES_6_0 if version.name == umaa_6_0.V6_0.name else GPS_NAMES + INS_NAMES


@dataclass
class Sent:
    """One command the checker sent, and what the provider answered."""

    service: Service
    session: uuid.UUID
    sample: Any
    sent_at: float  # the checker's clock, UTC seconds
    to: uuid.UUID  # its destination
    version: icd.Version
    topic: str  # its command topic's short name
    case: Case | None = None  # the test a status of the command counts for (the cleanup test once it disposed it)
    foreign: bool = False  # addressed to another GUID than the provider's: it must not answer
    flow: CommandFlow = field(default_factory=CommandFlow)
    at: list[float] = field(default_factory=list)  # when each transition of `flow` arrived
    ack: Any = None
    ack_at: float | None = None
    status_disposed: bool = False
    ack_disposed: bool = False
    disposed_at: float | None = None  # when the checker disposed the command
    disposed_in: Status | None = None  # the command's status then
    seen: tuple[int, int] = (0, 0)  # statuses and acks of the session already looked at
    breaches_reported: int = 0  # of `violations`, those already failed a case
    updated_at: float | None = None  # when the checker updated it (UMAA 6.0: a newer timeStamp, ICD 6.0 4.1.4.2)
    update_failed: bool = False  # the provider failed the update that crossed the command's end (ICD 6.0 4.1.4.2 step 2)
    earlier: list[str] = field(default_factory=list)  # the story of each flow an update restarted
    found: list[str] = field(default_factory=list)  # UMAA 6.0: every breach in the order seen (UPDATED out of place too)
    counted: int = 0  # the transitions of those flows

    def __post_init__(self) -> None:
        self.flow.figure = self.refs["figure"]  # its breaches name its version's figure (6.0: Figure 14)

    @property
    def refs(self) -> dict[str, str]:
        return dict(self.version.flow)

    @property
    def violations(self) -> list[str]:
        return self.found if self.version.name == umaa_6_0.V6_0.name else self.flow.violations

    @property
    def transitions(self) -> int:
        """Every transition seen, those of flows an update restarted included."""
        return self.counted + len(self.flow.transitions)

    def restart(self) -> None:
        """ISSUED/UPDATED: the flow restarts at ISSUED (ICD 6.0 4.1.4.2); the story keeps what came before."""
        self.earlier.append(self.story())
        self.counted += len(self.flow.transitions)
        self.flow, self.at = CommandFlow(figure=self.refs["figure"]), []

    def when(self, status: Status) -> float | None:
        for t, at in zip(self.flow.transitions, self.at, strict=True):
            if t.status is status:
                return at
        return None

    def story(self) -> str:
        steps = [
            f"{name(t.status)}/{name(t.reason)} +{at - self.sent_at:.2f} s"
            for t, at in zip(self.flow.transitions, self.at, strict=True)
        ]
        if self.earlier and steps:  # the first status of a restarted flow is ISSUED/UPDATED on the wire
            steps[0] = steps[0].replace("ISSUED/SUCCEEDED", "ISSUED/UPDATED", 1)
        now = ", ".join(steps) or "no status"
        return ", then ".join([*self.earlier, now]) if self.earlier else now


def _newer(seconds: int, nanoseconds: int) -> tuple[int, int]:
    """The time stamp one nanosecond after (seconds, nanoseconds): the least an update's timeStamp must be."""
    return (seconds, nanoseconds + 1) if nanoseconds < 999_999_999 else (seconds + 1, 0)


class Consumer:
    """The checker as a Service Consumer of one provider: writers are made only here, on first use."""

    def __init__(
        self,
        observer: Observer,
        provider: uuid.UUID,
        limits: CommandLimits,
        out: TextIO,
        progress: Progress | None = None,
        version: icd.Version = icd.V3_0_1,
    ) -> None:
        self.observer, self.provider, self.limits, self.out, self.progress = observer, provider, limits, out, progress
        self.version = version
        self.six = version.name == umaa_6_0.V6_0.name
        self.source = uuid.uuid4()  # this run's consumer GUID (RFC 4122 version 4)
        self.writers: dict[Service, DataWriter[Any]] = {}
        self.sent: list[Sent] = []
        self.left_told = False  # a failure named the provider's leaving the domain: the tests after it are skipped

    def writer(self, service: Service) -> DataWriter[Any] | None:
        """The service's command writer, once it matched a reader of the provider's participants."""
        if service not in self.writers:
            self.writers[service] = self.observer.bus.writer(self.topic(service, "command"))
        w = self.writers[service]
        participants = self.observer.source_participants.get(self.provider, set())

        def matched() -> bool:
            for h in w.get_matched_subscriptions():
                try:
                    data = w.get_matched_subscription_data(h)
                except Exception:  # a reader that just left
                    continue
                if data is not None and data.participant_key in participants:
                    return True
            return False

        return w if self.observer.wait(matched, self.limits.answer) else None

    def topic(self, service: Service, kind: str) -> AnySem:
        """The service's command, status or ack topic in the provider's UMAA version."""
        c = self.commanding(service)
        return {"command": c.command, "status": c.status, "ack": c.ack}[kind]

    def commanding(self, service: Service) -> Commanding:
        """How the provider's UMAA version commands `service` (`versions/commands.py`: its topics, command and status)."""
        c = commanding(cast(UmaaVersion, self.version.name), service)
        if c is None:
            raise ValueError(f"UMAA {self.version.name} has no {service.value} service")
        return c

    def send(
        self,
        service: Service,
        writer: DataWriter[Any],
        state: InsState | InsCmd | None = None,
        case: Case | None = None,
        destination: uuid.UUID | None = None,
    ) -> Sent:
        """A command to the provider (or, `destination`, to another GUID); its statuses count for `case`."""
        session = uuid.uuid4()
        to = destination or self.provider
        stamp = now_datetime()
        # to the provider's identifier as its reports say it (UMAA 6.0: its parent too, ICD 6.0 5.2.9)
        parent = self.observer.parents.get(to)
        sample = self.commanding(service).build(
            self.source, to, session, state.name if state is not None else None, (stamp.seconds, stamp.nanoseconds), parent
        )
        topic = icd.short(self.topic(service, "command"))
        what = topic + (f" {state.name}" if state is not None else "")
        sent = Sent(service, session, sample, time.time(), to, self.version, topic, case, foreign=destination is not None)
        self.sent.append(sent)  # before it is written: a SIGTERM or Ctrl-C from here on still disposes it (close)
        elsewhere = f" addressed to {destination}, not to the provider" if destination is not None else ""
        print(f"  sending {what}{elsewhere} (session {session})", file=self.out, flush=True)
        writer.write(sample)
        return sent

    def update_command(self, sent: Sent) -> None:
        """UMAA 6.0: write the command again with a newer timeStamp, the same source and sessionID: an update (ICD 6.0
        4.1.4.2)."""
        old, t = sent.sample, now_datetime()
        stamp = max((t.seconds, t.nanoseconds), _newer(old.timeStamp.seconds, old.timeStamp.nanoseconds))
        sent.sample = self.commanding(sent.service).build(
            self.source, sent.to, sent.session, old.state.name, stamp, parent_of(old.destination)
        )
        sent.updated_at = time.time()
        print(
            f"  updating {icd.short(self.topic(sent.service, 'command'))} {sent.sample.state.name} (session "
            f"{sent.session}): a newer timeStamp",
            file=self.out,
            flush=True,
        )
        self.writers[sent.service].write(sent.sample)

    def dispose(self, sent: Sent) -> None:
        if sent.disposed_at is None:
            self.writers[sent.service].dispose(sent.sample)
            sent.disposed_at, sent.disposed_in = time.time(), sent.flow.status

    def update(self, sent: Sent) -> None:
        """Feed the provider's new statuses and acks of the command to its flow."""
        statuses = self.observer.statuses.get(sent.session, [])
        acks = self.observer.acks.get(sent.session, [])
        for s in statuses[sent.seen[0] :]:
            if s.source != self.provider:
                continue
            if s.sample is not None and self.six:
                self._observe_6_0(sent, s.sample, s.received)
            elif s.sample is not None:
                t = sent.flow.observe(s.sample.commandStatus, s.sample.commandStatusReason, s.sample.logMessage)
                if t is not None:
                    sent.at.append(s.received)
            if s.disposed:  # a writer that left (no writers) disposed nothing: Figure 15 wants the dispose
                sent.status_disposed = True
        for a in acks[sent.seen[1] :]:
            if a.source != self.provider:
                continue
            if a.sample is not None:  # the last one: a provider acks an updated command again (ICD 6.0 4.1.4.2)
                sent.ack, sent.ack_at = a.sample, sent.ack_at or a.received
            if a.disposed:
                sent.ack_disposed = True
        sent.seen = (len(statuses), len(acks))

    def _observe_6_0(self, sent: Sent, sample: Any, received: float) -> None:
        """A UMAA 6.0 status: its literals as the flow monitor's; ISSUED/UPDATED restarts the flow when it answers the
        consumer's update of a running command, and is a breach otherwise (ICD 6.0 4.1.4.2; Figure 15)."""
        status, reason = self.commanding(sent.service).read_status(sample)
        last = sent.flow.transitions[-1] if sent.flow.transitions else None
        if reason is not UPDATED:
            if status is Status.FAILED and self._update_crossed_end(sent) and not sent.update_failed:
                sent.update_failed = True
                if sent.case is not None:
                    sent.case.note(
                        f"FAILED/{name(reason)} after {name(sent.flow.status)}: the answer to the consumer's "
                        f"update that crossed the end of the command, as {sent.refs['update']} step 2 has it "
                        "(its first paragraph has the update ignored; either is taken)"
                    )
                return
            before = sent.flow.status
            t = sent.flow.observe(status, reason, sample.logMessage)
            if t is not None:
                t.violation = t.violation or umaa_6_0.failed_reason(before, status, reason)
                sent.found += [t.violation] if t.violation else []
                sent.at.append(received)
            return
        if last is not None and sent.earlier and last.status is Status.ISSUED and len(sent.flow.transitions) == 1:
            return  # a repeat of the ISSUED/UPDATED already seen
        story = sent.story()
        if status is not Status.ISSUED:
            sent.found.append(f"{name(status)}/UPDATED: UPDATED is the reason of ISSUED only (ICD 6.0 4.1, Figure 15)")
        elif sent.updated_at is None:
            sent.found.append(
                f"ISSUED/UPDATED after {story}, though the consumer did not update the command (ICD 6.0 "
                "4.1.4.2: an update is a command with the same source and sessionID and a newer timeStamp)"
            )
        elif sent.flow.terminal:
            sent.found.append(
                f"ISSUED/UPDATED after {name(sent.flow.status)}: a command in a terminal state is not updated (ICD 6.0 4.1.4.2)"
            )
        else:
            sent.restart()
            sent.flow.observe(Status.ISSUED, Reason.SUCCEEDED, sample.logMessage)
            sent.at.append(received)

    @staticmethod
    def _update_crossed_end(sent: Sent) -> bool:
        """The consumer's update went out while the command ran, and the provider's terminal status came after it, with
        no ISSUED/UPDATED: the update reached a command in a terminal state."""
        return (
            sent.updated_at is not None
            and not sent.earlier
            and sent.flow.terminal
            and bool(sent.at)
            and sent.at[-1] >= sent.updated_at
        )

    def wait(self, sent: Sent, predicate: Callable[[], bool], seconds: float) -> bool:
        def fed() -> bool:
            self.update(sent)
            return predicate()

        return self.observer.wait(fed, seconds)

    def left(self) -> str:
        """What to add to a command test's failure when the provider is no longer on the domain: the cause."""
        if self.observer.present(self.provider):
            return ""
        self.left_told = True
        return f"; {LEFT}"

    def gone(self, case: Case) -> Case:
        """A test the provider's leaving kept from running: the first fails (a vehicle gone between two tests, or
        before them, must not pass a CI run by its command tests being skipped), those after it are skipped."""
        if self.left_told:
            return case.skip(LEFT)
        self.left_told = True
        return case.fail(LEFT)

    def close(self) -> None:
        """Service Consumer Shutdown Sequence (ICD 4.1.6.2): dispose every command still on the bus."""
        try:
            for sent in self.sent:
                self.dispose(sent)
            wait_for_acks(self.writers.values(), 2.0)
        except Stopped:  # the first SIGTERM or Ctrl-C came as the tests ended: the commands are disposed all the same
            self.close()  # (a second signal is only noted: runner.StopSignals)
            raise

    def settle(self) -> None:
        """After the command tests: every command to the provider is watched until --step-time after the consumer
        disposed it (unless the provider left), and what came after its test (a status after the cleanup, an answer
        to a command for another destination) fails the test it counts for."""
        ends = [s.disposed_at + self.limits.step for s in self.sent if s.disposed_at is not None and not s.foreign]
        if ends and self.observer.present(self.provider):
            self.observer.idle(max(0.0, max(ends) - time.time()))
        for sent in self.sent:
            self.update(sent)
            if sent.case is not None:
                (check_silent if sent.foreign else breaches)(sent, sent.case)


def other_sources(consumer: Consumer, table: dict[uuid.UUID, list[StatusSeen]], sent: Sent) -> str:
    """The sources other than the provider that answered the command (its statuses or acks), or ""."""
    return ", ".join(sorted({str(s.source) for s in table.get(sent.session, []) if s.source != consumer.provider}))


def follow(
    consumer: Consumer,
    sent: Sent,
    case: Case,
    cancel_when: frozenset[Status] = frozenset(),
    update_when: frozenset[Status] = frozenset(),
) -> bool:
    """Follow a command to a terminal status within the stated times (disposing it on reaching a status of
    `cancel_when`, updating it on reaching one of `update_when`); the Figure 4 verdict of every transition goes to the
    case. False when unanswered."""
    limits = consumer.limits
    ref = sent.refs
    answered = consumer.wait(sent, lambda: bool(sent.flow.transitions), limits.answer)
    if not answered:
        waited = time.time() - sent.sent_at
        others = other_sources(consumer, consumer.observer.statuses, sent)
        if others:  # answered, but not as the provider: say so, not "unanswered" (the network is fine)
            case.fail(
                f"the command's statuses came from source {others}, not from the provider's {consumer.provider} "
                f"(its reports' source) within {limits.answer:g} s ({ref['start']}: the provider publishes "
                "ISSUED, as itself)"
            )
            return False
        case.fail(
            f"unanswered: no status within {limits.answer:g} s of sending the command (waited {waited:.1f} s; "
            f"{ref['start']}: the provider publishes ISSUED when it receives a command){consumer.left()}"
        )
        return False
    # A provider that keeps publishing transitions (each a Figure 4 breach) must not keep the checker forever.
    overall = sent.sent_at + limits.answer + 3 * limits.step + limits.execute
    while not sent.flow.terminal:
        if time.time() > overall:
            case.fail(
                f"no terminal status within {overall - sent.sent_at:g} s of sending the command ({ref['every']}: "
                f"every command follows {ref['figure']} to its end); statuses: {sent.story()}"
            )
            break
        status = sent.flow.status
        if status in cancel_when and sent.disposed_at is None:
            consumer.dispose(sent)
        if status in update_when and sent.updated_at is None:
            consumer.update_command(sent)
            overall = max(overall, time.time() + limits.answer + 3 * limits.step + limits.execute)
        n = sent.transitions
        if status is Status.EXECUTING:
            deadline = sent.at[-1] + limits.execute
            missing = (
                f"no COMPLETED (or another terminal status) after EXECUTING ({ref['complete']}) within the stated "
                f"{limits.execute:g} s"
            )
        else:
            step = SUCCESS_NEXT.get(status)
            deadline = sent.at[-1] + limits.step
            missing = (
                f"no {name(step)} after {name(status)} ({ref[STEP_REF.get(step, 'flow')]}) within the stated {limits.step:g} s"
            )
        if sent.disposed_at is not None:
            # CANCELED answers the dispose; a command that cannot be canceled runs on to COMPLETED (ICD 4.1.4.4)
            deadline = max(deadline, sent.disposed_at + limits.step)
            missing = (
                f"no CANCELED within the stated {limits.step:g} s of the consumer's dispose ({ref['cancel']}), "
                f"nor {missing.removeprefix('no ')}"
            )

        if sent.updated_at is not None and not sent.earlier:  # the update is answered ISSUED/UPDATED
            deadline = sent.updated_at + limits.step
            missing = (
                f"no ISSUED/UPDATED within the stated {limits.step:g} s of the consumer's update of the "
                f"{name(status)} command (the same source and sessionID, a newer timeStamp: {ref['update']})"
            )

        def moved(n: int = n) -> bool:
            return sent.transitions > n

        if not consumer.wait(sent, moved, max(deadline - time.time(), 0.0)):
            case.fail(f"{missing}; statuses: {sent.story()}{consumer.left()}")
            break
    breaches(sent, case)
    case.note(f"{icd.short(consumer.topic(sent.service, 'command'))} {sent.session}: {sent.story()}")
    return True


def breaches(sent: Sent, case: Case) -> None:
    """Fail the case for each Figure 4 breach of the command not reported yet: statuses keep coming
    after `follow` (during the ack, report, cancel and cleanup checks, and after: Consumer.settle), and
    each is checked too."""
    figure = sent.refs["figure"]
    for v in sent.violations[sent.breaches_reported :]:
        case.fail(f"{figure} breach: {v} ({sent.refs['flow']}); statuses: {sent.story()}")
    sent.breaches_reported = len(sent.violations)


def check_end(sent: Sent, case: Case, canceled: bool = False, rejectable: bool = False) -> None:
    """How the command ended, against how it should have; `rejectable`: a command the provider may reject."""
    last = sent.flow.transitions[-1] if sent.flow.transitions else None
    if last is None or not sent.flow.terminal:
        return
    if sent.flow.status is Status.FAILED and rejectable:
        case.note(
            f"FAILED/{name(last.reason)} \"{last.log_message}\": rejected, an answer ({sent.refs['failed']}: the "
            "provider may reject a command)"
        )
    elif sent.flow.status is Status.FAILED:
        case.fail(f"the provider failed the command: FAILED/{name(last.reason)} \"{last.log_message}\" ({sent.refs['failed']})")
    elif sent.flow.status is Status.CANCELED and not canceled:
        case.fail(
            f"CANCELED, though the consumer did not cancel it ({sent.refs['cancel']}: CANCELED answers the consumer's dispose)"
        )


def check_ack(consumer: Consumer, sent: Sent, case: Case) -> None:
    """The ack report of a command the provider ran (ICD 4.1.4.1 step 1)."""
    if sent.flow.status in (Status.FAILED, Status.CANCELED) and sent.when(Status.EXECUTING) is None:
        return  # rejected, failed or canceled before running: no ack is due
    ack_topic = icd.short(consumer.topic(sent.service, "ack"))
    if sent.ack is None and not consumer.wait(sent, lambda: sent.ack is not None, consumer.limits.step):
        others = other_sources(consumer, consumer.observer.acks, sent)
        also = f" (one came from source {others}, not from the provider's {consumer.provider})" if others else ""
        case.fail(
            f"no {ack_topic} for the command within {consumer.limits.step:g} s of its last status{also} "
            f"({sent.refs['ack']}: the provider publishes the ack of the command it processes)"
        )
        return
    if consumer.six:
        _check_ack_6_0(consumer, sent, case, ack_topic)
    elif sent.service is Service.INERTIAL_SENSOR and sent.ack.state is not sent.sample.state:
        case.fail(f"{ack_topic} state {name(sent.ack.state)}, the command's is {sent.sample.state.name} ({sent.refs['ins ack']})")
    case.note(f"{ack_topic} +{(sent.ack_at or sent.sent_at) - sent.sent_at:.2f} s")


def _check_ack_6_0(consumer: Consumer, sent: Sent, case: Case, ack_topic: str) -> None:
    """A 6.0 ack carries the command it acknowledges (Table 11): its state, and after an update the updated command
    (its timeStamp), acked again as the flow restarts (ICD 6.0 4.1.4.2, 4.1.4.1 step 1)."""

    def current() -> bool:
        c = sent.ack.command
        return (c.timeStamp.seconds, c.timeStamp.nanoseconds) == (
            sent.sample.timeStamp.seconds,
            sent.sample.timeStamp.nanoseconds,
        )

    command = sent.ack.command
    if command.state is not sent.sample.state:
        case.fail(
            f"{ack_topic} command.state {name(command.state)}, the command's is {sent.sample.state.name} ({sent.refs['ins ack']})"
        )
    elif sent.updated_at is not None and not consumer.wait(sent, current, consumer.limits.step):
        case.fail(
            f"{ack_topic} still carries the command as it was before the consumer's update (its timeStamp) "
            f"{consumer.limits.step:g} s after the updated command's last status ({sent.refs['update']}: the flow "
            f"restarts through 4.1.4; {sent.refs['ack']}: the ack of the command it processes)"
        )


def check_silent(sent: Sent, case: Case) -> None:
    """A command addressed to another GUID: the provider published no status nor ack of it."""
    if case.outcome is Outcome.FAILED or not (sent.flow.transitions or sent.ack is not None):
        return
    answered = [f"statuses {sent.story()}" if sent.flow.transitions else "", "an ack" if sent.ack is not None else ""]
    case.fail(
        f"the provider answered the {sent.topic} addressed to {sent.to}, not to it "
        f"({' and '.join(a for a in answered if a)}; {sent.refs['destination']}{DESTINATION_REF})"
    )


def await_disposes(consumer: Consumer, sent: Sent, case: Case, after: str, ref: str) -> None:
    """The provider disposes the command's status and ack (its ack when it sent one) within --step-time."""
    need_ack = sent.ack is not None

    def done() -> bool:
        return sent.status_disposed and (sent.ack_disposed or not need_ack)

    if not consumer.wait(sent, done, consumer.limits.step):
        left = [
            icd.short(consumer.topic(sent.service, t))
            for t, d in (("status", sent.status_disposed), ("ack", sent.ack_disposed or not need_ack))
            if not d
        ]
        case.fail(
            f"the provider did not dispose its {' and '.join(left)} within {consumer.limits.step:g} s of {after} "
            f"({ref}){consumer.left()}"
        )
    else:
        case.note(f"{sent.session}: status and ack disposed after {after}")


def cleanup(consumer: Consumer, sent: Sent, case: Case) -> None:
    """Dispose a finished command; the provider disposes its status and ack (ICD 4.1.5, Figure 15). What it
    publishes from then on counts for `case`."""
    consumer.dispose(sent)
    sent.case = case
    await_disposes(
        consumer, sent, case, f"the consumer disposing the {name(sent.flow.status)} command {sent.session}", sent.refs["cleanup"]
    )
    breaches(sent, case)


def run_command_case(
    consumer: Consumer,
    service: Service,
    writer: DataWriter[Any],
    case: Case,
    offered: set[str],
    state: InsState | InsCmd | None = None,
    rejectable: bool = False,
) -> Sent:
    """One command through the flow to its end: the Figure 4 verdicts, how it ended, its ack and the report that
    shows its effect (ICD 4.1.4)."""
    sent = consumer.send(service, writer, state, case)
    if follow(consumer, sent, case):
        check_end(sent, case, rejectable=rejectable)
        if sent.flow.status is Status.COMPLETED:
            check_ack(consumer, sent, case)
            check_report = (
                _check_fix_report if service is Service.GPS_FIX else _check_ins_report_6_0 if consumer.six else _check_ins_report
            )
            check_report(consumer, sent, offered, case)
    breaches(sent, case)
    return sent


def send_foreign(
    consumer: Consumer, service: Service, writer: DataWriter[Any], case: Case, state: InsState | InsCmd | None = None
) -> Sent:
    """The destination test's command: addressed to a GUID no provider on the domain has."""
    other = uuid.uuid4()
    while other in consumer.observer.providers():
        other = uuid.uuid4()
    return consumer.send(service, writer, state, case, destination=other)


def judge_foreign(consumer: Consumer, foreign: Sent, case: Case) -> None:
    """No status nor ack of the command for another destination so far, and none until Consumer.settle looks
    again, --step-time after the dispose of the service's later commands (the provider has read the foreign one by
    then: it came first). When the provider answered no later command of the service, within --timeout of sending."""
    later = any(s.service is foreign.service and not s.foreign and s.at and s.sent_at > foreign.sent_at for s in consumer.sent)
    until = time.time() if later else foreign.sent_at + consumer.limits.answer
    consumer.wait(foreign, lambda: bool(foreign.flow.transitions) or foreign.ack is not None, max(until - time.time(), 0.0))
    check_silent(foreign, case)
    if case.outcome is Outcome.PASSED and not consumer.observer.present(consumer.provider):
        consumer.gone(case)  # its silence tells nothing
    elif case.outcome is Outcome.PASSED:
        case.note(
            f"no status nor ack of the command addressed to {foreign.to} in the "
            f"{time.time() - foreign.sent_at:.1f} s after sending it"
        )


def _reports_since(consumer: Consumer, sem: AnySem, since: float) -> list[dict[str, Any]]:
    return [
        r.body
        for r in consumer.observer.reports.get(sem, {}).get(consumer.provider, [])
        if r.alive and r.body is not None and r.received >= since
    ]


def gps_fix(consumer: Consumer, offered: set[str], selected: Callable[[str], bool]) -> list[Case]:
    cases = []
    complete, cancel, clean, destination = (Case(n) for n in GPS_NAMES)
    every = (complete, cancel, clean, destination)
    if not consumer.observer.present(consumer.provider):  # it left (in the test before, or between): waiting tells nothing
        return [consumer.gone(c) for c in every if selected(c.name)]
    writer = consumer.writer(Service.GPS_FIX)
    if writer is None:
        reason = (
            f"the provider's GPSFixCommand reader did not match the checker's command writer within "
            f"{consumer.limits.answer:g} s ({consumer.version.flow['subscribe']}: the provider subscribes to the "
            "command topic; "
            f"see discovery.GPSFixCommand){consumer.left()}"
        )
        return [c.fail(reason) if c.name in GPS_NAMES[:2] else c.skip(reason) for c in every if selected(c.name)]
    foreign = send_foreign(consumer, Service.GPS_FIX, writer, destination) if selected(destination.name) else None
    finished: Sent | None = None
    answered = True
    if selected(complete.name) or selected(clean.name):
        with Timer(complete, consumer.progress):
            sent = run_command_case(consumer, Service.GPS_FIX, writer, complete, offered)
            answered = bool(sent.flow.transitions)
            finished = sent if sent.flow.terminal else None
        cases.append(complete)
    if selected(cancel.name):
        with Timer(cancel, consumer.progress):
            if not answered:
                cancel.skip("the provider did not answer the previous GPSFix command")
            elif not consumer.observer.present(consumer.provider):
                consumer.gone(cancel)
            else:
                _cancel(consumer, writer, cancel)
        cases.append(cancel)
    if selected(clean.name):
        with Timer(clean, consumer.progress):
            if finished is None:
                clean.skip("needs a command that finished: see commands.GPSFix.complete")
            else:
                cleanup(consumer, finished, clean)
        cases.append(clean)
    if foreign is not None:
        with Timer(destination, consumer.progress):
            judge_foreign(consumer, foreign, destination)
        cases.append(destination)
    return [c for c in cases if selected(c.name)]


def _check_fix_report(consumer: Consumer, sent: Sent, offered: set[str], case: Case) -> None:
    if "GPSFixStatus" not in offered:
        case.note("the provider does not serve GPSFixReport: the position after the fix not checked")
        return
    executing = sent.when(Status.EXECUTING) or sent.sent_at

    def valid() -> bool:
        return any(b.get("GPSLatLongValid") for b in _reports_since(consumer, Sem.GPS_FIX_REPORT, executing))

    if not consumer.wait(sent, valid, consumer.limits.step):
        case.fail(
            f"COMPLETED, but no GPSFixReport with GPSLatLongValid since EXECUTING, nor within {consumer.limits.step:g} s "
            "after (ICD 5.1.1.3: the platform surfaces to update its GPS position)"
        )


def _cancel(
    consumer: Consumer, writer: DataWriter[Any], case: Case, service: Service = Service.GPS_FIX, state: InsCmd | None = None
) -> None:
    """A command disposed while EXECUTING; when it completes before that, a second one disposed at its first status."""
    for when in (frozenset({Status.EXECUTING}), ACTIVE):
        sent = consumer.send(service, writer, state, case=case)
        follow(consumer, sent, case, cancel_when=when)
        canceled = check_cancel(consumer, sent, case)
        breaches(sent, case)
        if canceled:
            return
        case.note(f"{sent.session} COMPLETED before the checker could dispose it at " + ", ".join(sorted(s.name for s in when)))
    case.skip(
        "both commands COMPLETED before the checker could dispose them; cancel not tested (each one's status "
        f"and ack were disposed after its dispose, {sent.refs['cleanup'].split(',')[0]})"
    )


def check_cancel(consumer: Consumer, sent: Sent, case: Case) -> bool:
    """What the provider did after the consumer's dispose (ICD 4.1.4.4). False: the command COMPLETED before the
    dispose, and is cleaned up instead (ICD 4.1.5)."""
    if not sent.flow.transitions:
        return True  # unanswered: already failed
    status = sent.flow.status
    if sent.disposed_at is None:
        if status is Status.COMPLETED:
            cleanup(consumer, sent, case)
            return False
        check_end(sent, case)
        return True
    last = sent.flow.transitions[-1]
    if status is Status.CANCELED:
        case.note(f"CANCELED/{name(last.reason)} +{sent.at[-1] - sent.disposed_at:.2f} s after the dispose")
    elif status is Status.COMPLETED:
        case.note(
            f"COMPLETED +{sent.at[-1] - sent.disposed_at:.2f} s after the dispose: the provider did not cancel it, "
            f"which {sent.refs['cancel']} allows for a command that cannot be canceled"
        )
    else:
        check_end(sent, case, canceled=True)
    check_ack(consumer, sent, case)
    if sent.flow.terminal:
        await_disposes(
            consumer,
            sent,
            case,
            f"{name(status)}, the consumer having disposed the command at {name(sent.disposed_in)}",
            f"{sent.refs['cancel']}, {sent.refs['cancel figure']}: CANCELED, or COMPLETED when it cannot be "
            "canceled, then the provider "
            "disposes the command's status and ack",
        )
    return True


def ins_state(consumer: Consumer) -> str | None:
    """The state the provider's InertialSensorReport shows now, a UMAA 6.0 provider's InertialSensorReportType its
    status (None: it sent none)."""
    sem, member = (Sem60.INS_REPORT, "status") if consumer.six else (Sem.INS_REPORT, "state")
    last = _reports_since(consumer, sem, 0.0)
    return last[-1].get(member) if last else None


def settled_state(consumer: Consumer) -> InsState | None:
    """The state the inertial sensor is in, or ends in (a restart ends ON), by its report; None: unknown."""
    now = ins_state(consumer) or ""
    now = SETTLED.get(now, now)
    return InsState[now] if now in InsState.__members__ else None


def ins_changed(consumer: Consumer, before: str | None) -> str | None:
    """What to tell the person running it when the inertial sensor reports another state than before the run's
    InertialSensor commands (a run stopped between them, a subset of them, a provider that failed one): a
    vehicle must not be left with its INS off unawares. A restart ends ON, as the plan says."""
    if before is None or not any(s.service is Service.INERTIAL_SENSOR for s in consumer.sent):
        return None
    consumer.observer.pump()
    now = ins_state(consumer)
    if consumer.six:  # an alignment of the kind it had before, whatever its stage now, is as found
        was = umaa_6_0.kind(before)
        if was is None or was is umaa_6_0.kind(now or ""):
            return None
        return (
            f"the inertial sensor reports {now or 'no status'} now; it reported {before} before the InertialSensor "
            f"commands: command {was.name} to set it back"
        )
    if SETTLED.get(now or "", now) == SETTLED.get(before, before):
        return None
    return (
        f"the inertial sensor reports {now or 'no state'} now; it reported {before} before the InertialSensor "
        f"commands: set it back to {SETTLED.get(before, before)}"
    )


def ins_plan(consumer: Consumer) -> list[InsState]:
    """OFF, ON, RESTARTING; from ON, RESTARTING, OFF when the INS reports OFF: it ends as found."""
    if ins_state(consumer) == "OFF":
        return [InsState.ON, InsState.RESTARTING, InsState.OFF]
    return [InsState.OFF, InsState.ON, InsState.RESTARTING]


def inertial_sensor(consumer: Consumer, offered: set[str], selected: Callable[[str], bool]) -> list[Case]:
    cases: list[Case] = []
    clean, destination = Case(INS_NAMES[-2]), Case(INS_NAMES[-1])
    if not consumer.observer.present(consumer.provider):  # it left (in the test before, or between): waiting tells nothing
        return [consumer.gone(Case(n)) for n in INS_NAMES if selected(n)]
    writer = consumer.writer(Service.INERTIAL_SENSOR)
    if writer is None:
        reason = (
            f"the provider's InertialSensorCommand reader did not match the checker's command writer within "
            f"{consumer.limits.answer:g} s ({consumer.version.flow['subscribe']}: the provider subscribes to the "
            "command topic; "
            f"see discovery.InertialSensorCommand){consumer.left()}"
        )
        return [
            Case(n).fail(reason) if n not in (clean.name, destination.name) else Case(n).skip(reason)
            for n in INS_NAMES
            if selected(n)
        ]
    # addressed elsewhere, for the state the sensor is in: a provider that answers it anyway changes nothing
    now = settled_state(consumer)
    foreign = (
        send_foreign(consumer, Service.INERTIAL_SENSOR, writer, destination, InsState.ON if now is None else now)
        if selected(destination.name)
        else None
    )
    answered = True
    finished: list[Sent] = []
    for state in [*ins_plan(consumer), None]:
        case = Case(f"commands.InertialSensor.{state.name if state is not None else 'same'}")
        if not selected(case.name):
            continue
        with Timer(case, consumer.progress):
            # the same test: a command for the state the sensor is in (its report, or the last command's)
            target = state if state is not None else _same(consumer, finished)
            if not answered:
                case.skip("the provider did not answer the previous InertialSensor command")
            elif not consumer.observer.present(consumer.provider):
                consumer.gone(case)
            elif target is None:
                case.skip(
                    "the state the inertial sensor is in is unknown: it serves no InertialSensorReport, and no "
                    "InertialSensor command of this run finished"
                )
            else:
                # the same test asks for an answer: a provider may reject a command for the state the sensor is in
                sent = run_command_case(
                    consumer, Service.INERTIAL_SENSOR, writer, case, offered, target, rejectable=state is None
                )
                answered = bool(sent.flow.transitions)
                if sent.flow.terminal:
                    finished.append(sent)
                    # clean up now: the next command must not find this one on the bus
                    cleanup(consumer, sent, clean)
                    if clean.outcome is Outcome.FAILED and consumer.progress is not None:
                        consumer.progress.add([clean])  # a run stopped later still reports this failure
        cases.append(case)
    return _last_cases(consumer, cases, clean, destination, foreign, finished, selected)


def _last_cases(
    consumer: Consumer,
    cases: list[Case],
    clean: Case,
    destination: Case,
    foreign: Sent | None,
    finished: list[Sent],
    selected: Callable[[str], bool],
) -> list[Case]:
    """The InertialSensor tests' last: the cleanup (skipped when no command finished) and the destination test."""
    if selected(clean.name):
        if not finished:
            clean.skip("needs a command that finished: see the commands.InertialSensor tests")
        cases.append(clean)
    if foreign is not None:
        with Timer(destination, consumer.progress):
            judge_foreign(consumer, foreign, destination)
        cases.append(destination)
    return cases


def _same(consumer: Consumer, finished: list[Sent]) -> InsState | None:
    """The state the inertial sensor is in: as it reports, else as the last InertialSensor command that COMPLETED
    left it."""
    now = settled_state(consumer)
    done = [s.sample.state for s in finished if s.flow.status is Status.COMPLETED]
    if now is not None or not done:
        return now
    return InsState[SETTLED.get(done[-1].name, done[-1].name)]


def _check_ins_report(consumer: Consumer, sent: Sent, offered: set[str], case: Case) -> None:
    if "InertialSensorStatus" not in offered:
        case.note("the provider does not serve InertialSensorReport: the reported state not checked")
        return
    target: InsState = sent.sample.state
    executing = sent.when(Status.EXECUTING) or sent.sent_at

    def seen() -> bool:
        bodies = _reports_since(consumer, Sem.INS_REPORT, executing)
        if target is InsState.RESTARTING:  # a restart shows as RESTARTING, or as a new alignment from INIT
            return any(b.get("state") == "RESTARTING" or b.get("status") == "INIT" for b in bodies)
        return bool(bodies) and bodies[-1].get("state") == target.name

    if not consumer.wait(sent, seen, consumer.limits.step):
        shown = [b.get("state") for b in _reports_since(consumer, Sem.INS_REPORT, executing)]
        case.fail(
            f"COMPLETED, but the InertialSensorReport did not show {target.name} from EXECUTING to "
            f"{consumer.limits.step:g} s after (it showed {', '.join(dict.fromkeys(map(str, shown))) or 'nothing'}; "
            "ICD 5.1.4.3 and 5.1.5.1)"
        )


def _check_ins_report_6_0(consumer: Consumer, sent: Sent, offered: set[str], case: Case) -> None:
    """The InertialSensorReportType shows the command's effect from EXECUTING: INIT, or a stage of the commanded kind
    of alignment (ICD 6.0 5.1.2.3, Table 13; 5.1.3.1, Table 15; 5.3.3, 5.3.4)."""
    if "InertialSensorStatus" not in offered:
        case.note("the provider does not serve InertialSensorReportType: the reported status not checked")
        return
    target: InsCmd = sent.sample.state
    executing = sent.when(Status.EXECUTING) or sent.sent_at

    def seen() -> bool:
        return any(umaa_6_0.shows(target, b) for b in _reports_since(consumer, Sem60.INS_REPORT, executing))

    if not consumer.wait(sent, seen, consumer.limits.step):
        shown = [b.get("status") for b in _reports_since(consumer, Sem60.INS_REPORT, executing)]
        what = "INIT" if target is InsCmd.INIT else f"a stage of its {target.name} alignment"
        case.fail(
            f"COMPLETED, but the InertialSensorReportType did not show {what} from EXECUTING to "
            f"{consumer.limits.step:g} s after (it showed {', '.join(dict.fromkeys(map(str, shown))) or 'nothing'}; "
            "ICD 6.0 5.1.2.3, Table 13; 5.1.3.1, Table 15; 5.3.3, Table 27; 5.3.4, Table 28)"
        )


def _update(consumer: Consumer, writer: DataWriter[Any], case: Case, clean: Case, offered: set[str]) -> Sent | None:
    """UMAA 6.0: a GPS_ALIGN updated (the same source and sessionID, a newer timeStamp) while EXECUTING, or, when it
    completes before that, a second one at its first status: ISSUED/UPDATED, then the flow again to its end, the ack of
    the updated command, its report, and the cleanup (ICD 6.0 4.1.4.2). The finished command, or None."""
    for when in (frozenset({Status.EXECUTING}), ACTIVE):
        sent = consumer.send(Service.INERTIAL_SENSOR, writer, umaa_6_0.LAST, case)
        if not follow(consumer, sent, case, update_when=when):
            return None
        if case.outcome is Outcome.FAILED:  # the update went unanswered, or the flow broke
            return sent
        if sent.updated_at is not None and sent.earlier:
            check_end(sent, case)
            if sent.flow.status is Status.COMPLETED:
                check_ack(consumer, sent, case)
                _check_ins_report_6_0(consumer, sent, offered, case)
            breaches(sent, case)
            return sent
        ended = sent.at[-1] if sent.at else sent.sent_at
        if sent.updated_at is not None and ended > sent.updated_at + consumer.limits.step:
            case.fail(
                f"the provider ran the command on to {name(sent.flow.status)} without answering the consumer's "
                f"update ISSUED/UPDATED ({sent.refs['update']}); statuses: {sent.story()}"
            )
            return sent
        case.note(
            f"{sent.session} {name(sent.flow.status)} before the checker could update it (or the provider "
            "could read the update) at " + ", ".join(sorted(s.name for s in when))
        )
        breaches(sent, case)
        cleanup(consumer, sent, clean)
    case.skip("both commands ended before the checker could update them; update not tested")
    return None


def inertial_sensor_6_0(consumer: Consumer, offered: set[str], selected: Callable[[str], bool]) -> list[Case]:
    """UMAA 6.0's InertialSensorControl (umaa_6_0.TESTS): each InertialSensorCmdEnumType command through the flow,
    GPS_ALIGN again (the alignment it is in: answered, or rejected), a cancel, an update, the cleanup after each, and
    first a command to another destination, which the provider must not answer."""
    cases: list[Case] = []
    by = {n: Case(n) for n in INS_NAMES_6_0}
    clean, destination = by["commands.InertialSensor.cleanup"], by["commands.InertialSensor.destination"]
    if not consumer.observer.present(consumer.provider):
        return [consumer.gone(c) for c in by.values() if selected(c.name)]
    writer = consumer.writer(Service.INERTIAL_SENSOR)
    if writer is None:
        reason = (
            f"the provider's InertialSensorCommandType reader did not match the checker's command writer within "
            f"{consumer.limits.answer:g} s ({consumer.version.flow['subscribe']}: the provider subscribes to the "
            f"command topic; see discovery.InertialSensorCommandType){consumer.left()}"
        )
        return [c.skip(reason) if c in (clean, destination) else c.fail(reason) for c in by.values() if selected(c.name)]
    foreign = (
        send_foreign(consumer, Service.INERTIAL_SENSOR, writer, destination, umaa_6_0.LAST)
        if selected(destination.name)
        else None
    )
    answered = True
    finished: list[Sent] = []
    for step in umaa_6_0.TESTS:
        case = by[f"commands.InertialSensor.{step if isinstance(step, str) else step.name}"]
        target = umaa_6_0.LAST if isinstance(step, str) else step  # same: the alignment the last GPS_ALIGN left
        if not selected(case.name):
            continue
        with Timer(case, consumer.progress):
            if not answered:
                case.skip("the provider did not answer the previous InertialSensor command")
            elif not consumer.observer.present(consumer.provider):
                consumer.gone(case)
            elif step == "cancel":
                _cancel(consumer, writer, case, Service.INERTIAL_SENSOR, umaa_6_0.LAST)
            elif step == "update":
                done = _update(consumer, writer, case, clean, offered)
                if done is not None and done.flow.terminal:
                    finished.append(done)
                    cleanup(consumer, done, clean)
            else:
                # same: a provider may reject it (ICD 6.0 4.1.4.4)
                if step == "same" and not any(s.sample.state is target and s.flow.status is Status.COMPLETED for s in finished):
                    case.skip(f"needs a {target.name} that COMPLETED: see commands.InertialSensor.{target.name}")
                else:
                    rejectable = step == "same" or step in umaa_6_0.REJECTABLE
                    sent = run_command_case(consumer, Service.INERTIAL_SENSOR, writer, case, offered, target, rejectable)
                    answered = bool(sent.flow.transitions)
                    if sent.flow.terminal:
                        finished.append(sent)
                        cleanup(consumer, sent, clean)
        if clean.outcome is Outcome.FAILED and consumer.progress is not None:
            consumer.progress.add([clean])
        cases.append(case)
    return _last_cases(consumer, cases, clean, destination, foreign, finished, selected)


def run(consumer: Consumer, offered: set[str], selected: Callable[[str], bool]) -> list[Case]:
    cases: list[Case] = []
    if consumer.six:
        try:
            if "InertialSensorControl" in offered:
                cases += inertial_sensor_6_0(consumer, offered, selected)
            else:
                cases += [
                    Case(n).skip("the provider does not offer the InertialSensorControl service")
                    for n in INS_NAMES_6_0
                    if selected(n)
                ]
        finally:
            consumer.close()
        consumer.settle()
        return cases
    try:
        if "GPSFixControl" in offered:
            cases += gps_fix(consumer, offered, selected)
        else:
            cases += [Case(n).skip("the provider does not offer the GPSFixControl service") for n in GPS_NAMES if selected(n)]
        if consumer.progress is not None:  # some ended without a Timer: a run stopped later reports them as they are
            consumer.progress.add(cases)
        if "InertialSensorControl" in offered:
            cases += inertial_sensor(consumer, offered, selected)
        else:
            cases += [
                Case(n).skip("the provider does not offer the InertialSensorControl service") for n in INS_NAMES if selected(n)
            ]
    finally:
        consumer.close()
    consumer.settle()
    return cases


def plan_6_0(offered: set[str], selected: Callable[[str], bool]) -> list[str]:
    """What --commands will send to a UMAA 6.0 provider."""
    if "InertialSensorControl" not in offered:
        return []
    last = umaa_6_0.LAST.name
    said = {
        "same": f"{last} again (the alignment it is in)",
        "cancel": f"{last} canceled while executing (another when it completes first)",
        "update": f"{last} updated (a newer timeStamp) while executing",
    }
    tests = [t if isinstance(t, str) else t.name for t in umaa_6_0.TESTS]
    sends = [said.get(t, t) for t in tests if selected(f"commands.InertialSensor.{t}")]
    if "same" in tests and selected("commands.InertialSensor.same") and not selected(f"commands.InertialSensor.{last}"):
        sends.remove(said["same"])  # it needs the GPS_ALIGN test's (it is skipped)
    ran = [t for t in tests if selected(f"commands.InertialSensor.{t}") and t not in ("same", "cancel")]
    text = ", then ".join(sends)
    if ran:
        left = last if ran[-1] in ("update", last) else ran[-1]
        text += f" (the inertial sensor is left {'initializing' if left == 'INIT' else 'aligned by ' + left})"
    if selected("commands.InertialSensor.destination"):
        other = "first one addressed to another GUID, which the vehicle must not answer"
        text = f"{text}; {other}" if text else other
    return [f"InertialSensorCommandType: {text}"] if text else []


def plan(consumer: Consumer, offered: set[str], selected: Callable[[str], bool]) -> list[str]:
    """What --commands will send, said before anything is sent."""
    if consumer.six:
        return plan_6_0(offered, selected)
    lines = []

    def elsewhere(text: str, what: str) -> str:  # the destination test's command
        other = f"one{what} addressed to another GUID, which the vehicle must not answer"
        return f"{text}; first {other}" if text else other

    gps = [n for n in GPS_NAMES if selected(n)]
    if "GPSFixControl" in offered and gps:
        text = "the vehicle surfaces for a GPS fix" if set(gps) & set(GPS_NAMES[:3]) else ""
        if GPS_NAMES[1] in gps:
            text += " (a second command is canceled while executing; a third when the second completes first)"
        lines.append(f"GPSFixCommand: {elsewhere(text, '') if GPS_NAMES[3] in gps else text}")
    ins = [s.name for s in ins_plan(consumer) if selected(f"commands.InertialSensor.{s.name}")]
    same = selected(INS_NAMES[3])
    if "InertialSensorControl" in offered and (ins or same or selected(INS_NAMES[5])):
        # The full plan ends as found; a --only/--skip subset may not, and the person running it must know.
        now = ins_state(consumer)
        settled = SETTLED.get(now or "", now)
        left = ("OFF" if ins[-1] == "OFF" else "ON") if ins else settled
        if now is None:
            tail = "; it reports no state now"
        elif left == settled:
            tail = ", as it reports now"
        else:
            tail = f"; it reports {now} now"
        sends = ins + ([f"{left} again"] if same and left else [])
        text = f"{', then '.join(sends)} (the inertial sensor is left {left or 'as it is'}{tail})" if sends else ""
        if selected(INS_NAMES[5]):
            text = elsewhere(text, f" for {settled or 'ON'}")
        if text:  # none: only the same test, for a state not known (it is skipped)
            lines.append(f"InertialSensorCommand: {text}")
    return lines
