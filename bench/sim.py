"""The simulator alone: `sem-sim`'s CPU with N vehicles (default 1,000) and every report at 1 Hz, as bench/scale.py
runs it (its `sim_args`), for each UMAA version asked (default both), with one passive reader per report topic in a
process of its own (matched, reliable and transient-local as the console's, so the simulator sends and is
acknowledged as it is with a console; the reader takes nothing). Printed beside its target: the simulator's CPU (at
most 0.25 core at 1,000 vehicles) and its CPU per sample written, over --seconds after --warm-up seconds, with the load
average (the machine's other processes share the cores: compare figures of one run).
Usage: python bench/sim.py [--vehicles 1000] [--umaa 3.0.1,6.0] [--seconds 30] [--warm-up 15]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from typing import Any

from common import BIN, CpuMeter, Proc, emit, free_domain, table, target
from scale import REPORTS, SIM_CORE_TARGET, sim_args


def read(domain: int, umaa: str) -> None:
    """The passive readers: one per report topic of `umaa`, with the console's reliable QoS, until stopped."""
    from sem_console.dds.bus import Bus
    from sem_console.dds.qos import TopicClass
    from sem_console.dds.topics import Sem, Sem60

    bus = Bus(domain)
    sems = [*Sem, *Sem60] if umaa == "6.0" else list(Sem)
    readers = [bus.reader(s) for s in sems if s.spec.cls is TopicClass.REPORT]
    try:
        while readers:
            time.sleep(1)
    except KeyboardInterrupt:
        bus.close()


def measure(n: int, umaa: str, seconds: float, warm_up: float) -> dict[str, Any]:
    domain, tmp = free_domain(), tempfile.mkdtemp(prefix="sem-bench-sim-")
    reader = Proc([sys.executable, __file__, "--read", str(domain), umaa])
    sim = Proc(
        [
            str(BIN / "sem-sim"),
            "--domain",
            str(domain),
            "--state-file",
            os.path.join(tmp, "sim.json"),
            "--log-level",
            "warning",
            *sim_args(n, umaa),
        ]
    )
    try:
        time.sleep(warm_up)
        if sim.p.poll() is not None:
            raise SystemExit(f"sem-sim stopped with {sim.p.returncode} during the warm-up")
        load0, meter = os.getloadavg()[0], CpuMeter(sim)
        time.sleep(seconds)
        cores = meter.read()
    finally:
        sim.stop()
        reader.stop()
    samples = n * (REPORTS - (umaa == "6.0"))
    return {
        "umaa": umaa,
        "vehicles": n,
        "sim_cores": round(cores, 4),
        "sim_us_per_sample": round(cores / samples * 1e6, 2),
        "samples_per_s_nominal": samples,
        "load_average": round((load0 + os.getloadavg()[0]) / 2, 2),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=1000)
    ap.add_argument("--umaa", default="3.0.1,6.0", help="the UMAA versions, comma separated (default: 3.0.1,6.0)")
    ap.add_argument("--seconds", type=float, default=30.0, help="CPU window per version (default: 30)")
    ap.add_argument("--warm-up", type=float, default=15.0, help="seconds from the start before the window (default: 15)")
    ap.add_argument("--read", nargs=2, metavar=("DOMAIN", "UMAA"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.read:
        read(int(args.read[0]), args.read[1])
        return
    versions = [v.strip() for v in args.umaa.split(",") if v.strip()]
    bad = [v for v in versions if v not in ("3.0.1", "6.0")]
    if bad or not versions:
        raise SystemExit(f"--umaa {args.umaa!r}: give 3.0.1, 6.0 or both (3.0.1,6.0)")
    runs = [measure(args.vehicles, v, args.seconds, args.warm_up) for v in versions]
    table(
        f"sem-sim alone, {args.vehicles} vehicles, every report at 1 Hz, {args.seconds:.0f} s each",
        ["UMAA", "core", "us per sample", "samples/s", "load average"],
        [[r["umaa"], r["sim_cores"], r["sim_us_per_sample"], r["samples_per_s_nominal"], r["load_average"]] for r in runs],
    )
    limit = round(SIM_CORE_TARGET * args.vehicles / 1000, 3)
    targets = [
        target(f"sem-sim CPU, UMAA {r['umaa']}", r["sim_cores"], "core", "<=", limit, f"{args.vehicles} vehicles at 1 Hz")
        for r in runs
    ]
    emit("sim", {"targets": targets, "vehicles": args.vehicles, "seconds": args.seconds, "runs": runs})


if __name__ == "__main__":
    main()
