"""The relays the console's vehicles come through (docs/relay.md#the-console-knows-the-hop).

A `sem-relay` of the operations side writes, once a second, a sample of the project's own topic (dds/hops.py) per relay
of the vehicles' side: its name, the vehicles it carries and the age of the last data over the link from it. The
console reads it (a listener that hands each sample to the loop), marks those vehicles "via relay ship-1" (their
lost-vehicle logic then counts from their own time stamps, `console/providers.py`, with how long each may be quiet by
the link's rate caps added to its comms-lost timeout), and a relay whose last data is older than the comms-lost
timeout (and its caps' quiet) is silent: one alarm for it, not one per vehicle (`console/alarms.py`)."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
import uuid
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from cyclonedds.core import Listener
from cyclonedds.sub import DataReader

from sem_console.dds import hops
from sem_console.dds.bus import Bus

log = logging.getLogger("sem-console.hops")


@dataclass
class Hop:
    """A relay of the vehicles' side, as its operations side's relay last said it."""

    relay: str
    vehicles: frozenset[uuid.UUID] = field(default_factory=frozenset)
    data_at: float | None = None  # UTC seconds (the console's clock) of the last data over the link from it; None: none
    quiet: Mapping[uuid.UUID, float] = field(default_factory=dict)  # s each vehicle may be quiet by the link's caps

    def age(self, wall: float) -> float | None:
        return None if self.data_at is None else max(0.0, wall - self.data_at)

    def silent(self, wall: float, after: float) -> bool:
        """Data came over its link once, and none for longer than `after` seconds (and the longest its vehicles may be
        quiet by its caps) since (never any: not silent)."""
        age = self.age(wall)
        return age is not None and age > after + max(self.quiet.values(), default=0.0)


class Hops:
    def __init__(self) -> None:
        self.by_relay: dict[str, Hop] = {}
        self.via: dict[uuid.UUID, str] = {}  # vehicle -> the relay that carries it
        self.writers: set[uuid.UUID] = set()  # the DDS participants of the operations side's relays
        self._warned: set[tuple[str, str]] = set()  # (relay, text) of a vehicle not a GUID: said once, not every second

    def seen(self, link: hops.RelayLink, received: float) -> set[uuid.UUID]:
        """A relay's sample, received at `received` (UTC seconds): the vehicles whose relay changed with it."""
        vehicles = set()
        for text in link.vehicles:
            try:
                vehicles.add(uuid.UUID(text))
            except ValueError:
                if (link.relay, text) not in self._warned:
                    self._warned.add((link.relay, text))
                    log.warning("relay %s names a vehicle that is not a GUID: %r", link.relay, text)
        data_at = None if link.ageMs < 0 else received - link.ageMs / 1000
        quiet = {}
        for text, ms in zip(link.vehicles, link.quietMs, strict=False):  # each vehicle's, in the same order
            with contextlib.suppress(ValueError):
                quiet[uuid.UUID(text)] = max(0, ms) / 1000
        self.by_relay[link.relay] = Hop(link.relay, frozenset(vehicles), data_at, quiet)
        changed = {v for v in vehicles if self.via.get(v) != link.relay}
        for v in changed:  # gone from the relay that carried it before (of which no more samples may come)
            old = self.via.get(v)
            before = None if old is None else self.by_relay.get(old)
            if before is not None:
                before.vehicles = before.vehicles - {v}
            self.via[v] = link.relay
        return changed

    def of(self, vehicle: uuid.UUID) -> Hop | None:
        relay = self.via.get(vehicle)
        return None if relay is None else self.by_relay.get(relay)


Links = list[tuple[hops.RelayLink, uuid.UUID | None]]  # each relay's sample, and the participant that wrote it


def listen(bus: Bus, loop: asyncio.AbstractEventLoop, on_links: Callable[[Links, float], None]) -> DataReader[Any]:
    """A reader of the relays' topic whose samples go to `on_links` on the loop, each with the DDS participant that
    wrote it (the operations side's relay, which writes the vehicles' samples too), with the time they came."""

    def writer(reader: DataReader[Any], sample: hops.RelayLink) -> uuid.UUID | None:
        data = reader.get_matched_publication_data(sample.sample_info.publication_handle)  # type: ignore[attr-defined]
        return None if data is None else data.participant_key

    def available(reader: DataReader[Any]) -> None:
        try:
            samples = [(s, writer(reader, s)) for s in reader.take(64) if isinstance(s, hops.RelayLink)]
        except Exception as e:  # Cyclone's listener thread: never raise there
            log.warning("could not read the relays' topic: %s", e)
            return
        if samples:
            with contextlib.suppress(RuntimeError):  # the loop closed under a listener still running: the console stopped
                loop.call_soon_threadsafe(on_links, samples, time.time())

    return hops.reader(bus.participant, Listener(on_data_available=available))


RELAY_GRACE = 2 * hops.PERIOD
"""Seconds a vehicle lost with its relay waits for the relay's alarm: what the console knows of the link's age is up
to one of the relay's samples old, and the relay's last data may have come just after the vehicle's."""


def relay_silent_after(comms_lost_timeout: float) -> float:
    """Seconds without data over a relay's link before it is silent: the console's comms-lost timeout, but at least
    three of the relay's samples (what a console knows of the link's age is up to one sample old)."""
    return max(comms_lost_timeout, 3 * hops.PERIOD)


def silent_relays(relays: Mapping[str, Hop], wall: float, after: float) -> list[Hop]:
    return [h for h in relays.values() if h.vehicles and h.silent(wall, after)]
