"""The private parts of cyclonedds the project uses (sem_console/dds/cyclone_private.py), pinned against the installed
cyclonedds: each exists and behaves as the console relies on. A new cyclonedds that changes one fails here by name.
(What fastcdr makes of the machine trees is pinned to cyclonedds' own decoding by tests/test_fastcdr.py.)"""

from __future__ import annotations

import random
import subprocess
import sys
import time
import tomllib
from dataclasses import fields
from importlib.metadata import version
from pathlib import Path
from typing import Any

from cyclonedds.core import InstanceState, WaitSet
from cyclonedds.idl import IdlStruct
from cyclonedds.util import duration

from sem_console.dds import cyclone_private
from sem_console.dds.bus import Bus, all_samples, take_each
from sem_console.dds.cyclone_private import (
    MACHINE_ATTRIBUTES,
    InvalidSample,
    Triggered,
    machinery,
    take_cdr,
    type_machine,
    wait_for_acks,
    write_cdr,
)
from sem_console.dds.topics import Sem
from support.domains import domain_free
from support.samplegen import random_sample

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def test_the_pinned_version_is_installed() -> None:
    """The contract below is 11.0.1's: the project pins exactly that version."""
    dependencies = tomllib.loads(PYPROJECT.read_text())["project"]["dependencies"]
    assert "cyclonedds==11.0.1" in dependencies
    assert version("cyclonedds") == "11.0.1"


def test_only_cyclone_private_imports_the_private_modules() -> None:
    package = Path(cyclone_private.__file__).parents[1]
    users = sorted(
        str(p.relative_to(package))
        for p in package.rglob("*.py")
        if p.name != "cyclone_private.py"
        and any(
            s in p.read_text() for s in ("cyclonedds._clayer", "cyclonedds.idl._machinery", "_machinery", "cyclonedds.internal")
        )
    )
    assert users == []


def _children(machine: Any) -> list[Any]:
    if isinstance(machine, machinery.InstanceMachine):
        return [type_machine(machine.type, machine.use_version_2)]
    if isinstance(machine, machinery.StructMachine):
        return list(machine.members_machines.values())
    if isinstance(machine, (machinery.OptionalMachine, machinery.SequenceMachine)):
        return [machine.submachine]
    return []


def test_machine_trees_have_what_fastcdr_reads() -> None:
    """Every machine in every SEM type's trees (XCDR1 and XCDR2) is of a class fastcdr handles, with the attributes it
    reads; a struct's members are its dataclass fields, in order."""
    seen: set[type] = set()
    for sem in Sem:
        for v2 in (False, True):
            todo = [type_machine(sem.spec.type, v2)]
            while todo:
                m = todo.pop()
                assert type(m) in MACHINE_ATTRIBUTES, f"{sem.spec.name}: {type(m).__name__} is not handled"
                for attribute in MACHINE_ATTRIBUTES[type(m)]:
                    assert hasattr(m, attribute), f"{type(m).__name__}.{attribute}"
                if isinstance(m, machinery.StructMachine):
                    assert list(m.members_machines) == [f.name for f in fields(m.type)]
                seen.add(type(m))
                todo.extend(_children(m))
    # the trees use most of the classes: the table is not a list of names nobody meets
    assert {
        machinery.StructMachine,
        machinery.PrimitiveMachine,
        machinery.OptionalMachine,
        machinery.EnumMachine,
        machinery.ByteArrayMachine,
        machinery.StringMachine,
    } <= seen


def test_invalid_sample_carries_a_key_and_its_info() -> None:
    assert {f.name for f in fields(InvalidSample)} == {"key_sample", "sample_info"}


def _take_all(reader: Any, seconds: float = 5.0) -> list[tuple[bytes, Any]]:
    deadline = time.monotonic() + seconds
    got: list[tuple[bytes, Any]] = []
    while time.monotonic() < deadline:
        raw = take_cdr(reader, all_samples(reader).mask, 256)
        assert not isinstance(raw, int), f"take failed: {raw}"
        got += raw
        if got:
            return got
        time.sleep(0.02)
    return got


def test_write_cdr_take_cdr_and_wait_for_acks(domain: int) -> None:
    """write_cdr publishes serialised CDR with the given source timestamp; take_cdr hands back (CDR, info) per sample,
    a dispose as a key with valid_data false; wait_for_acks returns True once a reliable reader has it all."""
    bus = Bus(domain)
    sem = Sem.INS_REPORT
    reader, writer = bus.reader(sem), bus.writer(sem)
    sample = random_sample(sem.spec.type, random.Random(1), absent=0.0)
    data = sample.serialize(use_version_2=sem.spec.xcdr2_only)
    data = data.ljust((len(data) + 3) & ~3, b"\0")
    deadline = time.monotonic() + 10
    while not writer.get_matched_subscriptions() and time.monotonic() < deadline:
        time.sleep(0.02)
    stamp = 1_700_000_000_123_456_789
    assert write_cdr(writer, data, stamp) >= 0
    assert wait_for_acks([writer], 5.0)
    ((cdr, info),) = _take_all(reader)
    assert info.valid_data and info.source_timestamp == stamp and info.instance_state == InstanceState.Alive
    assert sem.spec.type.deserialize(cdr) == sample
    writer.dispose(sample)
    ((key, info),) = _take_all(reader)
    assert not info.valid_data and info.instance_state == InstanceState.NotAliveDisposed
    assert isinstance(sem.spec.type.deserialize_key(key), IdlStruct)
    # take_each (bus.py) builds InvalidSample from a key's CDR, as a plain take would
    writer.write(sample)
    assert len(_take_all(reader)) == 1
    writer.dispose(sample)
    deadline = time.monotonic() + 5
    taken: list[Any] = []
    while not taken and time.monotonic() < deadline:
        taken = take_each(reader)[0]
        time.sleep(0.02)
    assert len(taken) == 1 and isinstance(taken[0], InvalidSample)
    assert taken[0].sample_info.instance_state == InstanceState.NotAliveDisposed
    bus.close()


