"""The floor: a plain cyclonedds-python reader in its own process, timing samples from their
timeStamp to arrival. Usage: floor_reader.py DOMAIN SECONDS TOPIC...; prints JSON latencies.
With NAIVE=1 it keeps every sample (KEEP_ALL) instead of the latest per instance: the reader
that takes and decodes everything, which the ingest benchmark compares the console with."""

from __future__ import annotations

import json
import os
import sys
import time

import common  # noqa: F401  (puts backend/ on the path)
from cyclonedds.core import Policy, Qos, WaitSet
from cyclonedds.util import duration

from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.qos import TopicClass, reader_qos
from sem_console.dds.topics import Sem


def main() -> None:
    domain, seconds, names = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3:]
    bus = Bus(domain)
    qos = reader_qos(TopicClass.REPORT)
    if os.environ.get("NAIVE"):
        qos = Qos(
            Policy.Reliability.Reliable(duration(seconds=1)),
            Policy.Durability.Volatile,
            Policy.History.KeepAll,
            Policy.DataRepresentation(use_cdrv0_representation=True, use_xcdrv2_representation=True),
        )
    readers = [bus.reader(Sem[n], qos) for n in names]
    ws = WaitSet(bus.participant)
    conds = [all_samples(r) for r in readers]
    for c in conds:
        ws.attach(c)
    print("ready", flush=True)
    latencies: list[float] = []
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        ws.wait(duration(milliseconds=100))
        for r, c in zip(readers, conds, strict=True):
            for s in r.take(N=256, condition=c):
                now = time.time()
                ts = getattr(s, "timeStamp", None)
                if ts is not None:
                    latencies.append(now - (ts.seconds + ts.nanoseconds / 1e9))
    print(json.dumps(latencies), flush=True)


if __name__ == "__main__":
    main()
