"""Which relay of the vehicles' side carries which vehicle: the vehicle's owner, where its commands go, and what the
operations side's consoles are told (docs/relay.md#the-console-knows-the-hop).

The vehicles' side holds a Zenoh liveliness token per vehicle it carries, `sem-relay-carries/<its name>/<its domain>/
<vehicle>/<quiet ms>`: nothing crosses the thin link for it once declared, and Zenoh declares it again when a link
comes back; it is undeclared once the vehicle has not been heard there for a while (it moved to another ship's network).
The operations side follows the tokens: a vehicle declared by one relay alone is that relay's (its owner), kept when
the relay's token goes (its link lost, or the relay stopped: its commands wait for it) but not when the relay undeclares
it while still there (the vehicle left it: a relay that alone declares it next owns it); a relay that declares a vehicle
another owns is refused, and a vehicle two relays declare when none owns it is owned by neither until one alone does.
It counts when each vehicle's data last came over the link, and writes once a second, for each relay of the vehicles'
side that owns vehicles, a sample of the project's DDS topic (dds/hops.py): the relay's name, its vehicles and the age
of the last data from it; its age grows when its link is lost, which is what a console calls a silent relay."""

from __future__ import annotations

import logging
import threading
import time
import uuid
from collections.abc import Callable
from typing import Any
from urllib.parse import quote, unquote

import zenoh

from sem_console.dds import hops
from sem_console.dds.bus import Bus

log = logging.getLogger("sem-relay")
CARRIES = "sem-relay-carries"
LIVELINESS = "sem-relay"  # the relays' own liveliness tokens (relay.py): `sem-relay/<side>/<name>/<session>`
RELAYS = f"{LIVELINESS}/vehicles"  # the vehicles' relays' ones
QUIET_MAX_MS = 86_400_000  # a token's quiet at most (a cap is a day at most, relay/link.py): a larger one is no token
LEFT_GRACE = 3.0  # s after a vehicle's token went: its relay's own token still there then, the vehicle left that relay
QUERY_SECONDS = 10.0  # how long the operations side's start waits for the router's list of the tokens declared
Origin = tuple[str, int]  # a vehicles' relay's name and its DDS domain


def carries_prefix(relay: str) -> str:
    """The key space of the tokens of a relay's vehicles (a relay's name in one chunk, whatever it holds)."""
    return f"{CARRIES}/{quote(relay, safe='')}"


def carries_key(relay: str, domain: int, vehicle: uuid.UUID, quiet_ms: int = 0) -> str:
    """A vehicle's token, with the longest its data may be quiet over the link by the relay's caps (`link.quiet_seconds`,
    ms)."""
    return f"{carries_prefix(relay)}/{domain}/{vehicle}/{quiet_ms}"


def parse_carries(text: str) -> tuple[Origin, uuid.UUID, int] | None:
    """A token's relay and domain, vehicle and quiet (ms; 0 in a token without it, of an earlier relay)."""
    parts = text.split("/")
    if len(parts) not in (4, 5) or parts[0] != CARRIES or not parts[2].isdigit():
        return None
    if len(parts) == 5 and not (parts[4].isdigit() and int(parts[4]) <= QUIET_MAX_MS):
        return None
    try:
        return (unquote(parts[1]), int(parts[2])), uuid.UUID(parts[3]), int(parts[4]) if len(parts) == 5 else 0
    except ValueError:
        return None


