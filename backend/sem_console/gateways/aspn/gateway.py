"""The ASPN gateway: the console's feed in, ASPN-23 messages out on LCM channels <prefix>/<vehicle>/<measurement>, where
<vehicle> is 16 hex digits digested from the vehicle's whole GUID (`channel_vehicle`): LCM over UDP refuses a channel name
over 63 characters, and with the whole GUID most measurements' names were longer (nothing was sent on them).

It also keeps each vehicle's last `log_seconds` of messages (at most `MAX_LOG_BYTES` of memory each,
per-message overhead included; a vehicle quiet for longer is forgotten), from which
`GET /api/providers/{id}/aspn-log` writes an LCM log file with LCM's own `EventLog`.
"""

from __future__ import annotations

import contextlib
import logging
import os
import queue
import tempfile
import threading
import time
import uuid
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import lcm

from sem_console.console.feed import Feed
from sem_console.core.messages import GatewayState
from sem_console.gateways import Stats

if TYPE_CHECKING:  # the encoder (ASPN's classes and numpy, a third of a second) is loaded only by a gateway that runs
    from sem_console.gateways.aspn.encode import Encoder

MAX_LOG_BYTES = 8 * 1024 * 1024
LCM_MAX_CHANNEL = 63  # characters: LCM over UDP refuses longer channel names (so --aspn-prefix takes at most 11)


def channel_vehicle(vehicle: uuid.UUID) -> str:
    """The vehicle's part of its channel names: its 64-bit key (`vehicle_key`, from the whole GUID) in 16 hex digits;
    its ASPN device_id is the same bits shifted right by one."""
    from sem_console.gateways.aspn.encode import vehicle_key

    return f"{vehicle_key(vehicle):016x}"


QUEUE_SIZE = 1000  # reports waiting for the worker; more are dropped and counted ("dropped: queue full")
TOPICS = ("GPSFixReport", "GPSReport")
log = logging.getLogger("sem-console.gateways")


def lcm_url(url: str) -> str:
    """A file:// URL without a mode appends to the log (LCM's file provider would read it; `mode=w` would
    wipe the previous run's log at each start). The file is never rotated."""
    if url.startswith("file://") and "mode=" not in url:
        return url + ("&" if "?" in url else "?") + "mode=a"
    return url


def open_lcm(url: str) -> lcm.LCM:
    """LCM on `url`; RuntimeError when LCM cannot open it (unknown provider, a file that cannot be written)."""
    return lcm.LCM(lcm_url(url))


def check_url(url: str) -> None:
    """RuntimeError when the gateway could not open `url`. A file:// log is checked without opening it
    (the gateway opens it once, at start); any other URL is opened once and let go."""
    if not url.startswith("file://"):
        try:
            open_lcm(url)
        except RuntimeError as e:  # lcm's own "Couldn't create LCM": liblcm printed the reason on stderr just before
            raise RuntimeError(
                f"{e} (LCM says why on the line above): give e.g. udpm://239.255.76.67:7667?ttl=0, file://PATH.lcm or memq://"
            ) from None
        return
    path = Path(url.removeprefix("file://").split("?", 1)[0])
    if path.is_dir():
        raise RuntimeError(f"{path} is a directory")
    target = path if path.exists() else path.parent
    if not target.is_dir() and not path.exists():
        raise RuntimeError(f"no such directory: {path.parent}")
    if not os.access(target, os.W_OK):
        raise RuntimeError(f"cannot write {target}")


# Memory one kept message costs beside its LCM bytes: the tuple, its int, the bytes object's header and the
# deque slot (measured with tracemalloc on CPython 3.11: ~141 bytes), rounded up. The channel string is
# held once per stream (`Recording.channels`), so it is not counted per message.
EVENT_OVERHEAD = 160


@dataclass
class Recording:
    events: deque[tuple[int, str, bytes]] = field(default_factory=deque)  # (UTC microseconds, channel, LCM bytes)
    size: int = 0  # bytes the events use: their LCM bytes plus EVENT_OVERHEAD each
    channels: dict[str, str] = field(default_factory=dict)  # each stream's channel string, held once


def write_log(events: list[tuple[int, str, bytes]]) -> bytes:
    """An LCM log file (LCM's EventLog format) holding `events` in order."""
    fd, path = tempfile.mkstemp(suffix=".lcm")
    os.close(fd)
    try:
        log = lcm.EventLog(path, "w", overwrite=True)
        for utime, channel, data in events:
            log.write_event(utime, channel, data)
        log.close()
        with open(path, "rb") as f:
            return f.read()
    finally:
        os.unlink(path)


