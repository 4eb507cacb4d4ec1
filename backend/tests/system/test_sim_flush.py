"""sem-sim's reports leave the process at the end of the tick that wrote them (its writers batch them; sim/provider.py
flushes them): read without repair (best-effort, from another process), every report of a tick has arrived once the
simulator is frozen after it, however long the reader looks. Without the flush the last tick's reports stay in the
writers' batches (Cyclone sends a batch when the next write finds its writer idle, or a reliable reader asks): the
functional form of a delay bound, which a loaded machine would break."""

from __future__ import annotations

import signal
import time
from typing import Any

from cyclonedds.core import Policy, Qos

from sem_console.dds.bus import Bus
from sem_console.dds.cyclone_private import InvalidSample
from sem_console.dds.qos import TopicClass, reader_qos
from sem_console.dds.topics import Sem

REPORTS = [sem for sem in Sem if sem.spec.cls is TopicClass.REPORT]


def test_each_ticks_reports_leave_at_its_end(sim: Any, new_bus: Any, domain: int) -> None:
    bus: Bus = new_bus(domain)
    best_effort = reader_qos(TopicClass.REPORT, durable=False) + Qos(Policy.Reliability.BestEffort)
    readers = {sem: bus.reader(sem, best_effort) for sem in REPORTS}
    counts: dict[tuple[str, bytes], int] = {}  # by topic and vehicle

    def take() -> None:
        for sem, r in readers.items():
            for s in r.take(N=1000):
                if not isinstance(s, InvalidSample):
                    key = (sem.name, bytes(s.source))
                    counts[key] = counts.get(key, 0) + 1

    # every report of the three vehicles once a second, all in the same tick: between ticks the writers are idle (the
    # first write of an idle writer goes at once; the next ones wait in its batch)
    p = sim("--vehicles", "3", "--fix-rate", "1", "--ins-rate", "1", "--gps-rate", "1")
    deadline = time.monotonic() + 30
    while (len(counts) < 3 * len(REPORTS) or min(counts.values()) < 3) and time.monotonic() < deadline:
        take()
        time.sleep(0.02)
    assert min(counts.values()) >= 3, counts
    assert p.proc is not None
    p.proc.send_signal(signal.SIGSTOP)  # frozen between two ticks (a tick's writes take a millisecond of its second)
    try:
        for _ in range(150):  # 3 s: what was sent has long arrived
            take()
            time.sleep(0.02)
    finally:
        p.proc.send_signal(signal.SIGCONT)
    assert len(counts) == 3 * len(REPORTS) and len(set(counts.values())) == 1, counts
