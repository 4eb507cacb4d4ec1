"""What the checker sees of the bus: every SEM sample, as a Service Consumer on the ICD's QoS
reads it, and every SEM endpoint that discovery announces.

Each report, status and ack topic is read by a reader with the consumer QoS of `dds/qos.py`
(reliable, transient-local): what it receives is what a conforming consumer receives, and the
report and command tests judge only that. Each report topic is also read by a best-effort
volatile reader (`any_writer_reader_qos`) that matches any writer, used only to find providers
and their participants: a provider whose writer a consumer cannot match is still found, and its
discovery test says why it does not match. The command topics are read only for a recording.

Samples are taken raw (their CDR as received) and decoded by the console's `Decoder`, the one
decode path of the console and its replays; the raw samples also go to the recorder (`--record`).

UMAA 6.0 topics (`Sem60`) are read too: each report topic by a best-effort volatile reader, which matches
any writer (6.0 mandates no QoS; RTI's UMAAQoSLib writes reports best-effort), the command status and ack
by a reliable volatile reader, as RTI's CommandQoS writes them, and by a best-effort one for the writers the
reliable one cannot match. Their samples are decoded as the 6.0 IDL
has them (`umaa_6_0.decode`), not as the console's model; each source's UMAA versions are noted from the
topics its samples came on (`versions`).
Endpoints come from Cyclone's built-in DCPSPublication and DCPSSubscription topics: topic and
type name, QoS and, where the peer sends it, the XTypes type identifier.
"""

from __future__ import annotations

import time
import uuid
from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription
from cyclonedds.builtin_types import DcpsEndpoint
from cyclonedds.core import InstanceState, Qos, ReadCondition
from cyclonedds.sub import DataReader

from sem_console.check import umaa_6_0
from sem_console.codec.decode import Decoder, ReportItem, StatusItem
from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.cyclone_private import take_cdr
from sem_console.dds.qos import TopicClass, any_writer_reader_qos, reader_qos
from sem_console.dds.topics import AnySem, Sem, Sem60, Service, final_type_qos
from sem_console.dds.vendors import Finding, PeerWatch
from sem_console.versions import UMAA_3_0_1, UMAA_6_0, UmaaVersion

if TYPE_CHECKING:
    from sem_console.recording.recorder import Recorder

_U64 = 0xFFFF_FFFF_FFFF_FFFF
SEM_TOPICS: dict[str, AnySem] = {sem.spec.name: sem for sem in [*Sem, *Sem60]}
REPORTS = [sem for sem in Sem if sem.spec.cls is TopicClass.REPORT]
TICK = 0.02  # s between takes while waiting


@dataclass
class Report:
    """One report sample as the consumer-QoS reader received it."""

    received: float  # the checker's clock (UTC seconds) when taken
    body: dict[str, Any] | None  # the report as JSON (codec/convert.py); None for a dispose or a lost writer
    invalid: list[str]  # what the decoder flagged: unknown enum ordinals, NaN, values out of their ICD range
    alive: bool
    writer: int  # publication handle


@dataclass
class StatusSeen:
    """One command status or ack sample (None: the instance was disposed or lost its writer)."""

    received: float
    source: uuid.UUID
    sample: Any | None
    disposed: bool = False  # by its writer; no sample and not disposed: the instance lost its writer (the provider left)


