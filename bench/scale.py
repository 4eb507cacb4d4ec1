"""A thousand vehicles on one console: N `sem-sim` vehicles (default 1,000, one simulator) with every report at 1 Hz,
and one console. Printed beside its target: sem-sim's CPU (at most 0.25 core at 1,000 vehicles, and per
vehicle-second), the console's ingest CPU (at most 1 core), start to all N listed in /api/providers (at most 10 s,
from the simulator's start, the console already up), sample (the simulator's timeStamp) to WebSocket p99 (at most
50 ms, GPSFixReport and InertialSensorReport as bench/ingest.py measures it) and the console's resident memory over a
soak (growth at most 5 % after the first 10 minutes; the soak is --soak seconds, 120 by default, so by default the
baseline is the RSS at a third of the run, and the JSON says which).
The simulator, the console and the measuring client share the machine's cores; the load average is in the JSON.
Usage: python bench/scale.py [--vehicles 1000] [--umaa 3.0.1|6.0] [--seconds 20] [--soak 120]
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import os
import time
from typing import Any

from common import BIN, CpuMeter, Proc, emit, get_json, ms, percentile, report_latency, stack, table, target, ws_collect

SIM_CORE_TARGET = 0.25  # at 1,000 vehicles
INGEST_CORE_TARGET = 1.0
LISTED_S_TARGET = 10.0
P99_MS_TARGET = 50.0
GROWTH_PCT_TARGET = 5.0
SOAK_BASELINE_S = 600.0  # the "after the first 10 minutes"
REPORTS = 4  # GPSReport, GPSFixReport, GPSFixStatusReport, InertialSensorReport (6.0: three of them)


def ask(url: str) -> Any:
    """A console's answer, None when it gives none in 60 s (a console behind its input answers late)."""
    try:
        return get_json(url, timeout=60)
    except OSError:
        return None


def sim_args(n: int, umaa: str) -> list[str]:
    return ["--vehicles", str(n), "--gps-rate", "1", "--fix-rate", "1", "--ins-rate", "1", "--umaa", umaa]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=1000)
    ap.add_argument("--umaa", choices=("3.0.1", "6.0"), default="3.0.1")
    ap.add_argument("--seconds", type=float, default=20.0, help="CPU and latency window (default: 20)")
    ap.add_argument("--soak", type=float, default=120.0, help="memory soak in seconds (default: 120; 3900: the hour)")
    args = ap.parse_args()
    n = args.vehicles
    with stack(sim_args=None) as st:
        console = st["procs"]["console"]
        t0 = time.monotonic()
        sim = st["procs"]["sim"] = Proc(
            [
                str(BIN / "sem-sim"),
                "--domain",
                str(st["domain"]),
                "--state-file",
                str(st["tmp"] / "sim.json"),
                "--log-level",
                "warning",
                *sim_args(n, args.umaa),
            ]
        )
        listed_s: float | None = None
        while time.monotonic() - t0 < 120:  # its count of providers, cheaper to ask than the list (asked at the end)
            with contextlib.suppress(OSError):
                if get_json(st["url"] + "/api/metrics", timeout=2)["providers"] >= n:
                    listed_s = round(time.monotonic() - t0, 2)
                    break
            time.sleep(0.25)
        print(f"all {n} listed after {listed_s} s" if listed_s else f"not all {n} listed in 120 s", flush=True)
        time.sleep(5)  # the simulator's reports settle to 1 Hz
        lat: list[float] = []

        def on(msg: dict, now: float) -> None:
            if msg["type"] == "report" and msg["topic"] in ("GPSFixReport", "InertialSensorReport", "GlobalPoseReport"):
                x = report_latency(msg, now)
                if x is not None:
                    lat.append(x)

        m0, cpu, sim_cpu = ask(st["url"] + "/api/metrics"), CpuMeter(console), CpuMeter(sim)
        w0 = time.monotonic()
        asyncio.run(ws_collect(st["ws"], args.seconds, on))
        elapsed = time.monotonic() - w0
        console_cpu, sim_cores = cpu.read(), sim_cpu.read()
        m1 = ask(st["url"] + "/api/metrics")
        print(f"sem-sim {sim_cores:.3f} core, console {console_cpu:.3f} core, {len(lat)} latencies", flush=True)
        taken = round((m1["samplesTaken"] - m0["samplesTaken"]) / elapsed) if m0 and m1 else None
        # the memory soak: RSS every tenth of it (at least every 10 s), the baseline at 10 minutes or a third of it
        soak0, rss = time.monotonic(), [(0, round(console.rss_mb(), 1))]
        baseline_at = min(SOAK_BASELINE_S, args.soak / 3)
        step = max(args.soak / 10, 10.0)
        while time.monotonic() - soak0 < args.soak:
            time.sleep(min(step, max(0.0, args.soak - (time.monotonic() - soak0))))
            rss.append((round(time.monotonic() - soak0), round(console.rss_mb(), 1)))
        base = next(r for t, r in rss if t >= baseline_at)
        growth = round((rss[-1][1] - base) / base * 100, 1)
        providers = ask(st["url"] + "/api/providers") or []
        listed, live = len(providers), sum(1 for p in providers if p.get("link") == "live")
    table(f"Console RSS over the soak ({args.soak:.0f} s, {n} vehicles)", ["t (s)", "RSS (MiB)"], rss)
    sim_ms = round(sim_cores / n * 1000, 3)
    targets = [
        target("sem-sim CPU", round(sim_cores, 3), "core", "<=", round(SIM_CORE_TARGET * n / 1000, 3), f"{n} vehicles at 1 Hz"),
        target("console ingest CPU", round(console_cpu, 3), "core", "<=", INGEST_CORE_TARGET),
        target("start to all listed", listed_s, "s", "<=", LISTED_S_TARGET),
        target("sample to WebSocket p99", ms(percentile(lat, 99)), "ms", "<=", P99_MS_TARGET),
        target(
            "RSS growth after the baseline",
            growth,
            "%",
            "<=",
            GROWTH_PCT_TARGET,
            f"baseline at {baseline_at:.0f} s of a {args.soak:.0f} s soak",
        ),
    ]
    emit(
        "scale",
        {
            "targets": targets,
            "vehicles": n,
            "umaa": args.umaa,
            "sim_cpu_ms_per_vehicle_s": sim_ms,
            "sim_samples_per_s_nominal": n * (REPORTS - (args.umaa == "6.0")),
            "console_samples_taken_per_s": taken,
            "p50_ms": ms(percentile(lat, 50)),
            "latency_samples": len(lat),
            "listed_at_end": listed,
            "live_at_end": live,
            "soak_seconds": args.soak,
            "soak_baseline_s": baseline_at,
            "soak_short": args.soak < SOAK_BASELINE_S + 3000,
            "rss_baseline_mb": base,
            "rss_end_mb": rss[-1][1],
            "load_average": round(os.getloadavg()[0], 2),
            "rss": [{"t_s": t, "rss_mb": r} for t, r in rss],
        },
    )


if __name__ == "__main__":
    main()
