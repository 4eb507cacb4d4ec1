"""The DDS participant of a process and the SEM readers and writers made from it."""

from __future__ import annotations

import logging
import os
import threading
from pathlib import Path
from typing import Any

from cyclonedds.core import DDSException, InstanceState, Listener, Qos, ReadCondition, SampleState, ViewState
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.pub import DataWriter, Publisher
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from sem_console.dds.config import dds_config, peers_problem
from sem_console.dds.cyclone_private import BatchingDataWriter, InvalidSample, delete_entity, take_cdr
from sem_console.dds.cyclone_private import wait_for_acks as wait_for_acks
from sem_console.dds.qos import PUBLISHER, TopicClass, reader_qos, representation, umaa_command_qos, writer_qos
from sem_console.dds.security import BusSecurity, SecurityError, from_uri, load, plugins_missing
from sem_console.dds.topics import AnySem

# One Domain object per domain id per process: Cyclone keeps the first config it was given (and its security). It
# holds the domain's sockets until deleted: it is deleted with the last Bus of its domain id, so that a process that
# used a domain id (a test worker, sem-check) does not look like a participant in it any more.
_domains: dict[int, Domain] = {}
_security: dict[int, BusSecurity | None] = {}
_buses: dict[int, int] = {}  # the Buses open in each domain id
_opening = threading.Lock()
log = logging.getLogger("sem-console.dds")


class DdsConfigError(RuntimeError):
    """Cyclone refused the configuration (a bad CYCLONEDDS_URI, an interface that does not exist, security
    documents it cannot join with)."""


def bus_security(folder: Path | None, domain_id: int) -> BusSecurity | None:
    """The DDS Security a process joins `domain_id` with: the identity in `folder` (--dds-security), else
    CYCLONEDDS_URI's <Security> section's for that domain, else None (an open bus); DdsConfigError (one line) for
    documents the participant could not join with, or a Cyclone DDS without the security plugins."""
    uri = os.environ.get("CYCLONEDDS_URI", "").strip()
    try:
        security = load(folder) if folder is not None else from_uri(uri, domain_id)
    except SecurityError as e:
        raise DdsConfigError(str(e)) from None
    if security is not None and (problem := plugins_missing()):
        raise DdsConfigError(problem)
    return security


def open_domain(domain_id: int, interface: str = "lo", peers: str = "127.0.0.1", security: BusSecurity | None = None) -> Domain:
    """The process's Domain for this id, created from CYCLONEDDS_URI or the interface and peers settings, with the
    identity's <Security> configuration beside it when given (bus_security)."""
    with _opening:
        return _open_domain(domain_id, interface, peers, security)


def _open_domain(domain_id: int, interface: str, peers: str, security: BusSecurity | None) -> Domain:
    if domain_id not in _domains:
        uri = bool(os.environ.get("CYCLONEDDS_URI", "").strip())
        if not uri and (problem := peers_problem(peers)):  # Cyclone would abort the process on it
            raise DdsConfigError(problem)
        source = "CYCLONEDDS_URI" if uri else f"interface {interface!r}, peers {peers!r}"
        config = dds_config(interface, peers)
        if security is None and uri:  # the operator's own <Security> section, told as the bus's state
            security = from_uri(os.environ["CYCLONEDDS_URI"], domain_id)
        if security is not None and security.config:
            config, source = f"{config},{security.config}", f"{source} and {security.source}"
        try:
            _domains[domain_id] = Domain(domain_id, config)
        except (DDSException, UnicodeEncodeError) as e:
            raise DdsConfigError(
                f"Cyclone DDS could not start domain {domain_id} with the configuration from {source} "
                f"(Cyclone prints the reason before this line): {e}"
            ) from None
        _security[domain_id] = security
        if security is not None:  # an open bus is said by the commands that keep a log (OPEN_BUS)
            log.info("domain %d: %s", domain_id, security.describe())
    return _domains[domain_id]


def domain_security(domain_id: int) -> BusSecurity | None:
    """The DDS Security the process's domain was opened with (None: an open bus, or not opened)."""
    return _security.get(domain_id)


