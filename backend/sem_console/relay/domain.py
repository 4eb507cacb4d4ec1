"""The relay's DDS side: raw readers of the SEM topics it sends (the CDR as it came off the wire, disposes and lost
writers included) and writers of those it receives, with the project's QoS per topic class."""

from __future__ import annotations

import logging
import threading
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from cyclonedds.core import InstanceState, Policy, Qos, ReadCondition, WaitSet
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader

from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.cyclone_private import Triggered, take_cdr, write_cdr
from sem_console.dds.qos import TopicClass, reader_qos, umaa_command_qos
from sem_console.dds.topics import AnySem, delimited, final_type_qos
from sem_console.relay.wire import Kind

log = logging.getLogger("sem-relay")
_IGNORE_OWN = Qos(Policy.IgnoreLocal.Participant)  # never read back what this relay wrote
# encapsulation ids (first two bytes, big endian) a writer of the project's QoS sends: XCDR1 or XCDR2, final types
_PLAIN_CDR, _PLAIN_CDR2 = {0x0000, 0x0001}, {0x0006, 0x0007}


@dataclass(frozen=True)
class Taken:
    """One sample, dispose or unregistration taken from the domain."""

    sem: AnySem
    kind: Kind
    data: bytes  # the sample's CDR; a dispose's or unregistration's: the key's CDR
    source_ns: int
    vehicle: uuid.UUID
    instance: tuple[str, bool, int]  # (topic, of the appendable copy, instance handle): unique on this domain


def vehicle_of(sem: AnySem, sample: Any) -> uuid.UUID:
    """The vehicle a sample is of: a command's destination, else its source (UMAA 6.0's identifiers: their `id`)."""
    raw = sample.destination if sem.spec.cls is TopicClass.COMMAND else sample.source
    return uuid.UUID(bytes=bytes(getattr(raw, "id", raw)))


class DomainSide:
    """Reads `reads` on the domain in a thread of its own (handing each take to `on_taken` there), writes `writes`."""

    def __init__(self, bus: Bus, reads: list[AnySem], on_taken: Callable[[Taken], None]) -> None:
        self.bus, self.on_taken = bus, on_taken
        self.readers: list[tuple[AnySem, bool, DataReader[Any], ReadCondition]] = []
        for sem in reads:
            for appendable in (False, True) if sem.spec.appendable is not None else (False,):
                qos = reader_qos(sem.spec.cls) + umaa_command_qos(False) if sem.spec.command_qos_lib else reader_qos(sem.spec.cls)
                qos = qos + _IGNORE_OWN + (Qos() if appendable else final_type_qos(sem))
                reader = bus.reader(sem, qos=qos, appendable=appendable)
                self.readers.append((sem, appendable, reader, all_samples(reader)))
        self.writers: dict[tuple[AnySem, bool], DataWriter[Any]] = {}
        self._vehicles: dict[tuple[str, bool, int], tuple[uuid.UUID, bytes]] = {}  # instance -> vehicle, key CDR
        self._write_lock = threading.Lock()
        self.stopping = threading.Event()
        self._thread = threading.Thread(target=self._run, name="relay-dds", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def _run(self) -> None:
        waitset = WaitSet(self.bus.participant)
        for _sem, _appendable, _reader, condition in self.readers:
            waitset.attach(condition)
        triggered = Triggered(waitset)
        while not self.stopping.is_set():
            for i in triggered.wait(200_000_000):
                sem, appendable, reader, condition = self.readers[i]
                raw = take_cdr(reader, condition.mask, 256)
                if isinstance(raw, int):
                    continue
                # a sample's instance state is its instance's at the take: an end goes after its instance's last sample
                last = {int(info.instance_handle): i for i, (_data, info) in enumerate(raw)}
                for i, (data, info) in enumerate(raw):
                    try:
                        self._take(sem, appendable, data, info, last[int(info.instance_handle)] == i)
                    except Exception as e:  # whatever a writer sent, only this sample is lost
                        log.warning("a sample of %s could not be read: %s", sem.spec.name, e)

    def _take(self, sem: AnySem, appendable: bool, data: bytes, info: Any, last: bool) -> None:
        """One sample taken; `last`: the last of its instance in its take (the one its instance's end follows)."""
        instance = (sem.spec.name, appendable, int(info.instance_handle))
        known = self._vehicles.get(instance)
        if known is None:
            dtype = sem.spec.appendable if appendable and sem.spec.appendable is not None else sem.spec.type
            sample = dtype.deserialize(data) if info.valid_data else dtype.deserialize_key(data)
            known = self._vehicles[instance] = (vehicle_of(sem, sample), sample.serialize_key() if info.valid_data else data)
        vehicle, key_cdr = known
        ts = int(info.source_timestamp)
        if info.valid_data:
            self.on_taken(Taken(sem, Kind.SAMPLE, data, ts, vehicle, instance))
        if last and info.instance_state != InstanceState.Alive:  # a dispose after an unread sample shows only in its state
            kind = Kind.DISPOSE if info.instance_state == InstanceState.NotAliveDisposed else Kind.UNREGISTER
            self.on_taken(Taken(sem, kind, key_cdr, ts, vehicle, instance))
            self._vehicles.pop(instance, None)

    def writer(self, sem: AnySem, appendable: bool) -> DataWriter[Any]:
        w = self.writers.get((sem, appendable))
        if w is None:
            w = self.writers[(sem, appendable)] = self.bus.writer(sem, appendable=appendable)
        return w

    def open_writers(self, sems: list[AnySem]) -> None:
        """Writers of these topics now, before their first sample: a checker on the domain finds every topic of a
        vehicle's service written (ICD 5.1.1, Table 6), as on the vehicle's own domain."""
        with self._write_lock:
            for sem in sems:
                self.writer(sem, False)

    def write(self, sem: AnySem, kind: Kind, data: bytes, source_ns: int) -> None:
        """Write what came over the link: a sample's CDR as it was sent (an appendable writer's by a writer of the
        type's appendable copy), or dispose or unregister the instance of a key's CDR."""
        appendable = sem.spec.appendable is not None and delimited(data)
        with self._write_lock:
            w = self.writer(sem, appendable)
            if kind is not Kind.SAMPLE:
                dtype = sem.spec.appendable if appendable and sem.spec.appendable is not None else sem.spec.type
                key = dtype.deserialize_key(data)
                if kind is Kind.DISPOSE:
                    w.dispose(key, timestamp=source_ns)
                else:
                    w.unregister_instance(key, timestamp=source_ns)
                return
            if not appendable and int.from_bytes(data[:2], "big") not in (_PLAIN_CDR2 if sem.spec.xcdr2_only else _PLAIN_CDR):
                data = sem.spec.type.deserialize(data).serialize(use_version_2=sem.spec.xcdr2_only)
            ret = write_cdr(w, data.ljust((len(data) + 3) & ~3, b"\0"), source_ns)
            if ret < 0:
                raise RuntimeError(f"Cyclone refused the write ({ret})")

    def stop(self) -> None:
        self.stopping.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2)
