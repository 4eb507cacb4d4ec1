"""The running console: DDS ingest, providers, the UMAA consumer, the WebSocket hub.

Owned by the FastAPI lifespan. Every method here runs on the event loop thread. The input is a
`Source` (`console/sources.py`), DDS or a recording, chosen once at construction: the console composes
it and never asks which one it has; a read-only source (a recording) publishes nothing.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
import uuid
from collections import OrderedDict
from collections.abc import Awaitable, Callable, Coroutine
from dataclasses import asdict
from typing import Any, NamedTuple, TypeVar

from pydantic import ValidationError
from sqlalchemy.exc import SQLAlchemyError

from sem_console.codec.decode import ReportItem, StatusItem
from sem_console.comap.c2 import C2, FINAL, Task, TaskError, VehicleInfo
from sem_console.comap.codec import BROADCAST, Header, Message
from sem_console.comap.geo import Feature
from sem_console.comap.transport import Addr, AsyncNode, Endpoint
from sem_console.console.alarms import Alarm, Alarms, overloaded_text
from sem_console.console.clock import Clock
from sem_console.console.commands import Command, Commands, provider_time
from sem_console.console.feed import Feed
from sem_console.console.history import History, Thinning
from sem_console.console.hops import Hops, Links, relay_silent_after
from sem_console.console.hub import Client, Hub
from sem_console.console.load import Load
from sem_console.console.providers import REPORTS, Provider, Providers
from sem_console.console.replay_source import RecordedAck, RecordedCommand, RecordedName, Replay
from sem_console.console.sources import Source, open_source
from sem_console.core import messages
from sem_console.core.config import Settings, parse_imc_vehicles
from sem_console.core.contract import LinkConfig
from sem_console.core.messages import (
    ConsoleLoad,
    DatabaseState,
    FixBrief,
    GatewayState,
    ProviderDetail,
    ProviderEvent,
    ProviderSummary,
    RecordingStatus,
    ReportEnvelope,
    ReportMessage,
    ServerMessage,
    SnapshotMessage,
    VehicleBrief,
    alarms_message,
    command_message,
    database_message,
    load_message,
    provider_message,
    recording_message,
    report_message,
    silences_message,
    thin_report_message,
)
from sem_console.dds.topics import AnySem
from sem_console.recording.recorder import Recorder, RecordingError
from sem_console.storage.comap import TaskRow, WorldRow
from sem_console.storage.commands import CommandRow
from sem_console.storage.database import Database, Unavailable
from sem_console.storage.models import AlarmShelfRecord, AuditRecord, PlannedSilenceRecord, SeriesPoint, TrackPoint
from sem_console.storage.notify import Listener
from sem_console.versions.commands import Commanding

log = logging.getLogger("sem-console")
T = TypeVar("T")
TICK = 0.2
HELD_RETRY = 2.0  # seconds between database upkeeps (PostgreSQL): an outage's end found, held writes, the name's lock
RESYNC_COMMANDS = 100  # the other stations' newest commands (and every unfinished one) read again after a reconnect
EARLY_SESSIONS = 1000  # replay: sessions whose statuses came before their recorded command message, kept (the newest)


class Resynced(NamedTuple):
    """What a resync reads of the database (Console._resync)."""

    commands: list[CommandRow]
    links: dict[str, Any]
    shelves: list[AlarmShelfRecord]
    silences: list[PlannedSilenceRecord]
    acked: dict[str, tuple[float, str | None]]


class SharedComap:
    """comap/c2.py's Saver: the world model and task changes go to the database (and from it to the other consoles)."""

    def __init__(self, store: Database) -> None:
        self.store = store

    def world(self, world: dict[str, Any]) -> None:
        self.store.set_comap_world(world)

    def task(self, task: Task) -> None:
        self.store.set_comap_task(asdict(task), frozenset(FINAL))


def stored_link_configs(rows: dict[str, Any]) -> dict[str, LinkConfig]:
    """The stored link configurations that pass the API's own validation (`core.contract.LinkConfig`, the one
    an operator's PUT passed); any other row (unreadable, out of range, of another version) gives way to
    the defaults, with one warning naming them all."""
    configs: dict[str, LinkConfig] = {}
    ignored: list[str] = []
    for vehicle, stored in rows.items():
        try:
            if not isinstance(stored, dict):
                raise ValueError("not a JSON object")
            configs[vehicle] = LinkConfig.model_validate({"policy": "STOP_MISSION", "regainedBehavior": 0, **stored})
        except (ValidationError, ValueError) as e:
            ignored.append(f"{vehicle} ({str(e).splitlines()[0]})")
    if ignored:
        log.warning("ignored %d stored link configuration(s), the defaults apply: %s", len(ignored), "; ".join(ignored))
    return configs


