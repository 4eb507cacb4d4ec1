"""Every private part of cyclonedds-python the project uses, in this one module (cyclonedds==11.0.1, pinned in
backend/pyproject.toml). `tests/system/test_cyclone_private.py` pins each of them against the installed version: a new
cyclonedds that moves or changes one fails there, by name, instead of somewhere in the console.

Why each is needed (none has a public equivalent in 11.0.1):
- `take_cdr`: `DataReader.take` without its decode, so the console decodes each sample itself (`codec/decode.py`:
  one sample Python cannot decode costs only itself; the copies of a sample other readers own are dropped
  undecoded) and the recorder keeps the CDR as it came off the wire.
- `write_cdr`: `DataWriter.write` of bytes already serialised, with their source timestamp (`sem-replay`
  republishes recorded CDR as it was recorded).
- `writer_version_2`: the XCDR version `DataWriter.write` serialises with, which `sem-sim` serialises its prepared
  samples with (`sim/prepared.py`) to write them with `write_cdr`.
- `wait_for_acks`: `DataWriter.wait_for_acks` raises AttributeError on a timeout in 11.0.1 (it compares with
  `Exception.DDS_RETCODE_TIMEOUT`, which does not exist), so the C function it wraps is called here.
- `type_machine` and `machinery`: the tree of "machines" cyclonedds serialises a type with (its layout rules:
  alignment, headers, optional flags), which `codec/fastcdr.py` compiles into a decoder per type.
- `delete_entity`: deletes a participant (or a domain) in Cyclone at once; cyclonedds-python has no public delete and leaves
  it to `__del__`, which never deletes an entity freed in a reference cycle (the function says why that crashes).
- `Triggered`: `WaitSet.wait` returns only how many conditions triggered, not which; the ingest threads take
  only the readers that have samples (a sample's copies reach two or three of a topic's readers, and every report
  topic has three to six, so a take of all of them on every wake cost more than the sample itself).
- `InvalidSample`: what a take returns for a dispose or an instance without writers (a key, no data).
- `BatchingDataWriter` and `write_flush`: a writer with Cyclone's writer batching QoS (its samples wait in the writer
  until `write_flush` sends them, many to a datagram), which cyclonedds-python's `Qos` has no policy for: `sem-sim`
  writes a thousand vehicles' reports in a tick and sends them at its end, at half the CPU of a datagram each.
"""

from __future__ import annotations

import ctypes as ct
import time
from collections.abc import Iterable
from enum import Enum
from typing import Any, cast

from cyclonedds._clayer import ddspy_take, ddspy_write_ts
from cyclonedds.core import DDSException, Entity, WaitSet
from cyclonedds.idl import IdlStruct
from cyclonedds.idl import _machinery as machinery
from cyclonedds.internal import DDS, SampleInfo, dds_c_t
from cyclonedds.internal import InvalidSample as InvalidSample
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.util import duration

__all__ = [
    "MACHINE_ATTRIBUTES",
    "BatchingDataWriter",
    "InvalidSample",
    "Triggered",
    "delete_entity",
    "enum_type",
    "machinery",
    "take_cdr",
    "type_machine",
    "wait_for_acks",
    "write_cdr",
    "write_flush",
    "writer_version_2",
]

# The machine classes codec/fastcdr.py handles and what it reads of each (the test walks every SEM type's trees)
MACHINE_ATTRIBUTES: dict[type, tuple[str, ...]] = {
    machinery.InstanceMachine: ("type", "use_version_2"),
    machinery.StructMachine: ("type", "members_machines"),
    machinery.PrimitiveMachine: ("code", "size", "alignment"),
    machinery.EnumMachine: ("enum", "alignment"),
    machinery.BitBoundEnumMachine: ("enum", "code", "size", "alignment"),
    machinery.ByteArrayMachine: ("size",),
    machinery.OptionalMachine: ("submachine",),
    machinery.StringMachine: (),
    machinery.PlainCdrV2SequenceOfPrimitiveMachine: ("code", "size", "alignment"),
    machinery.SequenceMachine: ("submachine", "add_size_header"),
    machinery.PlainCdrV2ArrayOfPrimitiveMachine: ("code", "size", "alignment"),
}


def take_cdr(reader: DataReader[Any], mask: int, n: int) -> list[tuple[bytes, SampleInfo]] | int:
    """Take up to `n` samples matching the read condition `mask`: (CDR with its 4-byte encapsulation header, info) per
    sample (a key's CDR when `info.valid_data` is false), or Cyclone's negative return code."""
    result: list[tuple[bytes, SampleInfo]] | int = ddspy_take(reader._ref, mask, n)  # noqa: SLF001 (see the module)
    return result


