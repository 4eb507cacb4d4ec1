"""DDS -> asyncio: two threads take SEM samples and hand them to the event loop.

- The status thread takes command status and ack samples as soon as they arrive, so
  every transition reaches the loop in order and none is lost.
- The report thread takes report samples at most every `report_interval` seconds.
  Report readers keep the latest sample per instance, so a provider publishing faster
  than that is conflated by DDS itself: the console's cost follows what it shows.

Samples are decoded and converted to JSON in these threads; the loop only applies them
(`loop.call_soon_threadsafe`), so DDS never blocks it. Disposes and lost writers are
read explicitly. A sample that cannot be decoded is counted, never raised.
"""

from __future__ import annotations

import asyncio
import logging
import threading
import time
import uuid
from dataclasses import dataclass
from typing import Any, Callable

from cyclonedds._clayer import ddspy_take
from cyclonedds.core import InstanceState, WaitSet
from cyclonedds.internal import InvalidSample
from cyclonedds.sub import DataReader
from cyclonedds.util import duration

from sem_console.console.convert import to_json
from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.qos import any_writer_reader_qos
from sem_console.dds.topics import Sem, Service

log = logging.getLogger("sem-console.ingest")

REPORT_TOPICS = {
    Sem.GPS_REPORT: "GPSReport", Sem.GPS_FIX_REPORT: "GPSFixReport",
    Sem.GPS_FIX_STATUS_REPORT: "GPSFixStatusReport", Sem.INS_REPORT: "InertialSensorReport",
}
STATUS_TOPICS = {Service.GPS_FIX.status: Service.GPS_FIX, Service.INERTIAL_SENSOR.status: Service.INERTIAL_SENSOR}
ACK_TOPICS = {Service.GPS_FIX.ack: Service.GPS_FIX, Service.INERTIAL_SENSOR.ack: Service.INERTIAL_SENSOR}


@dataclass
class ReportItem:
    topic: str
    source: uuid.UUID
    report: dict[str, Any] | None  # None: the instance was disposed or lost its writers
    invalid: list[str]
    alive: bool
    received_at: float


@dataclass
class StatusItem:
    service: Service
    kind: str  # "status" | "ack"
    source: uuid.UUID
    session: uuid.UUID
    sample: Any  # None when disposed
    alive: bool


def _guid(raw: Any) -> uuid.UUID | None:
    try:
        return uuid.UUID(bytes=bytes(raw))
    except (TypeError, ValueError):
        return None