def test_prepared_writes_put_on_the_wire_what_write_does(domain: int) -> None:
    """sem-sim writes its reports with write_cdr from bytes serialised with writer_version_2 (sim/prepared.py): for
    every report topic of both UMAA versions, final and appendable, a reader takes the very CDR DataWriter.write
    sends, of the same instance, whether the bytes came from a new layout or an existing one."""
    import copy

    from sem_console.dds.qos import TopicClass
    from sem_console.dds.topics import Sem60, to_appendable
    from sem_console.sim.prepared import PreparedWriter

    bus = Bus(domain)
    rng = random.Random(2)
    pinned = 0
    for sem in [s for s in (*Sem, *Sem60) if s.spec.cls is TopicClass.REPORT]:
        for appendable in (False, True) if sem.spec.appendable is not None else (False,):
            writer, reader = bus.writer(sem, appendable=appendable), bus.reader(sem, appendable=appendable)
            deadline = time.monotonic() + 10
            while not writer.get_matched_subscriptions() and time.monotonic() < deadline:
                time.sleep(0.02)
            prepared = PreparedWriter(writer)
            a = random_sample(sem.spec.type, rng)
            if getattr(a, "satellites", None):
                a.satellites = a.satellites[:6]
            b = copy.deepcopy(a)
            b.timeStamp = random_sample(type(a.timeStamp), rng)
            wire = []
            for write, sample in ((writer.write, a), (prepared.write, a), (prepared.write, b), (writer.write, b)):
                write(to_appendable(sample) if appendable else sample)
                assert wait_for_acks([writer], 5.0)
                ((cdr, info),) = _take_all(reader)
                wire.append((cdr, info.instance_handle))
            assert wire[0] == wire[1] and wire[2] == wire[3], (sem.name, appendable)
            assert wire[0][0] != wire[2][0]
            pinned += 1
    assert pinned >= 10
    bus.close()


def test_a_batching_writer_has_cyclones_batching_and_flushes(domain: int) -> None:
    """Bus.writer(batching=True) makes a BatchingDataWriter: Cyclone's own QoS of the writer says it batches (a plain
    writer's does not), its samples reach a reader, and write_flush is Cyclone's call (return code 0). The reader is on
    the writer's participant, which Cyclone serves directly: that the flush sends the batch over the wire is
    test_sim_flush.py's (a reader in another process)."""
    import ctypes as ct

    from cyclonedds.internal import DDS

    from sem_console.dds.cyclone_private import BatchingDataWriter, write_flush

    dll = ct.CDLL(DDS._dll_handle._name)  # Cyclone's own view of the writer's QoS (functions of its own)
    dll.dds_create_qos.restype = ct.c_void_p
    dll.dds_get_qos.argtypes = [ct.c_int32, ct.c_void_p]
    dll.dds_qget_writer_batching.argtypes = [ct.c_void_p, ct.POINTER(ct.c_bool)]
    dll.dds_qget_writer_batching.restype = ct.c_bool
    dll.dds_delete_qos.argtypes = [ct.c_void_p]

    def batching(writer: Any) -> bool:
        qos, flag = dll.dds_create_qos(), ct.c_bool(False)
        try:
            assert dll.dds_get_qos(writer._ref, qos) == 0
            return bool(dll.dds_qget_writer_batching(qos, ct.byref(flag)) and flag.value)
        finally:
            dll.dds_delete_qos(qos)

    bus = Bus(domain)
    sem = Sem.INS_REPORT
    batched, plain, reader = bus.writer(sem, batching=True), bus.writer(sem), bus.reader(sem)
    assert isinstance(batched, BatchingDataWriter) and batching(batched)
    assert not isinstance(plain, BatchingDataWriter) and not batching(plain)
    deadline = time.monotonic() + 10
    while not batched.get_matched_subscriptions() and time.monotonic() < deadline:
        time.sleep(0.02)
    sample = random_sample(sem.spec.type, random.Random(4), absent=0.0)
    batched.write(sample)
    assert write_flush(batched) == 0 and write_flush(plain) == 0
    assert wait_for_acks([batched], 5.0)
    ((cdr, info),) = _take_all(reader)
    assert info.valid_data and sem.spec.type.deserialize(cdr) == sample
    bus.close()


