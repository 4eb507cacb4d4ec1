"""foxglove-sdk's own cost at the Foxglove gateway's rate: the floor under bench/foxglove_gateway.py's figures. What one client
subscribed to every channel of a console at the 50-vehicle rate gets is captured for `--capture` seconds; the console
stops, and a bare foxglove-sdk server in a process of its own logs the same bytes on the same channels at the times
they came (the messages of each `--burst-ms` together, as the gateway hands a turn of its loop), with nothing else to
do. Its CPU is measured as bench/foxglove_gateway.py measures the console's: phases without a client, with one on every
channel and with one on the layout's channels (the same client), alternating. No target: figures only, none kept.
Usage: python bench/foxglove_floor.py [--vehicles 50] [--capture 20] [--seconds 12] [--pairs 3] [--burst-ms 10]
"""

from __future__ import annotations

import argparse
import asyncio
import pickle
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

Captured = tuple[float, str, bytes]  # arrival (monotonic seconds), topic, the message's bytes


def serve(port: int, capture: Path, burst: float) -> None:
    """The bare server: the captured messages again and again, at their times."""
    import foxglove

    captured = pickle.loads(capture.read_bytes())
    context = foxglove.Context()
    channels = {}
    for topic, ad in captured["channels"].items():
        schema = foxglove.Schema(name=ad["schemaName"], encoding=ad["schemaEncoding"], data=ad["schema"].encode())
        channels[topic] = foxglove.Channel(topic, schema=schema, message_encoding=ad["encoding"], context=context)
    foxglove.start_server(name="floor", host="127.0.0.1", port=port, capabilities=[], context=context)
    messages: list[Captured] = captured["messages"]
    plan = [(at - messages[0][0], channels[topic], data) for at, topic, data in messages]
    while True:
        start, i = time.monotonic(), 0
        while i < len(plan):
            time.sleep(max(0.0, start + (int(plan[i][0] / burst) + 1) * burst - time.monotonic()))
            now = time.monotonic() - start
            while i < len(plan) and plan[i][0] <= now:
                _, ch, data = plan[i]
                if ch.has_sinks():
                    ch.log(data, log_time=time.time_ns())
                i += 1


async def grab(url: str, seconds: float) -> dict[str, Any]:
    import common

    from support.foxglove import connect

    messages: list[Captured] = []
    async with connect(url) as client:
        subscribed: set[str] = set()
        async for m in common.for_seconds(client.messages(), seconds):
            if m is None:
                if new := [t for t in client.topics() if t not in subscribed]:
                    subscribed.update(new)
                    await client.subscribe(new)
            else:
                messages.append((time.monotonic(), m.topic, m.data))
        return {"messages": messages, "channels": client.topics()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=50)
    ap.add_argument("--capture", type=float, default=20.0, help="seconds of the console's messages to log again")
    ap.add_argument("--seconds", type=float, default=12.0)
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--burst-ms", type=float, default=10.0)
    ap.add_argument("--serve", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--messages", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.serve:
        return serve(args.serve, args.messages, args.burst_ms / 1000)
    from common import Proc, free_port, stack, table, wait_listed
    from foxglove_gateway import CLIENTS, phases
    from ingest import sim_args

    port = free_port()
    with stack(sim_args=sim_args(args.vehicles), console_env={"SEM_FOXGLOVE_PORT": str(port)}) as st:
        wait_listed(st["url"], args.vehicles)
        captured = asyncio.run(grab(f"ws://127.0.0.1:{port}", args.capture + 3))
    settled = captured["messages"][0][0] + 3  # the subscriptions taken
    captured["messages"] = [m for m in captured["messages"] if m[0] >= settled]
    rate = len(captured["messages"]) / args.capture
    with tempfile.TemporaryDirectory() as tmp:
        file = Path(tmp) / "captured.pickle"
        file.write_bytes(pickle.dumps(captured))
        port = free_port()
        server = Proc([sys.executable, __file__, "--serve", str(port), "--messages", str(file), "--burst-ms", str(args.burst_ms)])
        try:
            time.sleep(3.0)  # the server up
            rows = [
                {"phase": phase, "server_cpu": round(cpu, 4), "received_per_s": per_s}
                for phase, cpu, per_s in phases(server, f"ws://127.0.0.1:{port}", args.seconds, args.pairs)
            ]
        finally:
            server.stop()
    keys = ["phase", "server_cpu", "received_per_s"]
    title = f"bare foxglove-sdk server, {rate:.0f} captured messages/s logged in bursts of {args.burst_ms:g} ms"
    table(title, keys, [[r[k] for k in keys] for r in rows])
    without = [r["server_cpu"] for r in rows if r["phase"] == "no client"]
    for phase in CLIENTS:
        with_client = [r for r in rows if r["phase"] == phase]
        added = [r["server_cpu"] - o for r, o in zip(with_client, without, strict=True)]
        stderr = statistics.stdev(added) / len(added) ** 0.5 if len(added) > 1 else float("nan")
        per_s = statistics.mean(r["received_per_s"] for r in with_client)
        print(
            f"\nfloor with one client on {phase}: {statistics.mean(added):.4f} core added (standard error {stderr:.4f}), "
            f"{per_s:.0f} messages/s to it, {statistics.mean(added) / max(per_s, 1) * 1e6:.1f} µs a message"
        )


if __name__ == "__main__":
    main()
