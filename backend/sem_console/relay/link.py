"""The thin link's rate caps: per report topic a minimum interval (or "on change"), the latest sample of each instance
kept between two sends. Plain Python: time is given, nothing here touches DDS or Zenoh."""

from __future__ import annotations

from collections import deque
from collections.abc import Hashable
from dataclasses import dataclass, field
from typing import Generic, TypeVar

ON_CHANGE = "change"
Cap = float | str  # seconds between two samples of an instance (0: none), or ON_CHANGE

# The named link classes: a cap per report topic (the type's name without "Type", both UMAA versions alike)
LINK_CLASSES: dict[str, dict[str, Cap]] = {
    "satellite": {
        "GPSReport": 60.0,
        "GlobalPoseReport": 5.0,
        "GPSFixReport": 5.0,
        "GPSFixStatusReport": 5.0,
        "InertialSensorReport": ON_CHANGE,
    },
    "lan": {},
}
# the fields of a capped report whose change goes at once, not at the next slot: a fix lost or regained is on the
# operator's screen within the link's delay (the rest of the report, its carrier-to-noise values, waits for the slot)
AT_ONCE_FIELDS: dict[str, tuple[str, ...]] = {"GPSFixStatusReport": ("fixValid", "navSolution", "timeOut")}
REPORT_NAMES = ("GPSReport", "GlobalPoseReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport")


def quiet_seconds(caps: dict[str, Cap], reports: tuple[str, ...]) -> float:
    """The longest a live vehicle reporting on `reports` (its version's report topics, short names) may be quiet over
    the link by these caps: the shortest periodic cap of them (0: one of them is not capped, and comes at the vehicle's
    own rate; on-change topics promise nothing, and count only when all are: 0). A console adds it to the vehicle's
    comms-lost timeout, so that the caps alone never make a relayed vehicle lost."""
    periodic = [float(c) for c in (caps.get(t, 0.0) for t in reports) if c != ON_CHANGE]
    return min(periodic, default=0.0)


def short_name(topic: str) -> str:
    """`UMAA::SEM::GPSStatus::GPSReportType` and `UMAA::SEM::GPSStatus::GPSReport` -> GPSReport."""
    return topic.rsplit("::", 1)[-1].removesuffix("Type")


def parse_caps(text: str) -> dict[str, Cap]:
    """`GPSReport=30,InertialSensorReport=change` -> {...}; a ValueError naming the bad item and the fix."""
    caps: dict[str, Cap] = {}
    for item in (x.strip() for x in text.split(",") if x.strip()):
        name, sep, value = item.partition("=")
        if not sep or name not in REPORT_NAMES:
            raise ValueError(f"{item!r}: give TOPIC=SECONDS or TOPIC=change, TOPIC one of {', '.join(REPORT_NAMES)}")
        if value == ON_CHANGE:
            caps[name] = ON_CHANGE
            continue
        try:
            seconds = float(value)
        except ValueError:
            seconds = -1.0
        if not 0 <= seconds <= 86400:
            raise ValueError(f"{item!r}: the cap is seconds 0..86400 or 'change'")
        caps[name] = seconds
    return caps


T = TypeVar("T")


@dataclass
class _Instance(Generic[T]):
    cap: float  # seconds between two sends (0.0 for an on-change topic)
    last_sent: float = float("-inf")
    pending: T | None = None
    fingerprint: Hashable = None  # the last sent's
    has_fingerprint: bool = False
    pending_fingerprint: Hashable = None


