"""The Foxglove gateway's cost: the console's CPU with `--foxglove-port` at the ingest benchmark's 50-vehicle rate, with
no Foxglove client, then with one subscribed to every channel (tests/support/foxglove.py, in this process).
Phases alternate without, with, without, with... (`--pairs` of `--seconds` each) on one running console, so both see
the same input; the added CPU is the mean of the phases with a client minus the mean of those without, printed with
its standard error over the pairs.
Usage: python bench/foxglove.py [--vehicles 50] [--seconds 15] [--pairs 4]
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import time
from typing import Any

from common import CpuMeter, emit, free_port, get_json, stack, table, target
from foxglove_peer import foxglove_collect
from ingest import sim_args


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=15.0)
    ap.add_argument("--pairs", type=int, default=4, help="pairs of phases without and with a client")
    args = ap.parse_args()
    port = free_port()
    rows: list[dict[str, Any]] = []
    with stack(sim_args=sim_args(args.vehicles), console_env={"SEM_FOXGLOVE_PORT": str(port)}) as st:
        console, url = st["procs"]["console"], st["url"]
        deadline = time.monotonic() + 30
        while get_json(url + "/api/metrics")["providers"] < args.vehicles and time.monotonic() < deadline:
            time.sleep(0.5)
        time.sleep(3)  # warm up
        for phase in ("no client", "1 client") * args.pairs:
            received = 0

            def on(_topic: str, _sample: dict[str, Any], _at: float) -> None:
                nonlocal received
                received += 1

            cpu, t0 = CpuMeter(console), time.monotonic()
            if phase == "1 client":
                asyncio.run(foxglove_collect(f"ws://127.0.0.1:{port}", args.seconds, on))
            else:
                time.sleep(args.seconds)
            elapsed = time.monotonic() - t0
            rows.append({"phase": phase, "console_cpu": round(cpu.read(), 3), "received_per_s": round(received / elapsed)})
        state = {g["name"]: g for g in get_json(url + "/api/gateways")}["foxglove"]
    without = [r["console_cpu"] for r in rows if r["phase"] == "no client"]
    with_client = [r for r in rows if r["phase"] == "1 client"]
    cpu_without = sum(without) / len(without)
    cpu_with = sum(r["console_cpu"] for r in with_client) / len(with_client)
    differences = [r["console_cpu"] - o for r, o in zip(with_client, without, strict=False)]
    stderr = statistics.stdev(differences) / len(differences) ** 0.5 if len(differences) > 1 else float("nan")
    keys = ["phase", "console_cpu", "received_per_s"]
    table(
        f"Foxglove gateway at {args.vehicles} vehicles ({args.seconds:.0f} s per phase, {args.pairs} pairs)",
        keys,
        [[r[k] for k in keys] for r in rows],
    )
    figures = {
        "vehicles": args.vehicles,
        "console_cpu_no_client": round(cpu_without, 3),
        "console_cpu_one_client": round(cpu_with, 3),
        "added_cpu_core": round(cpu_with - cpu_without, 3),
        "added_cpu_percent": round((cpu_with - cpu_without) / max(cpu_without, 1e-9) * 100, 1),
        "added_cpu_stderr_percent": round(stderr / max(cpu_without, 1e-9) * 100, 1),
        "pairs": args.pairs,
        "received_per_s": round(sum(r["received_per_s"] for r in with_client) / len(with_client)),
        "gateway_errors": state["counters"].get("errors", 0),
    }
    print(
        f"\nadded console CPU with one Foxglove client: {figures['added_cpu_core']} core ({figures['added_cpu_percent']}% "
        f"of {figures['console_cpu_no_client']}, standard error {figures['added_cpu_stderr_percent']}% over {args.pairs} "
        f"pairs); {figures['received_per_s']} messages/s to the client"
    )
    figures["targets"] = [target("added console CPU, one Foxglove client", figures["added_cpu_percent"], "%", "<=", 10.0)]
    emit("foxglove", figures)


if __name__ == "__main__":
    main()
