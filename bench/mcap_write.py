"""MCAP write cost per message, µs of CPU: the recorder's whole path through its writer
(`recording/mcap_writer.py`) beside the `mcap` library's `Writer.add_message`, in one run, on the same
messages. The messages are what 50 vehicles send in a second at the ingest benchmark's rates (per
vehicle a GPSReport of 40 satellites at 1 Hz, GPSFixReport, GPSFixStatusReport and
InertialSensorReport at 10 Hz, made and serialised as sem-sim does, each vehicle's at its own
instant), taken five at a time as the ingest threads do; both write zstd chunks of 1 MiB to a file.
Single-threaded and alone: the running console adds the GIL and its other threads (`recording.py` measures that).
Best of several rounds.
Usage: python bench/mcap_write.py [--rounds 15] [--seconds 10]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
import uuid
from collections.abc import Callable
from pathlib import Path
from typing import Any

from common import emit, table
from decode import RATES
from mcap.writer import CompressionType, Writer

from sem_console.dds.topics import Sem
from sem_console.recording.recorder import Recorder, _File
from sem_console.recording.schema import MESSAGE_ENCODING, SCHEMA_ENCODING, idl_text, type_name
from sem_console.sim.options import SimOptions
from sem_console.sim.reports import Sensors

ALIVE = 16  # InstanceState.Alive
T0 = time.time_ns()


def takes(vehicles: int, seconds: int) -> list[tuple[Sem, list[tuple[bytes, bool, int, int]], int]]:
    """The recorder's input: (topic, samples of one take, receive time), five samples a take, each
    sample the simulator's report of its vehicle at that instant (so zstd sees data as live)."""
    sensors = [Sensors(SimOptions(vehicles=vehicles, satellites=40), n, uuid.UUID(int=n + 1), set()) for n in range(vehicles)]
    pending: dict[Sem, list[tuple[bytes, bool, int, int]]] = {sem: [] for sem in RATES}
    out, t, now = [], T0, time.monotonic()
    for tenth in range(seconds * 10):
        now += 0.1
        for s in sensors:
            sats = s.satellites(now)
            fix, status = s.fix_reports(now, sats)
            reports = {Sem.GPS_FIX_REPORT: fix, Sem.GPS_FIX_STATUS_REPORT: status, Sem.INS_REPORT: s.ins_report(now)}
            if tenth % 10 == 0:
                reports[Sem.GPS_REPORT] = s.gps_report(now, sats)
            for sem, report in reports.items():
                t += 60_000
                pending[sem].append((sem.spec.type.serialize(report, use_version_2=sem.spec.xcdr2_only), True, ALIVE, t - 50_000))
                if len(pending[sem]) == 5:
                    out.append((sem, pending[sem], t))
                    pending[sem] = []
    return out


def best_us(run: Callable[[Path], int], rounds: int) -> float:
    best = float("inf")
    for _ in range(rounds):
        with tempfile.TemporaryDirectory() as d:
            t0 = time.process_time()
            n = run(Path(d))
            best = min(best, (time.process_time() - t0) / n)
    return best * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--seconds", type=int, default=10, help="seconds of 50 vehicles' input per round")
    args = ap.parse_args()
    items = takes(50, args.seconds)

    def recorder(d: Path) -> int:
        r, f = Recorder(d, 1 << 40, 1e9), _File(d / "r.mcap")
        for sem, batch, log_ns in items:
            r._write(f, sem, batch, log_ns, len(batch))  # noqa: SLF001 (the writer thread's own step)
        f.close()
        return r.messages

    def library(d: Path) -> int:
        with open(d / "l.mcap", "wb") as fh:
            w = Writer(fh, compression=CompressionType.ZSTD)
            w.start()
            channels: dict[Any, int] = {}
            for sem in Sem:
                sid = w.register_schema(type_name(sem.spec.type), SCHEMA_ENCODING, idl_text(type_name(sem.spec.type)).encode())
                channels[sem] = w.register_channel(sem.spec.name, MESSAGE_ENCODING, sid)
            seq, n = dict.fromkeys(channels.values(), 0), 0
            for sem, batch, log_ns in items:
                cid = channels[sem]
                for raw, _valid, _state, source_ns in batch:
                    seq[cid] += 1
                    w.add_message(cid, log_ns, raw, source_ns, seq[cid])
                    n += 1
            w.finish()
        return n

    ours, theirs = best_us(recorder, args.rounds), best_us(library, args.rounds)
    messages_per_s = sum(len(batch) for _sem, batch, _t in items) / args.seconds
    rows = [
        ["recorder (mcap_writer.py)", round(ours, 2), round(ours * messages_per_s / 1e6, 4)],
        ["mcap library Writer.add_message", round(theirs, 2), round(theirs * messages_per_s / 1e6, 4)],
    ]
    table(
        f"MCAP write cost, 50 vehicles' input ({messages_per_s:.0f} messages/s)",
        ["path", "us_per_message", "core_at_50_vehicles"],
        rows,
    )
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    emit(
        "mcap_write",
        {
            "messages_per_s": messages_per_s,
            "recorder_us": round(ours, 2),
            "library_us": round(theirs, 2),
            "speedup": round(theirs / ours, 1),
            "load_average": round(os.getloadavg()[0], 2),
        },
    )


if __name__ == "__main__":
    main()