class Console:
    def __init__(self, settings: Settings, store: Database | None = None) -> None:
        """`store`: the database `sem-console` opened (and whose name it claimed) before the start; else opened here."""
        self.settings = settings
        self.source: Source = open_source(settings)  # owns the DDS participant (none for a recording)
        self.clock: Clock = self.source.clock
        self.station = self.source.station
        self.store = self.source.database(store)
        self.id = self.store.claim(self.station)
        self.history = History(
            self.store.engine, self.source.retention_hours, replay=self.source.seeks, thinning=Thinning.of(settings)
        )
        self.hub = Hub(
            settings.ws_max_queue,
            settings.ws_stall_seconds,
            settings.ws_window_bytes,
            self.clock.monotonic,
            settings.ws_cut_seconds,
        )
        self.feed = Feed()  # what the gateways subscribe to
        self.gateway_states: Callable[[], list[GatewayState]] = lambda: []  # set by whoever runs the gateways
        self.providers, self.commands = self._fresh_state()
        # replay: statuses and acks of a command not (yet) known, by session. Another station's command reaches the
        # recording console by the database's notification, which can come after the vehicle's first statuses (always
        # after them when that station's write was held in an outage): applied when its command message comes
        self._early: OrderedDict[uuid.UUID, list[StatusItem]] = OrderedDict()
        # replay: the commands of other stations than the one that recorded (shown, as they reached it, but not its
        # to raise alarms for: the live console raised none for them)
        self._others: set[uuid.UUID] = set()
        self.recorder = Recorder(
            settings.recording_dir(),
            settings.record_max_bytes,
            settings.record_max_seconds,
            settings.record_queue,
            self._recording_changed,
            self.station,
            lambda: self.providers.names,
        )
        self.feed.tap("recorder", self.recorder)  # every sample the console takes, raw, while it records
        # the ones not back to normal, from the database; each acknowledgement is recorded (a replay derives the alarms
        # again, and acknowledges them from the recording)
        self.alarms = Alarms(
            self.store,
            self.names(),
            self._record_ack,
            settings.silence_grace,
            (settings.chatter_count, settings.chatter_minutes * 60),
            relay_silent_after(settings.comms_lost_timeout),
            self.station,
        )
        self.hops = Hops()  # the relays the vehicles come through (console/hops.py)
        self.load = Load(settings.comms_lost_timeout, self.clock.wall)  # whether this console is the one behind
        self.alarms.baseline(self.commands.by_session.values())
        self.c2 = C2(parse_imc_vehicles(settings.imc_vehicles), self._imc_send, self._emit, SharedComap(self.store), self.station)
        self.imc: AsyncNode | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._names_lock, self._comap_lock, self._shared_lock = asyncio.Lock(), asyncio.Lock(), asyncio.Lock()
        self._reloads: set[asyncio.Task[None]] = set()  # reads of the database after a notification, off the loop
        self._ticker: asyncio.Task[None] | None = None
        self._history_task: asyncio.Task[None] | None = None
        self._listener: Listener | None = None  # the other consoles' changes (PostgreSQL LISTEN)
        self._writing_held: asyncio.Task[bool] | None = None  # writing what was held during a database outage
        self._held_tried = 0.0
        # a notification or resync not read because this console had not yet found the database back (its upkeep
        # every 2 s; the listener reopens each second and the other consoles NOTIFY their held writes meanwhile):
        # a resync when its upkeep does
        self._resync_pending = False
        self._database_sent: tuple[Any, ...] = (None, 0, 0, 0.0)  # (unavailable since, held, dropped, monotonic sent)
        self.closing = False
        self.quiet = False  # a replay seeking: state changes are not sent to clients (a snapshot follows)
        self.started_at = time.monotonic()
        self.reports_applied = 0
        self.c2.load_world(self.store.comap_world())  # a restarted console keeps the world model and the tasks
        for row in self.store.comap_tasks():
            self.c2.load_task(row)

    def _fresh_state(self) -> tuple[Providers, Commands]:
        settings = self.settings
        providers = Providers(
            settings.comms_lost_timeout,
            settings.regained_time,
            self.names(),
            stored_link_configs(self.store.link_configs()),
            settings.jaus_subsystem if settings.jaus_port is not None else None,
        )
        commands = Commands(
            self.id,
            self.store,
            self._write_command,
            self._dispose_command,
            self._emit,
            self.settings.unanswered_timeout,
            self.clock,
            self.station,
            self.settings.cancel_unheard_bound,
        )
        return providers, commands

    def reset(self) -> None:
        """A replay seeking backwards: forget every provider, report and command (the audit trail stays)."""
        self.store.clear_commands()
        self.providers, self.commands = self._fresh_state()
        self.alarms.names = self.names()  # as the providers': the recorded names are applied again from the start
        self._early.clear()
        self._others.clear()
        self.alarms.reset()
        self.reports_applied = 0

    def _on_shared(self, message: dict[str, Any]) -> None:
        """What another console station on the database changed (storage/notify.py), on the loop: its commands
        reach this console's clients; a link configuration applies here too."""
        if self.closing:
            return
        kind = message.get("kind")
        try:
            # a name (this console's own too: the last write to the database is shown everywhere even when held
            # writes of two consoles land one after the other after an outage), or the listener reopened (what was
            # sent meanwhile is lost): every stored name read again, off the loop
            if kind in ("name", "resync"):
                self._reload(self._reload_names())
            # the CoMap world model and tasks the same way (own changes too: a held write may have been overtaken by
            # another station's newer one, which the database keeps)
            if kind in ("task", "worldmodel", "resync"):
                self._reload(self._reload_comap(str(kind), int(message["id"]) if kind == "task" else None))
            if kind == "resync":
                self._reload(self._resync(first=message.get("first") is True))
            elif kind in ("name", "task", "worldmodel") or message.get("console") == self.station:
                return
            elif kind == "command":  # a cancel applied at once; the row read off the loop, applied in order
                session = str(uuid.UUID(str(message["session"])))
                changed = message.get("changed")
                if isinstance(changed, dict):
                    self.commands.canceled_elsewhere(uuid.UUID(session), changed)
                self._reload(
                    self._read_stored(
                        self._shared_lock,
                        "a command of another console",
                        lambda: self.store.commands(session_id=session),
                        self._shared_command,
                    )
                )
            elif kind == "link":
                provider = str(message["provider"])
                self._reload(
                    self._read_stored(
                        self._shared_lock,
                        "the link configurations",
                        self.store.link_configs,
                        lambda rows: self._shared_link_config(provider, rows),
                    )
                )
            elif kind in ("shelf", "silence"):  # after a resync's read under way, or its older rows would undo it
                self._reload(self._in_order(self._shared_lock, message, self._shared_watch))
            elif kind == "alarm-ack":
                by = message.get("by")
                station = message.get("console")
                if self.alarms.acknowledged_elsewhere(
                    str(message["key"]),
                    by if isinstance(by, str) else None,
                    float(message["at"]),
                    station if isinstance(station, str) else None,
                ):
                    self._alarms_changed()
        except (KeyError, ValueError) as e:
            log.warning("ignored a notification of another console (%s): %.200s", e, message)
        except Unavailable as e:  # away again, or this console has not found it back yet (its upkeep every 2 s): what
            log.warning("%s", e)  # was missed is read when its upkeep finds the database back
            self._resync_pending = True

    async def _resync(self, first: bool = False) -> None:
        """The listening connection was reopened (the server restarted, an outage), or opened `first` (after this
        console read the shared state at its start): what the other stations changed meanwhile was not heard, so it
        is read from the database (in a worker thread) and sent to this console's clients."""
        since = {k: a.since for k, a in self.alarms.open.items() if a.acked_at is None}

        def read() -> Resynced:
            return Resynced(
                self.store.commands(limit=RESYNC_COMMANDS, unfinished=True),
                self.store.link_configs(),
                self.store.shelves(),
                self.store.silences(),
                self.store.acked_elsewhere(since),
            )

        def apply(got: Resynced) -> None:
            for row in got.commands:  # this station's too: another may have canceled one of them meanwhile
                merged = self.commands.merge_shared(row)
                if not first:  # at the start no client has seen a command yet (nor should a recording: as new ones)
                    self._emit(command_message(merged.to_json()))
            for provider_id in got.links:
                self._shared_link_config(provider_id, got.links)
            self.alarms.reload_shared(got.shelves, got.silences)
            self._alarms_changed()
            if any([self.alarms.acknowledged_elsewhere(k, by, at) for k, (at, by) in got.acked.items()]):
                self._alarms_changed()
            if first:
                log.debug("listening to the other consoles: read what they changed before")
            else:
                log.info("listening to the other consoles again: resynced from the database")

        await self._read_stored(self._shared_lock, "what the other consoles changed", read, apply)

    async def _in_order(self, lock: asyncio.Lock, message: dict[str, Any], apply: Callable[[dict[str, Any]], None]) -> None:
        """`apply` another console's notification on the loop after the reads under `lock` asked before it."""
        async with lock:
            if self.closing:
                return
            try:
                apply(message)
            except (KeyError, ValueError) as e:
                log.warning("ignored a notification of another console (%s): %.200s", e, message)

    def _shared_watch(self, message: dict[str, Any]) -> None:
        """Another station's shelf or planned silence, begun or ended."""
        if message["kind"] == "shelf":
            if self.alarms.shared_shelf(dict(message["row"])):
                self._alarms_changed()
        else:
            self.alarms.shared_silence(dict(message["row"]))
            self._update_alarms()  # a vehicle lost meanwhile: its loss is an alarm, or no longer one

    def _shared_command(self, rows: list[CommandRow]) -> None:
        """Another station's command as stored (see Commands.merge_shared), to this console's clients."""
        if rows:
            self._emit(command_message(self.commands.merge_shared(rows[0]).to_json()))

    def _shared_link_config(self, provider_id: str, rows: dict[str, Any]) -> None:
        config = stored_link_configs({k: v for k, v in rows.items() if k == provider_id})
        p = self.providers.by_id.get(uuid.UUID(provider_id))
        if p is not None and provider_id in config:
            p.config = config[provider_id]
            self._provider_event(p, "configured")

    def _heard(self, provider_id: uuid.UUID) -> float | None:
        """When a vehicle was last heard, while its link is up (None: never heard, or lost)."""
        p = self.providers.by_id.get(provider_id)
        return None if p is None or p.link == "lost" else p.last_seen()

    def _write_command(self, topic: AnySem, sample: Any) -> None:
        self.source.write(topic, sample)  # a recording publishes nothing

    def _dispose_command(self, topic: AnySem, sample: Any) -> None:
        self.source.dispose(topic, sample)

    # ---- lifecycle ------------------------------------------------------------------
    async def start(self) -> None:
        loop = self._loop = asyncio.get_running_loop()
        self._history_task = loop.create_task(self.history.run())
        self.source.attach(self)
        if self.source.read_only:  # a recording: no other station, no commands to resume, nothing recorded or sent
            await self.source.start()
            return
        self._listener = self.store.listen(lambda message: loop.call_soon_threadsafe(self._on_shared, message))
        if self.settings.record is not None:
            try:
                await asyncio.to_thread(self.recorder.start)
            except RecordingError as e:
                log.error("%s", e)
        resumed = self.commands.startup()
        if resumed:
            log.info("resumed following %d commands", len(resumed))
        await self.source.start()
        if self.settings.imc_port is not None:
            node = AsyncNode(Endpoint(self.settings.imc_id, self.settings.imc_peer_addresses()), self._on_imc)
            await node.open(self.settings.imc_host, self.settings.imc_port)
            self.imc = node
            self.c2.linked = True
            log.info("CoMap: IMC system %d on UDP %s:%d", self.settings.imc_id, self.settings.imc_host, self.settings.imc_port)
        self._ticker = loop.create_task(self._tick_forever())  # a recording ticks at its own time (Replay)

    async def stop(self, answer_wait: float = 3.0) -> None:
        """Consumer Shutdown Sequence: cancel what is incomplete, then leave the bus.

        The providers' answers (CANCELED) are awaited for up to `answer_wait` seconds so the
        history records how each command ended; they dispose those statuses right after.
        A recording has nothing to cancel and no bus to leave.
        """
        if self._listener is not None:
            await asyncio.to_thread(self._listener.stop)
        if not self.source.read_only:
            canceled = self.commands.shutdown()
            await asyncio.to_thread(self.source.wait_for_acks, 1.0)
            deadline = time.monotonic() + answer_wait
            while any(not c.terminal for c in canceled) and time.monotonic() < deadline:
                await asyncio.sleep(0.05)
        self.closing = True  # from here on, samples still queued for the loop are ignored
        if self.imc is not None:
            self.imc.close()
        if self._ticker:
            self._ticker.cancel()
        if self._reloads:  # a read of the vehicle names or CoMap under way ends before the store closes
            await asyncio.gather(*self._reloads, return_exceptions=True)
        if self._writing_held is not None:  # the upkeep (held writes, the name's lock) too: one thread per connection
            await asyncio.gather(self._writing_held, return_exceptions=True)
        await self.source.stop()  # the DDS ingest's threads joined; a playback's task ended
        await self._stop_history()
        await asyncio.to_thread(self.recorder.stop)
        await self.source.close()  # the embedded simulator, the command writers, the bus; a replay's database
        await asyncio.to_thread(self.store.close)  # what is still held written: a connect timeout off the loop

    async def _stop_history(self) -> None:
        if self._history_task:  # writes what it still holds
            self._history_task.cancel()
            await asyncio.gather(self._history_task, return_exceptions=True)
        self.history.close()

    async def _tick_forever(self) -> None:
        due = time.monotonic() + TICK
        while True:
            await asyncio.sleep(max(0.0, due - time.monotonic()))
            now = time.monotonic()
            try:
                self._measure_load(now - due, now)
                self.hub.sweep(now)
                self.tick(now)
            except Exception:  # a bug here must not stop link health or unanswered checks for good
                log.exception("tick failed")
            due = max(due + TICK, now)

    def _measure_load(self, delay: float, now: float) -> None:
        """How late this tick ran: whether the console is behind (console/load.py); every station told when that
        changes, and the log."""
        self.load.samples_lost = self.source.counters().get("samplesLost", 0)
        if not self.load.tick(delay, now):
            return
        state = self.load.state()
        if self.load.behind:
            log.warning(
                "this console is behind: its event loop ran %.0f ms late, samples waited %.0f ms (%.2f cores); "
                "vehicles' silences are not judged until it keeps up",
                state["loopDelayMs"],
                state["ingestLagMs"],
                state["cpuCores"],
            )
        else:
            log.warning("this console keeps up again: vehicles' silences are judged again")
        self._emit(load_message(state))

    def _maintained(self, done: asyncio.Task[bool]) -> None:
        self._writing_held = None
        if self._resync_pending and not done.cancelled() and done.exception() is None and done.result():
            self._resync_pending = False
            self._on_shared({"kind": "resync"})

    def tick(self, now: float) -> None:
        if self.store.db.path is None and self._writing_held is None and now - self._held_tried >= HELD_RETRY:
            # PostgreSQL's upkeep in a worker thread (never a connect timeout on the loop): the end of an outage
            # found and what was held written; this console's name held again after a server restart
            self._held_tried = now
            self._writing_held = asyncio.get_running_loop().create_task(asyncio.to_thread(self.store.maintain))
            self._writing_held.add_done_callback(self._maintained)
        for p, event in self.providers.tick(now, self.clock.wall(), self.load.excuse(now)):
            self._provider_event(p, event, now)
        if self.load.behind:
            unchecked = sum(p.link == "unchecked" for p in self.providers.by_id.values())
            self.load.withheld = max(self.load.withheld, unchecked)
        self.commands.tick(now, self._heard)
        self._database_changed(now)
        self._update_alarms()  # conditions that hold for a time (no fix after a completed GPS fix command)

    # ---- input from the source: DDS (ingest) or a recording (replay), on the loop -------------------------------
    def apply(self, item: ReportItem | StatusItem | RecordedCommand | RecordedAck | RecordedName) -> None:
        """One item of a replay: a decoded report or status sample, a recorded command message, alarm
        acknowledgement or vehicle name."""
        if isinstance(item, ReportItem):
            self.on_reports([item])
        elif isinstance(item, RecordedName):  # the recording station's name over this console's --vehicle-names
            self._apply_name(item.provider_id, item.name)
        elif isinstance(item, RecordedAck):
            if self.alarms.acknowledged_elsewhere(item.key, item.by, item.at, item.station):
                self._alarms_changed()
            else:  # derived again, the alarm is not (or no longer) in the active set at that instant
                log.info("a recorded acknowledgement of alarm %s matches no unacknowledged alarm of the replay", item.key)
        elif isinstance(item, StatusItem):
            if item.sample is not None and item.session not in self.commands.by_session:
                self._early.setdefault(item.session, []).append(item)
                if len(self._early) > EARLY_SESSIONS:  # other consumers' commands, never in the recording
                    self._early.popitem(last=False)
            self.on_statuses([item])
        else:
            followed = item.followed
            if followed is None:  # a file recorded before the marker: the recording console's commands by their station
                recorded_by = self.source.replay.station if self.source.replay else None
                followed = recorded_by is None or item.command.get("console") in (None, recorded_by)
            with contextlib.suppress(KeyError, ValueError, TypeError, AttributeError):
                # before adopt() emits it; a command taken over from another station is followed from then on
                session = uuid.UUID(item.command["sessionId"])
                if followed:
                    self._others.discard(session)
                else:
                    self._others.add(session)
            try:
                cmd = self.commands.adopt(item.command)
            except (KeyError, ValueError, TypeError) as e:
                log.warning("skipped a recorded command that cannot be read: %s", e)
                return
            for early in self._early.pop(cmd.session_id, []):
                self._command_status(early)

    def on_reports(self, items: list[ReportItem]) -> None:
        if self.closing:
            return
        now = self.clock.monotonic()
        if items and not self.source.read_only:  # how long the take waited for the loop (a replay's time is its own)
            self.load.handled(self.clock.wall() - items[0].received_at, now)
        alarming = False
        for it in items:
            p, new = self.providers.seen(
                it.topic, it.source, self._envelope(it), now, it.received_at, it.alive, it.version, it.parent
            )
            if new:
                self._appeared(p, now)
            elif p.version_changed:
                self._version_changed(p, now)
            if it.writer is not None and it.report is not None:
                self._follow_path(p, it.writer, now)
            if it.report is not None:
                changed = self.alarms.report_changed(it.source, it.topic, it.report)  # INS status, fixValid
                alarming = changed or alarming
                self.reports_applied += 1
                pid = str(it.source)
                message = report_message(pid, it.topic, p.reports[it.topic])
                if not self.quiet:
                    # one that may raise an alarm goes unpaced: not seconds behind the alarm it raised
                    self.hub.publish(message, key=(pid, it.topic), thin=_thin(message), unpaced=changed)
                    self.feed.publish(message)
                self._record(p, it)
        if alarming:
            self._update_alarms()

    def _record(self, p: Provider, it: ReportItem) -> None:
        """Track and chart history (at most one point per vehicle and second each)."""
        assert it.report is not None
        if it.topic == "GPSFixReport":
            status = p.reports.get("GPSFixStatusReport")
            fix_valid = status["report"].get("fixValid") if status else None
            self.history.on_fix(
                it.source, it.received_at, it.report, it.invalid, fix_valid if isinstance(fix_valid, bool) else None
            )
        elif it.topic == "GPSReport":
            self.history.on_gps(it.source, it.received_at, it.report)

    @staticmethod
    def _envelope(it: ReportItem) -> ReportEnvelope | None:
        if it.report is None:
            return None
        return {"report": it.report, "invalid": it.invalid, "receivedAt": it.received_at}

    def on_statuses(self, items: list[StatusItem]) -> None:
        if self.closing:
            return
        now = self.clock.monotonic()
        for it in items:
            try:
                self._on_status(it, now)
            except Exception:  # one bad sample must not lose the rest of the batch
                log.exception("could not apply a %s %s sample", it.service.value, it.kind)

    def _on_status(self, it: StatusItem, now: float) -> None:
        topic = f"{it.service.value}CommandStatus" if it.kind == "status" else f"{it.service.value}CommandAckReport"
        # a vehicle first heard on its command status or ack (transient-local, before its first report) speaks that
        # topic's version
        p, new = self.providers.seen(
            topic, it.source, None, now, self.clock.wall(), it.alive or it.sample is not None, it.version, it.parent
        )
        if new:
            self._appeared(p, now)
        elif p.version_changed:
            self._version_changed(p, now)
        if it.sample is not None:
            self._command_status(it)

    def _appeared(self, p: Provider, now: float) -> None:
        p.relay = self.hops.via.get(p.id)  # a relay that said it carries the vehicle before its first sample came
        hop = self.hops.of(p.id)
        p.quiet = 0.0 if hop is None else hop.quiet.get(p.id, 0.0)
        self._provider_event(p, "appeared", now)

    def _follow_path(self, p: Provider, writer: uuid.UUID, now: float) -> None:
        """The mark follows the path: a report another participant than a relay's wrote (the vehicle heard on this
        domain itself) takes the mark away, and a report a relay wrote marks its vehicle via the relay that carries it
        once none came directly for its comms-lost timeout (heard both ways, it is shown direct, not marked and unmarked
        at each report)."""
        p.writer = writer
        if writer not in self.hops.writers:
            p.direct = (writer, now)
        relay = self.hops.via.get(p.id) if self._relayed(p, now) else None
        if p.relay != relay:
            p.relay = relay
            self._provider_event(p, "configured", now)

    def on_relay_links(self, links: Links, received: float) -> None:
        """The relays' samples (console/hops.py), received at `received` (UTC seconds), with the participant that wrote
        each: their vehicles marked (but one heard last on this domain itself), each whose relay changed sent again to
        every station."""
        if self.closing:
            return
        now = self.clock.monotonic()
        for link, writer in links:
            if writer is not None:
                self.hops.writers.add(writer)  # a report it wrote before this sample came is now known for a relay's
            self.hops.seen(link, received)
            hop = self.hops.by_relay[link.relay]
            for vehicle in hop.vehicles:
                p = self.providers.by_id.get(vehicle)
                if p is None:
                    continue
                marked = p.relay != link.relay and self._relayed(p, now)
                if marked:
                    p.relay = link.relay
                quiet, p.quiet = p.quiet, hop.quiet.get(vehicle, 0.0)
                if marked or (quiet != p.quiet and p.relay is not None):  # what every station's dashboard shows of it
                    self._provider_event(p, "configured", now)
        self._update_alarms()

    def _relayed(self, p: Provider, now: float) -> bool:
        """Its latest report was written by an operations relay (or by a writer not known: a recording's), and none
        by another participant (one not learned since to be a relay's) for its comms-lost timeout."""
        direct = p.direct is not None and p.direct[0] not in self.hops.writers and now - p.direct[1] <= p.config.commsLostTimeout
        return (p.writer is None or p.writer in self.hops.writers) and not direct

    def _version_changed(self, p: Provider, now: float) -> None:
        """A vehicle now heard on the topics of another UMAA version than before: every station shows its new version
        (a summary the dashboard applies as it does a rename's)."""
        p.version_changed = False
        log.info("vehicle %s now speaks UMAA %s", str(p.id)[:8], p.umaa_version)
        self._provider_event(p, "configured", now)

    def _command_status(self, it: StatusItem) -> None:
        """A status or ack sample (not a dispose) to the command it answers, if this console follows it."""
        if it.kind == "ack":
            self.commands.on_ack(it.service, it.session, it.source)
            return
        s = it.sample
        assert it.status is not None and it.reason is not None  # a status sample's, in the model (codec/decode.py)
        self.commands.on_status(it.service, it.session, it.source, it.status, it.reason, s.logMessage, provider_time(s))

    # ---- CoMap over IMC (on the loop) ---------------------------------------------------------
    def _on_imc(self, header: Header, m: Message, _addr: Addr) -> None:
        if not self.closing:
            self.c2.on_message(header, m)

    def _imc_send(self, m: Message, dst: int = BROADCAST) -> int:
        return self.imc.send(m, dst) if self.imc is not None else 0

    def comap_status(self) -> dict[str, Any]:
        ep = self.imc.endpoint if self.imc is not None else None
        return {
            "enabled": ep is not None,
            "imcId": self.settings.imc_id,
            "port": self.settings.imc_port,
            "peers": [f"{h}:{p}" for h, p in ep.peers] if ep else [],
            "counters": {**ep.counters, "refusedWorldModels": self.c2.refused_world_models} if ep else {},
            "vehicles": [v.to_json() for v in self.c2.vehicles.values()],
        }

    def _emit(self, message: ServerMessage) -> None:
        if not self.quiet:
            self.hub.publish(message)
            self.feed.publish(message)
        # a command message says whether this console follows the command (issued it, or took it over from another
        # station): its alarms are this console's (below), and a replay of the recording raises them as it did
        followed = None
        if message["type"] == "command" and self.recorder.active:
            followed = uuid.UUID(message["command"]["sessionId"]) in self.commands.by_session
        self.recorder.on_message(message, followed)
        if message["type"] == "command" or message["type"] == "transition":  # the alarms are re-derived after these
            changed = self.commands.by_session.get(uuid.UUID(message["command"]["sessionId"]))
            self._update_alarms([changed] if changed is not None and changed.session_id not in self._others else [])
        elif message["type"] == "provider":
            self._update_alarms([])

    def _provider_event(self, p: Provider, event: ProviderEvent, now: float | None = None) -> None:
        """Send the vehicle's summary with what happened to it (`now`: monotonic seconds, default the clock's)."""
        self._emit(provider_message(event, p.summary(self.clock.monotonic() if now is None else now, self.clock.wall())))

    def _alarms_changed(self) -> None:
        """Send the active alarm set (it changed)."""
        self._emit(alarms_message(self.alarms.active()))

    def _update_alarms(self, changed: list[Command] | None = None) -> None:
        """Re-derive the alarms (looking again at the `changed` commands); publish the set when it changed."""
        if self.closing:  # shutting down: the database closes
            return
        load = self.load
        overloaded = overloaded_text(load.worst, load.withheld) if load.behind and load.withheld else None
        if self.alarms.update(
            self.clock.wall(), self.providers.by_id, changed or (), self.recorder.error, self.hops.by_relay, overloaded
        ):
            self._alarms_changed()
        if self.alarms.silences_changed:
            self.alarms.silences_changed = False
            self._emit(silences_message(self.alarms.planned_silences()))

    def acknowledge(self, alarm_id: int, operator: str | None) -> Alarm | None:
        """An operator acknowledges an alarm of the active set (None: there is none with that id)."""
        before = self.alarms.active()
        alarm = self.alarms.acknowledge(alarm_id, operator, self.clock.wall(), self.station)
        if alarm is not None and self.alarms.active() != before:
            self._alarms_changed()
        return alarm

    def shelve(self, alarm_id: int, reason: str, minutes: float, operator: str | None) -> Alarm | None:
        """An operator shelves an alarm of the active set for `minutes` (None: there is none with that id)."""
        alarm = self.alarms.shelve(alarm_id, reason, minutes * 60, operator, self.clock.wall(), self.station)
        if alarm is not None:
            self._alarms_changed()
        return alarm

    def unshelve(self, alarm_id: int, operator: str | None) -> Alarm | None:
        alarm = self.alarms.unshelve(alarm_id, operator, self.clock.wall())
        if alarm is not None:
            self._alarms_changed()
        return alarm

    def plan_silence(self, p: Provider, until: float, reason: str, operator: str | None) -> None:
        """Declare the vehicle out of comms until `until` (UTC seconds): its loss raises no alarm until then and the
        grace after it."""
        self.alarms.silence(str(p.id), until, reason, operator, self.clock.wall(), self.station)
        self._update_alarms()

    def cancel_silence(self, provider_id: uuid.UUID, operator: str | None) -> bool:
        """End the vehicle's planned silence now (False: it has none)."""
        ended = self.alarms.cancel_silence(str(provider_id), operator, self.clock.wall()) is not None
        self._update_alarms()
        return ended

    def _record_ack(self, alarm: Alarm, station: str | None) -> None:
        """An alarm just acknowledged, here or on another station: in the recording (`recorder.AlarmAckEvent`)."""
        self.recorder.on_message(
            {
                "type": "alarm-ack",
                "key": alarm.key,
                "kind": alarm.kind,
                "providerId": alarm.provider_id,
                "sessionId": alarm.session_id,
                "ackedAt": alarm.acked_at,
                "ackedBy": alarm.acked_by,
                "station": station,
            }
        )

    def _recording_changed(self, status: RecordingStatus) -> None:
        """From any thread: the recording started, stopped, rolled over or failed."""
        loop = self._loop
        if loop is not None:
            try:
                loop.call_soon_threadsafe(self.hub.publish, recording_message(status))
                loop.call_soon_threadsafe(self._update_alarms)  # a failed recording is an alarm
            except RuntimeError:  # the loop has closed (shutdown)
                pass

    # ---- queries and commands (REST, WebSocket) -----------------------------------------
    def provider(self, provider_id: uuid.UUID) -> Provider | None:
        return self.providers.by_id.get(provider_id)

    def provider_detail(self, p: Provider, now: float) -> ProviderDetail:
        return {**p.summary(now, self.clock.wall()), "reports": {t: p.reports.get(t) for t in REPORTS}}

    def selected_reports(self, provider_id: uuid.UUID) -> list[ReportMessage]:
        """The vehicle's latest report of each topic as report messages, its GPSReport's satellites and all (a client has
        just selected it: the reports it was sent of it were thin, paced, or its snapshot's brief); none when it is
        unknown."""
        p = self.providers.by_id.get(provider_id)
        reports = {} if p is None else p.reports
        return [report_message(str(provider_id), t, env) for t in REPORTS if (env := reports.get(t)) is not None]

    def first_screen_detail(self, p: Provider, now: float) -> ProviderDetail:
        """A vehicle as the snapshot has it: its GPSReport without its satellites, which only the selected vehicle's
        panel draws (it asks GET /api/providers/{id}); 40 satellites of each of 50 vehicles were most of a snapshot."""
        detail = self.provider_detail(p, now)
        gps = detail["reports"].get("GPSReport")
        if gps and gps["report"].get("satellites"):
            detail["reports"] = {**detail["reports"], "GPSReport": _without_satellites(gps)}
        return detail

    def load_state(self) -> ConsoleLoad | None:
        """Whether this console is the one behind (None in a replay: a recording's time is its own)."""
        return None if self.source.read_only else self.load.state()

    def database_state(self) -> DatabaseState | None:
        """The database's reach, for the clients (None in a replay: its own temporary file)."""
        if self.source.read_only:
            return None
        return self.database_reach()

    def _database_changed(self, now: float) -> None:
        """A `database` message when the database went away or came back (at the tick that finds it: the banner within
        a fraction of a second, as an alarm), or what is held for it changed (at most once a second)."""
        state = self.database_state()
        if state is None:
            return
        since, held, dropped, sent = self._database_sent
        if (
            state["unavailableSince"] == since
            and state["writesDropped"] == dropped
            and (state["writesHeld"] == held or now - sent < 1.0)
        ):
            return
        self._database_sent = (state["unavailableSince"], state["writesHeld"], state["writesDropped"], now)
        self._emit(database_message(state))

    def snapshot(self, vehicle: str | None = None) -> SnapshotMessage:
        """What a new client draws first: every vehicle as `first_screen_detail`; to one that named the vehicle it
        draws (`vehicle`), that one so and every other as its brief (`vehicle_brief`: 2.5 kB a vehicle against 0.3)."""
        now = self.clock.monotonic()
        shown = list(self.providers.by_id.values())
        briefs: list[VehicleBrief] = []
        if vehicle is not None:
            shown = [p for p in self.providers.by_id.values() if str(p.id) == vehicle]
            wall = self.clock.wall()
            briefs = [vehicle_brief(p, now, wall) for p in self.providers.by_id.values() if str(p.id) != vehicle]
        return {
            "type": "snapshot",
            "consoleId": str(self.id),
            "serverTime": self.clock.wall(),
            "authRequired": bool(self.settings.operators()),
            "providers": [self.first_screen_detail(p, now) for p in shown],
            "fleet": briefs,
            "commands": [c.to_json() for c in self.commands.by_session.values()],
            "gateways": self.gateway_states(),
            "recording": self.recorder.status(),
            "replay": self.source.status(),
            "alarms": self.alarms.active(),
            "database": self.database_state(),
            "silences": self.alarms.planned_silences(),
            "load": self.load_state(),
        }

    def metrics(self) -> dict[str, Any]:
        return {
            "uptimeSeconds": round(time.monotonic() - self.started_at, 3),
            **self.source.counters(),
            "reportsApplied": self.reports_applied,
            "wsClients": len(self.hub.clients),
            "wsMessagesPublished": self.hub.published,
            "wsClientsDropped": self.hub.dropped,
            "providers": len(self.providers.by_id),
            "commandsInMemory": len(self.commands.by_session),
            "historyRowsWritten": self.history.rows_written,
            "historyRowsPruned": self.history.rows_pruned,
            "historyRowsRolledUp": self.history.rows_rolled_up,
            "historyWriteSecondsMax": round(self.history.max_write_seconds, 6),
        }

    def set_link_config(self, p: Provider, config: LinkConfig) -> None:
        """A vehicle's link thresholds and comms-lost configuration, kept in the database; link health
        follows the new thresholds from the next tick."""
        self.store.set_link_config(str(p.id), dict(config.to_json()))
        p.config = config
        self._provider_event(p, "configured")

    def names(self) -> dict[str, str]:
        """provider GUID string -> the vehicle's name: the one set from the dashboard (stored, shared), else
        --vehicle-names'."""
        return {**self.settings.names(), **self.store.vehicle_names()}

    def set_vehicle_name(self, p: Provider, name: str | None, operator: str | None) -> None:
        """Name a vehicle (None: back to its --vehicle-names name, or none), kept in the database and shared."""
        self.store.set_vehicle_name(str(p.id), name, operator)
        self._apply_name(p.id, name)

    def _reload(self, read: Coroutine[Any, Any, None]) -> None:
        task = asyncio.get_running_loop().create_task(read)
        self._reloads.add(task)
        task.add_done_callback(self._reloads.discard)

    async def _read_stored(self, lock: asyncio.Lock, what: str, read: Callable[[], T], apply: Callable[[T], None]) -> None:
        """`read` the database in a worker thread and `apply` it on the loop; one read at a time per `lock`, in the
        order asked, so an older read never lands after a newer one; read again when this console wrote meanwhile (the
        read waits for the writes asked before it, not for one asked while it ran). The database away: read again when
        it is back."""
        async with lock:
            while not self.closing:
                asked = self.store.writes_asked
                try:
                    got = await asyncio.to_thread(read)
                except (SQLAlchemyError, Unavailable) as e:
                    log.warning("could not read %s: %s", what, e)
                    self._resync_pending = True
                    return
                if self.store.writes_asked == asked and not self.closing:
                    apply(got)
                    return

    async def _reload_comap(self, kind: str, task_id: int | None) -> None:
        """The stored world model (kind worldmodel), task `task_id` (task) or both with every task (resync), applied
        where newer than this console's."""

        def read() -> tuple[WorldRow | None, list[TaskRow]]:
            world = self.store.comap_world() if kind != "task" else None
            return world, self.store.comap_tasks(task_id) if kind != "worldmodel" else []

        def apply(got: tuple[WorldRow | None, list[TaskRow]]) -> None:
            self.c2.load_world(got[0])
            for row in got[1]:
                self.c2.load_task(row)

        await self._read_stored(self._comap_lock, "the CoMap world model and tasks", read, apply)

    async def assign(self, task: Task) -> Task:
        """Send a planned CoMap task (C2.plan) under an id taken in the database, so no two stations send one id."""
        try:
            tid = await asyncio.to_thread(self.store.new_comap_task, asdict(task), frozenset(FINAL))
        except Unavailable as e:
            raise TaskError(503, str(e)) from None
        if tid is None:
            raise TaskError(409, "every task id is taken by an unfinished task (of the consoles on this database)")
        task.task_id = tid
        return self.c2.assign(task)

    async def _reload_names(self) -> None:
        """Every vehicle's stored name again, applied where it changed."""

        def apply(stored: dict[str, str]) -> None:
            for key in {*self.providers.names, *stored, *(str(i) for i in self.providers.by_id)}:
                name = stored.get(key) or self.settings.names().get(key)
                if self.providers.names.get(key) != name:
                    self._apply_name(uuid.UUID(key), stored.get(key))

        await self._read_stored(self._names_lock, "the vehicle names", self.store.vehicle_names, apply)

    def _apply_name(self, provider_id: uuid.UUID, stored: str | None) -> None:
        """A vehicle's stored name (None: removed) from here on: its summary, its alarms' text (as sent: each row
        keeps what it said when raised), clients."""
        key = str(provider_id)
        name = stored or self.settings.names().get(key)
        for names in (self.providers.names, self.alarms.names):
            if name is None:
                names.pop(key, None)
            else:
                names[key] = name
        # in the recording (a replay names the vehicle so from here on); each file starts with those in force
        self.recorder.on_message({"type": "vehicle-name", "providerId": key, "name": name, "initial": False})
        p = self.providers.by_id.get(provider_id)
        if p is not None:
            p.name = name
            self._provider_event(p, "configured")
        if any(a.provider_id == key for a in self.alarms.open.values()):
            self._alarms_changed()

    def issue(self, commanding: Commanding, provider_id: uuid.UUID, state: str | None, operator: str | None) -> Command:
        """A command to a vehicle, as its version commands it (`commanding`: versions/commands.py), addressed to its
        identifier as it reports it (its parent too)."""
        p = self.providers.by_id.get(provider_id)
        return self.commands.issue(commanding, provider_id, state, operator, p.parent if p is not None else None)

    # ---- what the API asks of the console (api/routes call these, never the console's parts) ------------------------
    def wall_time(self) -> float:
        """UTC seconds now, as the console's clock has it (a replay's: the instant shown)."""
        return self.clock.wall()

    def provider_summaries(self) -> list[ProviderSummary]:
        now = self.clock.monotonic()
        wall = self.clock.wall()
        return [p.summary(now, wall) for p in self.providers.by_id.values()]

    def detail(self, p: Provider) -> ProviderDetail:
        """A vehicle with its latest reports, satellites and all."""
        return self.provider_detail(p, self.clock.monotonic())

    def silent_for(self, p: Provider) -> float:
        """Seconds since the vehicle was last heard."""
        return self.clock.monotonic() - p.last_seen()

    async def command(self, session_id: uuid.UUID) -> Command | None:
        """A command of this console's memory or of the database, read in a worker thread (None: none has that
        session)."""
        return await self.commands.get(session_id)

    async def take_over(self, session_id: uuid.UUID) -> Command | None:
        """Another station's running command taken into this console's care (Commands.take_over)."""
        return await self.commands.take_over(session_id)

    def cancel(self, session_id: uuid.UUID, operator: str | None) -> Command:
        """Cancel a command (CommandError: it cannot be)."""
        return self.commands.cancel(session_id, operator)

    async def command_history(self, limit: int, offset: int, provider_id: uuid.UUID | None) -> list[messages.Command]:
        """Newest first, from the database, read in a worker thread."""
        return await asyncio.to_thread(self.commands.history, limit, offset, provider_id)

    def export_commands(self, provider_id: uuid.UUID | None, since: float | None, until: float | None) -> list[Command]:
        """The commands created in [since, until] (to `provider_id` when given), oldest first; blocking (a worker
        thread's)."""
        rows = self.store.export_commands(None if provider_id is None else str(provider_id), since, until)
        return [self.commands.from_row(r) for r in rows]

    def active_alarms(self) -> list[messages.Alarm]:
        return self.alarms.active()

    def shelved(self, alarm_id: int) -> bool | None:
        """Whether the alarm of the active set is shelved (None: there is none with that id)."""
        alarm = next((a for a in self.alarms.open.values() if a.id == alarm_id), None)
        return None if alarm is None else alarm.key in self.alarms.shelves

    def planned_silences(self) -> list[messages.PlannedSilence]:
        return self.alarms.planned_silences()

    async def has_history(self, provider_id: uuid.UUID) -> bool:
        return await self.history.has(provider_id)

    async def track(self, provider_id: uuid.UUID, since: float | None, until: float | None) -> list[TrackPoint]:
        return await self.history.track(provider_id, since, until)

    async def series(self, provider_id: uuid.UUID, since: float | None, until: float | None) -> list[SeriesPoint]:
        return await self.history.series(provider_id, since, until)

    def database_reach(self) -> DatabaseState:
        """Whether the database can be reached and what is held for it (a replay: its own file, always reached)."""
        store = self.store
        return {"unavailableSince": store.unavailable_since, "writesHeld": store.held, "writesDropped": store.dropped}

    async def audit_trail(self, limit: int, offset: int) -> list[AuditRecord]:
        """The audit trail, newest first, read in a worker thread."""
        return await asyncio.to_thread(self.store.audit, limit, offset)

    def add_audit(self, entry: dict[str, Any]) -> None:
        self.store.add_audit(entry)

    def recording(self) -> Recorder:
        """The recorder (its start, stop, status and files)."""
        return self.recorder

    def playback(self) -> Replay | None:
        """A replay's playback (its controls and status); None live."""
        return self.source.replay

    def comap_linked(self) -> bool:
        """CoMap is on: the console's IMC node is open."""
        return self.imc is not None

    def world_model(self) -> dict[str, Any]:
        return self.c2.world_model()

    def put_world_model(self, features: list[Feature]) -> dict[str, Any]:
        return self.c2.put_world_model(features)

    def tasks(self) -> list[Task]:
        """Every CoMap task, newest first."""
        return sorted(self.c2.tasks.values(), key=lambda t: t.created_at, reverse=True)

    def task(self, task_id: int) -> Task | None:
        return self.c2.tasks.get(task_id)

    async def assign_task(
        self,
        kind: str,
        vehicle: uuid.UUID,
        operator: str | None,
        *,
        feature_id: int | None,
        sensor: str,
        resolution: float,
        deadline: float | None,
        point: dict[str, float] | None,
    ) -> Task:
        """Plan a CoMap task (C2.plan) and send it (`assign`); TaskError: it cannot be."""
        return await self.assign(
            self.c2.plan(
                kind,
                vehicle,
                operator,
                feature_id=feature_id,
                sensor=sensor,
                resolution=resolution,
                deadline=deadline,
                point=point,
            )
        )

    def synch(self, task_id: int, action: str) -> Task:
        return self.c2.synch(task_id, action)

    def capabilities_of(self, provider_id: uuid.UUID) -> VehicleInfo | None:
        return self.c2.capabilities_of(provider_id)

    def attach_client(self, send: Callable[[str], Awaitable[None]], batch: bool, ack: bool, vehicle: str | None = None) -> Client:
        """A WebSocket client, its snapshot first (built for the vehicle it draws, `vehicle`, when it named one)."""
        return self.hub.attach(send, self.snapshot(vehicle), batch=batch, ack=ack, vehicle=vehicle)

    def detach_client(self, client: Client) -> None:
        self.hub.detach(client)

    def select_for(self, client: Client, provider_id: str | None) -> None:
        """The client draws this vehicle now (its `select`)."""
        self.hub.select(client, provider_id)


