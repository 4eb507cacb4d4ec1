"""Operations centre: two consoles on one DDS domain and one PostgreSQL database (a cluster of its own in a
temporary directory, as the tests start it: backend/tests/support/pg.py), with --vehicles simulated vehicles.
Console A issues GPS fix commands round the fleet; for each transition, the time from its `transition` message on
A's WebSocket to the `command` message with that status on B's (the NOTIFY path: A's write, PostgreSQL, B's
listener, B's loop and hub): p50/p99. Over the window, the database's write load (transactions committed per
second, pg_stat_database) and its growth (pg_database_size) per vehicle-hour. Then the database stopped --outages
times: from the instant console B finds it unreachable (its `unavailableSince`) to its `database` message on B's
WebSocket, which the shared-database banner draws (issue 33 asks for it within 2 s).
Usage: python bench/opscentre.py [--vehicles 100] [--seconds 60] [--commands 40] [--outages 3]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import sys
import time
import urllib.request
from pathlib import Path
from typing import Any

import common
from common import BIN, Proc, emit, free_domain, free_port, ms, percentile, table, wait_http

sys.path.insert(0, str(common.ROOT / "backend" / "tests"))
from support.pg import PASSWORD, Cluster  # the tests' own PostgreSQL cluster

SIM = ["--step-seconds", "0.2", "--surface-seconds", "0", "--fix-rate", "1", "--gps-rate", "1", "--ins-rate", "1"]


def stats(cluster: Cluster, database: str) -> tuple[int, int]:
    """(transactions committed, bytes) of the database now."""
    import psycopg

    with psycopg.connect(
        host="127.0.0.1", port=cluster.port, user="postgres", password=PASSWORD, dbname=database, autocommit=True
    ) as c:
        row = c.execute(
            "SELECT xact_commit, pg_database_size(datname) FROM pg_stat_database WHERE datname = %s", (database,)
        ).fetchone()
        assert row is not None
        return int(row[0]), int(row[1])


async def propagation(a: str, b: str, vehicles: list[str], commands: int) -> list[float]:
    import websockets

    on_a: dict[tuple[str, str], float] = {}
    on_b: dict[tuple[str, str], float] = {}

    async def read(url: str, into: dict[tuple[str, str], float], kind: str) -> None:
        async with websockets.connect(url, max_size=2**26) as ws:
            async for text in ws:
                now = time.perf_counter()
                msg = json.loads(text)
                if msg["type"] == kind == "transition":
                    into.setdefault((msg["sessionId"], msg["transition"]["status"]), now)
                elif msg["type"] == kind == "command" and msg["command"]["status"]:
                    into.setdefault((msg["command"]["sessionId"], msg["command"]["status"]), now)

    readers = [
        asyncio.create_task(read(f"ws://{a}/ws", on_a, "transition")),
        asyncio.create_task(read(f"ws://{b}/ws", on_b, "command")),
    ]
    await asyncio.sleep(1)
    loop = asyncio.get_running_loop()
    for n in range(commands):
        req = urllib.request.Request(
            f"http://{a}/api/providers/{vehicles[n % len(vehicles)]}/gps-fix",
            method="POST",
            data=b"{}",
            headers={"Content-Type": "application/json"},
        )
        await loop.run_in_executor(None, lambda r=req: urllib.request.urlopen(r, timeout=10).read())
        await asyncio.sleep(0.25)
    await asyncio.sleep(5)
    for t in readers:
        t.cancel()
    return [on_b[k] - on_a[k] for k in on_a if k in on_b]


async def banner_after(cluster: Cluster, b: str) -> float:
    """The database stopped: seconds from B's `unavailableSince` to its `database` message on B's WebSocket; the
    database started again and awaited back (no banner) before returning."""
    import websockets

    async with websockets.connect(f"ws://{b}/ws", max_size=2**26) as ws:
        await asyncio.sleep(1)
        await asyncio.get_running_loop().run_in_executor(None, cluster.stop)
        after = None
        try:
            async with asyncio.timeout(60):
                async for text in ws:
                    msg = json.loads(text)
                    if msg["type"] == "database" and msg["database"]["unavailableSince"] is not None:
                        after = time.time() - msg["database"]["unavailableSince"]
                        break
        finally:
            await asyncio.get_running_loop().run_in_executor(None, cluster.start)
        async with asyncio.timeout(60):
            async for text in ws:
                msg = json.loads(text)
                if msg["type"] == "database" and msg["database"]["unavailableSince"] is None:
                    break
    assert after is not None
    return after


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=100)
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--commands", type=int, default=40)
    ap.add_argument("--outages", type=int, default=3)
    args = ap.parse_args()
    cluster = Cluster()
    procs: list[Proc] = []
    try:
        url = cluster.new_database()
        database = url.rsplit("/", 1)[1]
        domain = free_domain()
        tmp = Path(cluster.root)
        procs.append(
            Proc(
                [
                    str(BIN / "sem-sim"),
                    "--domain",
                    str(domain),
                    "--state-file",
                    str(tmp / "sim.json"),
                    "--vehicles",
                    str(args.vehicles),
                    "--log-level",
                    "warning",
                    *SIM,
                ]
            )
        )
        hosts = []
        for name in ("watch", "relief"):
            port = free_port()
            procs.append(
                Proc(
                    [
                        str(BIN / "sem-console"),
                        "--domain",
                        str(domain),
                        "--port",
                        str(port),
                        "--database-url",
                        url,
                        "--console-name",
                        name,
                        "--log-level",
                        "warning",
                    ]
                )
            )
            hosts.append(f"127.0.0.1:{port}")
        for h in hosts:
            wait_http(f"http://{h}/api/health")
        deadline = time.monotonic() + 120
        while len(common.get_json(f"http://{hosts[0]}/api/providers")) < args.vehicles and time.monotonic() < deadline:
            time.sleep(1)
        vehicles = [p["id"] for p in common.get_json(f"http://{hosts[0]}/api/providers")]
        commits0, size0 = stats(cluster, database)
        t0 = time.monotonic()
        delays = asyncio.run(propagation(hosts[0], hosts[1], vehicles, args.commands))
        rest = args.seconds - (time.monotonic() - t0)
        if rest > 0:
            time.sleep(rest)
        elapsed = time.monotonic() - t0
        commits1, size1 = stats(cluster, database)
        banners = [asyncio.run(banner_after(cluster, hosts[1])) for _ in range(args.outages)]
    finally:
        for p in reversed(procs):
            p.stop()
        cluster.close()
    vehicle_hours = len(vehicles) * elapsed / 3600
    figures: dict[str, Any] = {
        "vehicles": len(vehicles),
        "consoles": 2,
        "seconds": round(elapsed, 1),
        "transitions": len(delays),
        "propagation_p50_ms": ms(percentile(delays, 50)) if delays else None,
        "propagation_p99_ms": ms(percentile(delays, 99)) if delays else None,
        "commits_per_second": round((commits1 - commits0) / elapsed, 1),
        "growth_mb_per_vehicle_hour": round((size1 - size0) / 2**20 / vehicle_hours, 3) if vehicle_hours else None,
        "outages": len(banners),
        "banner_after_max_s": round(max(banners), 2) if banners else None,
    }
    table(
        "A -> B propagation of a command transition (WebSocket to WebSocket), database load",
        ["vehicles", "transitions", "p50 ms", "p99 ms", "commits/s", "MB per vehicle-hour", "banner after s (max)"],
        [
            [
                figures["vehicles"],
                figures["transitions"],
                figures["propagation_p50_ms"],
                figures["propagation_p99_ms"],
                figures["commits_per_second"],
                figures["growth_mb_per_vehicle_hour"],
                figures["banner_after_max_s"],
            ]
        ],
    )
    emit("opscentre", figures)


if __name__ == "__main__":
    main()
