"""Fan-out: 1, 10 and 50 WebSocket clients on one console with 5 vehicles at full rate (GPSFixReport,
GPSFixStatusReport, InertialSensorReport at 10 Hz, GPSReport of 40 satellites at 1 Hz): p99 latency
(sample timeStamp to arrival) per client count; then 10 clients beside one stalled client that
never reads. All clients run in this one process, which shares the 2 cores with the console and
the simulator, so the figures include the clients' own JSON decoding.

Then the peer in the same run: 50 vehicles at the same rates, one client of the console and one
of the generic answer (a cyclonedds reader feeding Foxglove's WebSocket server, each sample as
JSON: bench/foxglove_peer.py, its own process) at once, on the same input. Each server process's
CPU over the window divided by the report messages its client received: CPU per delivered sample.
Targets: the console beats the peer in CPU per delivered sample and at p50 and p99 latency.
Usage: python bench/fanout.py [--seconds 10] [--peer-vehicles 50]
"""

from __future__ import annotations

import argparse
import asyncio
import socket
import time

import common
from common import CpuMeter, emit, get_json, ms, percentile, report_latency, stack, table, ws_collect
from foxglove_peer import foxglove_collect, peer, sample_latency
from ingest import sim_args


async def clients(url: str, k: int, seconds: float) -> list[list[float]]:
    per_client: list[list[float]] = [[] for _ in range(k)]

    def collector(i: int):
        def on(msg: dict, now: float) -> None:
            if msg["type"] == "report" and msg["topic"] in ("GPSFixReport", "InertialSensorReport"):
                x = report_latency(msg, now)
                if x is not None:
                    per_client[i].append(x)

        return on

    await asyncio.gather(*(ws_collect(url, seconds, collector(i)) for i in range(k)))
    return per_client


def stalled_client(port: int) -> socket.socket:
    s = socket.create_connection(("127.0.0.1", port))
    s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    s.sendall(
        b"GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
    )
    return s  # never read from again


def against_peer(vehicles: int, seconds: float) -> list[dict]:
    """The console and the peer on the same `vehicles`, one client each, at once."""
    with stack(sim_args=sim_args(vehicles)) as st, peer(st["domain"]) as (peer_proc, peer_url):
        deadline = time.monotonic() + 30
        while get_json(st["url"] + "/api/metrics")["providers"] < vehicles and time.monotonic() < deadline:
            time.sleep(0.5)
        time.sleep(3)  # warm up
        got = {"console": [0, []], "peer": [0, []]}  # delivered reports, latencies (GPSFixReport, InertialSensorReport)

        def on_console(msg: dict, now: float) -> None:
            if msg["type"] == "report":
                got["console"][0] += 1
                x = report_latency(msg, now) if msg["topic"] in ("GPSFixReport", "InertialSensorReport") else None
                if x is not None:
                    got["console"][1].append(x)

        def on_peer(topic: str, sample: dict, now: float) -> None:
            got["peer"][0] += 1
            x = sample_latency(sample, now) if topic in ("GPSFixReport", "InertialSensorReport") else None
            if x is not None:
                got["peer"][1].append(x)

        async def both() -> None:
            await asyncio.gather(ws_collect(st["ws"], seconds, on_console), foxglove_collect(peer_url, seconds, on_peer))

        meters = {"console": CpuMeter(st["procs"]["console"]), "peer": CpuMeter(peer_proc)}
        t0 = time.monotonic()
        asyncio.run(both())
        elapsed = time.monotonic() - t0
        rows = []
        for name, label in (("console", "console"), ("peer", "peer: cyclonedds + Foxglove WS (JSON)")):
            cpu, (delivered, lat) = meters[name].read(), got[name]
            rows.append(
                {
                    "system": label,
                    "vehicles": vehicles,
                    "cpu_cores": round(cpu, 2),
                    "delivered_per_s": round(delivered / elapsed),
                    "cpu_us_per_delivered": round(cpu * elapsed / max(delivered, 1) * 1e6, 1),
                    "p50_ms": ms(percentile(lat, 50)),
                    "p99_ms": ms(percentile(lat, 99)),
                }
            )
        return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--peer-vehicles", type=int, default=50)
    args = ap.parse_args()
    rows = []
    with stack(sim_args=sim_args(5)) as st:
        time.sleep(5)
        for k, stalled in ((1, False), (10, False), (50, False), (10, True)):
            sock = stalled_client(st["port"]) if stalled else None
            if sock:
                time.sleep(1)
            lat = asyncio.run(clients(st["ws"], k, args.seconds))
            allv = [x for c in lat for x in c]
            rows.append(
                {
                    "clients": k,
                    "stalled_beside": stalled,
                    "samples": len(allv),
                    "p50_ms": ms(percentile(allv, 50)),
                    "p99_ms": ms(percentile(allv, 99)),
                    "worst_client_p99_ms": ms(max(percentile(c, 99) for c in lat)),
                }
            )
            if sock:
                sock.close()
    keys = list(rows[0])
    table(
        "Fan-out: latency per number of WebSocket clients (5 vehicles at full rate)", keys, [[r[k] for k in keys] for r in rows]
    )
    base = next(r for r in rows if r["clients"] == 10 and not r["stalled_beside"])
    with_stalled = rows[-1]
    print(f"\np99 with 10 clients: {base['p99_ms']} ms; with one stalled client beside them: {with_stalled['p99_ms']} ms")
    vs = against_peer(args.peer_vehicles, args.seconds)
    keys = list(vs[0])
    table(
        f"Against the peer: {args.peer_vehicles} vehicles, one client each, same input", keys, [[r[k] for k in keys] for r in vs]
    )
    c, g = vs
    targets = [
        common.target(
            f"console CPU per delivered sample ({args.peer_vehicles} vehicles) against the peer's",
            c["cpu_us_per_delivered"],
            "µs",
            "<",
            g["cpu_us_per_delivered"],
            "the peer",
        ),
        common.target("console p50 latency against the peer's", c["p50_ms"], "ms", "<", g["p50_ms"], "the peer"),
        common.target("console p99 latency against the peer's", c["p99_ms"], "ms", "<", g["p99_ms"], "the peer"),
    ]
    emit("fanout", {"rows": rows, "peer": vs, "targets": targets})


if __name__ == "__main__":
    main()