class Bus:
    """Owns one DomainParticipant and a Topic per SEM topic (created on first use)."""

    def __init__(
        self, domain_id: int, interface: str = "lo", peers: str = "127.0.0.1", security: BusSecurity | None = None
    ) -> None:
        self.domain_id = domain_id
        with _opening:
            _open_domain(domain_id, interface, peers, security)
            secured = domain_security(domain_id)
            try:
                self.participant = DomainParticipant(domain_id)
            except DDSException as e:
                if secured is None:
                    raise
                raise DdsConfigError(
                    f"Cyclone DDS refused a participant with the DDS Security of {secured.source} "
                    f"(Cyclone prints the reason before this line): {e}"
                ) from None
            _buses[domain_id] = _buses.get(domain_id, 0) + 1
        self.publisher = Publisher(self.participant, qos=PUBLISHER)  # every writer's (qos.PUBLISHER: RTI's UMAA kit)
        self._topics: dict[AnySem, Topic[Any]] = {}
        self._appendable_topics: dict[AnySem, Topic[Any]] = {}  # of the types' appendable copies (TopicSpec.appendable)

    def topic(self, sem: AnySem, appendable: bool = False) -> Topic[Any]:
        """The topic of the type, or of its appendable copy (TopicSpec.appendable)."""
        if appendable:
            return self._appendable_topic(sem)
        if sem not in self._topics:
            self._topics[sem] = Topic(self.participant, sem.spec.name, sem.spec.type)
        return self._topics[sem]

    def writer(self, sem: AnySem, appendable: bool = False, batching: bool = False) -> DataWriter[Any]:
        """A writer with the topic class's QoS and the type's data representation; `appendable`: of the type's
        appendable copy (TopicSpec.appendable: sem-replay republishes an RTI vehicle's samples as they were sent);
        `batching`: its samples wait in it until `cyclone_private.write_flush` sends them, many to a datagram."""
        topic = self._appendable_topic(sem) if appendable else self.topic(sem)
        qos = writer_qos(sem.spec.cls) + representation(sem.spec.xcdr2_only, writer=True)
        kind = BatchingDataWriter if batching else DataWriter
        try:
            return kind(self.publisher, topic, qos=qos + umaa_command_qos(True) if sem.spec.command_qos_lib else qos)
        except DDSException as e:
            raise self._refused(e, sem, "write") from None

    def _appendable_topic(self, sem: AnySem) -> Topic[Any]:
        cls = sem.spec.appendable
        if cls is None:
            raise ValueError(f"{sem.spec.name} has no appendable copy")
        if sem not in self._appendable_topics:  # the same topic name, another type: Cyclone keeps a type per topic
            self._appendable_topics[sem] = Topic(self.participant, sem.spec.name, cls)
        return self._appendable_topics[sem]

    def reader(
        self, sem: AnySem, qos: Qos | None = None, listener: Listener | None = None, appendable: bool = False
    ) -> DataReader[Any]:
        """A reader with the given QoS (else the topic class's, with RTI's CommandQoS on a topic that takes it),
        always with the type's data representation; `appendable`: of the type's appendable copy (TopicSpec.appendable)."""
        if qos is None:
            qos = reader_qos(sem.spec.cls) + umaa_command_qos(False) if sem.spec.command_qos_lib else reader_qos(sem.spec.cls)
        qos = qos + representation(sem.spec.xcdr2_only, writer=False)
        topic = self._appendable_topic(sem) if appendable else self.topic(sem)
        try:
            return DataReader(self.participant, topic, qos=qos, listener=listener)
        except DDSException as e:
            raise self._refused(e, sem, "read") from None

    def _refused(self, e: DDSException, sem: AnySem, what: str) -> Exception:
        """DdsConfigError (one line) for an endpoint the identity's permissions do not allow, else `e`."""
        secured = domain_security(self.domain_id)
        if secured is None or e.code != DDSException.DDS_RETCODE_NOT_ALLOWED_BY_SECURITY:
            return e
        role = "station" if sem.spec.cls is TopicClass.COMMAND else "vehicle"
        return DdsConfigError(
            f"{secured.describe()}: its permissions do not let it {what} {sem.spec.name}: give this command an identity "
            f"that may (sem-keys issue FLEET NAME --role {role}; docs/security.md)"
        )

    def close(self) -> None:
        """Delete the participant, and in Cyclone everything made from it, now (closing twice does nothing)."""
        self._topics.clear()
        self._appendable_topics.clear()
        if self.participant is None:
            return
        with _opening:
            delete_entity(self.participant)
            self.participant = None  # type: ignore[assignment]
            _buses[self.domain_id] -= 1
            if _buses[self.domain_id] == 0:
                del _buses[self.domain_id]
                _security.pop(self.domain_id, None)
                domain = _domains.pop(self.domain_id, None)
                if domain is not None:
                    delete_entity(domain)


def all_samples(reader: DataReader[Any]) -> ReadCondition:
    """Every sample, including disposed and no-writer instances.

    cyclonedds-python's plain take/read use this mask already, but its take_iter/read_iter
    and async iterators default to alive instances only and would hide a cancel; we pass
    the condition explicitly, and it doubles as a WaitSet trigger.
    """
    return ReadCondition(reader, ViewState.Any | InstanceState.Any | SampleState.Any)


def take_each(reader: DataReader[Any], condition: ReadCondition | None = None, n: int = 256) -> tuple[list[Any], int]:
    """Take every sample (by `condition`, else all, disposes included) and decode each on its own:
    one a Python decoder refuses (a string that is not UTF-8, say) costs only itself. Returns the
    decoded samples (InvalidSample for a dispose) and how many could not be decoded."""
    mask = (condition or all_samples(reader)).mask
    dtype = reader.topic.data_type
    out: list[Any] = []
    bad = 0
    while True:
        raw = take_cdr(reader, mask, n)
        if isinstance(raw, int):
            break
        for data, info in raw:
            try:
                sample = dtype.deserialize(data) if info.valid_data else InvalidSample(dtype.deserialize_key(data), info)
            except Exception:  # whatever a peer sent, only this sample is lost
                bad += 1
                continue
            if info.valid_data:
                sample.sample_info = info
            out.append(sample)
        if len(raw) < n:
            break
    return out, bad