class Observer:
    def __init__(self, bus: Bus, recorder: Recorder | None = None) -> None:
        self.bus = bus
        self.recorder = recorder
        self.decoder = Decoder()

        # (topic, reader, consumer QoS?) for every topic we read. GPSReport and GPSFixReport also by readers of their
        # appendable copies, for RTI vehicles, as the console reads them (console/ingest.py; a writer matches the
        # readers of one extensibility only, and Decoder tells the two apart by the encapsulation header).
        def both(sem: Sem, qos: Qos) -> list[DataReader[Any]]:
            readers = [bus.reader(sem, qos + final_type_qos(sem))]
            return readers + ([bus.reader(sem, qos, appendable=True)] if sem.spec.appendable is not None else [])

        self.readers: list[tuple[AnySem, DataReader[Any], bool]] = [
            (sem, r, True) for sem in Sem if sem.spec.cls is not TopicClass.COMMAND for r in both(sem, reader_qos(sem.spec.cls))
        ]
        self.readers += [(sem, r, False) for sem in REPORTS for r in both(sem, any_writer_reader_qos(sem.spec.cls))]
        if recorder is not None:  # the checker's own commands (and anyone else's) as evidence
            self.readers += [(s.command, bus.reader(s.command), True) for s in Service]
        self.readers += [
            (sem, bus.reader(sem, any_writer_reader_qos(sem.spec.cls)), True)
            for sem in Sem60
            if sem.spec.cls is TopicClass.REPORT
        ]
        # 6.0 mandates no QoS: a status or ack writer the reliable reader cannot match (a best-effort one) is read by a
        # best-effort reader, which takes the samples of the writers the reliable one has not matched only
        self._primary: dict[int, DataReader[Any]] = {}
        for topic in Sem60:
            if topic.spec.cls is TopicClass.STATUS:
                reliable = bus.reader(topic, reader_qos(topic.spec.cls, durable=False))
                any_writer = bus.reader(topic, any_writer_reader_qos(topic.spec.cls))
                self.readers += [(topic, reliable, True), (topic, any_writer, True)]
                self._primary[id(any_writer)] = reliable
        self._conditions = [all_samples(r) for _, r, _ in self.readers]
        self.consumer_readers: dict[AnySem, list[DataReader[Any]]] = {}
        for sem, r, consumer in self.readers:
            if consumer:
                self.consumer_readers.setdefault(sem, []).append(r)
        self._pubs = BuiltinDataReader(bus.participant, BuiltinTopicDcpsPublication)
        self._subs = BuiltinDataReader(bus.participant, BuiltinTopicDcpsSubscription)
        self.publications: dict[uuid.UUID, DcpsEndpoint] = {}
        self.subscriptions: dict[uuid.UUID, DcpsEndpoint] = {}
        self.reports: dict[AnySem, dict[uuid.UUID, list[Report]]] = defaultdict(lambda: defaultdict(list))
        self.statuses: dict[uuid.UUID, list[StatusSeen]] = defaultdict(list)  # by sessionID
        self.acks: dict[uuid.UUID, list[StatusSeen]] = defaultdict(list)
        self.alive_sources: dict[uuid.UUID, float] = {}  # provider source -> when first seen alive
        self.versions: dict[uuid.UUID, set[UmaaVersion]] = defaultdict(set)  # of the topics its samples came on
        self.parents: dict[uuid.UUID, uuid.UUID] = {}  # a 6.0 provider's parent, as its reports' source says
        self.source_participants: dict[uuid.UUID, set[uuid.UUID]] = defaultdict(set)
        self._writer_participant: dict[int, uuid.UUID] = {}
        self.peers = PeerWatch(bus.participant)  # other vendors' participants: what their operator must change

    # ---- taking -------------------------------------------------------------------------
    def pump(self) -> None:
        """Take everything that arrived: endpoints first, so a sample's writer is known."""
        self._take_endpoints()
        self.peers.poll(time.monotonic())
        for (sem, reader, consumer), cond in zip(self.readers, self._conditions, strict=True):
            self._take(sem, reader, consumer, cond)

    def wait(self, predicate: Callable[[], bool], seconds: float) -> bool:
        """Pump until `predicate` holds (True) or `seconds` pass (False)."""
        deadline = time.monotonic() + seconds
        while True:
            self.pump()
            if predicate():
                return True
            if time.monotonic() >= deadline:
                return False
            time.sleep(TICK)

    def idle(self, seconds: float) -> None:
        self.wait(lambda: False, seconds)

    def _take_endpoints(self) -> None:
        for builtin, table in ((self._pubs, self.publications), (self._subs, self.subscriptions)):
            while True:
                got = builtin.take(N=256)
                for e in got:
                    if e.sample_info.instance_state == InstanceState.Alive and e.topic_name in SEM_TOPICS:
                        table[e.key] = e
                    else:
                        table.pop(e.key, None)
                if len(got) < 256:
                    break

    def _participant_of(self, reader: DataReader[Any], handle: int) -> uuid.UUID | None:
        if handle not in self._writer_participant:
            try:
                data = reader.get_matched_publication_data(handle)
            except Exception:  # a writer that already left: asked again with its next sample
                return None
            if data is None:
                return None
            self._writer_participant[handle] = data.participant_key
        return self._writer_participant[handle]

    def _take(self, sem: AnySem, reader: DataReader[Any], consumer: bool, cond: ReadCondition) -> None:
        while True:
            raw = take_cdr(reader, cond.mask, 256)  # raw CDR, as console/ingest.py takes it
            if isinstance(raw, int) or not raw:
                return
            now = time.time()
            tapped: list[tuple[bytes, bool, int, int]] = []
            primary = self._primary.get(id(reader))
            theirs = {h & _U64 for h in primary.get_matched_publications()} if primary is not None else set()
            for data, info in raw:
                handle = info.publication_handle & _U64
                if handle in theirs:
                    continue  # the reliable reader's
                six = isinstance(sem, Sem60)
                if consumer and not six and self.recorder is not None and self.recorder.active:
                    tapped.append((data, info.valid_data, info.instance_state, info.source_timestamp))
                item = (
                    umaa_6_0.decode(sem, data, info.valid_data, info.instance_state, now)
                    if isinstance(sem, Sem60)
                    else self.decoder.decode(sem, data, info.valid_data, info.instance_state, now)
                )
                if item is None:
                    if six:
                        self.decoder.undecodable[sem.spec.name] = self.decoder.undecodable.get(sem.spec.name, 0) + 1
                    continue  # undecodable (counted by the decoder) or a command topic (recorded only)
                if item.alive:
                    self.alive_sources.setdefault(item.source, now)
                    self.versions[item.source].add(UMAA_6_0 if six else UMAA_3_0_1)
                    participant = self._participant_of(reader, handle)
                    if participant is not None:
                        self.source_participants[item.source].add(participant)
                if not consumer:
                    continue
                if isinstance(item, ReportItem):
                    self.reports[sem][item.source].append(Report(now, item.report, item.invalid, item.alive, handle))
                    parent = umaa_6_0.parent_in(item.report) if six else None
                    if parent is not None:
                        self.parents[item.source] = parent
                elif isinstance(item, StatusItem):
                    table = self.statuses if item.kind == "status" else self.acks
                    disposed = info.instance_state == InstanceState.NotAliveDisposed
                    table[item.session].append(StatusSeen(now, item.source, item.sample, disposed))
            if tapped and isinstance(sem, Sem) and self.recorder is not None and self.recorder.active:
                self.recorder.on_samples(sem, tapped, time.time_ns())
            if len(raw) < 256:
                return

    # ---- what was seen ------------------------------------------------------------------
    def providers(self) -> set[uuid.UUID]:
        return set(self.alive_sources)

    def unclaimed_controls(self) -> set[uuid.UUID]:
        """Participants with a writer of command statuses or acks none of whose samples named a source yet: a
        vehicle's control service in a process of its own writes only in answer to a command, so no sample ties
        it to its provider before the command tests (consumers never write statuses)."""
        self._take_endpoints()
        claimed = set().union(*self.source_participants.values())
        return {
            e.participant_key for e in self.publications.values() if SEM_TOPICS[e.topic_name].spec.cls is TopicClass.STATUS
        } - claimed

    def present(self, source: uuid.UUID) -> bool:
        """Whether a DDS endpoint of the provider's participants remains (False: it left the domain, stopped or
        off the network; a participant that went without a word goes when its lease runs out)."""
        self._take_endpoints()
        participants = self.source_participants.get(source, set())
        return any(e.participant_key in participants for t in (self.publications, self.subscriptions) for e in t.values())

    def version(self, source: uuid.UUID) -> UmaaVersion:
        """The UMAA version a provider speaks, by the topics its samples came on: 6.0 when any came on a 6.0 topic."""
        return UMAA_6_0 if UMAA_6_0 in self.versions.get(source, set()) else UMAA_3_0_1

    def endpoints(self, participants: set[uuid.UUID], sem: AnySem, writers: bool) -> list[DcpsEndpoint]:
        """The provider's writers (or readers) of a topic, found by its participants."""
        table = self.publications if writers else self.subscriptions
        return [e for e in table.values() if e.participant_key in participants and e.topic_name == sem.spec.name]

    def peer_findings(self) -> list[Finding]:
        """What other vendors' participants on the bus must change for a consumer to read them (dds/vendors.py)."""
        return self.peers.findings(self._matched_writers, time.monotonic())

    def _matched_writers(self, sem: AnySem) -> set[int]:
        return {h & _U64 for s, r, _ in self.readers if s is sem for h in r.get_matched_publications()}

    def matched_by_consumer(self, sem: AnySem, endpoint: DcpsEndpoint) -> bool:
        """Whether one of the checker's consumer-QoS readers of the topic matched this writer."""
        return any(self._matched_by(reader, endpoint) for reader in self.consumer_readers.get(sem, []))

    @staticmethod
    def _matched_by(reader: DataReader[Any], endpoint: DcpsEndpoint) -> bool:
        for handle in reader.get_matched_publications():
            try:
                data = reader.get_matched_publication_data(handle)
            except Exception:  # a writer that just left
                continue
            if data is not None and data.key == endpoint.key:
                return True
        return False
