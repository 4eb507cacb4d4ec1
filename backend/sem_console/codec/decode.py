"""Raw SEM samples -> what the console applies: the one decode path of live DDS and of a replay.

`Decoder.decode` takes a sample as it came off the wire (its CDR with the encapsulation header,
or only the key for a dispose or an instance that lost its writers) and turns it into a
`ReportItem` (report topics, converted to JSON) or a `StatusItem` (command status and ack
topics). The DDS ingest threads call it for every sample taken from its owner reader; a replay
(`console/replay_source.py`) calls it for every recorded message. A sample that cannot be decoded is
counted per topic and logged, never raised.

Samples are decoded by the code `codec/fastcdr.py` generates per type (a report straight to its
JSON, the same as `convert.to_json` of cyclonedds' sample, a status to the same sample cyclonedds
builds); a key (disposes, lost writers) by cyclonedds.
"""

from __future__ import annotations

import logging
import threading
import uuid
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from cyclonedds.core import InstanceState
from cyclonedds.idl import IdlStruct

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status

from sem_console.codec import fastcdr
from sem_console.dds.topics import AnySem, Sem, Sem60, Service, delimited
from sem_console.umaa.flow import AnyReason
from sem_console.versions import UMAA_3_0_1, UMAA_6_0, UmaaVersion, umaa_6_0
from sem_console.versions.commands import ACK_TOPICS as ACKS
from sem_console.versions.commands import COMMAND_TOPICS as COMMANDS
from sem_console.versions.commands import STATUS_TOPICS as STATUSES
from sem_console.versions.commands import Commanding, parent_of
from sem_console.versions.shape import Adapter

log = logging.getLogger("sem-console.ingest")

REPORT_TOPICS = {
    Sem.GPS_REPORT: "GPSReport",
    Sem.GPS_FIX_REPORT: "GPSFixReport",
    Sem.GPS_FIX_STATUS_REPORT: "GPSFixStatusReport",
    Sem.INS_REPORT: "InertialSensorReport",
}
# The command status and ack topics of every version (versions/commands.py), and the service each answers
STATUS_TOPICS = {sem: c.service for sem, c in STATUSES.items()}
ACK_TOPICS = {sem: c.service for sem, c in ACKS.items()}
COMMAND_TOPICS = COMMANDS  # recorded, never decoded: the console follows its own commands
# The UMAA 6.0 report topics the console reads, and what each feeds (versions/umaa_6_0.py)
REPORT_TOPICS_6_0 = list(umaa_6_0.REPORTS)
# Every topic name a vehicle's report samples count under for its link (provider health): the model's, whatever the
# version
REPORT_HEALTH_TOPICS = tuple(REPORT_TOPICS.values())


@dataclass
class ReportItem:
    topic: str
    source: uuid.UUID
    report: dict[str, Any] | None  # None: the instance was disposed or lost its writers
    invalid: list[str]
    alive: bool
    received_at: float
    sample: Any = None  # the (report, invalid) JSON not yet applied (`Decoder.decode(..., convert=False)`)
    version: UmaaVersion = UMAA_3_0_1  # the UMAA version of the topic it came on
    parent: uuid.UUID | None = None  # the parent its source says it has (UMAA 6.0's IdentifierType; the nil UUID: none)
    writer: uuid.UUID | None = None  # the DDS participant that wrote it (live DDS only): a relay's, or another's


@dataclass
class StatusItem:
    service: Service
    kind: str  # "status" | "ack"
    source: uuid.UUID
    session: uuid.UUID
    sample: Any  # None when disposed
    alive: bool
    # a status sample's status and reason in the model (`umaa/flow.py`), whatever the version's enumerations
    status: Status | int | None = None
    reason: AnyReason | int | None = None
    version: UmaaVersion = UMAA_3_0_1  # the UMAA version of the topic it came on
    parent: uuid.UUID | None = None  # as ReportItem's


Item = ReportItem | StatusItem


