"""WebSocket fan-out: every client has its own sender task and queues.

Ordered events (commands, transitions, providers, alarms) are queued per client, never
conflated, and each goes out before any report waiting; then the reports of the vehicle the client selected (`select`);
a selecting client's reports of the other vehicles wait (`later`) so that each goes at most once a topic every pace
(OTHERS_EVERY, longer when their streams pass a budget of reports a second, OTHERS_BUDGET); reports are conflated per
client (the latest per provider and topic), so a client that reads slowly gets fewer reports, not later ones, of those
not yet written: what was written waits in
the sockets' buffers in order (with 250 vehicles, megabytes: the selected vehicle's tail, docs/rendering.md).
A client is dropped when its ordered queue passes `max_queue` and it has sent nothing for `stall_seconds` (it
stopped reading), or when the queue reaches four times `max_queue` whatever it does, or when one send to it has not
completed for `cut_seconds` whatever waits (a laptop gone to sleep: its reports are conflated, so only time bounds it);
so no client holds memory without bound nor delays anyone else, and a burst does not
drop a healthy client. A client dropped is told why in the WebSocket's close reason (`Client.dropped_for`).
A client that asks for batches (the dashboard: /ws?batch=1) gets the
reports waiting for it when its sender is free as one JSON array: a lone report goes out alone and
at once, so only load makes batches (a browser pays about 0.13 ms of its main thread per WebSocket
message, whatever its size: 30 % of it with 250 vehicles). Everything here runs on the event loop thread.
"""

from __future__ import annotations

import asyncio
import json
import logging
import time
import zlib
from collections import Counter, deque
from collections.abc import Awaitable, Callable, Mapping
from heapq import heappop, heappush
from itertools import islice
from typing import Any

import orjson

from sem_console.core.messages import ReportMessage, ServerMessage, SnapshotMessage, pace_message

log = logging.getLogger("sem-console.hub")


MAX_QUEUED_BYTES = 64 * 1024 * 1024
MAX_UNACKED_FRAMES = 40_000  # a client on /ws?ack=1 that acknowledges none: 17 minutes of the selected vehicle's frames
BATCH_MAX = 500  # reports in one batch at most (a frame of a few hundred kB)
OTHERS_EVERY = 0.25  # s: at most one report a topic this often of each vehicle a selecting client does not draw in full
# (its fleet on the map redraws every 0.45 s, its list with it): 10 Hz vehicles sent whole were the page's most work
OTHERS_BUDGET = 400  # reports a second of the vehicles a selecting client does not draw in full, all of them together:
# each one's topic goes at most every max(OTHERS_EVERY, their streams / OTHERS_BUDGET) s (its `pace`, told to the page).
# The page met every target at 800 a second (50 vehicles at 10 Hz, 4 a second each: panels p99 41-48 ms, 0.27 renderer
# cores, quiet machine) and missed at 1,000 (250 vehicles at 1 Hz: p99 100-170 ms, long tasks) and 4,000 (1,000
# vehicles: p99 3 s); half of the 800, since at 1,000 vehicles the console and the simulator take most of the 2 cores:
# 100 vehicles of four topics at 1 Hz, 1,000 vehicles' each every 10 s (the map's dots move every 10 s)
FULL_EVERY = 5.0  # seconds: a vehicle not selected still gets its GPSReport's satellites this often (the sky plot's
# trails take a point every 5 s of every vehicle, so a vehicle selected later shows the last ten minutes' trails)
WHOLE_BUDGET = 10  # whole GPSReports a second (of wall time, a replay's too) of the vehicles a selecting client does not
# draw (about 10 kB each, 40 satellites): each one's at most every FULL_EVERY s of the console's clock and every
# their count / WHOLE_BUDGET s of wall time; at 1,000 vehicles one every 100 s (their trails sparser), where every
# vehicle's every 5 s was 2 MB a second to each page
STREAMS_EVERY = 5.0  # s: the streams (a vehicle's topic) published within this long are what the budgets share
RETELL = 0.1  # a client is told its pace again when it moved by more than this share


