"""Gateways: the console's state out to neighbouring worlds, each in its own package (`aspn`, `jaus`, `foxglove`).

A gateway reads the console only through its feed (`sem_console.console.feed.Feed`): it never touches
DDS. Each is off unless its option is given; its state (on or off, messages out per second, last error,
its counters) is in `GET /api/gateways` and in the WebSocket `gateways` message.
"""

from __future__ import annotations

import functools
import logging
import math
import threading
import time
from collections import deque
from typing import Any

from sem_console.core.messages import GatewayState

log = logging.getLogger("sem-console.gateways")
RATE_WINDOW = 5.0  # seconds the messages-per-second figure averages over


@functools.lru_cache(maxsize=1024)
def _parts(path: str) -> tuple[str, ...]:
    """A dotted path's members (split once: a gateway reads the same few paths of every report)."""
    return tuple(path.split("."))


def number(report: dict[str, Any], invalid: list[str], path: str) -> float | None:
    """The finite number at `path` (dotted) of a report the console decoded, or None when it is absent, null, not a
    number or listed invalid."""
    if invalid and any(x.startswith(f"{path}:") or x.startswith(f"{path}.") for x in invalid):
        return None
    v: Any = report
    for part in _parts(path):
        v = v.get(part) if isinstance(v, dict) else None
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        return None
    return float(v)


class Stats:
    """What a gateway shows: on or off, where it sends, messages out and their rate, last error, counters. Counted on
    the event loop and on the ingest threads (the Foxglove gateway's raw channels): under a lock."""

    def __init__(self, name: str, enabled: bool, endpoint: str | None = None) -> None:
        self.name, self.enabled, self.endpoint = name, enabled, endpoint
        self.messages_out = 0
        self.counters: dict[str, int] = {}
        self.last_error: str | None = None
        self.last_error_at: float | None = None
        self._recent: deque[tuple[float, int]] = deque()  # (monotonic second, messages out in it)
        self.started = time.monotonic()
        self._lock = threading.Lock()

    def sent(self, n: int = 1) -> None:
        second = float(int(time.monotonic()))
        with self._lock:
            self.messages_out += n
            if self._recent and self._recent[-1][0] == second:
                self._recent[-1] = (second, self._recent[-1][1] + n)
            else:
                self._recent.append((second, n))

    def count(self, key: str, n: int = 1) -> None:
        with self._lock:
            self.counters[key] = self.counters.get(key, 0) + n

    def error(self, text: str) -> None:
        if text != self.last_error:
            log.warning("%s gateway: %s", self.name, text)
        self.last_error, self.last_error_at = text[:500], time.time()
        self.count("errors")

    def per_second(self, now: float | None = None) -> float:
        now = time.monotonic() if now is None else now
        with self._lock:
            while self._recent and self._recent[0][0] < now - RATE_WINDOW:
                self._recent.popleft()
            total = sum(n for _, n in self._recent)
        span = min(RATE_WINDOW, max(now - self.started, 1.0))
        return round(total / span, 1)

    def state(self) -> GatewayState:
        return {
            "name": self.name,
            "enabled": self.enabled,
            "endpoint": self.endpoint,
            "messagesOut": self.messages_out,
            "messagesPerSecond": self.per_second() if self.enabled else 0.0,
            "lastError": self.last_error,
            "lastErrorAt": self.last_error_at,
            "counters": self._counters(),
        }

    def _counters(self) -> dict[str, int]:
        with self._lock:
            return dict(self.counters)
