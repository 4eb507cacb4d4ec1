"""The Foxglove gateway's cost: the console's CPU with `--foxglove-port` at the ingest benchmark's 50-vehicle rate, with
no Foxglove client, with one subscribed to every channel (the raw ones too), and with one subscribed to the channels
the shipped layout reads (docs/foxglove-layout.json: every vehicle's LocationFix, three report channels, the log), as
Foxglove subscribes to what its panels show (tests/support/foxglove.py, in this process).
Phases alternate without, every channel, the layout's, without... (`--pairs` rounds of `--seconds` each) on one
running console, so all see the same input; the added CPU is the mean of the phases with a client minus the mean of
those without, printed with its standard error over the rounds.
Usage: python bench/foxglove_gateway.py [--vehicles 50] [--seconds 15] [--pairs 4]
"""

from __future__ import annotations

import argparse
import asyncio
import re
import statistics
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from common import CpuMeter, Proc, emit, free_port, get_json, stack, table, target, wait_listed
from foxglove_peer import foxglove_collect
from ingest import sim_args

LAYOUT = Path(__file__).resolve().parents[1] / "docs" / "foxglove-layout.json"


def layout_topics(topic: str) -> bool:
    """The channels the shipped layout's panels read: the report channels its paths name, the log, and every vehicle's
    LocationFix (its Map shows each, and leaves out the fleet's topic)."""
    text = LAYOUT.read_text()
    logs = re.findall(r'"topicToRender":\s*"([^"]+)"', text)
    return topic.startswith("/vehicles/") or topic in {*re.findall(r"/reports/\w+", text), *logs}


CLIENTS: dict[str, Callable[[str], bool]] = {"every channel": lambda _t: True, "the layout's channels": layout_topics}


def phases(proc: Proc, url: str, seconds: float, pairs: int) -> list[tuple[str, float, int]]:
    """`pairs` rounds of phases of `seconds` each: no client, then each of CLIENTS on the Foxglove server at `url`; per
    phase, the share of a core `proc` used and the messages a second the client received."""
    rows = []
    for phase in ("no client", *CLIENTS) * pairs:
        received = 0

        def on(_topic: str, _sample: dict[str, Any], _at: float) -> None:
            nonlocal received
            received += 1

        cpu, t0 = CpuMeter(proc), time.monotonic()
        if phase in CLIENTS:
            asyncio.run(foxglove_collect(url, seconds, on, CLIENTS[phase]))
        else:
            time.sleep(seconds)
        rows.append((phase, cpu.read(), round(received / (time.monotonic() - t0))))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=15.0)
    ap.add_argument("--pairs", type=int, default=4, help="rounds of phases: without a client, then each client")
    args = ap.parse_args()
    port = free_port()
    with stack(sim_args=sim_args(args.vehicles), console_env={"SEM_FOXGLOVE_PORT": str(port)}) as st:
        console, url = st["procs"]["console"], st["url"]
        wait_listed(url, args.vehicles)
        rows = [
            {"phase": phase, "console_cpu": round(cpu, 3), "received_per_s": per_s}
            for phase, cpu, per_s in phases(console, f"ws://127.0.0.1:{port}", args.seconds, args.pairs)
        ]
        state = {g["name"]: g for g in get_json(url + "/api/gateways")}["foxglove"]
    without = [r["console_cpu"] for r in rows if r["phase"] == "no client"]
    cpu_without = sum(without) / len(without)
    keys = ["phase", "console_cpu", "received_per_s"]
    table(
        f"Foxglove gateway at {args.vehicles} vehicles ({args.seconds:.0f} s per phase, {args.pairs} rounds)",
        keys,
        [[r[k] for k in keys] for r in rows],
    )
    figures: dict[str, Any] = {"vehicles": args.vehicles, "console_cpu_no_client": round(cpu_without, 3), "pairs": args.pairs}
    targets = []
    for phase, prefix in zip(CLIENTS, ("", "layout_"), strict=True):
        with_client = [r for r in rows if r["phase"] == phase]
        cpu_with = sum(r["console_cpu"] for r in with_client) / len(with_client)
        differences = [r["console_cpu"] - o for r, o in zip(with_client, without, strict=False)]
        stderr = statistics.stdev(differences) / len(differences) ** 0.5 if len(differences) > 1 else float("nan")
        added = {
            "console_cpu_one_client": round(cpu_with, 3),
            "added_cpu_core": round(cpu_with - cpu_without, 3),
            "added_cpu_percent": round((cpu_with - cpu_without) / max(cpu_without, 1e-9) * 100, 1),
            "added_cpu_stderr_percent": round(stderr / max(cpu_without, 1e-9) * 100, 1),
            "received_per_s": round(sum(r["received_per_s"] for r in with_client) / len(with_client)),
        }
        figures.update({prefix + k: v for k, v in added.items()})
        print(
            f"\nadded console CPU with one Foxglove client on {phase}: {added['added_cpu_core']} core "
            f"({added['added_cpu_percent']}% of {figures['console_cpu_no_client']}, standard error "
            f"{added['added_cpu_stderr_percent']}% over {args.pairs} rounds); {added['received_per_s']} messages/s to it"
        )
        targets.append(target(f"added console CPU, one Foxglove client on {phase}", added["added_cpu_percent"], "%", "<=", 10.0))
    figures["gateway_errors"] = state["counters"].get("errors", 0)
    figures["targets"] = targets
    emit("foxglove", figures)


if __name__ == "__main__":
    main()