class Carried:
    """The vehicles' side: a token per vehicle this relay carries, declared at the vehicle's first sample and undeclared
    once the vehicle has not been heard on this relay's domain for `gone_after` seconds (`forget`: it moved to another
    ship's network, whose relay may then carry it); declared again when it is heard again."""

    def __init__(self, session: zenoh.Session, name: str, domain: int, gone_after: float = 600.0) -> None:
        self.session, self.name, self.domain, self.gone_after = session, name, domain, gone_after
        self.tokens: dict[uuid.UUID, Any] = {}
        self.heard: dict[uuid.UUID, float] = {}  # monotonic: each vehicle's last sample on this domain
        self._lock = threading.Lock()

    def saw(self, vehicle: uuid.UUID, quiet: float = 0.0, now: float | None = None) -> None:
        """`quiet`: the longest its data may be quiet over the link by this relay's caps, for its version's topics."""
        self.heard[vehicle] = time.monotonic() if now is None else now
        if vehicle in self.tokens:
            return
        with self._lock:
            if vehicle not in self.tokens:
                key = carries_key(self.name, self.domain, vehicle, round(quiet * 1000))
                self.tokens[vehicle] = self.session.liveliness().declare_token(key)

    def forget(self, now: float) -> list[uuid.UUID]:
        """Undeclare the tokens of the vehicles not heard for `gone_after` seconds; returns them."""
        with self._lock:
            gone = [v for v in self.tokens if now - self.heard.get(v, now) >= self.gone_after]
            for vehicle in gone:
                self.tokens.pop(vehicle).undeclare()
        for vehicle in gone:
            log.info(
                "vehicle %s not heard for %.0f s: no longer said to be carried here (another relay may carry it)",
                vehicle,
                self.gone_after,
            )
        return gone

    def close(self) -> None:
        with self._lock:
            for token in self.tokens.values():
                token.undeclare()
            self.tokens.clear()


