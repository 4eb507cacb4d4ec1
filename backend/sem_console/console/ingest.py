"""DDS -> asyncio: two threads take SEM samples and hand them to the event loop.

- The status thread takes command status and ack samples as soon as they arrive, so
  every transition reaches the loop in order and none is lost.
- The report thread takes report samples as they arrive while input is sparse, and at most
  every `report_interval` seconds under load (`Pacer`: a burst of `report_burst` takes, then
  one per window). Report readers keep the latest sample per instance, so a provider
  publishing faster than that is conflated by DDS itself: the console's cost follows what it shows.

Samples are decoded and converted to JSON in these threads; the loop only applies them
(`loop.call_soon_threadsafe`), so DDS never blocks it. Disposes and lost writers are
read explicitly. A sample that cannot be decoded is counted, never raised.

Every topic is read by three readers, so that any writer is matched and a reliable one
loses nothing whatever its durability: reliable transient-local (also receives what a
writer published before the console started), reliable volatile (matches a reliable
volatile writer) and best-effort volatile (matches any writer with shared ownership in the
default partition and the type's data representation; see _on_incompatible). A writer's samples are
applied from exactly one of them, its owner: the most reliable reader its offered QoS
matches, decided from that QoS when a reader first matches the writer (`Owners`). The
copies the other readers receive are dropped undecoded. Nothing depends on timestamps
or payloads: equal, repeated or backward source timestamps are all applied, in order.
GPSReport and GPSFixReport have three more readers, of appendable copies of their types, for
RTI vehicles; a writer matches the readers of one extensibility only (Via.qos, docs/dds.md
"One reader per extensibility").

A `Tap` (the console's feed, for the recorder and the Foxglove gateway) gets every sample taken from its owner reader
as the raw CDR from the wire, before it is decoded; the command topics of both UMAA versions are read for it alone
(the console's own commands and any other consumer's), never decoded here, and the UMAA 6.0 status and ack topics for it
at least.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import time
import uuid
from collections.abc import Callable, Sequence
from enum import Enum
from typing import Any, Protocol

from cyclonedds.core import DDSException, Listener, Policy, Qos, WaitSet
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.util import duration

from sem_console.codec.decode import (
    ACK_TOPICS,
    COMMAND_TOPICS,
    REPORT_TOPICS,
    REPORT_TOPICS_6_0,
    STATUS_TOPICS,
    Decoder,
    Item,
    ReportItem,
    StatusItem,
)
from sem_console.console.pace import Pacer
from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.cyclone_private import Triggered, take_cdr
from sem_console.dds.qos import TopicClass, any_writer_reader_qos, reader_qos
from sem_console.dds.topics import AnySem, Sem60, final_type_qos
from sem_console.dds.vendors import Finding, PeerWatch

log = logging.getLogger("sem-console.ingest")
# The UMAA 6.0 command, status and ack topics: read for the recorder (Tap) whether or not the decoder follows them
COMMAND_FLOW_6_0 = [sem for sem in Sem60 if sem.spec.cls is not TopicClass.REPORT]
__all__ = ["REPORT_TOPICS", "Ingest", "ReportItem", "StatusItem", "Tap", "Via", "owner_of"]


class Tap(Protocol):
    """Where every sample the console takes goes too, raw (the recorder). Called on the ingest
    threads: it must return at once. `active` is read before each call."""

    @property
    def active(self) -> bool: ...

    def on_samples(self, sem: AnySem, samples: list[tuple[bytes, bool, int, int]], received_ns: int) -> None:
        """One take of a topic: (data, valid, instance state, source timestamp in ns) per sample, where data is
        the sample's CDR with its encapsulation header (only the key when not valid)."""


