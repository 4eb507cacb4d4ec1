"""Providers seen on the bus, their latest reports, and link health (JAUS ReportCommsLostConfiguration semantics).

A provider is `lost` after its comms-lost timeout without any sample (or at once when all
its report instances lose their writers or are disposed), and `regained` only after samples
have kept arriving, with no gap longer than the comms-lost timeout, for its regained time.
It shows `regained` for one regained time, then `live`. Both thresholds are per vehicle
(`LinkConfig`, default from the console's settings), with the comms-lost policy and
regained behaviour the vehicle is recorded to follow (reported, never enforced, by the console).

A vehicle seen through a relay (`relay`: console/hops.py) is silent by its own time stamps, not by arrival: a relay
that holds samples through an outage and releases them late must not make a lost vehicle look live. Its clock need
not agree with the console's: its newest time stamp is moved to the console's clock by the least lag (receipt minus
time stamp) its reports have had; a time stamp ahead of its receipt (a clock ahead, or a bad one) makes it silent from
arrival until its time stamps can be read again. The longest its relay's rate caps keep its data quiet is added to
its comms-lost timeout: the caps alone never make it lost.
"""

from __future__ import annotations

import time
import uuid
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from sem_console.codec.decode import REPORT_HEALTH_TOPICS, REPORT_TOPICS
from sem_console.core import messages
from sem_console.core.contract import LinkConfig
from sem_console.core.messages import ProviderEvent
from sem_console.versions import UMAA_3_0_1, UmaaVersion

REPORTS = tuple(REPORT_TOPICS.values())  # the model's report topics (core/contract.ReportTopic)
MAX_JAUS_COMPONENT = 254  # component ids are a u8; 255 is JAUS's broadcast
STAMP_AHEAD = 1.0  # s a report's own time stamp may be ahead of its receipt (clocks a little apart); more: not read


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
    config: LinkConfig
    name: str | None = None
    ordinal: int = 0  # 1-based order of appearance, kept for the console's lifetime
    jaus_subsystem: int | None = None
    reports: dict[str, messages.ReportEnvelope] = field(default_factory=dict)
    health: dict[str, TopicHealth] = field(default_factory=dict)
    link: str = "live"  # live | lost | regained
    regaining_since: float | None = None
    regained_at: float | None = None
    umaa_version: UmaaVersion = UMAA_3_0_1  # of the report topics its samples come on
    parent: uuid.UUID | None = None  # the parent its source says it has (UMAA 6.0): a command's destination carries it
    version_changed: bool = False  # its version changed on the last sample: the stations must be told (Console)
    relay: str | None = None  # the relay it is seen through (console/hops.py), None: on this domain itself
    writer: uuid.UUID | None = None  # the DDS participant that wrote its latest report (a relay's, or another's)
    direct: tuple[uuid.UUID, float] | None = None  # the writer and time (monotonic) of its latest report not a relay's
    stamp: float | None = None  # UTC seconds: the newest of its reports' own time stamps (timeStamp)
    lag: float | None = None  # the least receipt (console's clock) minus own time stamp: its clock's offset, the link's
    quiet: float = 0.0  # s its data may be quiet by the rate caps of the relay it is seen through (console/hops.py)

    def lost_after(self) -> float:
        """Seconds of silence before it is lost: its comms-lost timeout, and seen through a relay, the longest the
        relay's rate caps may keep its data quiet (at the satellite caps a fix every 5 s: lost after 3 + 5 s)."""
        return self.config.commsLostTimeout + (self.quiet if self.relay is not None else 0.0)

    def data_at(self) -> float | None:
        """When its newest data was made, on the console's clock (UTC seconds): its newest time stamp moved by the
        least lag seen, so that a vehicle's clock behind or ahead of the console's counts no silence of its own."""
        return None if self.stamp is None or self.lag is None else self.stamp + self.lag

    def silent_for(self, now: float, wall: float) -> float:
        """Seconds it has been silent: since its newest report's own time stamp when seen through a relay (once it
        has one), else since its last sample arrived."""
        made = self.data_at()
        if self.relay is not None and made is not None:
            return wall - made
        return now - self.last_seen()

    def last_seen(self) -> float:
        return max((h.last_seen for h in self.health.values()), default=self.first_seen)

    def summary(self, now: float, wall: float | None = None) -> messages.ProviderSummary:
        """`now`: monotonic seconds; `wall`: UTC seconds, for the relay's age (None: time.time())."""
        return {
            "id": str(self.id),
            "name": self.name,
            "link": self.link,
            "umaaVersion": self.umaa_version,
            "linkConfig": self.config.to_json(),
            "jausId": self.jaus_id(),
            "ageSeconds": round(now - self.last_seen(), 3),
            "topics": {
                name: {
                    "ageSeconds": round(now - h.last_seen, 3),
                    "samples": h.samples,
                    "alive": h.alive,
                    "receivedAt": h.received_at,
                }
                for name, h in self.health.items()
            },
            "relay": None if self.relay is None else self.hop(time.time() if wall is None else wall),
        }

    def hop(self, wall: float) -> messages.RelayHop:
        return {
            "name": self.relay or "",
            "dataTime": self.stamp,
            "ageSeconds": None if self.stamp is None else round(max(0.0, wall - self.stamp), 3),
            "quietSeconds": self.quiet,
        }

    def jaus_id(self) -> str | None:
        """ "S.1.C": subsystem S, node 1, component C (the order of appearance), when the JAUS gateway is on."""
        if self.jaus_subsystem is None or not 0 < self.ordinal <= MAX_JAUS_COMPONENT:
            return None
        return f"{self.jaus_subsystem}.1.{self.ordinal}"