class Hops:
    """The operations side: which relay owns each vehicle (its tokens), when its data last came, told to the consoles.
    `on_owned(vehicle, origin)` is called, outside this object's lock, when a vehicle gets its owner."""

    def __init__(self, session: zenoh.Session, bus: Bus, on_owned: Callable[[uuid.UUID, Origin], None]) -> None:
        self.on_owned = on_owned
        # the vehicles' relays whose own liveliness token is there (`sem-relay/vehicles/<name>/<session>`): a vehicle's
        # token gone while its relay's is there is a vehicle that left it, not a link lost
        self.alive: dict[str, set[str]] = {}
        self.leaving: dict[tuple[uuid.UUID, Origin], float] = {}  # a token gone, and when to look again (`release`)
        self.owner: dict[uuid.UUID, Origin] = {}
        self.claims: dict[uuid.UUID, set[Origin]] = {}  # the relays whose token for the vehicle is there
        self.heard: dict[uuid.UUID, float] = {}  # vehicle -> monotonic time of its last message over the link
        self.quiet: dict[tuple[uuid.UUID, Origin], int] = {}  # ms a vehicle may be quiet by the caps of a relay of it
        self._warned: set[tuple[uuid.UUID, frozenset[Origin]]] = set()
        self._ready = False  # the tokens declared before this relay started all read (a claim alone is then alone)
        self._lock = threading.Lock()
        self.writer = hops.writer(bus.participant)
        self.session = session
        self.subscriber = session.liveliness().declare_subscriber(f"{CARRIES}/**", self._carries)
        self.relays = session.liveliness().declare_subscriber(f"{RELAYS}/**", self._relay, history=True)

    def start(self) -> None:
        """The tokens declared already, read at once: a vehicle two relays say they carry is owned by neither."""
        for reply in self.session.liveliness().get(f"{CARRIES}/**", timeout=QUERY_SECONDS):
            if reply.ok is not None:
                self._carries(reply.ok)
        with self._lock:
            self._ready = True
            owned = [(v, o) for v in list(self.claims) if (o := self._decide(v)) is not None]
        for vehicle, origin in owned:
            self.on_owned(vehicle, origin)

    def owner_of(self, vehicle: uuid.UUID) -> Origin | None:
        with self._lock:
            return self.owner.get(vehicle)

    def _carries(self, sample: zenoh.Sample) -> None:
        found = parse_carries(str(sample.key_expr))
        if found is None:
            return
        origin, vehicle, quiet_ms = found
        with self._lock:
            claims = self.claims.setdefault(vehicle, set())
            if sample.kind == zenoh.SampleKind.PUT:
                claims.add(origin)
                self.quiet[vehicle, origin] = quiet_ms
                self.leaving.pop((vehicle, origin), None)
            else:
                # a token gone: its owner keeps the vehicle (its age grows: silent), unless its relay is still there a
                # moment later (`release`): the relay no longer carries it
                claims.discard(origin)
                if self.owner.get(vehicle) == origin:
                    self.leaving[vehicle, origin] = time.monotonic() + LEFT_GRACE
            owned = self._decide(vehicle) if self._ready else None
        if owned is not None:
            self.on_owned(vehicle, owned)

    def _decide(self, vehicle: uuid.UUID) -> Origin | None:
        """The vehicle's owner if it gets one now (this object's lock held); a claim refused is said once."""
        claims, owner = self.claims.get(vehicle, set()), self.owner.get(vehicle)
        if owner is None and len(claims) == 1:
            self.owner[vehicle] = owner = next(iter(claims))
            log.info("vehicle %s is carried by relay %s, domain %d: its commands go there", vehicle, *owner)
            return owner
        others = frozenset(claims - {owner} if owner is not None else claims)
        if others and (len(others) > 1 or owner is not None) and (vehicle, others) not in self._warned:
            self._warned.add((vehicle, others))
            names = ", ".join(f"relay {r}, domain {d}" for r, d in sorted(others))
            if owner is not None:
                log.warning(
                    "vehicle %s is carried by relay %s, domain %d: %s also says it carries it; refused (its samples are "
                    "not written, its commands not sent there)",
                    vehicle,
                    *owner,
                    names,
                )
            else:
                log.warning(
                    "vehicle %s is said to be carried by %s: its commands wait, and its samples are not written, until "
                    "one relay alone says so",
                    vehicle,
                    names,
                )
        return None

    def _relay(self, sample: zenoh.Sample) -> None:
        parts = str(sample.key_expr).split("/")
        if len(parts) < 4:
            return
        with self._lock:
            sessions = self.alive.setdefault(parts[2], set())
            if sample.kind == zenoh.SampleKind.PUT:
                sessions.add(parts[3])
            else:
                sessions.discard(parts[3])

    def release(self, now: float) -> None:
        """The vehicles whose owner undeclared their token while it is still there (LEFT_GRACE later: a link lost takes
        the relay's own token as well) are no longer its: a relay that alone declares one now owns it."""
        owned: list[tuple[uuid.UUID, Origin]] = []
        with self._lock:
            for (vehicle, origin), at in list(self.leaving.items()):
                if now < at:
                    continue
                del self.leaving[vehicle, origin]
                if self.owner.get(vehicle) != origin or origin in self.claims.get(vehicle, ()) or not self.alive.get(origin[0]):
                    continue
                del self.owner[vehicle]
                log.info(
                    "vehicle %s is no longer carried by relay %s, domain %d: its commands wait for its next relay",
                    vehicle,
                    *origin,
                )
                if (new := self._decide(vehicle)) is not None:
                    owned.append((vehicle, new))
        for vehicle, origin in owned:
            self.on_owned(vehicle, origin)

    def heard_from(self, vehicle: uuid.UUID, now: float) -> None:
        with self._lock:
            self.heard[vehicle] = now

    def links(self, now: float) -> list[hops.RelayLink]:
        """One sample per relay: its vehicles, the age of the last data from any of them (NEVER: none yet) and how long
        each may be quiet by the caps."""
        with self._lock:
            relays: dict[str, list[tuple[uuid.UUID, Origin]]] = {}
            for vehicle, origin in self.owner.items():
                relays.setdefault(origin[0], []).append((vehicle, origin))
            out = []
            for relay, owned in sorted(relays.items()):
                owned.sort(key=lambda vo: vo[0])
                last = max((self.heard[v] for v, _o in owned if v in self.heard), default=None)
                age = hops.NEVER if last is None else round((now - last) * 1000)
                quiet = [self.quiet.get((v, o), 0) for v, o in owned]
                out.append(hops.RelayLink(relay, [str(v) for v, _o in owned], age, quiet))
            return out

    def write(self, now: float | None = None) -> None:
        now = time.monotonic() if now is None else now
        self.release(now)
        for link in self.links(now):
            try:
                self.writer.write(link)
            except Exception as e:  # the consoles miss one second of it; the relay's timer goes on
                log.warning("could not write relay %s's link to the consoles: %s", link.relay, e)

    def close(self) -> None:
        self.subscriber.undeclare()
        self.relays.undeclare()
