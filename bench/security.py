"""DDS Security's cost: latency, sample to WebSocket, p50 and p99, and the console's CPU, with 20 simulated vehicles
(sem-sim's default rates), on an open bus and on a secure one (a fleet made by sem-keys: a station, a vehicle;
governance encrypting discovery, liveliness, RTPS and every topic's data). Both runs on the secure build of Cyclone
DDS (scripts/setup.sh --secure), so that the only difference is the security itself.
Usage: python bench/security.py [--seconds 20] [--vehicles 20]
"""

from __future__ import annotations

import argparse
import asyncio
import datetime as dt
import tempfile
import time
from pathlib import Path
from typing import Any

import common
from common import CpuMeter, emit, get_json, ms, percentile, stack, table, ws_collect

from sem_console.keys.documents import Role
from sem_console.keys.fleet import Fleet
from support.secure import secure_env


def fleet(folder: Path, domain: int) -> Path:
    now = dt.datetime.now(dt.UTC)
    f = Fleet(folder)
    f.init("Bench", [domain], 2, False, now)
    f.issue("ops-1", Role.STATION, 1, now)
    f.issue("usv", Role.VEHICLE, 1, now)
    return folder / "identities"


def run(secured: bool, vehicles: int, seconds: float, env: dict[str, str]) -> dict[str, Any]:
    domain = common.free_domain()
    with tempfile.TemporaryDirectory(prefix="sem-bench-keys-") as keys:
        ids = fleet(Path(keys), domain)
        console_args = ["--dds-security", str(ids / "ops-1")] if secured else []
        sim_args = ["--vehicles", str(vehicles), *(["--dds-security", str(ids / "usv")] if secured else [])]
        with stack(sim_args, console_env=env, console_args=console_args, sim_env=env, domain=domain) as st:
            deadline = time.monotonic() + 90
            while len(get_json(st["url"] + "/api/providers")) < vehicles and time.monotonic() < deadline:
                time.sleep(0.5)
            seen = len(get_json(st["url"] + "/api/providers"))
            health = get_json(st["url"] + "/api/health")["ddsSecurity"]
            time.sleep(2)  # every vehicle's reports flowing
            latencies: list[float] = []

            def on(msg: dict[str, Any], now: float) -> None:
                lat = common.report_latency(msg, now)
                if lat is not None:
                    latencies.append(lat)

            cpu = CpuMeter(st["procs"]["console"])
            asyncio.run(ws_collect(st["ws"], seconds, on))
            console_cpu = cpu.read()
    return {
        "bus": "secure" if secured else "open",
        "secured": bool(health and health["secured"]),
        "vehicles": seen,
        "reports": len(latencies),
        "p50_ms": ms(percentile(latencies, 50)),
        "p99_ms": ms(percentile(latencies, 99)),
        "console_cpu_percent": round(100 * console_cpu, 1),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--vehicles", type=int, default=20)
    args = ap.parse_args()
    env = secure_env()
    if isinstance(env, str):
        raise SystemExit(f"bench/security.py needs the secure build: {env}")
    runs = [run(secured, args.vehicles, args.seconds, env) for secured in (False, True)]
    keys = ["bus", "secured", "vehicles", "reports", "p50_ms", "p99_ms", "console_cpu_percent"]
    table(
        "DDS Security's cost: sample to WebSocket and the console's CPU, open and secure bus",
        keys,
        [[r[k] for k in keys] for r in runs],
    )
    open_run, secure_run = runs
    emit(
        "security",
        {
            "runs": runs,
            "seconds": args.seconds,
            "p50_added_ms": round(secure_run["p50_ms"] - open_run["p50_ms"], 2),
            "p99_added_ms": round(secure_run["p99_ms"] - open_run["p99_ms"], 2),
            "cpu_added_points": round(secure_run["console_cpu_percent"] - open_run["console_cpu_percent"], 1),
        },
    )


if __name__ == "__main__":
    main()