def dumps(message: Mapping[str, Any]) -> str:
    """Compact JSON, by orjson (a tenth of json.dumps' CPU for a report); json.dumps for what orjson
    refuses (an integer past 64 bits). orjson writes a non-finite float as null, json.dumps as NaN,
    which no browser parses: reports never carry one (convert nulls them)."""
    try:
        return orjson.dumps(message, option=orjson.OPT_NON_STR_KEYS).decode()
    except TypeError:
        return json.dumps(message, separators=(",", ":"))


class Client:
    """One WebSocket client's queues: ordered events (never conflated) and the newest report per vehicle and topic.

    `window`: with acknowledgements (`/ws?ack=1`), reports go out only while fewer than this many bytes are sent and not
    yet acknowledged. What was written waits in the sockets' buffers in order, beyond conflation: with 250 vehicles a
    page that stalls for a moment has megabytes queued there, and the selected vehicle's next fix waits behind all of
    it (p99 0.2 s, seconds on a busy machine). With the window the reports wait here, where each is replaced by the
    newer. Ordered events (snapshots, alarms, commands) are not held by it, nor the selected vehicle's reports (a few
    kB a second, what the operator watches); a client that takes frames and acknowledges none is dropped once
    MAX_UNACKED_FRAMES or MAX_QUEUED_BYTES are unacknowledged (those pass the window, and each is counted in `inflight`).

    `select`: a client that names the vehicle it draws (the dashboard: `select` messages, or /ws?vehicle=) gets every
    other vehicle's GPSReport thin (without its satellites, marked `partial`) but once every FULL_EVERY (of `clock`) and
    `whole_every` (of wall time) seconds, and
    each other vehicle's reports at most once a topic every `pace` seconds, the newest (`later` holds them meanwhile,
    `due` says when each is due): the hub sets both from its budgets (`Hub.repace`) and tells the client its pace (a
    `pace` message), by which the page judges a vehicle it does not draw silent. One that never does gets every report
    whole, as it comes. `clock`: the console's (a replay's is the recording's time, as the page's trails are)."""

    def __init__(
        self,
        send: Callable[[str], Awaitable[None]],
        max_queue: int,
        stall_seconds: float,
        batch: bool = False,
        window: int | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.send, self.max_queue, self.stall_seconds, self.batch = send, max_queue, stall_seconds, batch
        self.clock = clock
        self.window = window
        self.sent_frames = 0  # frames sent on this socket
        self.inflight: deque[int] = deque()  # the sizes of the frames sent and not yet acknowledged, oldest first
        self.inflight_bytes = 0
        self.last_sent = time.monotonic()
        self.sending_since: float | None = None  # monotonic: when the send under way began (None: none under way)
        self.sending_bytes = 0  # the size of the send under way
        self.ordered: deque[str] = deque()
        self.queued_bytes = 0
        self.snapshot_pending = False
        self.reports: dict[tuple[str, str], str | tuple[str, str]] = {}  # the text, or (whole, thin) of a GPSReport
        self.first: dict[tuple[str, str], str | tuple[str, str]] = {}  # the same, of the selected vehicle: sent first
        self.selecting = False  # it has named the vehicle it draws: others' GPSReports go thin
        self.selected: str | None = None
        self.full_at: dict[str, float] = {}  # when each vehicle's last whole GPSReport went out to it (by `clock`)
        self.full_wall: dict[str, float] = {}  # the same, monotonic (the budget's)
        self.since = clock()  # when it came, or its replay last seeked (`_last_whole`)
        self.came = time.monotonic()  # when it came (`_sent_at`)
        self.pace = OTHERS_EVERY  # s: each other vehicle's topic at most this often (the pace told, once selecting)
        self.whole_every = 0.0  # s of wall time: each other vehicle's whole GPSReport at most this often (the budget)
        self.due: list[tuple[float, tuple[str, str]]] = []  # the reports parked in `later`: when each was last sent
        self.later: dict[tuple[str, str], str | tuple[str, str]] = {}  # other vehicles' reports not yet due to go
        self.sent_at: dict[tuple[str, str], float] = {}  # when each other vehicle's report of a topic last went
        self.release: asyncio.TimerHandle | None = None
        self.wake = asyncio.Event()
        self.task: asyncio.Task[None] | None = None
        self.dropped = False
        self.dropped_for = ""  # why, for the log

    def push(self, text: str, key: tuple[str, str] | None = None, thin: str | None = None, unpaced: bool = False) -> None:
        """Queue an ordered event, or with `key` the newest report of its vehicle and topic (`thin`: the same without
        what only a client drawing that vehicle needs; which of the two goes out is chosen when it is sent; `unpaced`:
        it goes with the next reports whatever the pace, as a report that raised or changed an alarm does, so that it
        is not seconds behind the alarm)."""
        if self.dropped:
            return
        if key is not None:
            # a report waiting keeps its place with the newest text: the longest-waiting go out first, and a frequent
            # one (the selected vehicle's 10 Hz fix) is not sent to the back of the queue by each of its updates
            # both kept while it waits: which goes is decided when it is sent (a `select` may come meanwhile: a new
            # page's reports wait for its code, and went whole though it had named its vehicle by then)
            # the selected vehicle's (what the operator watches) go out ahead of the fleet's and past the window
            value = text if thin is None else (text, thin)
            if key[0] == self.selected:
                self.first[key] = value
            elif unpaced:
                self.later.pop(key, None)  # its place in `due` is skipped by `_release`
                self.reports[key] = value
            elif key in self.later:
                self.later[key] = value  # another vehicle's, sent a moment ago: the newest goes when it is due
                return
            elif self.selecting and key not in self.reports and time.monotonic() - (sent := self._sent_at(key)) < self.pace:
                self.later[key] = value
                heappush(self.due, (sent, key))
                if self.release is None:
                    self.release = asyncio.get_running_loop().call_later(OTHERS_EVERY / 4, self._release)
                return
            else:
                self.reports[key] = value
        elif self.queued_bytes + len(text) > MAX_QUEUED_BYTES or (
            len(self.ordered) >= self.max_queue
            and (time.monotonic() - self.last_sent > self.stall_seconds or len(self.ordered) >= 4 * self.max_queue)
        ):
            self.drop(f"stopped reading: {len(self.ordered)} messages behind")
            return
        else:
            self.ordered.append(text)
            self.queued_bytes += len(text)
        self.wake.set()

    def push_snapshot(self, text: str) -> None:
        """Queue a snapshot unless one is already waiting to go out (a resync storm costs one)."""
        if not self.snapshot_pending:
            self.snapshot_pending = True
            self.push(text)

    def _sent_at(self, key: tuple[str, str]) -> float:
        """When another vehicle's report of a topic last went to this client (monotonic). Before its first: as if one
        went at a point of the pace before the client came, spread by the key, so that each stream's first comes
        within a pace, not all at once: the snapshot has every vehicle's newest, and a new page's first second was a
        report of every topic of every vehicle (4,000 with 1,000 vehicles)."""
        sent = self.sent_at.get(key)
        return self.came - self.pace * (zlib.crc32("/".join(key).encode()) % 1000) / 1000 if sent is None else sent

    def _release(self) -> None:
        """Every OTHERS_EVERY / 4 while some wait: the other vehicles' reports now due join the queue, the longest
        waiting first (`due` is a heap by when each was last sent: the few due are found without a look at the rest)."""
        self.release = None
        now = time.monotonic()
        while self.due and now - self.due[0][0] >= self.pace:
            _, key = heappop(self.due)
            if key not in self.later:  # it went meanwhile (its vehicle selected)
                continue
            if now - (sent := self._sent_at(key)) < self.pace:  # sent since it was parked, or the pace grew
                heappush(self.due, (sent, key))
                continue
            self.reports[key] = self.later.pop(key)
        if self.reports:
            self.wake.set()
        if self.later and not self.dropped:
            self.release = asyncio.get_running_loop().call_later(OTHERS_EVERY / 4, self._release)

    def select(self, provider_id: str | None) -> None:
        """The client draws this vehicle now (None: none): its GPSReports go out whole, and its reports first; the
        first `select` tells it the pace of the others."""
        if not self.selecting:
            self.push(dumps(pace_message(self.pace)))
        self.selecting, self.selected = True, provider_id
        for key in [k for k in self.later if k[0] == provider_id]:
            self.first[key] = self.later.pop(key)
        for key in [k for k in self.reports if k[0] == provider_id]:
            self.first[key] = self.reports.pop(key)
        for key in [k for k in self.first if k[0] != provider_id]:
            self.reports[key] = self.first.pop(key)
        if self.first:  # its parked reports (`later`) had woken none, and the window may hold those in `reports`
            self.wake.set()

    def _peek(self, key: tuple[str, str], waiting: dict[tuple[str, str], str | tuple[str, str]] | None = None) -> str:
        """The text the report waiting for `key` would go out as: whole to a client that has named no vehicle yet, for
        the selected vehicle, or when its vehicle's whole one is due (`_whole_due`); thin otherwise."""
        value = (self.reports if waiting is None else waiting)[key]
        if isinstance(value, str):
            return value
        return value[0] if not self.selecting or key[0] == self.selected or self._whole_due(key[0]) else value[1]

    def _whole_due(self, provider_id: str) -> bool:
        """Whether the vehicle's whole GPSReport may go: FULL_EVERY after its last by the console's clock (a replay's is
        the recording's, as the page's trails are), and `whole_every` after it by wall time (the budget is of bytes a
        second to the page, at any replay speed). Before its first: as if one went at a point of each before the client
        came (or a replay seeked), spread by the vehicle's id, so that each vehicle's first comes within them and not all
        at once: a new page's first reports were every vehicle's whole, 40 satellites each (50 vehicles: 650 kB), which
        the snapshot had left out."""
        spread = (zlib.crc32(provider_id.encode()) % 1000) / 1000
        last = self.full_at.get(provider_id, self.since - FULL_EVERY * spread)
        wall = self.full_wall.get(provider_id, self.came - self.whole_every * spread)
        return self.clock() - last >= FULL_EVERY and time.monotonic() - wall >= self.whole_every

    def _text(
        self, key: tuple[str, str], text: str | None = None, waiting: dict[tuple[str, str], str | tuple[str, str]] | None = None
    ) -> str:
        """Take the report waiting for `key` as `text`, what `_peek` said (asked again, the clock may have passed
        FULL_EVERY: a batch measured thin against the window's room went whole)."""
        text = self._peek(key, waiting) if text is None else text
        value = (self.reports if waiting is None else waiting).pop(key)
        if not isinstance(value, str) and text is value[0]:
            self.full_at[key[0]] = self.clock()
            self.full_wall[key[0]] = time.monotonic()
        if self.selecting and key[0] != self.selected:
            self.sent_at[key] = time.monotonic()
        return text

    def ack(self, frames: int) -> bool:
        """The client has taken the first `frames` frames of this socket: the reports held by the window may go.
        False, and the window stays as it was, for a count that is not one of this socket's (more than were sent).
        On a socket without a window (not /ws?ack=1) an ack changes nothing, and is no error: its frames are not
        counted (an error there said "0 were sent" of a socket that had sent thousands)."""
        if self.window is None:
            return True
        unacked = self.sent_frames - frames
        if frames < 0 or unacked < 0:
            return False
        while len(self.inflight) > unacked:
            self.inflight_bytes -= self.inflight.popleft()
        self.wake.set()
        return True

    def _batch(self) -> list[str]:
        """The reports of the next batch, longest waiting first: at most BATCH_MAX, and within the window's room (at
        least one), so that one frame does not put megabytes in flight past it."""
        room = float("inf") if self.window is None else self.window - self.inflight_bytes
        out: list[str] = []
        for key in list(islice(self.reports, BATCH_MAX)):
            text = self._peek(key)
            if out and len(text) > room:
                break
            self._text(key, text)
            room -= len(text) + 1
            out.append(text)
        return out

    def _window_open(self) -> bool:
        return self.window is None or self.inflight_bytes < self.window

    def drop(self, why: str) -> None:
        self.dropped, self.dropped_for = True, why
        self.ordered.clear()
        self.queued_bytes = 0
        self.reports.clear()
        self.first.clear()
        self.close()

    def close(self) -> None:
        """Its sender and its release timer stop (Hub.detach: the socket closed; a timer left pending kept the client
        alive and moved its parked reports to a queue nobody sends)."""
        self.later.clear()
        self.due.clear()
        if self.release is not None:
            self.release.cancel()
            self.release = None
        if self.task is not None:
            self.task.cancel()

    async def run(self) -> None:
        while True:
            await self.wake.wait()
            self.wake.clear()
            # an ordered event goes out next, whatever reports wait: under load more reports arrive during each send
            # than one send takes, and an alarm, a lost vehicle or a command waiting for them all waited for ever
            # then the selected vehicle's reports, not held by the window: under load its fix waited behind the
            # window's refill with a thousand reports of the fleet ahead of it (250 vehicles: p99 0.1-0.2 s)
            while self.ordered or self.first or (self.reports and self._window_open()):
                if self.ordered:
                    text = self.ordered.popleft()
                    self.queued_bytes -= len(text)
                    if text.startswith('{"type":"snapshot"'):
                        self.snapshot_pending = False
                elif self.first:
                    texts = [self._text(k, waiting=self.first) for k in list(self.first)[: None if self.batch else 1]]
                    text = texts[0] if len(texts) == 1 else "[" + ",".join(texts) + "]"
                elif self.batch and len(self.reports) > 1:
                    text = "[" + ",".join(self._batch()) + "]"
                else:
                    text = self._text(next(iter(self.reports)))
                if self.window is not None:
                    self.sent_frames += 1
                    self.inflight.append(len(text))
                    self.inflight_bytes += len(text)
                    if len(self.inflight) > MAX_UNACKED_FRAMES or self.inflight_bytes > MAX_QUEUED_BYTES:
                        # it reads but never acknowledges: what passes the window (the selected vehicle's reports,
                        # ordered events) would grow `inflight` and the sockets' buffers without bound
                        self.drop(f"acknowledged none of {len(self.inflight)} frames")
                        return
                self.sending_since, self.sending_bytes = time.monotonic(), len(text)
                await self.send(text)
                self.last_sent, self.sending_since = time.monotonic(), None


SLOWEST_LINK = 2_000  # bytes a second: a 16 kbit/s satellite link, the thinnest a dashboard is served over


class Hub:
    def __init__(
        self,
        max_queue: int = 10_000,
        stall_seconds: float = 5.0,
        window: int = 256 * 1024,
        clock: Callable[[], float] = time.monotonic,
        cut_seconds: float = 30.0,
    ) -> None:
        """`clock`: of the whole GPSReports of vehicles not selected (FULL_EVERY): the console's, a replay's recording
        time, since the page's trails step in it (at 20x, 5 s of wall time were 100 s of trails); their budget
        (WHOLE_BUDGET) is of wall time."""
        self.max_queue, self.stall_seconds, self.window, self.clock = max_queue, stall_seconds, window, clock
        self.cut_seconds = cut_seconds
        self.clients: set[Client] = set()
        self.published = 0  # messages handed to clients (one per client), for /api/metrics
        self.dropped = 0
        self.heard: set[tuple[str, str]] = set()  # the streams (a vehicle's topic) published since `counted_at`
        self.counted_at: float | None = None  # monotonic: when `streams` were last counted (`sweep`)
        self.streams: Counter[str] = Counter()  # per vehicle, its streams published within STREAMS_EVERY
        self.gps: set[str] = set()  # the vehicles among them with a GPSReport

    def publish(
        self,
        message: ServerMessage,
        key: tuple[str, str] | None = None,
        thin: ReportMessage | None = None,
        unpaced: bool = False,
    ) -> None:
        """Send `message` to every client (with `key`: a report, conflated per client; `thin`: the same report without
        what only a client drawing that vehicle needs, for the clients that draw another; `unpaced`: a report whose
        change raised or changed an alarm, not held by the pace of the vehicles a client does not draw)."""
        if key is not None:
            self.heard.add(key)
        if not self.clients:
            return
        text = dumps(message)
        thin_text = None if thin is None else dumps(thin)
        self.published += len(self.clients)
        for c in list(self.clients):
            c.push(text, key, thin_text, unpaced)
            if c.dropped:
                self._dropped(c)

    def sweep(self, now: float) -> None:
        """Cut every client one send to which has not completed for `cut_seconds` (it stopped reading: a laptop
        asleep), whatever waits for it (`now`: monotonic seconds; the console's tick); every STREAMS_EVERY, count the
        streams published and set each client's pace by them."""
        if self.counted_at is None:
            self.counted_at = now
        elif now - self.counted_at >= STREAMS_EVERY:
            self.counted_at = now
            heard, self.heard = self.heard, set()
            self.streams = Counter(p for p, _ in heard)
            self.gps = {p for p, topic in heard if topic == "GPSReport"}
            for c in list(self.clients):
                self.repace(c)
        for c in list(self.clients):
            # a send completes only once the frame is nearly all out: a snapshot of hundreds of kB takes minutes on a
            # satellite link that is still reading, so its size at the slowest link served is added to the bound
            if c.sending_since is not None and now - c.sending_since > self.cut_seconds + c.sending_bytes / SLOWEST_LINK:
                c.drop(f"stopped reading: nothing taken for {now - c.sending_since:.0f} s")
                self._dropped(c)

    def repace(self, c: Client) -> None:
        """Set the client's pace of the vehicles it does not draw from the budgets and the streams counted (the
        selected vehicle's not among them); tell it when it moved by more than RETELL."""
        others = sum(self.streams.values()) - self.streams.get(c.selected, 0) if c.selected else sum(self.streams.values())
        c.whole_every = (len(self.gps) - (c.selected in self.gps)) / WHOLE_BUDGET
        pace = round(max(OTHERS_EVERY, others / OTHERS_BUDGET), 2)
        if abs(pace - c.pace) > RETELL * c.pace:
            c.pace = pace
            if c.selecting:
                c.push(dumps(pace_message(pace)))
                if c.dropped:
                    self._dropped(c)

    def select(self, c: Client, provider_id: str | None) -> None:
        """The client draws this vehicle now (`Client.select`); one dropped by the pace told it is counted."""
        c.select(provider_id)
        if c.dropped:
            self._dropped(c)

    def _dropped(self, c: Client) -> None:
        if c not in self.clients:  # counted when it was cut (a cut client's socket may still send a select)
            return
        self.dropped += 1
        log.warning("dropped a WebSocket client that %s", c.dropped_for)
        self.clients.discard(c)

    def attach(
        self,
        send: Callable[[str], Awaitable[None]],
        first: SnapshotMessage,
        batch: bool = False,
        ack: bool = False,
        vehicle: str | None = None,
    ) -> Client:
        """Register a client with `first` (its snapshot) queued ahead of any later event; `batch`: it takes the
        reports waiting for it as one JSON array; `ack`: it acknowledges the frames it has taken, and its reports go
        out within the hub's window (`Client`); `vehicle`: the vehicle it draws, named as it came (/ws?vehicle=: its
        snapshot is built for it), as a `select` of it."""
        client = Client(send, self.max_queue, self.stall_seconds, batch, self.window if ack else None, self.clock)
        client.push_snapshot(json.dumps(first, separators=(",", ":")))
        self.repace(client)
        self.clients.add(client)
        client.task = asyncio.get_running_loop().create_task(client.run())
        if vehicle is not None:
            self.select(client, vehicle)
        return client

    def resync(self, snapshot: SnapshotMessage) -> None:
        """Every client starts again from `snapshot` (a replay seeked): what was queued for it is dropped."""
        text = json.dumps(snapshot, separators=(",", ":"))
        for c in self.clients:
            c.ordered.clear()
            c.queued_bytes = 0
            c.reports.clear()
            c.first.clear()
            c.later.clear()
            c.due.clear()
            c.full_at.clear()  # a seek back: the recording's clock went back, and each vehicle's next is due afresh
            c.since = self.clock()
            c.snapshot_pending = False
            c.push_snapshot(text)
            if c.selecting:  # the pace told may have waited behind a snapshot in flight: it went with the rest
                c.push(dumps(pace_message(c.pace)))
        self.published += len(self.clients)

    def detach(self, client: Client) -> None:
        self.clients.discard(client)
        client.close()