class Via(str, Enum):
    """The three readers of a topic, most reliable first."""

    RELIABLE_TRANSIENT_LOCAL = "reliableTransientLocal"
    RELIABLE_VOLATILE = "reliableVolatile"
    BEST_EFFORT = "bestEffort"

    def qos(self, sem: AnySem, appendable: bool = False) -> Qos:
        """The reader's QoS. A topic with an appendable copy (TopicSpec.appendable) is read by a reader of each type:
        the final one validates the writer's type (`force_type_validation`: a writer that sends no type information, as
        RTI on the recipe, is refused, not matched by name and misread), the appendable one matches by name."""
        qos = (
            any_writer_reader_qos(sem.spec.cls)
            if self is Via.BEST_EFFORT
            else reader_qos(sem.spec.cls, durable=self is Via.RELIABLE_TRANSIENT_LOCAL)
        )
        return qos if appendable else qos + final_type_qos(sem)


def owner_of(writer_qos: Qos) -> Via:
    """The most reliable of our readers that a writer offering `writer_qos` matches.

    Our three readers differ only in reliability and durability and accept any latency
    budget and data representation, so that is all that decides it: reliable and at
    least transient-local, reliable and volatile, or best-effort.
    """
    # (no .get(): Qos has `in` and [] only)
    reliability = writer_qos[Policy.Reliability] if Policy.Reliability in writer_qos else None  # noqa: SIM401
    durability = writer_qos[Policy.Durability] if Policy.Durability in writer_qos else Policy.Durability.Volatile  # noqa: SIM401
    if not isinstance(reliability, Policy.Reliability.Reliable):
        return Via.BEST_EFFORT
    return Via.RELIABLE_VOLATILE if durability == Policy.Durability.Volatile else Via.RELIABLE_TRANSIENT_LOCAL


_U64 = 0xFFFF_FFFF_FFFF_FFFF
# Cyclone's dds_qos_policy_id_t values a requested-incompatible-QoS status may name.
_POLICY_NAMES = {
    2: "Durability",
    3: "Presentation",
    4: "Deadline",
    5: "LatencyBudget",
    6: "Ownership",
    8: "Liveliness",
    11: "Reliability",
    12: "DestinationOrder",
    24: "TypeConsistencyEnforcement",
    25: "DataRepresentation",
}
_TYPE_CONSISTENCY = 24
FORGET_AFTER = 10.0  # s after a writer left every reader: its samples were taken long before
PEER_CHECK = 1.0  # s between looks at other vendors' participants in discovery (dds/vendors.py)


class Owners:
    """publication handle -> the reader that applies that writer's samples.

    Learnt in each reader's subscription-matched listener (Cyclone calls it as the match is
    made, before the writer's samples can be taken), from the writer's own QoS, so all three
    readers agree on it from the first sample, including those that arrive while discovery is
    still matching the writer to the other readers. An entry goes FORGET_AFTER seconds after
    the writer left.
    """

    def __init__(self) -> None:
        self.by_handle: dict[int, Via] = {}
        self.participant: dict[int, uuid.UUID] = {}  # the participant of each writer (a relay's, or the vehicle's)
        self._left: dict[int, float] = {}

    def listener(self, **more: Callable[..., None]) -> Listener:
        return Listener(on_subscription_matched=self._on_matched, **more)

    def _on_matched(self, reader: DataReader[Any], status: Any) -> None:
        handle = status.last_publication_handle & _U64
        if status.current_count_change > 0:
            self._left.pop(handle, None)
            if reader is not None:  # None while the reader is still being created: owner() learns it at the first take
                self.learn(reader, handle)
        elif status.current_count_change < 0:
            self._left[handle] = time.monotonic()

    def learn(self, reader: DataReader[Any], handle: int) -> Via | None:
        try:
            data = reader.get_matched_publication_data(handle)
        except Exception as e:  # called from Cyclone's listener thread: never raise there
            log.warning("cannot read the QoS of writer %x: %s", handle, e)
            return None
        if data is None:
            return None
        self.participant[handle] = data.participant_key
        via = self.by_handle[handle] = owner_of(data.qos)
        return via

    def owner(self, reader: DataReader[Any], handle: int) -> Via | None:
        """None only for a writer that left before any reader could read its QoS."""
        return self.by_handle.get(handle) or self.learn(reader, handle)

    def forget_departed(self, now: float) -> None:
        for handle, left in list(self._left.items()):  # the listener thread may change _left meanwhile
            if now - left > FORGET_AFTER:
                self._left.pop(handle, None)
                self.by_handle.pop(handle, None)
                self.participant.pop(handle, None)


