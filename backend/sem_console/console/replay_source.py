"""`sem-console --replay FILE.mcap`: the console's state rebuilt from a recording instead of DDS.

The recorded CDR of each report, status and ack topic of either UMAA version goes through the same `Decoder` the DDS
ingest uses (a 6.0 report through its version's adapter, as live) and is applied by the same console methods (and, as
it is played, not while seeking, goes raw to the console's feed, as the ingest's samples do live);
disposes and lost writers come from the
`sem-console/instances` channel, the commands the recording console issued (and cancel requests)
from `sem-console/commands`, the alarm acknowledgements from `sem-console/alarm-acks` and the vehicles' names from
`sem-console/names`. Everything else is computed again as a live console computes it (the alarms too):
transitions with their Figure 4 verdicts from the recorded statuses, acks, link health (the
console's tick, run at every TICK of recording time, at each recorded alarm acknowledgement's instant before it is
applied, and at the recording's end), unanswered commands. The console's clock is the recording's time
(`RecordingClock`), so ages, receive times and timeouts are those of the recording.

Playback: play, pause, speed (0.25x to 20x) and seek. Playing advances the position by the wall
time elapsed times the speed, every STEP seconds; the messages up to the new position are read
and decoded on a worker thread (never on the loop) and applied on the loop. Seeking backwards
resets the state (providers, reports, commands) and applies everything from the start up to the
target without sending it to clients; seeking forwards does the same from the current position.
Every client then gets a fresh snapshot. A `replay` WebSocket message carries the position on
every change and every STATUS_EVERY seconds while playing.
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import json
import logging
import struct
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from cyclonedds.core import InstanceState
from mcap.exceptions import McapError

from sem_console.codec.decode import DECODED_TOPICS, Decoder, Item, ReportItem
from sem_console.console.alarms import WATCHED
from sem_console.console.clock import RecordingClock
from sem_console.console.history import History
from sem_console.console.hub import Hub
from sem_console.core.messages import ReplayStatus, SnapshotMessage, replay_message
from sem_console.recording.reader import (
    ALARM_ACKS,
    COMMANDS,
    INSTANCES,
    NAMES,
    iter_messages,
    recorded_station,
    time_range,
)

if TYPE_CHECKING:
    from sem_console.console.ingest import Tap

log = logging.getLogger("sem-console.replay")

SEM_TOPICS = {s.spec.name: s for s in DECODED_TOPICS}  # both UMAA versions' (topic names differ between them)
TOPICS = {*SEM_TOPICS, INSTANCES, COMMANDS, ALARM_ACKS, NAMES}
_ALIVE = int(InstanceState.Alive)
STEP = 0.05  # wall seconds between steps while playing
STATUS_EVERY = 0.5  # wall seconds between `replay` messages while playing
BATCH = 2_000  # decoded messages per worker-thread read while playing
REBUILD_BATCH = 10_000  # the same while seeking: the larger, the fewer superseded reports converted
TICK = 0.2  # recording seconds between link-health and unanswered checks (the live console's tick)
MIN_SPEED, MAX_SPEED = 0.25, 20.0


class ReplayError(Exception):
    """A replay request that cannot be carried out (a position outside the recording)."""


@dataclass
class RecordedCommand:
    """A message of `sem-console/commands`: the command as the recording console sent it to its clients, and whether
    that console followed it as its own (issued it or took it over: it raised its alarms); None in a file whose recorder
    did not say."""

    command: dict[str, Any]
    followed: bool | None


@dataclass
class RecordedAck:
    """A message of `sem-console/alarm-acks`: the recording console's alarm of `key` acknowledged at `at` by `by` (an
    operator, or None) on `station` (None: not known)."""

    key: str
    at: float
    by: str | None
    station: str | None


@dataclass
class RecordedName:
    """A message of `sem-console/names`: the recording console named vehicle `provider_id` `name` from this instant on
    (None: no name there; the replaying console's --vehicle-names name, if any, then applies)."""

    provider_id: uuid.UUID
    name: str | None


Played = Item | RecordedCommand | RecordedAck | RecordedName  # what the cursor reads and the console applies


class Cursor:
    """Reads a recording from its start, in log time order, and decodes each message. Used from one
    worker thread at a time."""

    def __init__(self, path: Path, decoder: Decoder, tap: Tap | None = None) -> None:
        """`tap`: where each recorded SEM sample goes too, raw, as it is played (not while seeking): the console's
        feed, as the ingest's samples live (the Foxglove gateway's raw channels)."""
        self.decoder, self.tap = decoder, tap
        self._messages = iter_messages(path, TOPICS)
        self._pending: tuple[str, Any] | None = None
        self.done = False
        self.skipped = 0
        self._watched: dict[tuple[str, Any], Any] = {}  # (topic, source) -> the value the alarms watch, as last read

    def read_until(self, until_ns: int, limit: int = BATCH, rebuild: bool = False) -> list[tuple[int, Played]]:
        """(log time, item) of the next messages logged at or before `until_ns`, at most `limit` of them. With
        `rebuild` (a seek: nothing is sent to clients on the way) only the last report of each provider and topic
        is converted to JSON; the ones before it count for link health only (a report with no JSON, alive)."""
        out: list[tuple[int, Played]] = []
        tap = self.tap if self.tap is not None and self.tap.active and not rebuild else None
        while len(out) < limit and not self.done:
            if self._pending is None:
                try:
                    self._pending = next(self._messages)
                except StopIteration:
                    self.done = True
                    break
                except (McapError, OSError, EOFError, ValueError, struct.error) as e:  # a file cut short: play what came before
                    log.warning("the recording ends early: %s", e)
                    self.done = True
                    break
            topic, message = self._pending
            if message.log_time > until_ns:
                break
            self._pending = None
            if tap is not None and topic in SEM_TOPICS:
                tap.on_samples(SEM_TOPICS[topic], [(message.data, True, _ALIVE, message.publish_time)], message.log_time)
            item = self._decode(topic, message, convert=not rebuild)
            if item is not None:
                out.append((message.log_time, item))
        changes = self._watched_changes(out)
        if rebuild:
            last: dict[tuple[str, Any], ReportItem] = {}
            for _at, item in out:
                if isinstance(item, ReportItem) and item.sample is not None:
                    last[(item.topic, item.source)] = item
            # a report that changes what an alarm watches (INS status, fixValid) is applied too: the alarm is
            # then raised or cleared at its own time, not at the batch's last report, minutes later
            for item in {id(i): i for i in (*changes, *last.values())}.values():
                self.decoder.convert(item)
            for _at, item in out:
                if isinstance(item, ReportItem):
                    item.sample = None
        return out

    def _watched_changes(self, out: list[tuple[int, Played]]) -> list[ReportItem]:
        """The reports of `out` whose field the alarms watch (`console.alarms.WATCHED`) differs from the
        report before it of the same provider and topic."""
        changes: list[ReportItem] = []
        for _at, item in out:
            field = WATCHED.get(item.topic) if isinstance(item, ReportItem) else None
            if field is None:
                continue
            assert isinstance(item, ReportItem)
            report = item.report if item.sample is None else item.sample[0]
            if report is None:
                continue
            key, value = (item.topic, item.source), report.get(field)
            if key not in self._watched or self._watched[key] != value:
                self._watched[key] = value
                changes.append(item)
        return changes

    def _decode(self, topic: str, message: Any, convert: bool) -> Played | None:
        at = message.log_time / 1e9
        if topic in SEM_TOPICS:
            return self.decoder.decode(SEM_TOPICS[topic], message.data, True, InstanceState.Alive, at, convert)
        try:
            event = json.loads(message.data)
            if topic == COMMANDS:
                followed = event.get("followed")
                return RecordedCommand(dict(event["command"]), followed if isinstance(followed, bool) else None)
            if topic == ALARM_ACKS:
                by, station = event.get("ackedBy"), event.get("station")
                return RecordedAck(
                    str(event["key"]),
                    float(event["ackedAt"]),
                    by if isinstance(by, str) else None,
                    station if isinstance(station, str) else None,
                )
            if topic == NAMES:
                name = event["name"]
                return RecordedName(uuid.UUID(event["providerId"]), name if isinstance(name, str) and name else None)
            sem = SEM_TOPICS.get(event["topic"])
            if sem is None:  # a command topic's dispose: the console follows its own commands from COMMANDS
                return None
            state = InstanceState.NotAliveDisposed if event["state"] == "disposed" else InstanceState.NotAliveNoWriters
            return self.decoder.decode(sem, base64.b64decode(event["key"]), False, state, at)
        except (ValueError, KeyError, TypeError, AttributeError) as e:  # AttributeError: not a dict, a UUID not a str
            self.skipped += 1
            log.warning("skipped a message on %s at %d: %s", topic, message.log_time, e)
            return None

    def close(self) -> None:
        with contextlib.suppress(ValueError):  # still being read on a worker thread (shutdown): the file closes with it
            self._messages.close()


class Replayed(Protocol):
    """What a replay drives: the console (`service.Console`), which owns the replay and hands itself in."""

    history: History
    hub: Hub
    quiet: bool  # True while seeking: state changes are not sent to clients (a snapshot follows)

    @property
    def feed(self) -> Tap: ...

    def reset(self) -> None: ...
    def snapshot(self) -> SnapshotMessage: ...
    def apply(self, item: Played) -> None: ...
    def tick(self, now: float) -> None: ...


class Replay:
    """Owned by the console's `RecordingSource` (`console/sources.py`); every method runs on the event loop."""

    def __init__(self, console: Replayed, path: Path, speed: float, clock: RecordingClock) -> None:
        self.console, self.path, self.speed, self.clock = console, path, speed, clock
        self.station: str | None = None  # the recording console's (--console-name); None when the file does not say
        self.playing = True
        self.start = self.end = self.position = 0.0
        self.decoder = Decoder()
        self._cursor: Cursor | None = None
        self._next_tick = 0.0
        self._end_ns = 0
        self._lock = asyncio.Lock()
        self._task: asyncio.Task[None] | None = None
        self._since = 0.0  # loop time from which playing advances (after a seek or play)
        self._sent = 0.0  # loop time of the last `replay` message
        self.seeks = 0  # seeks done, whoever asked (the Foxglove gateway tells its clients each one)

    # ---- lifecycle -------------------------------------------------------------------------
    async def open(self) -> None:
        span = await asyncio.to_thread(time_range, self.path)
        self.station = await asyncio.to_thread(recorded_station, self.path)
        first, last = span if span is not None else (0, 0)
        self.start, self.end, self._end_ns = first / 1e9, last / 1e9, last
        self._rewind()
        self.position = self.start
        log.info("replaying %s: %.1f s of recording, at %gx", self.path, self.end - self.start, self.speed)
        self._task = asyncio.get_running_loop().create_task(self._run())

    async def close(self) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
        async with self._lock:
            if self._cursor is not None:
                self._cursor.close()

    def _rewind(self) -> None:
        if self._cursor is not None:
            self._cursor.close()
        self._cursor = Cursor(self.path, self.decoder, self.console.feed)
        self._next_tick = self.start + TICK
        self.clock.at = self.start

    # ---- control (the REST route) --------------------------------------------------------------
    def status(self) -> ReplayStatus:
        return {
            "file": self.path.name,
            "state": "playing" if self.playing else "paused",
            "speed": self.speed,
            "position": self.position,
            "start": self.start,
            "end": self.end,
        }

    async def play(self) -> None:
        if self.position >= self.end:  # at the end: from the start again
            await self.seek(self.start)
        self.playing = True
        self._since = asyncio.get_running_loop().time()
        self._broadcast()

    def pause(self) -> None:
        self.playing = False
        self._broadcast()

    def set_speed(self, speed: float) -> None:
        if not MIN_SPEED <= speed <= MAX_SPEED:
            raise ReplayError(f"speed {speed} is outside {MIN_SPEED}..{MAX_SPEED}")
        self.speed = speed
        self._broadcast()

    async def seek(self, position: float) -> None:
        """Rebuild the state at `position` (UTC seconds, within the recording), then send every client a snapshot."""
        if not self.start <= position <= self.end:
            raise ReplayError(f"position {position} is outside the recording ({self.start} to {self.end})")
        async with self._lock:
            if position < self.position:
                try:  # first: if the database fails, the seek goes on and the charts show a little more
                    await self.console.history.forget_after(position)
                except Exception:
                    log.exception("could not forget the track and series after %s", position)
                self._rewind()
                self.console.reset()
            self.console.quiet = True  # what happens on the way is not sent: the snapshot after it is
            try:
                await self._advance(position, rebuild=True)
            finally:
                self.console.quiet = False
            self._since = asyncio.get_running_loop().time()
            self.console.hub.resync(self.console.snapshot())
            self.seeks += 1
            self._broadcast()

    # ---- playing ---------------------------------------------------------------------------------
    async def _run(self) -> None:
        loop = asyncio.get_running_loop()
        last = loop.time()
        while True:
            await asyncio.sleep(STEP)
            now = loop.time()
            elapsed, last = now - max(last, self._since), now
            if not self.playing:
                continue
            try:
                async with self._lock:
                    if not self.playing:
                        continue
                    await self._advance(min(self.end, self.position + max(0.0, elapsed) * self.speed))
                    if self.position >= self.end:
                        self.playing = False
                        self._broadcast()
            except Exception:  # a bug here must not stop the replay for good
                log.exception("replay step failed")
            if now - self._sent >= STATUS_EVERY:
                self._broadcast()

    async def _advance(self, target: float, rebuild: bool = False) -> None:
        """Read, decode (on a worker thread) and apply every message up to `target`, ticking the console
        at every TICK of recording time on the way, as the live console's ticker does (and at an acknowledgement's
        instant and the recording's end, below)."""
        cursor = self._cursor
        assert cursor is not None
        until = self._end_ns if target >= self.end else int(target * 1e9)  # the last message, whatever float rounding does
        batch = REBUILD_BATCH if rebuild else BATCH
        while True:
            items = await asyncio.to_thread(cursor.read_until, until, batch, rebuild)
            for at_ns, item in items:
                at = at_ns / 1e9
                self._tick_to(at)
                self.clock.at = at
                if isinstance(item, RecordedAck):
                    # the alarms as they stand at the acknowledgement's instant: the live console's ticker, of its own
                    # phase, can find an alarm's condition up to a TICK before this grid of ticks does
                    self.console.tick(at)
                self.console.apply(item)
            if len(items) < batch:
                break
        self._tick_to(target)
        if target >= self.end:
            # the live console ticked on after the last message until the recording stopped: its last judgement (a
            # vehicle lost by its disposes within the TICK before the end) is the file's last state, whatever this
            # grid of ticks' phase
            self.clock.at = target
            self.console.tick(target)
        self.clock.at = self.position = target

    def _tick_to(self, at: float) -> None:
        while self._next_tick <= at:
            self.clock.at = self._next_tick
            self.console.tick(self._next_tick)
            self._next_tick += TICK

    def _broadcast(self) -> None:
        self._sent = asyncio.get_running_loop().time()
        self.console.hub.publish(replay_message(self.status()))