class Ingest:
    def __init__(self, bus: Bus, loop: asyncio.AbstractEventLoop, on_reports: Callable[[list[ReportItem]], None],
                 on_statuses: Callable[[list[StatusItem]], None], report_interval: float) -> None:
        self.loop, self.on_reports, self.on_statuses = loop, on_reports, on_statuses
        self.report_interval = report_interval
        self.undecodable: dict[str, int] = {}
        self.taken = 0  # samples taken from DDS (both readers of every topic), for /api/metrics
        self.decoded = 0  # of those, decoded (the rest came through the other reader too)
        self._matched: dict[int, tuple[float, frozenset[int]]] = {}
        self.running = False
        # Two readers per topic (see qos.any_writer_reader_qos); a sample seen by both is applied once.
        self.report_readers = self._readers(bus, list(REPORT_TOPICS))
        self.status_readers = self._readers(bus, list(STATUS_TOPICS) + list(ACK_TOPICS))
        self._last_ts: dict[tuple[Sem, uuid.UUID, uuid.UUID | None], int] = {}
        self.threads: list[threading.Thread] = []
        self._waitsets = {}
        for name, readers in (("reports", self.report_readers), ("statuses", self.status_readers)):
            ws = WaitSet(bus.participant)
            conds = []
            for _sem, r, _partner in readers:
                c = all_samples(r)
                ws.attach(c)
                conds.append(c)
            self._waitsets[name] = (ws, conds)

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

    @staticmethod
    def _readers(bus: Bus, sems: list[Sem]) -> list[tuple[Sem, DataReader, DataReader | None]]:
        """Per topic the reliable transient-local reader, then the any-writer one paired with it."""
        out: list[tuple[Sem, DataReader, DataReader | None]] = []
        for sem in sems:
            reliable = bus.reader(sem)
            out += [(sem, reliable, None), (sem, bus.reader(sem, any_writer_reader_qos(sem.spec.cls)), reliable)]
        return out

    def _skip_set(self, partner: DataReader | None, now: float) -> frozenset[int]:
        """Writers the partner (reliable) reader also matches, refreshed twice a second."""
        if partner is None:
            return frozenset()
        cached = self._matched.get(id(partner))
        if cached is None or now - cached[0] > 0.5:
            # get_matched_publications gives the handles as signed 64-bit, SampleInfo as unsigned
            cached = (now, frozenset(h & 0xFFFF_FFFF_FFFF_FFFF for h in partner.get_matched_publications()))
            self._matched[id(partner)] = cached
        return cached[1]

    def _take(self, sem: Sem, reader: DataReader, condition: Any, partner: DataReader | None = None) -> list[Any]:
        """Take raw samples and decode them one by one: a sample that cannot be decoded costs only
        itself, and one from a writer the partner reader also matches is dropped undecoded (it
        reaches us through the partner): each sample is decoded once."""
        skip = self._skip_set(partner, time.monotonic())
        dtype = sem.spec.type
        out: list[Any] = []
        while True:
            raw = ddspy_take(reader._ref, condition.mask, 256)  # noqa: SLF001 (DataReader.take, without its decode)
            if isinstance(raw, int):
                log.warning("take on %s failed: %d", sem.spec.name, raw)
                break
            self.taken += len(raw)
            for data, info in raw:
                if info.publication_handle in skip:
                    continue
                try:
                    if info.valid_data:
                        sample = dtype.deserialize(data)
                        sample.sample_info = info
                        out.append(sample)
                    else:
                        out.append(InvalidSample(dtype.deserialize_key(data), info))
                except Exception as e:
                    self.undecodable[sem.spec.name] = self.undecodable.get(sem.spec.name, 0) + 1
                    log.warning("undecodable sample on %s: %s", sem.spec.name, e)
            if len(raw) < 256:
                break
        self.decoded += len(out)
        return out

    def _is_new(self, sem: Sem, source: uuid.UUID, session: uuid.UUID | None, s: Any) -> bool:
        """False for a sample already applied through the other reader of the topic."""
        key = (sem, source, session)
        if isinstance(s, InvalidSample):
            self._last_ts.pop(key, None)  # the instance ended: forget it (one entry per command otherwise)
            return True
        if s.sample_info.source_timestamp <= self._last_ts.get(key, -1):
            return False
        self._last_ts[key] = s.sample_info.source_timestamp
        return True

    def _report_loop(self) -> None:
        ws, conds = self._waitsets["reports"]
        while self.running:
            ws.wait(duration(milliseconds=200))
            started = time.monotonic()
            items: list[ReportItem] = []
            for (sem, reader, partner), cond in zip(self.report_readers, conds):
                for s in self._take(sem, reader, cond, partner):
                    item = self._report(sem, s)
                    if item is not None:
                        items.append(item)
            if items:
                self.loop.call_soon_threadsafe(self.on_reports, items)
            time.sleep(max(0.0, self.report_interval - (time.monotonic() - started)))

    def _report(self, sem: Sem, s: Any) -> ReportItem | None:
        info = s.sample_info
        key = s.key_sample if isinstance(s, InvalidSample) else s
        source = _guid(getattr(key, "source", None))
        if source is None:
            self.undecodable[sem.spec.name] = self.undecodable.get(sem.spec.name, 0) + 1
            return None
        alive = info.instance_state == InstanceState.Alive
        if isinstance(s, InvalidSample):
            return ReportItem(REPORT_TOPICS[sem], source, None, [], False, time.time())
        if not self._is_new(sem, source, None, s):
            return None
        try:
            report, invalid = to_json(s)
        except Exception as e:  # never let one bad sample stop the reader
            report, invalid = {}, [f"sample could not be converted: {e}"]
        return ReportItem(REPORT_TOPICS[sem], source, report, invalid, alive, time.time())

    def _status_loop(self) -> None:
        ws, conds = self._waitsets["statuses"]
        while self.running:
            ws.wait(duration(milliseconds=200))
            items: list[StatusItem] = []
            for (sem, reader, partner), cond in zip(self.status_readers, conds):
                for s in self._take(sem, reader, cond, partner):
                    key = s.key_sample if isinstance(s, InvalidSample) else s
                    source, session = _guid(getattr(key, "source", None)), _guid(getattr(key, "sessionID", None))
                    if source is None or session is None or not self._is_new(sem, source, session, s):
                        continue
                    service = STATUS_TOPICS.get(sem) or ACK_TOPICS[sem]
                    kind = "status" if sem in STATUS_TOPICS else "ack"
                    alive = s.sample_info.instance_state == InstanceState.Alive
                    sample = None if isinstance(s, InvalidSample) else s
                    items.append(StatusItem(service, kind, source, session, sample, alive))
            if items:
                self.loop.call_soon_threadsafe(self.on_statuses, items)
