"""The console's state as an in-process feed: the one interface the gateways (ASPN, JAUS) read it through.

Every message the console hands its WebSocket clients (`report`, `provider`, `command`, `transition`;
see /api/ws-schema) is also delivered, unconflated and in order, to each subscriber's callback on the
event loop thread. A subscriber never sees DDS, and a subscriber that raises costs only itself: the
error is logged and counted, the console and the other subscribers go on.

The feed is also the ingest's `Tap`: every sample the console takes, raw (its CDR as it came off the wire), goes to
each tap (`tap`: the recorder, the Foxglove gateway's raw channels) that is active, on the ingest threads, before it
is decoded. A tap must return at once; one that raises costs only itself, as above.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING

from sem_console.core.messages import ServerMessage

if TYPE_CHECKING:
    from sem_console.console.ingest import Tap
    from sem_console.dds.topics import AnySem

log = logging.getLogger("sem-console.feed")
Subscriber = Callable[[ServerMessage], None]


class Feed:
    def __init__(self) -> None:
        self._subscribers: dict[int, tuple[str, Subscriber]] = {}
        self._next = 0
        self.errors: dict[str, int] = {}
        self._taps: dict[int, tuple[str, Tap]] = {}

    def subscribe(self, name: str, callback: Subscriber) -> Callable[[], None]:
        """Deliver every later message to `callback`; returns the function that ends the subscription."""
        key = self._next
        self._next += 1
        self._subscribers[key] = (name, callback)
        return lambda: self._subscribers.pop(key, None) and None

    def tap(self, name: str, tap: Tap) -> Callable[[], None]:
        """Hand every later raw sample to `tap` while it is active; returns the function that ends it."""
        key = self._next
        self._next += 1
        self._taps[key] = (name, tap)
        return lambda: self._taps.pop(key, None) and None

    @property
    def active(self) -> bool:
        """Whether a tap wants raw samples now (read by the ingest before each take)."""
        return any(tap.active for _name, tap in self._taps.values())

    def on_samples(self, sem: AnySem, samples: list[tuple[bytes, bool, int, int]], received_ns: int) -> None:
        """One take of a topic (`ingest.Tap`), to every active tap."""
        for name, tap in list(self._taps.values()):
            if not tap.active:
                continue
            try:
                tap.on_samples(sem, samples, received_ns)
            except Exception:
                self.errors[name] = self.errors.get(name, 0) + 1
                log.exception("feed tap %s failed on a take of %s", name, sem.spec.name)

    def publish(self, message: ServerMessage) -> None:
        for name, callback in list(self._subscribers.values()):
            try:
                callback(message)
            except Exception:
                self.errors[name] = self.errors.get(name, 0) + 1
                log.exception("feed subscriber %s failed on a %s message", name, message["type"])