class Ingest:
    def __init__(
        self,
        bus: Bus,
        loop: asyncio.AbstractEventLoop,
        on_reports: Callable[[list[ReportItem]], None],
        on_statuses: Callable[[list[StatusItem]], None],
        report_interval: float,
        tap: Tap | None = None,
        report_burst: int = 32,
        command_writers: dict[AnySem, DataWriter[Any]] | None = None,
    ) -> None:
        self.loop, self.on_reports, self.on_statuses, self.tap = loop, on_reports, on_statuses, tap
        self.pace = Pacer(report_interval, report_burst)
        self.decoder = Decoder()
        self.undecodable = self.decoder.undecodable
        self.incompatible: dict[str, int] = {}  # topic -> writers no reader of ours matches (see _on_incompatible)
        self._warned: set[tuple[AnySem, str]] = set()
        self.taken = 0  # samples taken from DDS (every reader of every topic), for /api/metrics
        self.decoded = 0  # of those, decoded: those taken from their writer's owner reader
        self.by_reader = {v.value: 0 for v in Via}  # decoded samples per reader kind
        self.samples_lost = 0  # samples Cyclone says its readers lost (SAMPLE_LOST: a gap, or no room), for /api/health
        self.window_waits = 0  # report takes that waited for the conflation window (dense input), for /api/metrics
        self.owners = Owners()
        self.command_writers = command_writers or {}  # the console's, by topic: whose readers they reach (dds/vendors.py)
        self.findings: list[Finding] = []  # what other vendors' participants must change (dds/vendors.py), for /api/metrics
        self._logged: set[tuple[str, str, str | None]] = set()
        self._peers_checked = 0.0
        self._counting = threading.Lock()
        self.running = False
        self.report_readers = self._readers(bus, [*REPORT_TOPICS, *REPORT_TOPICS_6_0])
        self.status_readers = self._readers(
            bus, list(dict.fromkeys([*STATUS_TOPICS, *ACK_TOPICS, *COMMAND_TOPICS, *COMMAND_FLOW_6_0]))
        )
        # other vendors' endpoints of the topics it reads or writes (dds/vendors.py)
        self.peers = PeerWatch(
            bus.participant, [*{s for s, _v, _r in self.report_readers + self.status_readers}, *self.command_writers]
        )
        self.threads: list[threading.Thread] = []
        self._waitsets: dict[str, tuple[Triggered, list[Any]]] = {}
        for name, readers in (("reports", self.report_readers), ("statuses", self.status_readers)):
            ws = WaitSet(bus.participant)
            conds = []
            for _sem, _via, r in readers:
                c = all_samples(r)
                ws.attach(c)
                conds.append(c)
            self._waitsets[name] = (Triggered(ws), conds)

    def start(self) -> None:
        self.running = True
        for name, fn in (("reports", self._report_loop), ("statuses", self._status_loop)):
            t = threading.Thread(target=fn, name=f"sem-ingest-{name}", daemon=True)
            t.start()
            self.threads.append(t)

    def stop(self) -> None:
        self.running = False
        for t in self.threads:
            t.join(timeout=2)

    def _wait(self, ws: Triggered) -> list[int] | None:
        """Wait for samples (at most 200 ms): the indices of the readers that have some (their conditions, in attach
        order; a sample's copies reach only some of a topic's readers, so only those are taken). None when the loop
        should end: stopped, or the bus was closed under a thread that outlived stop()'s join (its waitset then
        refuses; that is the end, not a failure to report)."""
        try:
            ready = ws.wait(duration(milliseconds=200))
        except DDSException:
            if not self.running:
                return None
            raise
        return ready if self.running else None

    def _readers(self, bus: Bus, sems: Sequence[AnySem]) -> list[tuple[AnySem, Via, DataReader[Any]]]:
        """The three readers of every topic (see the module docstring), and three more of its appendable copy if it
        has one (Via.qos). A writer matches the readers of one type only, so `Owners` needs no change: its samples are
        taken from its owner among them, and `Decoder` tells the two types apart by the encapsulation header."""
        return [
            (
                sem,
                via,
                bus.reader(
                    sem,
                    via.qos(sem, appendable),
                    appendable=appendable,
                    listener=self.owners.listener(
                        on_requested_incompatible_qos=self._on_incompatible(sem, via), on_sample_lost=self._on_lost
                    ),
                ),
            )
            for sem in sems
            for appendable in (False, True)
            if not appendable or sem.spec.appendable is not None
            for via in Via
        ]

    def _on_lost(self, _reader: DataReader[Any], status: Any) -> None:
        """Cyclone's SAMPLE_LOST status of a reader (in its listener thread): counted (console/load.py shows it)."""
        with self._counting:
            self.samples_lost += status.total_count_change

    def _on_incompatible(self, sem: AnySem, via: Via) -> Callable[[DataReader[Any], Any], None]:
        """Count the writers of a topic that no reader of ours can match. The best-effort reader
        accepts any reliability, durability and latency budget, so what it refuses is refused by
        all three: in practice a data representation (an XCDR1 writer of a type with @optional
        members, README "Other DDS vendors"). Logged once per topic and policy.
        A topic with an appendable copy has two best-effort readers. Each counts what it refuses other than for the
        type (status.total_count counts those too: a writer of the other extensibility, which the other reader reads),
        and the topic shows the larger count, as a writer both refuse (an XCDR1 GPS writer) is counted by each."""
        refused = 0

        def on(_reader: DataReader[Any], status: Any) -> None:
            nonlocal refused
            if via is not Via.BEST_EFFORT or (sem.spec.appendable is not None and status.last_policy_id == _TYPE_CONSISTENCY):
                return  # a writer of the other extensibility: the other reader of the topic reads it
            with self._counting:  # the two readers' listeners may run in two of Cyclone's threads
                refused += status.total_count_change
                self.incompatible[sem.spec.name] = max(self.incompatible.get(sem.spec.name, 0), refused)
            policy = _POLICY_NAMES.get(status.last_policy_id, f"policy {status.last_policy_id}")
            if (sem, policy) not in self._warned:
                self._warned.add((sem, policy))
                log.warning(
                    "a writer of %s offers a %s no reader of the console accepts; it is not read%s",
                    sem.spec.name,
                    policy,
                    " (XCDR1 for a type with optional members: offer XCDR2)" if policy == "DataRepresentation" else "",
                )

        return on

    def _take(self, sem: AnySem, via: Via, reader: DataReader[Any], condition: Any) -> list[Item]:
        """Take raw samples and decode those of writers this reader owns, one by one (`Decoder`, the
        path a replay takes too): a sample that cannot be decoded costs only itself, and the copies
        other readers own are dropped undecoded, so each sample is decoded and applied once."""
        decode = sem.spec.cls is not TopicClass.COMMAND
        out: list[Item] = []
        while True:
            raw = take_cdr(reader, condition.mask, 256)
            if isinstance(raw, int):
                log.warning("take on %s failed: %d", sem.spec.name, raw)
                break
            with self._counting:  # both ingest threads count
                self.taken += len(raw)
            tap = self.tap if self.tap is not None and self.tap.active else None
            tapped: list[tuple[bytes, bool, int, int]] = []
            received_ns = time.time_ns()  # the receive time of the recording's messages and of the state alike
            for data, info in raw:
                if self.owners.owner(reader, info.publication_handle & _U64) not in (via, None):
                    continue
                if tap is not None:
                    tapped.append((data, info.valid_data, info.instance_state, info.source_timestamp))
                if not decode:
                    continue
                item = self.decoder.decode(sem, data, info.valid_data, info.instance_state, received_ns / 1e9)
                if item is not None:
                    if isinstance(item, ReportItem):
                        item.writer = self.owners.participant.get(info.publication_handle & _U64)
                    out.append(item)
            if tapped and tap is not None:
                tap.on_samples(sem, tapped, received_ns)
            if len(raw) < 256:
                break
        with self._counting:
            self.decoded += len(out)
            self.by_reader[via.value] += len(out)
        return out

    def _report_loop(self) -> None:
        ws, conds = self._waitsets["reports"]
        while self.running:
            if (ready := self._wait(ws)) is None:
                return
            started = time.monotonic()
            items: list[ReportItem] = []
            try:
                for i in ready:
                    sem, via, reader = self.report_readers[i]
                    items.extend(it for it in self._take(sem, via, reader, conds[i]) if isinstance(it, ReportItem))
                if items:
                    # a take counts only when it applied something: a wake by the timeout, or by the copies
                    # of a sample in the topic's other readers (taken and dropped), spends no token
                    self.pace.took()
                self.owners.forget_departed(started)
            except Exception:  # a bug here must not stop every report for good
                log.exception("report ingest cycle failed")
            wait = self.pace.delay()
            if items:
                # the hand-off last: this thread releases the GIL next (in the wait or the sleep), so the loop thread,
                # woken by it, finds the GIL free instead of waiting for this thread's bookkeeping (0.2 ms a sample)
                self.loop.call_soon_threadsafe(self.on_reports, items)
            if wait > 0:
                self.window_waits += 1  # input dense enough that the conflation window applies
                time.sleep(wait)

    def _status_loop(self) -> None:
        ws, conds = self._waitsets["statuses"]
        while self.running:
            if (ready := self._wait(ws)) is None:
                return
            try:
                self._check_peers(time.monotonic())
                self._status_cycle(conds, ready)  # its hand-off last, as the report thread's
            except Exception:  # a bug here must not stop every status for good
                log.exception("status ingest cycle failed")

    def _check_peers(self, now: float) -> None:
        """Every PEER_CHECK s: what other vendors' participants must change; each finding logged once."""
        if now - self._peers_checked < PEER_CHECK:
            return
        self._peers_checked = now
        self.peers.poll(now)
        findings = self.peers.findings(self.matched_writers, now, self.reached_readers)
        for f in findings:
            if (f.participant, f.kind, f.topic) not in self._logged:
                self._logged.add((f.participant, f.kind, f.topic))
                log.warning("%s", f.message)
        self.findings = findings  # replaced whole: /api/metrics reads it from the loop

    def matched_writers(self, sem: AnySem) -> set[int]:
        """The publication handles any reader of ours of this topic matched."""
        return {
            h & _U64 for s, _via, r in self.report_readers + self.status_readers if s is sem for h in r.get_matched_publications()
        }

    def reached_readers(self, sem: AnySem) -> set[int] | None:
        """The subscription handles the console's writer of this topic matched (None: the console writes no such topic)."""
        writer = next((w for s, w in self.command_writers.items() if s is sem), None)
        return None if writer is None else {h & _U64 for h in writer.get_matched_subscriptions()}

    def _status_cycle(self, conds: list[Any], ready: list[int]) -> None:
        items: list[StatusItem] = []
        for i in ready:
            sem, via, reader = self.status_readers[i]
            items.extend(it for it in self._take(sem, via, reader, conds[i]) if isinstance(it, StatusItem))
        if items:
            self.loop.call_soon_threadsafe(self.on_statuses, items)
