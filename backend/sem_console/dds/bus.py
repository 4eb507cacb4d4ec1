"""The DDS participant of a process and the SEM readers and writers made from it."""

from __future__ import annotations

from cyclonedds.core import InstanceState, Qos, ReadCondition, SampleState, ViewState
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from sem_console.dds.config import dds_config
from sem_console.dds.qos import reader_qos, writer_qos
from sem_console.dds.topics import Sem

# One Domain object per domain id per process: Cyclone keeps the first config it was given.
_domains: dict[int, Domain] = {}


class Bus:
    """Owns one DomainParticipant and a Topic per SEM topic (created on first use)."""

    def __init__(self, domain_id: int, interface: str = "lo", peers: str = "127.0.0.1") -> None:
        if domain_id not in _domains:
            _domains[domain_id] = Domain(domain_id, dds_config(interface, peers))
        self.domain_id = domain_id
        self.participant = DomainParticipant(domain_id)
        self._topics: dict[Sem, Topic] = {}

    def topic(self, sem: Sem) -> Topic:
        if sem not in self._topics:
            self._topics[sem] = Topic(self.participant, sem.spec.name, sem.spec.type)
        return self._topics[sem]

    def writer(self, sem: Sem) -> DataWriter:
        return DataWriter(self.participant, self.topic(sem), qos=writer_qos(sem.spec.cls, sem.spec.xcdr1))

    def reader(self, sem: Sem, qos: Qos | None = None) -> DataReader:
        return DataReader(self.participant, self.topic(sem), qos=qos or reader_qos(sem.spec.cls))

    def close(self) -> None:
        self._topics.clear()
        self.participant = None  # type: ignore[assignment]  # entities are deleted with the last reference


def all_samples(reader: DataReader) -> ReadCondition:
    """Every sample, including disposed and no-writer instances.

    cyclonedds-python's plain take/read use this mask already, but its take_iter/read_iter
    and async iterators default to alive instances only and would hide a cancel; we pass
    the condition explicitly, and it doubles as a WaitSet trigger.
    """
    return ReadCondition(reader, ViewState.Any | InstanceState.Any | SampleState.Any)