@dataclass
class Limiter(Generic[T]):
    """Which samples of capped topics go now, which wait (the latest of an instance replaces the one waiting)."""

    caps: dict[str, Cap]
    _instances: dict[Hashable, _Instance[T]] = field(default_factory=dict)
    conflated: int = 0  # samples replaced by a later one of their instance before they were sent
    unchanged: int = 0  # samples of an on-change topic not sent: the same as the last one sent

    def cap(self, topic: str) -> Cap:
        return self.caps.get(topic, 0.0)

    def offer(self, topic: str, instance: Hashable, item: T, now: float, fingerprint: Hashable = None) -> T | None:
        """The item to send now, or None: it waits for its instance's next slot (or, on change, is the same as the
        last one sent). A capped topic's item with a fingerprint (its AT_ONCE_FIELDS) other than the last sent's goes
        at once."""
        cap = self.cap(topic)
        if cap == 0.0:
            return item
        state = self._instances.get(instance)
        if state is None:
            state = self._instances[instance] = _Instance(cap if isinstance(cap, float) else 0.0)
        if cap == ON_CHANGE:
            if state.has_fingerprint and fingerprint == state.fingerprint:
                self.unchanged += 1
                return None
            state.fingerprint, state.has_fingerprint = fingerprint, True
            return item
        changed = fingerprint is not None and state.has_fingerprint and fingerprint != state.fingerprint
        if now - state.last_sent >= state.cap or changed:
            if state.pending is not None:
                self.conflated += 1
            state.last_sent, state.pending = now, None
            state.fingerprint, state.has_fingerprint = fingerprint, True
            return item
        if state.pending is not None:
            self.conflated += 1
        state.pending, state.pending_fingerprint = item, fingerprint
        return None

    def due(self, now: float) -> list[T]:
        """The waiting items whose slot has come."""
        out = []
        for state in self._instances.values():
            if state.pending is not None and now - state.last_sent >= state.cap:
                out.append(state.pending)
                state.pending, state.last_sent = None, now
                state.fingerprint, state.has_fingerprint = state.pending_fingerprint, True
        return out

    def take(self, instance: Hashable) -> T | None:
        """The item waiting for `instance`, now (before its dispose or unregistration goes), and its state forgotten."""
        state = self._instances.pop(instance, None)
        return None if state is None else state.pending


@dataclass
class _Sent(Generic[T]):
    items: deque[tuple[float, T]]  # (when sent, item), oldest first
    ended: float | None = None  # when its dispose or unregistration was sent


class SentLog(Generic[T]):
    """What was sent of each instance, to send again after an outage: every item of an instance whose history counts
    (a command's, its statuses', its ack's: at most `depth`), the latest of one whose does not (a report's); once an
    instance ended, only its end is sent again."""

    def __init__(self, depth: int) -> None:
        self.depth = depth
        self._instances: dict[Hashable, _Sent[T]] = {}

    def add(self, instance: Hashable, item: T, at: float, latest_only: bool, ends: bool) -> None:
        sent = self._instances.get(instance)
        if sent is None:
            sent = self._instances[instance] = _Sent(deque(maxlen=self.depth))
        if latest_only:
            sent.items.clear()
        sent.items.append((at, item))
        if ends:
            sent.ended = at

    def since(self, t: float) -> list[T]:
        """What was sent at `t` or later, each instance's in the order sent (an ended instance: its end only)."""
        return [
            item
            for sent in self._instances.values()
            for at, item in (sent.items if sent.ended is None else list(sent.items)[-1:])
            if at >= t
        ]

    def forget(self, ended_before: float) -> None:
        """Forget the instances that ended before then."""
        for instance in [i for i, s in self._instances.items() if s.ended is not None and s.ended < ended_before]:
            del self._instances[instance]

    def __len__(self) -> int:
        return len(self._instances)


class Held(Generic[T]):
    """The commands for vehicles not heard yet, held until a vehicle is: what a provider that starts later finds
    persisted on the bus (UMAA ICD 4.1.2.1), at most `depth` messages per vehicle, the oldest given up. An instance that
    ends while held (cancelled, cleaned up, or its consumer gone) is dropped whole: none of it went, and its command
    and dispose delivered late would start the command on the vehicle and cancel it."""

    def __init__(self, depth: int) -> None:
        self.depth = depth
        self._vehicles: dict[Hashable, deque[tuple[Hashable, T]]] = {}

    def hold(self, vehicle: Hashable, instance: Hashable, item: T, ends: bool) -> None:
        held = self._vehicles.get(vehicle)
        if ends:
            if held is not None:
                kept = [(i, x) for i, x in held if i != instance]
                held.clear()
                held.extend(kept)
            return
        if held is None:
            held = self._vehicles[vehicle] = deque(maxlen=self.depth)
        held.append((instance, item))

    def release(self, vehicle: Hashable) -> list[T]:
        """What is held for `vehicle`, in the order it came, no longer held."""
        return [item for _instance, item in self._vehicles.pop(vehicle, ())]

    def __len__(self) -> int:
        return sum(len(h) for h in self._vehicles.values())