def guid(raw: Any) -> uuid.UUID | None:
    """A NumericGUID as a UUID; of an identifier (UMAA 6.0's IdentifierType), its `id`."""
    raw = getattr(raw, "id", raw)
    try:
        return uuid.UUID(bytes=bytes(raw))
    except (TypeError, ValueError):
        return None


def _source(report: dict[str, Any]) -> Any:
    return report.get("source")


def _same(report: dict[str, Any], invalid: list[str]) -> tuple[dict[str, Any], list[str]]:
    return report, invalid


@dataclass(frozen=True)
class _Route:
    """What `Decoder.decode` needs of a topic, looked up once per sample."""

    name: str
    type: type[IdlStruct]
    fast: fastcdr.TypeDecoder
    report: str | None  # the report's topic name (report topics)
    service: Service | None  # status and ack topics
    kind: str  # "report" | "status" | "ack"
    version: UmaaVersion = UMAA_3_0_1
    commanding: Commanding | None = None  # status and ack topics: the version's commanding
    source: Callable[[dict[str, Any]], Any] = _source  # the vehicle's GUID text in a report's JSON
    model: Adapter = _same  # a report's JSON and invalid values as the model's (its version's adapter)


def _decoder(sem: AnySem, cls: type[IdlStruct]) -> fastcdr.TypeDecoder:
    """The generated decoder of topic `sem`'s samples of type `cls`, its final type or its appendable copy: a 6.0
    report said as data (`Report.spec`) is decoded straight to the model's JSON, whichever type it came in."""
    r = umaa_6_0.REPORTS.get(sem) if isinstance(sem, Sem60) else None
    if r is None or r.spec is None:
        return fastcdr.decoder(cls)
    return fastcdr.decoder(cls, r.spec, umaa_6_0.model_path, r.model)


_ROUTES: dict[AnySem, _Route] = {
    **{
        sem: _Route(sem.spec.name, sem.spec.type, _decoder(sem, sem.spec.type), topic, None, "report")
        for sem, topic in REPORT_TOPICS.items()
    },
    **{
        sem: _Route(sem.spec.name, sem.spec.type, _decoder(sem, sem.spec.type), None, c.service, "status", c.version, c)
        for sem, c in STATUSES.items()
    },
    **{
        sem: _Route(sem.spec.name, sem.spec.type, _decoder(sem, sem.spec.type), None, c.service, "ack", c.version, c)
        for sem, c in ACKS.items()
    },
    # a 6.0 report not said as data is adapted after its decoder
    **{
        sem: _Route(
            sem.spec.name,
            sem.spec.type,
            _decoder(sem, sem.spec.type),
            r.topic,
            None,
            "report",
            UMAA_6_0,
            source=_source if r.spec is not None else umaa_6_0.source_of,
            model=_same if r.spec is not None else r.model,
        )
        for sem, r in umaa_6_0.REPORTS.items()
    },
}
DECODED_TOPICS: tuple[AnySem, ...] = tuple(_ROUTES)  # every topic the decoder decodes, of both UMAA versions
# The appendable copies of the topics that have one (TopicSpec.appendable): a sample whose encapsulation header says
# delimited XCDR2 (D_CDR2, DDS-XTypes 7.6.3.1.2), what an appendable writer sends, is decoded with the appendable copy;
# any other with the topic's final type. So live samples from either reader, and recorded ones, take the same path.
_APPENDABLE_ROUTES: dict[AnySem, _Route] = {
    sem: replace(route, type=sem.spec.appendable, fast=_decoder(sem, sem.spec.appendable))
    for sem, route in _ROUTES.items()
    if sem.spec.appendable is not None
}
_ALIVE = InstanceState.Alive


def report_json(sem: AnySem) -> Callable[[bytes], tuple[dict[str, Any], list[str]]]:
    """What `Decoder.decode` runs for a sample of report topic `sem` (its final type): the CDR to the model's JSON and
    invalid values, through its version's adapter (the benchmarks time it)."""
    route = _ROUTES[sem]
    if route.model is _same:
        return route.fast.json
    fast, model = route.fast.json, route.model
    return lambda data: model(*fast(data))


