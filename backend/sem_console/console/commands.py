"""The console as UMAA Service Consumer for GPSFixControl and InertialSensorControl (ICD 4.1).

Plain Python: DDS writes go through the `write` and `dispose` callables given to it.
Each command gets a fresh RFC 4122 sessionID; every status is checked against Figure 4
(umaa.flow); cancel is a dispose; cleanup disposes the command once it is COMPLETED or
FAILED; a command with no ISSUED within `unanswered_timeout` is marked unanswered. A canceled command the
vehicle never answered is ended by the console (`closed_unheard`): once the vehicle is heard again for the
unanswered timeout without a status of it (it never heard the command: the cancel disposed it first), or when the
vehicle is not heard within `cancel_unheard_bound` of the cancel. An operator's cancel is disposed once the database
has it (`CANCEL_STORED_WAIT` at most): the other stations are told who cancelled before the vehicle can answer, and
never show a command CANCELED with its canceller unknown. Another station's canceled command with no status
is ended here by the same rule (`others`), whether or not that station still runs: the first ending stored stands, and
every station shows it.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import uuid
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any, Literal, cast

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status

from sem_console.console.clock import Clock
from sem_console.core import messages
from sem_console.core.messages import ServerMessage, command_message, transition_message
from sem_console.dds.topics import AnySem, Service
from sem_console.storage.commands import CommandRow
from sem_console.storage.database import Database
from sem_console.umaa.flow import AnyReason, CommandFlow, name, parse, parse_reason
from sem_console.umaa.samples import datetime_to_float, now_datetime
from sem_console.versions.commands import Commanding, of_command

log = logging.getLogger("sem-console.commands")
Emit = Callable[[ServerMessage], None]
Heard = Callable[[uuid.UUID], float | None]  # a provider's last sample, monotonic seconds (None: not heard, or lost)
ClosedUnheard = Literal["heard", "bound"]
CancelCause = Literal["operator", "shutdown"]  # an operator asked it; its station's shutdown cancelled it
KEEP_FINISHED = 500  # finished commands kept in memory and in snapshots; older ones are read from the database
CANCEL_STORED_WAIT = 0.5  # s: the longest a cancel's dispose waits for the database to store it (a write is ms; an
# outage or a queue of writes must not hold a cancel on its way to the vehicle)


@dataclass
class Command:
    session_id: uuid.UUID
    service: Service
    provider_id: uuid.UUID
    state: str | None  # the commanded state's literal (InertialSensor), of its vehicle's version
    operator: str | None
    created_at: float
    sample: Any
    commanding: Commanding  # its version's topics and samples (versions/commands.py)
    flow: CommandFlow = field(default_factory=CommandFlow)
    times: list[tuple[float | None, float]] = field(default_factory=list)  # (provider time, received) per transition
    unanswered: bool = False
    cancel_requested: bool = False
    canceled_by: str | None = None
    canceled_on: str | None = None  # the station its cancel was asked on
    canceled_at: float | None = None  # wall seconds
    cancel_cause: CancelCause | None = None  # None: not canceled, or canceled before the cause was recorded
    closed_unheard: ClosedUnheard | None = None
    closed_at: float | None = None
    heard_from: float | None = None  # canceled, unanswered: its vehicle's first sample since the cancel (monotonic)
    cancel_mono: float = 0.0  # monotonic seconds of the cancel (or of the console's start, for one loaded)
    cleaned_up: bool = False
    acked_at: float | None = None
    issued_by_deadline: float = 0.0
    console: str | None = None  # the console station that issued it (--console-name); None: before station names
    answered_late_after: float | None = None  # seconds it was unanswered, when a status came after all (not stored)
    # Loaded from history: the statuses already recorded, which the provider's transient-local
    # history delivers again after a restart (in order, perhaps only the last few).
    replay: list[tuple[Status | int, AnyReason | int, float | None]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.flow.figure = self.commanding.figure  # its violations name its version's figure

    @property
    def terminal(self) -> bool:
        """Finished: a final status, or ended by the console, canceled and never answered."""
        return self.flow.terminal or self.closed_unheard is not None

    def to_json(self) -> messages.Command:
        return {
            "sessionId": str(self.session_id),
            "service": self.service.value,
            "providerId": str(self.provider_id),
            "state": self.state,
            "operator": self.operator,
            "createdAt": self.created_at,
            "status": name(self.flow.status) if self.flow.status else None,
            "terminal": self.terminal,
            "unanswered": self.unanswered,
            "cancelRequested": self.cancel_requested,
            "canceledBy": self.canceled_by,
            "canceledOn": self.canceled_on,
            "canceledAt": self.canceled_at,
            "cancelCause": self.cancel_cause,
            "closedUnheard": self.closed_unheard,
            "closedAt": self.closed_at,
            "cleanedUp": self.cleaned_up,
            "console": self.console,
            "ackedAt": self.acked_at,
            "violations": self.flow.violations,
            "transitions": [
                transition_json(i, t, pt, rt)
                for i, (t, (pt, rt)) in enumerate(zip(self.flow.transitions, self.times, strict=True), start=1)
            ],
        }


def transition_json(seq: int, t: Any, provider_time: float | None, received_at: float) -> messages.Transition:
    return {
        "seq": seq,
        "status": name(t.status),
        "reason": name(t.reason),
        "logMessage": t.log_message,
        "violation": t.violation,
        "providerTime": provider_time,
        "receivedAt": received_at,
    }


def _uuid_or_none(text: Any) -> uuid.UUID | None:
    return uuid.UUID(text) if isinstance(text, str) else None


class CommandError(Exception):
    """A command request the console cannot carry out (unknown session, already finished...)."""


class Commands:
    def __init__(
        self,
        source: uuid.UUID,
        store: Database,
        write: Callable[[AnySem, Any], None],  # a command sample on its topic
        dispose: Callable[[AnySem, Any], None],
        emit: Emit,
        unanswered_timeout: float,
        clock: Clock | None = None,
        station: str | None = None,
        cancel_unheard_bound: float = 3600.0,
    ) -> None:
        self.station = station  # this console's name: the commands it issued are its own to follow and clean up
        self.source, self.store, self._write, self._dispose, self.emit = source, store, write, dispose, emit
        self.clock = clock or Clock()
        self.unanswered_timeout, self.cancel_unheard_bound = unanswered_timeout, cancel_unheard_bound
        self.by_session: dict[uuid.UUID, Command] = {}
        # other stations' canceled commands with no status, which this station ends too if the vehicle never answers
        # (`_watch`): from the database at start, then from the other stations' notifications
        self.others: dict[uuid.UUID, Command] = {}
        # endings as never heard asked of the database, until written: one refused shows what is stored (`tick`)
        self._endings: list[tuple[Command, Future[CommandRow | None]]] = []
        self._cancels: list[tuple[Command, Future[CommandRow | None]]] = []  # cancels written behind (`_refused_cancels`)
        # cancels waiting for the database to store them before their dispose goes (`_withdraw_once_stored`)
        self._withdrawing: dict[uuid.UUID, Callable[[], None]] = {}
        self._load_history()

    # ---- history --------------------------------------------------------------------
    def _load_history(self) -> None:
        for row in self.store.commands(limit=KEEP_FINISHED, unfinished=True, console=self.station):
            cmd = self.from_row(row)
            cmd.replay = [(t.status, t.reason, pt) for t, (pt, _rt) in zip(cmd.flow.transitions, cmd.times, strict=True)]
            self.by_session[cmd.session_id] = cmd
        for row in self.store.commands(limit=0, unfinished=True):
            self._watch(self.from_row(row))

    def from_row(self, row: CommandRow, source: uuid.UUID | None = None) -> Command:
        """The command of a database row; `source`: the GUID of the console that issued it when not this one."""
        service = Service(row["service"])
        state: str | None = row["state"] or None
        provider, session = uuid.UUID(row["provider_id"]), uuid.UUID(row["session_id"])
        commanding = of_command(service, state)
        cmd = Command(
            session,
            service,
            provider,
            state,
            row["operator"],
            row["created_at"],
            self._sample(
                commanding,
                provider,
                session,
                state,
                row["command"]["timeStamp"],
                source,
                _uuid_or_none(row["command"].get("destinationParent")),
            ),
            commanding,
            unanswered=bool(row["unanswered"]),
            cancel_requested=bool(row["cancel_requested"]),
            canceled_by=row["canceled_by"],
            canceled_on=row.get("canceled_on"),
            canceled_at=row.get("canceled_at"),
            cancel_cause=cast(CancelCause | None, row.get("cancel_cause")),
            closed_unheard=cast(ClosedUnheard | None, row.get("closed_unheard")),
            closed_at=row.get("closed_at"),
            cleaned_up=bool(row["cleaned_up"]),
            acked_at=row["acked_at"],
            console=row.get("console"),
            cancel_mono=self.clock.monotonic(),
        )
        for t in row["transitions"]:
            if (
                cmd.flow.observe(parse(Status, t["status"]), parse_reason(t["reason"]), t["log_message"], t["provider_time"])
                is not None
            ):
                cmd.times.append((t["provider_time"], t["received_at"]))  # times stay parallel to the transitions
        return cmd

    def history(self, limit: int, offset: int, provider_id: uuid.UUID | None = None) -> list[messages.Command]:
        """Newest first, from the database (memory holds only active and recent commands); for a worker thread."""
        rows = self.store.commands(limit=limit, offset=offset, provider_id=None if provider_id is None else str(provider_id))
        return [self.from_row(r).to_json() for r in rows]

    async def get(self, session: uuid.UUID) -> Command | None:
        """From memory, else from the database (read in a worker thread: never on the event loop)."""
        if session in self.by_session:
            return self.by_session[session]
        rows = await asyncio.to_thread(self.store.commands, session_id=str(session))
        return self.from_row(rows[0]) if rows else None

    def _forget_old(self) -> None:
        """Keep the active commands and the KEEP_FINISHED most recent finished ones in memory."""
        finished = [c for c in self.by_session.values() if c.cleaned_up]
        if len(finished) > KEEP_FINISHED:
            for c in sorted(finished, key=lambda c: c.created_at)[: len(finished) - KEEP_FINISHED]:
                del self.by_session[c.session_id]

    def _sample(
        self,
        commanding: Commanding,
        provider: uuid.UUID,
        session: uuid.UUID,
        state: str | None,
        stamp: tuple[int, int] | list[int],
        source: uuid.UUID | None = None,
        parent: uuid.UUID | None = None,
    ) -> Any:
        """The command sample, as its vehicle's version writes it (`source`: another station's, when not ours;
        `parent`: the provider's, UMAA 6.0)."""
        return commanding.build(source or self.source, provider, session, state, (int(stamp[0]), int(stamp[1])), parent)

    def _publish(self, cmd: Command) -> None:
        self._write(cmd.commanding.command, cmd.sample)

    def _withdraw(self, cmd: Command) -> None:
        self._dispose(cmd.commanding.command, cmd.sample)

    # ---- consumer flow --------------------------------------------------------------
    def on_ack(self, service: Service, session: uuid.UUID, source: uuid.UUID) -> None:
        """The provider reports it is executing this command (its CommandAckReport)."""
        cmd = self.by_session.get(session)
        if cmd is None or cmd.service is not service or source != cmd.provider_id or cmd.acked_at is not None:
            return
        cmd.acked_at = self.clock.wall()
        self.store.set_acked(str(session), cmd.acked_at)
        self.emit(command_message(cmd.to_json()))

    def startup(self) -> list[Command]:
        """Consumer Startup Sequence: resume following our commands that were not finished."""
        resumed = [c for c in self.by_session.values() if not c.cleaned_up and not c.flow.terminal and not c.cancel_requested]
        for c in resumed:
            c.issued_by_deadline = self.clock.monotonic() + self.unanswered_timeout
            try:
                self._publish(c)  # the same immutable command: a provider that has it sees no change
            except Exception as e:  # a bad row must not stop the others
                log.warning("cannot publish command %s again: %s", c.session_id, e)
        for c in self.by_session.values():
            if c.flow.terminal and not c.cleaned_up and not c.cancel_requested:
                self.cleanup(c)
        return resumed

    def issue(
        self,
        commanding: Commanding,
        provider: uuid.UUID,
        state: str | None,
        operator: str | None,
        parent: uuid.UUID | None = None,
    ) -> Command:
        """Publish a command of `commanding` (the vehicle's version's) with the `state` literal of its choices, to the
        provider's identifier (`parent`: the parent it reports, UMAA 6.0)."""
        session = uuid.uuid4()
        stamp = now_datetime()
        cmd = Command(
            session,
            commanding.service,
            provider,
            state,
            operator,
            self.clock.wall(),
            self._sample(commanding, provider, session, state, (stamp.seconds, stamp.nanoseconds), None, parent),
            commanding,
            issued_by_deadline=self.clock.monotonic() + self.unanswered_timeout,
            console=self.station,
        )
        self.by_session[session] = cmd
        sent: dict[str, Any] = {"timeStamp": [stamp.seconds, stamp.nanoseconds]}
        if parent is not None:
            sent["destinationParent"] = str(parent)  # the command's key: the same instance when it is disposed later
        self.store.add_command(dict(cmd.to_json()), sent, self.station)
        self._publish(cmd)
        self.emit(command_message(cmd.to_json()))
        return cmd

    def adopt(self, c: dict[str, Any]) -> Command:
        """Replay: a command the recorded console issued or changed (its `command` message, as on the
        WebSocket). A new one is followed from here on like one issued here, but never published; its cancel
        request and the console's ending of it unanswered are taken over. Statuses and acks come from the recorded
        samples."""
        session = uuid.UUID(c["sessionId"])
        cmd = self.by_session.get(session)
        changed = cmd is None
        if cmd is None:
            service, provider = Service(c["service"]), uuid.UUID(c["providerId"])
            state = c.get("state") or None
            commanding = of_command(service, state)
            stamp = (int(c["createdAt"]), int(c["createdAt"] % 1 * 1e9))
            cmd = Command(
                session,
                service,
                provider,
                state,
                c.get("operator"),
                float(c["createdAt"]),
                self._sample(commanding, provider, session, state, stamp),
                commanding,
                issued_by_deadline=self.clock.monotonic() + self.unanswered_timeout,
                console=c.get("console"),
            )
            self.by_session[session] = cmd  # the station that issued it is the recorded console's
            self.store.add_command(dict(cmd.to_json()), {"timeStamp": list(stamp)}, cmd.console)
        # a message carries the whole command: the first one of a file may be of one already canceled, or ended
        if c.get("cancelRequested") and not cmd.cancel_requested:
            self._canceled(
                cmd, c.get("canceledBy"), c.get("canceledOn"), c.get("canceledAt") or self.clock.wall(), c.get("cancelCause")
            )
            changed = True
        elif c.get("cancelRequested") and (c.get("canceledBy"), c.get("canceledOn")) != (cmd.canceled_by, cmd.canceled_on):
            # the recorded console's own cancel was refused (another was stored first, `_refused_cancels`): it showed
            # that one from then on, and so does the replay
            cmd.canceled_by, cmd.canceled_on, cmd.canceled_at = c.get("canceledBy"), c.get("canceledOn"), c.get("canceledAt")
            cmd.cancel_cause = cast(CancelCause | None, c.get("cancelCause"))
            self.store.set_canceller(str(cmd.session_id), cmd.canceled_by, cmd.canceled_on, cmd.canceled_at, cmd.cancel_cause)
            changed = True
        if c.get("closedUnheard") and cmd.closed_unheard is None and not cmd.flow.transitions:
            self._close_unheard(cmd, c["closedUnheard"], c.get("closedAt") or self.clock.wall(), emit=False)
            changed = True
        if changed:
            self.emit(command_message(cmd.to_json()))
        return cmd

    def cancel(self, session: uuid.UUID, operator: str | None = None, cause: CancelCause = "operator") -> Command:
        cmd = self.by_session.get(session)
        if cmd is None:  # not in memory: unknown, finished long ago, or another station's not taken over
            raise CommandError(f"command {session} is not running")
        if cmd.flow.terminal or cmd.cleaned_up:
            raise CommandError(
                f"command {session} already finished ({name(cmd.flow.status) if cmd.flow.status else 'cleaned up'})"
            )
        if not cmd.cancel_requested:
            stored = self._canceled(cmd, operator, self.station, self.clock.wall(), cause)
            if cause == "shutdown" or stored is None:
                self._withdraw(cmd)
            else:
                self._withdraw_once_stored(cmd, stored)
            self.emit(command_message(cmd.to_json()))
        return cmd

    def _withdraw_once_stored(self, cmd: Command, stored: Future[CommandRow | None]) -> None:
        """Dispose `cmd` (the cancel on the wire) once its cancel is stored, or after CANCEL_STORED_WAIT: the other
        stations are notified on the write's commit, so they know who cancelled before the vehicle's CANCELED comes."""
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:  # no loop (a caller of its own thread): at once
            self._withdraw(cmd)
            return

        def go() -> None:
            if self._withdrawing.pop(cmd.session_id, None) is None:
                return  # gone already (stored, the wait ran out, or the console stopped)
            timer.cancel()
            cmd.cancel_mono, cmd.heard_from = self.clock.monotonic(), None  # the vehicle may answer from now
            self._withdraw(cmd)

        def written(_f: Future[CommandRow | None]) -> None:
            with contextlib.suppress(RuntimeError):  # the loop closed meanwhile: `flush_withdrawals` sent it
                loop.call_soon_threadsafe(go)

        timer = loop.call_later(CANCEL_STORED_WAIT, go)
        self._withdrawing[cmd.session_id] = go
        stored.add_done_callback(written)

    def flush_withdrawals(self) -> None:
        """Every cancel still waiting for the database goes to its vehicle now (the console stops)."""
        for go in list(self._withdrawing.values()):
            go()

    def _canceled(
        self,
        cmd: Command,
        operator: str | None,
        station: str | None,
        at: float | None,
        cause: CancelCause | None,
        record: bool = True,
    ) -> Future[CommandRow | None] | None:
        """A cancel asked: its vehicle heard since now, and only since now, may end it unanswered (`_unheard_cancel`).
        With `record`, the future of its write to the database, which refuses it when another cancel was stored first
        (then shown from the tick after, `_refused_cancels`)."""
        cmd.cancel_requested, cmd.canceled_by, cmd.canceled_on, cmd.canceled_at = True, operator, station, at
        cmd.cancel_cause, cmd.cancel_mono = cause, self.clock.monotonic()
        if record:
            stored = self.store.set_canceled(str(cmd.session_id), operator, station, cmd.canceled_at or self.clock.wall(), cause)
            self._cancels.append((cmd, stored))
            return stored
        return None

    def _close_unheard(self, cmd: Command, why: ClosedUnheard, at: float, emit: bool = True) -> None:
        """End a canceled command the vehicle never answered (its dispose, the cancel, was published already); refused
        by the database once a status of it is stored or another station ended it first: what is stored stands, shown
        from the tick after the writer thread wrote it (`_refused_endings`)."""
        cmd.closed_unheard, cmd.closed_at, cmd.cleaned_up = why, at, True
        self._endings.append((cmd, self.store.set_closed_unheard(str(cmd.session_id), why, at)))
        if emit:
            self.emit(command_message(cmd.to_json()))
        self._forget_old()

    async def take_over(self, session: uuid.UUID) -> Command | None:
        """Hand-over: a running command another console station on this database issued, taken into this
        console's care (to cancel it, whether or not that station still runs): its sample keeps that
        station's source GUID, so the dispose reaches the vehicle's instance of it; its statuses are
        followed and recorded from here on as well (a transition both record is stored once). The database is
        read in a worker thread."""
        if session in self.by_session:
            return self.by_session[session]

        def read() -> tuple[list[CommandRow], dict[str, uuid.UUID]]:
            rows = self.store.commands(session_id=str(session))
            return rows, self.store.consoles() if rows else {}

        rows, consoles = await asyncio.to_thread(read)
        if session in self.by_session:  # taken meanwhile (another request, a notification)
            return self.by_session[session]
        if not rows or rows[0]["console"] in (None, self.station) or rows[0]["cleaned_up"]:
            return None
        source = consoles.get(rows[0]["console"] or "")
        if source is None:
            return None
        cmd = self.from_row(rows[0], source)
        if cmd.terminal:
            return None
        cmd.replay = [(t.status, t.reason, pt) for t, (pt, _rt) in zip(cmd.flow.transitions, cmd.times, strict=True)]
        self.by_session[session] = cmd
        log.info("took over command %s of console %r to cancel it", session, cmd.console)
        return cmd

    def canceled_elsewhere(self, session: uuid.UUID, changed: dict[str, Any]) -> None:
        """Another station asked to cancel a command this one follows (the columns it stored, as notified): taken over
        at once, as the vehicle's answer to that cancel may come before the row is read."""
        mine = self.by_session.get(session)
        if mine is not None and changed.get("cancel_requested") and not mine.cancel_requested:
            self._canceled(
                mine,
                changed.get("canceled_by"),
                changed.get("canceled_on"),
                changed.get("canceled_at"),
                changed.get("cancel_cause"),
                record=False,
            )

    def merge_shared(self, row: CommandRow) -> Command:
        """The command of a shared database row (another station's, as stored)."""
        stored = self.from_row(row)
        mine = self.by_session.get(stored.session_id)
        if mine is None:
            self._watch(stored)
            return stored
        if stored.cancel_requested and not mine.cancel_requested:  # recorded by the station that asked it
            self._canceled(mine, stored.canceled_by, stored.canceled_on, stored.canceled_at, stored.cancel_cause, record=False)
        if stored.closed_unheard is not None and not mine.flow.transitions:
            self._take_stored(mine, stored)  # the one ending stored, whichever station's
        return mine

    def _take_stored(self, cmd: Command, stored: Command) -> None:
        """What the database has of a command this station ended, or was about to end, as never heard: the ending
        another station stored first, or the statuses another station recorded (repeated by the vehicle, skipped)."""
        cmd.closed_unheard, cmd.closed_at, cmd.cleaned_up = stored.closed_unheard, stored.closed_at, stored.cleaned_up
        if stored.flow.transitions and not cmd.flow.transitions:
            cmd.flow, cmd.times = stored.flow, stored.times
            cmd.replay = [(t.status, t.reason, pt) for t, (pt, _rt) in zip(cmd.flow.transitions, cmd.times, strict=True)]

    def _watch(self, stored: Command) -> None:
        """Another station's command as stored: followed here while it is canceled with no status (`tick` ends it if
        the vehicle never answers), whether or not that station still runs (it may have stopped for good)."""
        if stored.console == self.station or stored.session_id in self.by_session:
            return
        if stored.terminal or stored.cleaned_up or not stored.cancel_requested or stored.flow.transitions:
            self.others.pop(stored.session_id, None)
        else:
            self.others.setdefault(stored.session_id, stored)  # one already followed keeps when its vehicle was heard

    def cleanup(self, cmd: Command) -> None:
        """Command Cleanup: dispose a COMPLETED or FAILED command (CANCELED was disposed to cancel it)."""
        if not cmd.cleaned_up:
            if not cmd.cancel_requested:
                self._withdraw(cmd)
            cmd.cleaned_up = True
            self.store.set_flag(str(cmd.session_id), "cleaned_up")
            self._forget_old()

    def on_status(
        self,
        service: Service,
        session: uuid.UUID,
        source: uuid.UUID,
        status: Status | int,
        reason: AnyReason | int,
        log_message: str,
        provider_time: float | None,
    ) -> None:
        cmd = self.by_session.get(session) or self.others.get(session)
        if cmd is None or cmd.service is not service or source != cmd.provider_id:
            return  # not ours (another consumer's command, or a provider it was not sent to)
        if cmd.replay:  # after our restart: skip what the provider's history repeats of what we recorded
            seen = (status, reason, provider_time)
            if seen in cmd.replay:
                del cmd.replay[: cmd.replay.index(seen) + 1]
                return
            cmd.replay.clear()  # the first status we had not recorded: the replay is over
        t = cmd.flow.observe(status, reason, log_message, provider_time)
        if t is None:
            return
        received = self.clock.wall()
        cmd.times.append((provider_time, received))
        seq = len(cmd.flow.transitions)
        self.store.add_transition(str(session), seq, dict(transition_json(seq, t, provider_time, received)))
        if cmd.closed_unheard is not None:  # ended as never heard, and it answers after all: what it says stands
            cmd.closed_unheard, cmd.closed_at, cmd.cleaned_up = None, None, False  # as add_transition stored it
        if cmd.unanswered:
            cmd.unanswered = False  # it did answer, late
            cmd.answered_late_after = received - cmd.created_at
            self.store.set_flag(str(session), "unanswered", False)
        self.emit(transition_message(transition_json(seq, t, provider_time, received), cmd.to_json()))
        if cmd.flow.terminal:
            self.cleanup(cmd)

    def tick(self, now: float, heard: Heard) -> None:
        """`now`: monotonic seconds; `heard`: when a provider was last heard."""
        self._refused_endings()
        self._refused_cancels()
        for cmd in [*self.by_session.values(), *self.others.values()]:
            if cmd.flow.transitions or cmd.cleaned_up:
                continue
            if cmd.cancel_requested:
                if cmd.session_id not in self._withdrawing:  # not ended unheard before its cancel went
                    self._unheard_cancel(cmd, heard(cmd.provider_id))
            elif not cmd.unanswered and cmd.issued_by_deadline and now >= cmd.issued_by_deadline:
                cmd.unanswered = True
                self.store.set_flag(str(cmd.session_id), "unanswered")
                self.emit(command_message(cmd.to_json()))
        self.others = {s: c for s, c in self.others.items() if not c.terminal and not c.cleaned_up}

    def _refused_endings(self) -> None:
        """The endings as never heard the database has written: one it refused shows the command as stored."""
        written = [(cmd, f) for cmd, f in self._endings if f.done()]
        self._endings = [(cmd, f) for cmd, f in self._endings if not f.done()]
        for cmd, f in written:
            stored = None if f.cancelled() or f.exception() is not None else f.result()
            if stored is not None:
                self._take_stored(cmd, self.from_row(stored))
                self.emit(command_message(cmd.to_json()))

    def _refused_cancels(self) -> None:
        """The cancels the database has written: one it refused (another cancel was stored first: two operators, or an
        operator and another station's stop, at once) shows who cancelled first, as every station and the history do."""
        written = [(cmd, f) for cmd, f in self._cancels if f.done()]
        self._cancels = [(cmd, f) for cmd, f in self._cancels if not f.done()]
        for cmd, f in written:
            stored = None if f.cancelled() or f.exception() is not None else f.result()
            if stored is not None and stored["cancel_requested"]:
                cmd.canceled_by, cmd.canceled_on = stored["canceled_by"], stored.get("canceled_on")
                cmd.canceled_at, cmd.cancel_cause = (
                    stored.get("canceled_at"),
                    cast(CancelCause | None, stored.get("cancel_cause")),
                )
                self.emit(command_message(cmd.to_json()))

    def _unheard_cancel(self, cmd: Command, seen: float | None) -> None:
        """A canceled command with no status: ended once its vehicle has been heard for the unanswered timeout since
        the cancel without a word of it (a loss of its link meanwhile starts that again: its answer comes when the link
        is back), or once the bound since the cancel has passed."""
        if seen is None:
            cmd.heard_from = None
        elif seen >= cmd.cancel_mono:
            if cmd.heard_from is None:
                cmd.heard_from = seen
            elif seen - cmd.heard_from >= self.unanswered_timeout:
                self._close_unheard(cmd, "heard", self.clock.wall())
                return
        if self.clock.wall() - (cmd.canceled_at or cmd.created_at) >= self.cancel_unheard_bound:
            self._close_unheard(cmd, "bound", self.clock.wall())

    def shutdown(self) -> list[Command]:
        """Consumer Shutdown Sequence: cancel every incomplete command (asked by no operator); returns them."""
        canceled = [c for c in self.by_session.values() if not c.flow.terminal and not c.cleaned_up]
        for cmd in canceled:
            if not cmd.cancel_requested:
                self.cancel(cmd.session_id, None, "shutdown")
        self.flush_withdrawals()
        return canceled


def provider_time(sample: Any) -> float | None:
    try:
        return datetime_to_float(sample.timeStamp)
    except (AttributeError, TypeError):
        return None