def _thin(message: ReportMessage) -> ReportMessage | None:
    """A GPSReport message without its satellites (`partial`), for the clients that draw another vehicle's: 40 satellites
    of each of 250 vehicles were two thirds of every client's bytes. None for any other report, or one without any."""
    env = message["report"]
    if message["topic"] != "GPSReport" or not env["report"].get("satellites"):
        return None
    return thin_report_message(message, _without_satellites(env))


def vehicle_brief(p: Provider, now: float, wall: float) -> VehicleBrief:
    """The vehicle as a page that draws another shows it (its list row, fleet-bar chip, map dot and origin): the members
    of its newest fix, fix status and INS reports it draws, each with its receipt; positions to 1e-7 degrees (1 cm)."""
    summary = p.summary(now, wall)
    fix, status, ins = (p.reports.get(t) for t in ("GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"))
    brief: VehicleBrief = {
        "id": summary["id"],
        "name": summary["name"],
        "link": summary["link"],
        "umaaVersion": summary["umaaVersion"],
        "jausId": summary["jausId"],
        "relay": summary.get("relay"),
        "fix": None,
        "fixStatus": None,
        "ins": None,
    }
    if fix is not None:
        r = fix["report"]
        g = (r.get("position2DWithTime") or {}).get("geodeticPosition") or {}
        fix_brief: FixBrief = {
            "lat": _rounded((g.get("geodeticLatitude") or {}).get("latitude"), 7),
            "lon": _rounded((g.get("geodeticLongitude") or {}).get("longitude"), 7),
            "course": _rounded(r.get("trueCourse"), 5),
            "sog": _rounded(r.get("SOG"), 3),
            "latLongValid": r.get("GPSLatLongValid"),
            "invalid": fix["invalid"],
            "receivedAt": fix["receivedAt"],
        }
        if p.relay is not None:
            fix_brief["timeStamp"] = r.get("timeStamp")
        brief["fix"] = fix_brief
    if status is not None:
        r = status["report"]
        o = (r.get("originPosition") or {}).get("geodeticPosition") or {}
        brief["fixStatus"] = {
            "fixValid": r.get("fixValid"),
            "originLat": _rounded((o.get("geodeticLatitude") or {}).get("latitude"), 7),
            "originLon": _rounded((o.get("geodeticLongitude") or {}).get("longitude"), 7),
            "receivedAt": status["receivedAt"],
        }
    if ins is not None:
        r = ins["report"]
        brief["ins"] = {"state": r.get("state"), "status": r.get("status"), "receivedAt": ins["receivedAt"]}
    return brief


def _rounded(value: Any, digits: int) -> float | None:
    return round(value, digits) if isinstance(value, float | int) and not isinstance(value, bool) else None


def _without_satellites(env: ReportEnvelope) -> ReportEnvelope:
    """A GPSReport's envelope with an empty satellite list (numberSatellitesInView and the rest as sent)."""
    return {**env, "report": {**env["report"], "satellites": []}}