class AspnGateway:
    """On the event loop only a cheap enqueue (`on_message`); one worker thread maps, encodes, keeps and
    publishes in arrival order, so a slow LCM (a full disk, a blocking socket) never stalls the console."""

    def __init__(self, feed: Feed, url: str | None, prefix: str = "aspn23", log_seconds: float = 300.0) -> None:
        self.prefix, self.log_seconds = prefix, log_seconds
        self.stats = Stats("aspn", url is not None, f"{url} ({prefix}/<vehicle>/<measurement>)" if url else None)
        self.encoder: Encoder | None = None
        self.recordings: dict[uuid.UUID, Recording] = {}
        self.lcm: lcm.LCM | None = None
        self._unsubscribe = None
        self._lock = threading.Lock()  # stats, encoder counters and recordings: written by the worker, read by the loop
        self._queue: queue.Queue[tuple[Mapping[str, Any], int] | None] = queue.Queue(QUEUE_SIZE)
        self._worker: threading.Thread | None = None
        if url is not None:
            from sem_console.gateways.aspn.encode import Encoder

            self.encoder = Encoder()
            self.lcm = open_lcm(url)
            self.stats.count("dropped: queue full", 0)
            self._worker = threading.Thread(target=self._work, name="aspn-gateway", daemon=True)
            self._worker.start()
            self._unsubscribe = feed.subscribe("aspn", self.on_message)

    @property
    def enabled(self) -> bool:
        return self.lcm is not None

    def close(self) -> None:
        if self._unsubscribe:
            self._unsubscribe()
        if self._worker is not None:
            while True:  # the stop mark goes in even when the queue is full: the oldest waiting report gives way
                try:
                    self._queue.put_nowait(None)
                    break
                except queue.Full:
                    with contextlib.suppress(queue.Empty):
                        self._queue.get_nowait()
            self._worker.join(timeout=5.0)
            if self._worker.is_alive():
                log.warning("aspn gateway: the worker did not stop within 5 s (LCM publish blocked)")
            self._worker = None
        self.lcm = None  # LCM closes its sockets or log file when the object goes

    def state(self) -> GatewayState:
        with self._lock:
            out = self.stats.state()
            if self.encoder is not None:
                out["counters"].update({f"left out: {why}": n for why, n in self.encoder.skipped.items()})
        return out

    def on_message(self, message: Mapping[str, Any]) -> None:
        """On the event loop: queue the report for the worker, or drop and count it when the queue is full."""
        if message.get("type") != "report" or message.get("topic") not in TOPICS or self.lcm is None:
            return
        try:
            self._queue.put_nowait((message, int(time.time() * 1e6)))
        except queue.Full:
            with self._lock:
                self.stats.count("dropped: queue full")

    def _work(self) -> None:
        while (item := self._queue.get()) is not None:
            try:
                self._handle(*item)
            except Exception as e:  # the worker outlives any one report
                with self._lock:
                    self.stats.error(f"worker: {e!r}")

    def _handle(self, message: Mapping[str, Any], now_us: int) -> None:
        from sem_console.gateways.aspn.encode import encode

        envelope = message["report"]
        vehicle = uuid.UUID(message["providerId"])
        assert self.encoder is not None  # the worker runs only with an LCM URL
        try:
            with self._lock:
                if message["topic"] == "GPSFixReport":
                    measurements = self.encoder.fix_report(vehicle, envelope["report"], envelope["invalid"])
                else:
                    measurements = self.encoder.gps_report(vehicle, envelope["report"], envelope["invalid"])
        except Exception as e:  # a report we cannot map costs only itself
            with self._lock:
                self.stats.error(f"could not map a {message['topic']} of {vehicle}: {e!r}")
            return
        for measurement, msg in measurements:
            channel = f"{self.prefix}/{channel_vehicle(vehicle)}/{measurement}"
            try:
                data = encode(measurement, msg)
            except Exception as e:
                with self._lock:
                    self.stats.error(f"could not encode {channel}: {e!r}")
                continue
            with self._lock:
                self._record(vehicle, now_us, channel, data)
            lcm_ = self.lcm
            if lcm_ is None:
                return
            try:
                lcm_.publish(channel, data)
            except Exception as e:  # e.g. the network is unreachable: shown, and the next message tries again
                with self._lock:
                    self.stats.error(f"publish on {channel}: {e}")
                continue
            with self._lock:
                self.stats.sent()

    def _record(self, vehicle: uuid.UUID, utime: int, channel: str, data: bytes) -> None:
        """Keep the message (caller holds the lock); forget what is older than the window or over
        MAX_LOG_BYTES, and every vehicle quiet for longer than the window."""
        rec = self.recordings.setdefault(vehicle, Recording())
        rec.events.append((utime, rec.channels.setdefault(channel, channel), data))
        rec.size += len(data) + EVENT_OVERHEAD
        oldest = utime - int(self.log_seconds * 1e6)
        while rec.events and (rec.events[0][0] < oldest or rec.size > MAX_LOG_BYTES):
            rec.size -= len(rec.events.popleft()[2]) + EVENT_OVERHEAD
        for other in [v for v, r in self.recordings.items() if not r.events or r.events[-1][0] < oldest]:
            del self.recordings[other]  # it left (or went quiet): nothing of it is inside the window any more

    def events(
        self, vehicle: uuid.UUID, since: float | None = None, seconds: float | None = None
    ) -> list[tuple[int, str, bytes]]:
        """The vehicle's kept messages from UTC `since` (seconds) and/or of the last `seconds`, oldest first."""
        with self._lock:
            rec = self.recordings.get(vehicle)
            if rec is None:
                return []
            kept = list(rec.events)
        start = 0
        if since is not None:
            start = int(since * 1e6)
        if seconds is not None:
            start = max(start, int((time.time() - seconds) * 1e6))
        return [e for e in kept if e[0] >= start]
