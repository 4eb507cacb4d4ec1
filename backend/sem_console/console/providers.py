"""Providers seen on the bus, their latest reports, and link health (JAUS ReportCommsLostConfiguration semantics).

A provider is `lost` after `comms_lost_timeout` seconds without any sample (or at once
when all its report instances lose their writers or are disposed), and `regained` only
after samples have kept arriving, with no gap longer than the comms-lost timeout, for
`regained_time` seconds. It shows `regained` for one regained time, then `live`.
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass, field
from typing import Any

REPORTS = ("GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport")


@dataclass
class TopicHealth:
    last_seen: float  # monotonic
    received_at: float  # wall clock, for display
    samples: int = 0
    alive: bool = True


@dataclass
class Provider:
    id: uuid.UUID
    first_seen: float
    name: str | None = None
    reports: dict[str, dict[str, Any]] = field(default_factory=dict)
    health: dict[str, TopicHealth] = field(default_factory=dict)
    link: str = "live"  # live | lost | regained
    regaining_since: float | None = None
    regained_at: float | None = None

    def last_seen(self) -> float:
        return max((h.last_seen for h in self.health.values()), default=self.first_seen)

    def summary(self, now: float) -> dict[str, Any]:
        return {
            "id": str(self.id),
            "name": self.name,
            "link": self.link,
            "ageSeconds": round(now - self.last_seen(), 3),
            "topics": {name: {"ageSeconds": round(now - h.last_seen, 3), "samples": h.samples, "alive": h.alive,
                              "receivedAt": h.received_at} for name, h in self.health.items()},
        }


@dataclass
class Providers:
    comms_lost_timeout: float
    regained_time: float
    names: dict[str, str] = field(default_factory=dict)  # GUID string -> configured name
    by_id: dict[uuid.UUID, Provider] = field(default_factory=dict)

    def seen(self, topic: str, source: uuid.UUID, report: dict[str, Any] | None, now: float, wall: float,
             alive: bool) -> tuple[Provider, bool]:
        """Record a sample on `topic`; `report` None with alive False: the instance ended
        (disposed, or no writers). Returns (provider, whether it is new)."""
        new = source not in self.by_id
        p = self.by_id.get(source) or self.by_id.setdefault(source, Provider(source, now, self.names.get(str(source))))
        h = p.health.get(topic)
        if report is None and not alive:
            if h:
                h.alive = False
            return p, new
        gap = now - p.last_seen() if p.health else 0.0
        if h is None:
            h = p.health[topic] = TopicHealth(now, wall)
        h.last_seen, h.received_at, h.alive = now, wall, alive
        h.samples += 1
        if report is not None:
            p.reports[topic] = report
        if p.link == "lost" and (p.regaining_since is None or gap > self.comms_lost_timeout):
            p.regaining_since = now
        return p, new

    def tick(self, now: float) -> list[tuple[Provider, str]]:
        """Advance link states; returns (provider, 'lost' | 'regained' | 'live') events."""
        events: list[tuple[Provider, str]] = []
        for p in self.by_id.values():
            silent = now - p.last_seen() > self.comms_lost_timeout
            reports = [h for t, h in p.health.items() if t in REPORTS]
            gone = bool(reports) and not any(h.alive for h in reports)
            if p.link != "lost" and (silent or gone):
                p.link, p.regaining_since = "lost", None
                events.append((p, "lost"))
            elif p.link == "lost":
                if silent or gone:
                    p.regaining_since = None
                elif p.regaining_since is not None and now - p.regaining_since >= self.regained_time:
                    p.link, p.regained_at, p.regaining_since = "regained", now, None
                    events.append((p, "regained"))
            elif p.link == "regained" and p.regained_at is not None and now - p.regained_at >= self.regained_time:
                p.link = "live"
                events.append((p, "live"))
        return events