@dataclass
class Providers:
    comms_lost_timeout: float
    regained_time: float
    names: dict[str, str] = field(default_factory=dict)  # GUID string -> configured name
    configs: dict[str, LinkConfig] = field(default_factory=dict)  # GUID string -> stored per-vehicle config
    jaus_subsystem: int | None = None
    by_id: dict[uuid.UUID, Provider] = field(default_factory=dict)

    def default_config(self) -> LinkConfig:
        """The console's own thresholds (Settings, checked there: they may be shorter than an operator may set)."""
        return LinkConfig.model_construct(
            commsLostTimeout=self.comms_lost_timeout, regainedTime=self.regained_time, policy="STOP_MISSION", regainedBehavior=0
        )

    def seen(
        self,
        topic: str,
        source: uuid.UUID,
        report: messages.ReportEnvelope | None,
        now: float,
        wall: float,
        alive: bool,
        version: UmaaVersion | None = None,
        parent: uuid.UUID | None = None,
    ) -> tuple[Provider, bool]:
        """Record a sample on `topic`; `report` None with alive False: the instance ended
        (disposed, or no writers). `version`: the UMAA version of the topic (a report, a command status or an ack).
        Returns (provider, whether it is new)."""
        p = self.by_id.get(source)
        new = p is None
        if p is None:
            key = str(source)
            p = self.by_id[source] = Provider(
                source,
                now,
                self.configs.get(key) or self.default_config(),
                self.names.get(key),
                len(self.by_id) + 1,
                self.jaus_subsystem,
            )
        if version is not None and version != p.umaa_version:
            p.umaa_version = version
            p.version_changed = not new
        if parent is not None:
            p.parent = parent
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
            stamp = report_stamp(report.get("report") or {})
            if stamp is not None and stamp > wall + STAMP_AHEAD:  # its clock ahead (now): silent from arrival
                p.stamp = p.lag = None
            elif stamp is not None:
                p.lag = wall - stamp if p.lag is None else min(p.lag, wall - stamp)
                p.stamp = stamp if p.stamp is None else max(p.stamp, stamp)
        if p.link == "lost" and (p.regaining_since is None or gap > p.lost_after()):
            p.regaining_since = now
        return p, new

    def tick(self, now: float, wall: float | None = None, behind_by: float | None = None) -> list[tuple[Provider, ProviderEvent]]:
        """Advance link states at `now` (monotonic) and `wall` (UTC seconds, for the vehicles seen through a relay;
        None: time.time()); returns (provider, 'lost' | 'regained' | 'live' | 'unchecked') events. `behind_by`: while
        the console is behind, how much silence its own delays may explain (console/load.py, `Load.excuse`): a
        vehicle silent past its timeout by no more than that is `unchecked`, not lost, until it is heard or the console
        keeps up; silent past it by more, its silence is its own and it is lost whatever the console's load (as a
        writer gone or a disposed instance, which DDS says)."""
        events: list[tuple[Provider, ProviderEvent]] = []
        wall = time.time() if wall is None else wall
        for p in self.by_id.values():
            lost_after, regain_after = p.lost_after(), p.config.regainedTime
            silence = p.silent_for(now, wall)
            silent = silence > lost_after
            excused = behind_by is not None and silence <= lost_after + behind_by
            reports = [h for t, h in p.health.items() if t in REPORT_HEALTH_TOPICS]
            gone = bool(reports) and not any(h.alive for h in reports)
            if p.link in ("live", "regained") and silent and not gone and excused:
                p.link = "unchecked"
                events.append((p, "unchecked"))
            elif p.link == "unchecked" and not silent and not gone:
                p.link = "live"  # heard again: its silence was the console's
                events.append((p, "live"))
            elif p.link == "unchecked" and not gone and excused:
                continue
            elif p.link != "lost" and (silent or gone):
                p.link, p.regaining_since = "lost", None
                events.append((p, "lost"))
            elif p.link == "lost":
                if silent or gone:
                    p.regaining_since = None
                elif p.regaining_since is not None and now - p.regaining_since >= regain_after:
                    p.link, p.regained_at, p.regaining_since = "regained", now, None
                    events.append((p, "regained"))
            elif p.link == "regained" and p.regained_at is not None and now - p.regained_at >= regain_after:
                p.link = "live"
                events.append((p, "live"))
        return events


def report_stamp(report: Mapping[str, Any]) -> float | None:
    """A report's own time stamp (its `timeStamp`, UTC seconds), None when it has none the console can read."""
    ts = report.get("timeStamp")
    if not isinstance(ts, Mapping):
        return None
    seconds, nanoseconds = ts.get("seconds"), ts.get("nanoseconds", 0)
    if not isinstance(seconds, (int, float)) or not isinstance(nanoseconds, (int, float)):
        return None
    return seconds + nanoseconds / 1e9
