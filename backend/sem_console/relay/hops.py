"""Which relay of the vehicles' side carries which vehicle, told to the operations side's consoles
(docs/relay.md#the-console-knows-the-hop).

The vehicles' side holds a Zenoh liveliness token per vehicle it carries, `sem-relay-carries/<its name>/<vehicle>`:
nothing crosses the thin link for it once declared, and Zenoh declares it again when a link comes back. The operations
side follows the tokens, counts when each vehicle's data last came over the link, and writes once a second, for each
relay of the vehicles' side it heard, a sample of the project's DDS topic (dds/hops.py): the relay's name, its vehicles
and the age of the last data from it. A relay whose tokens went (its link lost, or the relay stopped) keeps its
vehicles: its age grows, which is what a console calls a silent relay."""

from __future__ import annotations

import logging
import threading
import time
import uuid
from typing import Any
from urllib.parse import quote, unquote

import zenoh

from sem_console.dds import hops
from sem_console.dds.bus import Bus

log = logging.getLogger("sem-relay")
CARRIES = "sem-relay-carries"


def carries_key(relay: str, vehicle: uuid.UUID) -> str:
    return f"{CARRIES}/{quote(relay, safe='')}/{vehicle}"  # a relay's name in one chunk of the key, whatever it holds


def parse_carries(text: str) -> tuple[str, uuid.UUID] | None:
    parts = text.split("/")
    if len(parts) != 3 or parts[0] != CARRIES:
        return None
    try:
        return unquote(parts[1]), uuid.UUID(parts[2])
    except ValueError:
        return None


class Carried:
    """The vehicles' side: a token per vehicle this relay carries, declared at the vehicle's first sample."""

    def __init__(self, session: zenoh.Session, name: str) -> None:
        self.session, self.name = session, name
        self.tokens: dict[uuid.UUID, Any] = {}
        self._lock = threading.Lock()

    def saw(self, vehicle: uuid.UUID) -> None:
        if vehicle in self.tokens:
            return
        with self._lock:
            if vehicle not in self.tokens:
                self.tokens[vehicle] = self.session.liveliness().declare_token(carries_key(self.name, vehicle))

    def close(self) -> None:
        with self._lock:
            for token in self.tokens.values():
                token.undeclare()
            self.tokens.clear()


class Hops:
    """The operations side: which relay carries each vehicle, when its data last came, written to the consoles."""

    def __init__(self, session: zenoh.Session, bus: Bus) -> None:
        self.carrier: dict[uuid.UUID, str] = {}
        self.heard: dict[uuid.UUID, float] = {}  # vehicle -> monotonic time of its last message over the link
        self._lock = threading.Lock()
        self.writer = hops.writer(bus.participant)
        self.subscriber = session.liveliness().declare_subscriber(f"{CARRIES}/**", self._carries, history=True)

    def _carries(self, sample: zenoh.Sample) -> None:
        found = parse_carries(str(sample.key_expr))
        if found is None or sample.kind != zenoh.SampleKind.PUT:
            return  # a token gone: the relay keeps its vehicles (its age grows: silent)
        relay, vehicle = found
        with self._lock:
            before = self.carrier.get(vehicle)
            self.carrier[vehicle] = relay
        if before != relay:
            log.info("vehicle %s is carried by relay %s", vehicle, relay)

    def heard_from(self, vehicle: uuid.UUID, now: float) -> None:
        with self._lock:
            self.heard[vehicle] = now

    def links(self, now: float) -> list[hops.RelayLink]:
        """One sample per relay: its vehicles, and the age of the last data from any of them (NEVER: none yet)."""
        with self._lock:
            relays: dict[str, list[uuid.UUID]] = {}
            for vehicle, relay in self.carrier.items():
                relays.setdefault(relay, []).append(vehicle)
            out = []
            for relay, vehicles in sorted(relays.items()):
                last = max((self.heard[v] for v in vehicles if v in self.heard), default=None)
                age = hops.NEVER if last is None else round((now - last) * 1000)
                out.append(hops.RelayLink(relay, [str(v) for v in sorted(vehicles)], age))
            return out

    def write(self, now: float | None = None) -> None:
        for link in self.links(time.monotonic() if now is None else now):
            try:
                self.writer.write(link)
            except Exception as e:  # the consoles miss one second of it; the relay's timer goes on
                log.warning("could not write relay %s's link to the consoles: %s", link.relay, e)

    def close(self) -> None:
        self.subscriber.undeclare()