def test_triggered_names_the_conditions_with_samples(domain: int) -> None:
    """Triggered.wait hands back the attach-order index of each triggered condition (by a sample, a dispose, a writer
    gone; several at once in attach order), and none on a timeout."""
    bus = Bus(domain)
    readers = [bus.reader(sem) for sem in (Sem.GPS_FIX_REPORT, Sem.INS_REPORT, Sem.GPS_REPORT)]
    waitset = WaitSet(bus.participant)
    conditions = [all_samples(r) for r in readers]
    for c in conditions:
        waitset.attach(c)
    triggered = Triggered(waitset)
    assert triggered.wait(duration(milliseconds=1)) == []
    writer = bus.writer(Sem.INS_REPORT)
    deadline = time.monotonic() + 10
    while not writer.get_matched_subscriptions() and time.monotonic() < deadline:
        time.sleep(0.02)
    writer.write(random_sample(Sem.INS_REPORT.spec.type, random.Random(2), absent=0.0))
    assert wait_for_acks([writer], 5.0)
    assert triggered.wait(duration(seconds=5)) == [1]
    assert len(_take_all(readers[1])) == 1
    assert triggered.wait(duration(milliseconds=1)) == []  # taken: no longer triggered
    # a dispose and a writer gone (no data, an instance state) trigger the condition too: the console learns of both
    # only by taking them
    ins = random_sample(Sem.INS_REPORT.spec.type, random.Random(3), absent=0.0)
    for change in (writer.dispose, writer.unregister_instance):
        writer.write(ins)
        assert wait_for_acks([writer], 5.0)
        assert triggered.wait(duration(seconds=5)) == [1]
        assert len(_take_all(readers[1])) == 1
        change(ins)
        assert triggered.wait(duration(seconds=5)) == [1]
        ((_key, info),) = _take_all(readers[1])
        assert not info.valid_data and info.instance_state != InstanceState.Alive
    # two conditions at once: both, in attach order
    others = [bus.writer(sem) for sem in (Sem.GPS_REPORT, Sem.GPS_FIX_REPORT)]
    deadline = time.monotonic() + 10
    while not all(w.get_matched_subscriptions() for w in others) and time.monotonic() < deadline:
        time.sleep(0.02)
    for w, sem in zip(others, (Sem.GPS_REPORT, Sem.GPS_FIX_REPORT), strict=True):
        w.write(random_sample(sem.spec.type, random.Random(4), absent=0.0))
    assert wait_for_acks(others, 5.0)
    assert triggered.wait(duration(seconds=5)) == [0, 2]
    bus.close()


_CYCLE_SCRIPT = """
import gc, sys, time
from cyclonedds.core import Listener
from sem_console.dds.bus import Bus
from sem_console.dds.topics import Sem
domain = int(sys.argv[1])
bus = Bus(domain)
reader = bus.reader(Sem.GPS_FIX_COMMAND_STATUS, listener=Listener(on_subscription_matched=lambda r, s: None))
holder = {"reader": reader}
holder["self"] = holder  # the cycle
reader.holder = holder
bus.close()
del reader, holder
gc.collect()
other = Bus(domain)
writer = other.writer(Sem.GPS_FIX_COMMAND_STATUS)  # matched with the reader here, were it left
time.sleep(1.0)
print("matched", len(writer.get_matched_subscriptions()))
other.close()
other.close()  # closing twice does nothing
"""


def test_closing_a_bus_deletes_readers_held_in_a_reference_cycle(domain: int) -> None:
    """A reader whose Python object sits in a reference cycle, with a listener (as the console's readers have), is
    gone from Cyclone once its bus is closed. cyclonedds-python alone never deletes such an entity; a reader left so,
    its listener's callback freed, crashes the next writer to match it in the process (a child here: that crash
    fails this test by its exit signal, not the worker running it)."""
    done = subprocess.run([sys.executable, "-c", _CYCLE_SCRIPT, str(domain)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    assert done.stdout.split() == ["matched", "0"]


def test_the_last_bus_of_a_domain_closed_leaves_no_socket_of_it(domain: int) -> None:
    """A process that used a domain id does not look like a participant in it once its buses are closed: the domain
    (which holds the sockets) is deleted with its last bus, and a later bus opens it again. A pytest worker's domains
    stay free for its later tests so (tests/conftest.py `free_domain`)."""
    first, second = Bus(domain), Bus(domain)
    assert not domain_free(domain, own_ok=False)
    first.close()
    assert not domain_free(domain, own_ok=False), "the second bus is still open"
    second.close()
    assert domain_free(domain, own_ok=False)
    again = Bus(domain)
    try:
        writer, reader = again.writer(Sem.INS_REPORT), again.reader(Sem.INS_REPORT)
        sample = random_sample(Sem.INS_REPORT.spec.type, random.Random(1))
        writer.write(sample)
        deadline = time.monotonic() + 5
        while not (got := reader.take(N=1)) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert got, "the reopened domain carries samples"
    finally:
        again.close()
    assert domain_free(domain, own_ok=False)