class Decoder:
    def __init__(self) -> None:
        self.undecodable: dict[str, int] = {}
        self.decoded = 0
        # a vehicle's parent by (vehicle, report type): its source's parentID (UMAA 6.0's IdentifierType; None for a
        # NumericGUID, which has none), with the bytes of its source as they were (its id and parentID, None without
        # a parent): the model's report leaves the parent out, so a report is decoded whole only when those bytes are
        # not in it (its first, or its parent changed)
        self._parents: dict[tuple[uuid.UUID, type], tuple[uuid.UUID | None, bytes | None]] = {}
        self._counting = threading.Lock()  # both DDS ingest threads decode

    def _bad(self, name: str) -> None:
        with self._counting:
            self.undecodable[name] = self.undecodable.get(name, 0) + 1

    def decode(
        self, sem: AnySem, data: bytes, valid: bool, instance_state: int, received_at: float, convert: bool = True
    ) -> Item | None:
        """One sample of a report, status or ack topic: `data` is its CDR (only the key when not
        `valid`), `instance_state` the DDS instance state it came with, `received_at` when it was
        taken (UTC seconds). None for a sample that cannot be decoded (counted) or of another topic.
        With `convert` False a report keeps its JSON aside (`convert` applies it): a replay rebuilding
        its state applies only the reports that are not superseded on the way."""
        route = _ROUTES.get(sem)
        if route is None:
            return None
        if sem in _APPENDABLE_ROUTES and delimited(data):
            route = _APPENDABLE_ROUTES[sem]
        report = sample = None
        try:
            if not valid:
                sample = route.type.deserialize_key(data)
                source = guid(getattr(sample, "source", None))
            elif route.report is not None:
                report = route.fast.json(data)
                text = route.source(report[0])
                source = fastcdr.guid_uuid(text) if isinstance(text, str) else None
                if route.model is not _same:
                    report = route.model(*report)
            else:
                sample = route.fast.sample(data)
                source = guid(getattr(sample, "source", None))
        except Exception as e:
            self._bad(route.name)
            log.warning("undecodable sample on %s: %s", route.name, e)
            return None
        with self._counting:
            self.decoded += 1
        if source is None:
            self._bad(route.name)
            return None
        alive = instance_state == _ALIVE
        if route.report is not None:
            parent = self._parent(route, source, data) if valid else None
            if report is None:
                return ReportItem(
                    route.report, source, None, [], alive and valid, received_at, version=route.version, parent=parent
                )
            if convert:
                return ReportItem(
                    route.report, source, report[0], report[1], alive, received_at, version=route.version, parent=parent
                )
            return ReportItem(route.report, source, None, [], alive, received_at, report, route.version, parent)
        session = guid(getattr(sample, "sessionID", None))
        if session is None:
            return None
        assert route.service is not None and route.commanding is not None
        parent = parent_of(getattr(sample, "source", None))
        if route.kind == "status" and valid:
            status, reason = route.commanding.read_status(sample)
            return StatusItem(route.service, route.kind, source, session, sample, alive, status, reason, route.version, parent)
        return StatusItem(
            route.service, route.kind, source, session, sample if valid else None, alive, version=route.version, parent=parent
        )

    def _parent(self, route: _Route, source: uuid.UUID, data: bytes) -> uuid.UUID | None:
        """A vehicle's parent, from a report of it decoded whole: its first on this type, and again when the parent it
        says is no longer the one known (a vehicle given another parent, or speaking another version)."""
        key = (source, route.type)
        known = self._parents.get(key)
        if known is not None and (known[1] is None or known[1] in data):
            return known[0]
        try:
            parent = parent_of(route.fast.sample(data).source)
        except Exception:  # the report itself decoded: its parent is not known, and is asked again on the next one
            return None
        self._parents[key] = (parent, None if parent is None else source.bytes + parent.bytes)
        return parent

    @staticmethod
    def convert(item: ReportItem) -> ReportItem:
        """The report's JSON, decoded with the sample, applied to the item."""
        item.report, item.invalid = item.sample
        item.sample = None
        return item