class Triggered:
    """Which attached conditions triggered: `wait(timeout_ns)` waits at most that long for any of them and returns the
    indices (in attach order) of those that did, none on a timeout. `WaitSet.wait` asks Cyclone for no list; this asks
    for every attached entity's slot. The slots and their index are built once, here (the waitset's attachments must
    not change afterwards): an ingest thread waits once per sample, and what it does after a wake delays that sample."""

    def __init__(self, waitset: WaitSet) -> None:
        self.waitset = waitset
        attached = waitset.attached  # (entity, its attach argument: a c_int whose address Cyclone hands back)
        self._slots = (dds_c_t.attach * len(attached))()
        self._index = {ct.addressof(arg): i for i, (_entity, arg) in enumerate(attached)}

    def wait(self, timeout_ns: int) -> list[int]:
        n: int = self.waitset._waitset_wait(self.waitset._ref, self._slots, len(self._slots), timeout_ns)  # noqa: SLF001 (see the module)
        if n < 0:
            raise DDSException(n, "Occurred while waiting in a WaitSet")
        index = self._index
        return sorted(index[slot] for slot in self._slots[:n] if slot in index)


def write_cdr(writer: DataWriter[Any], data: bytes, timestamp_ns: int) -> int:
    """Write serialised CDR (encapsulation header included, padded to 4 bytes) with this source timestamp (ns since
    the epoch). Returns Cyclone's return code (negative on failure)."""
    result: int = ddspy_write_ts(writer._ref, data, timestamp_ns)  # noqa: SLF001 (see the module)
    return result


_qset_writer_batching = DDS._dll_handle.dds_qset_writer_batching  # noqa: SLF001 (see the module)
_qset_writer_batching.argtypes, _qset_writer_batching.restype = [dds_c_t.qos_p, ct.c_bool], None
_write_flush = DDS._dll_handle.dds_write_flush  # noqa: SLF001 (see the module)
_write_flush.argtypes, _write_flush.restype = [dds_c_t.entity], dds_c_t.returnv


class BatchingDataWriter(DataWriter[Any]):
    """A DataWriter whose samples wait in Cyclone until `write_flush` sends them (Cyclone's writer batching QoS). Give
    it a QoS: the batching is set on it."""

    def _create_writer(self, publisher: int, topic: int, qos: Any, listener: Any) -> int:
        if not qos:
            raise ValueError("a batching writer needs a QoS to set its batching on")
        _qset_writer_batching(qos, True)
        ref: int = DataWriter._create_writer(self, publisher, topic, qos, listener)  # noqa: SLF001 (see the module)
        return ref


def write_flush(writer: DataWriter[Any]) -> int:
    """Send what a batching writer holds now. Returns Cyclone's return code (negative on failure)."""
    result: int = _write_flush(writer._ref)  # noqa: SLF001 (see the module)
    return result


def writer_version_2(writer: DataWriter[Any]) -> bool | None:
    """The XCDR version `DataWriter.write` serialises with: True XCDR2, False XCDR1, None the type's own."""
    v2: bool | None = writer._use_version_2  # noqa: SLF001 (see the module)
    return v2


def wait_for_acks(writers: Iterable[DataWriter[Any]], seconds: float) -> bool:
    """Wait until every matched reliable reader has acknowledged what the writers wrote, `seconds` in all (not
    each). True when all were acknowledged."""
    deadline = time.monotonic() + seconds
    ok = True
    for w in writers:
        remaining = max(0.0, deadline - time.monotonic())
        ret = w._wait_for_acks(w._ref, duration(seconds=remaining))  # noqa: SLF001 (see the module)
        ok = ok and ret == 0
    return ok


def enum_type(machine: machinery.EnumMachine | machinery.BitBoundEnumMachine) -> type[Enum]:
    """The enum class an enum machine reads (cyclonedds annotates the attribute as an Enum; it holds the class)."""
    return cast("type[Enum]", machine.enum)


def type_machine(cls: type[IdlStruct], v2: bool) -> machinery.Machine:
    """The root machine cyclonedds serialises `cls` with: XCDR2 (`v2`) or XCDR1."""
    idl = cls.__idl__
    idl.populate()
    machine: machinery.Machine = idl.v2_machine if v2 else idl.v1_machine
    return machine


def delete_entity(entity: Entity) -> None:
    """Delete a participant and its readers, writers, topics and conditions (or a domain and its participants, whose
    sockets it holds) in Cyclone at once.

    Not left to Python's collector: cyclonedds-python deletes an entity in its `__del__` only while its weak
    registry still holds it, and the cycle collector clears weak references before it calls `__del__`, so an
    entity freed as part of a reference cycle is never deleted in Cyclone. Such a reader stays matched with its
    listener's callback freed, and the next writer to match it in this process calls freed memory: a segfault
    (seen as a pytest worker lost after an in-process console had left a domain id the worker used again). The
    Python objects of the children stay until collected; deleting their stale handles then does nothing.
    """
    ref: int = entity._ref  # noqa: SLF001 (see the module)
    Entity._entities.pop(ref, None)  # noqa: SLF001 (its own __del__ must not delete the handle again)
    entity._delete(ref)  # noqa: SLF001 (see the module)
