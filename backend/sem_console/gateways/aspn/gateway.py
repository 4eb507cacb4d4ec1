"""The ASPN gateway: the console's feed in, ASPN-23 messages out on LCM channels <prefix>/<vehicle>/<measurement>.

It also keeps each vehicle's last `log_seconds` of messages (at most `MAX_LOG_BYTES` each), from which
`GET /api/providers/{id}/aspn-log` writes an LCM log file with LCM's own `EventLog`.
"""

from __future__ import annotations

import os
import tempfile
import time
import uuid
from collections import deque
from dataclasses import dataclass, field
from typing import Any

import lcm

from sem_console.console.feed import Feed
from sem_console.gateways import Stats
from sem_console.gateways.aspn.encode import Encoder, encode

MAX_LOG_BYTES = 8 * 1024 * 1024
TOPICS = ("GPSFixReport", "GPSReport")


def lcm_url(url: str) -> str:
    """A file:// URL without a mode writes the log (LCM's file provider would read it)."""
    if url.startswith("file://") and "mode=" not in url:
        return url + ("&" if "?" in url else "?") + "mode=w"
    return url


def open_lcm(url: str) -> lcm.LCM:
    """LCM on `url`; RuntimeError when LCM cannot open it (unknown provider, a file that cannot be written)."""
    return lcm.LCM(lcm_url(url))


@dataclass
class Recording:
    events: deque[tuple[int, str, bytes]] = field(default_factory=deque)  # (UTC microseconds, channel, LCM bytes)
    size: int = 0


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
    def __init__(self, feed: Feed, url: str | None, prefix: str = "aspn23", log_seconds: float = 300.0) -> None:
        self.prefix, self.log_seconds = prefix, log_seconds
        self.stats = Stats("aspn", url is not None, f"{url} ({prefix}/<vehicle>/<measurement>)" if url else None)
        self.encoder = Encoder()
        self.recordings: dict[uuid.UUID, Recording] = {}
        self.lcm: lcm.LCM | None = None
        self._unsubscribe = None
        if url is not None:
            self.lcm = open_lcm(url)
            self._unsubscribe = feed.subscribe("aspn", self.on_message)

    @property
    def enabled(self) -> bool:
        return self.lcm is not None

    def close(self) -> None:
        if self._unsubscribe:
            self._unsubscribe()
        self.lcm = None  # LCM closes its sockets or log file when the object goes

    def state(self) -> dict[str, Any]:
        out = self.stats.state()
        out["counters"].update({f"left out: {why}": n for why, n in self.encoder.skipped.items()})
        return out

    def on_message(self, message: dict[str, Any]) -> None:
        if message.get("type") != "report" or message.get("topic") not in TOPICS or self.lcm is None:
            return
        envelope = message["report"]
        vehicle = uuid.UUID(message["providerId"])
        try:
            if message["topic"] == "GPSFixReport":
                measurements = self.encoder.fix_report(vehicle, envelope["report"], envelope["invalid"])
            else:
                measurements = self.encoder.gps_report(vehicle, envelope["report"], envelope["invalid"])
        except Exception as e:  # a report we cannot map costs only itself
            self.stats.error(f"could not map a {message['topic']} of {vehicle}: {e!r}")
            return
        now_us = int(time.time() * 1e6)
        for measurement, msg in measurements:
            channel = f"{self.prefix}/{vehicle}/{measurement}"
            try:
                data = encode(measurement, msg)
            except Exception as e:
                self.stats.error(f"could not encode {channel}: {e!r}")
                continue
            self._record(vehicle, now_us, channel, data)
            try:
                self.lcm.publish(channel, data)
            except Exception as e:  # e.g. the network is unreachable: shown, and the next message tries again
                self.stats.error(f"publish on {channel}: {e}")
                continue
            self.stats.sent()

    def _record(self, vehicle: uuid.UUID, utime: int, channel: str, data: bytes) -> None:
        rec = self.recordings.setdefault(vehicle, Recording())
        rec.events.append((utime, channel, data))
        rec.size += len(data)
        oldest = utime - int(self.log_seconds * 1e6)
        while rec.events and (rec.events[0][0] < oldest or rec.size > MAX_LOG_BYTES):
            rec.size -= len(rec.events.popleft()[2])

    def events(self, vehicle: uuid.UUID, since: float | None = None, seconds: float | None = None) -> list[tuple[int, str, bytes]]:
        """The vehicle's kept messages from UTC `since` (seconds) and/or of the last `seconds`, oldest first."""
        rec = self.recordings.get(vehicle)
        if rec is None:
            return []
        start = 0
        if since is not None:
            start = int(since * 1e6)
        if seconds is not None:
            start = max(start, int((time.time() - seconds) * 1e6))
        return [e for e in rec.events if e[0] >= start]
