"""Fan-out: 1, 10 and 50 WebSocket clients on one console with 5 vehicles at full rate (GPSFixReport,
GPSFixStatusReport, InertialSensorReport at 10 Hz, GPSReport of 40 satellites at 1 Hz): p99 latency
(sample timeStamp to arrival) per client count; then 10 clients beside one stalled client that
never reads. All clients run in this one process, which shares the 2 cores with the console and
the simulator, so the figures include the clients' own JSON decoding.
Usage: python bench/fanout.py [--seconds 10]
"""

from __future__ import annotations

import argparse
import asyncio
import socket
import time

from common import emit, ms, percentile, report_latency, stack, table, ws_collect
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
    s.sendall(b"GET /ws HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
              b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
    return s  # never read from again


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0)
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
            rows.append({"clients": k, "stalled_beside": stalled, "samples": len(allv), "p50_ms": ms(percentile(allv, 50)),
                         "p99_ms": ms(percentile(allv, 99)), "worst_client_p99_ms": ms(max(percentile(c, 99) for c in lat))})
            if sock:
                sock.close()
    keys = list(rows[0])
    table("Fan-out: latency per number of WebSocket clients (5 vehicles at full rate)", keys, [[r[k] for k in keys] for r in rows])
    base = next(r for r in rows if r["clients"] == 10 and not r["stalled_beside"])
    with_stalled = rows[-1]
    print(f"\np99 with 10 clients: {base['p99_ms']} ms; with one stalled client beside them: {with_stalled['p99_ms']} ms")
    emit("fanout", {"rows": rows})


if __name__ == "__main__":
    main()
