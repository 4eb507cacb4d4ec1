"""The console's state as an in-process feed: the one interface the gateways (ASPN, JAUS) read it through.

Every message the console hands its WebSocket clients (`report`, `provider`, `command`, `transition`;
see /api/ws-schema) is also delivered, unconflated and in order, to each subscriber's callback on the
event loop thread. A subscriber never sees DDS, and a subscriber that raises costs only itself: the
error is logged and counted, the console and the other subscribers go on.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from sem_console.core.messages import ServerMessage

log = logging.getLogger("sem-console.feed")
Subscriber = Callable[[ServerMessage], None]


class Feed:
    def __init__(self) -> None:
        self._subscribers: dict[int, tuple[str, Subscriber]] = {}
        self._next = 0
        self.errors: dict[str, int] = {}

    def subscribe(self, name: str, callback: Subscriber) -> Callable[[], None]:
        """Deliver every later message to `callback`; returns the function that ends the subscription."""
        key = self._next
        self._next += 1
        self._subscribers[key] = (name, callback)
        return lambda: self._subscribers.pop(key, None) and None

    def publish(self, message: ServerMessage) -> None:
        for name, callback in list(self._subscribers.values()):
            try:
                callback(message)
            except Exception:
                self.errors[name] = self.errors.get(name, 0) + 1
                log.exception("feed subscriber %s failed on a %s message", name, message["type"])
