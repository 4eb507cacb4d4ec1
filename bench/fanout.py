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

Then a fleet on many screens: 100 clients on one console with 250 vehicles at 1 Hz per report topic, beside one
client that stops reading (a laptop gone to sleep: a socket with a small receive buffer, never read). Each client
selects one vehicle, as a dashboard does: every client's p99 of that vehicle's reports (sample timeStamp to arrival,
after a warm-up; the others' come at the console's pace by design, their age printed apart), before and after the
console cut the sleeper, the time it took to cut it (the console's ws_cut_seconds set to 10 here), and the console's
CPU per report delivered to all the clients.
The 100 clients are one process of this script (orjson, one event loop) on the same cores as the console and the
simulator: their own decoding is in the figures.
Usage: python bench/fanout.py [--seconds 10] [--peer-vehicles 50] [--clients 100] [--vehicles 250] [--fleet-seconds 45]
       [--fleet-only]
"""

from __future__ import annotations

import argparse
import asyncio
import math
import socket
import threading
import time

import common
from common import CpuMeter, emit, for_seconds, get_json, ms, percentile, report_latency, stack, table, wait_listed, ws_collect
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
        (
            f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
        ).encode()
    )
    return s  # never read from again


FLEET_CUT_SECONDS = 10.0  # the console's ws_cut_seconds in the fleet run: the sleeper is cut within it
FLEET_STAGGER = 0.1  # s between two clients' connections: 100 snapshots of 250 vehicles at once timed the handshakes out
FLEET_WARM_UP = 10.0  # s after the last client connected before latencies count, and the sleeper stops reading


def fleet_sim_args(vehicles: int) -> list[str]:
    return ["--vehicles", str(vehicles), "--gps-rate", "1", "--fix-rate", "1", "--ins-rate", "1", "--align-seconds", "1"]


async def fleet_clients(
    url: str,
    k: int,
    until: float,
    counted_from: float,
    delivered: list[int],
    closed: list[str],
    paced: list[list[tuple[float, float]]],
) -> list[list[tuple[float, float]]]:
    """`k` clients reading /ws?batch=1&ack=1 as the dashboard does (each frame acknowledged, one vehicle selected: the
    others' reports at the console's pace for vehicles a client does not draw, their GPSReports without satellites),
    one every FLEET_STAGGER s, until `until` (wall clock): per client, (arrival, latency) of its selected vehicle's
    GPSFixReports and InertialSensorReports that arrived after `counted_from` (the others' in `paced`, per client: their
    age is the pace's by design); `delivered[0]` counts every report then; `closed`: the clients the console closed,
    with its reason."""
    import orjson
    import websockets

    got: list[list[tuple[float, float]]] = [[] for _ in range(k)]
    drawn: list[str | None] = [None] * k  # each client's selected vehicle

    async def one(i: int) -> None:
        await asyncio.sleep(i * FLEET_STAGGER)
        try:
            await read(i)
        except websockets.ConnectionClosed as e:  # the console cut it (it fell behind): counted, not a failure
            closed.append(f"client {i}: {e.rcvd.reason if e.rcvd else e}")

    async def read(i: int) -> None:
        async with websockets.connect(url + "?batch=1&ack=1", max_size=2**26, open_timeout=60) as ws:
            frames = 0
            async for text in for_seconds(ws, until - time.time()):
                now = time.time()
                frames += 1
                await ws.send(f'{{"type":"ack","frames":{frames}}}')
                msg = orjson.loads(text)
                if frames == 1:  # its snapshot: it draws one vehicle, as a dashboard does
                    drawn[i] = msg["providers"][i % len(msg["providers"])]["id"]
                    await ws.send(orjson.dumps({"type": "select", "providerId": drawn[i]}).decode())
                if now < counted_from:
                    continue
                for m in msg if isinstance(msg, list) else [msg]:
                    if m["type"] == "report":
                        delivered[0] += 1
                        if m["topic"] in ("GPSFixReport", "InertialSensorReport"):
                            x = report_latency(m, now)
                            if x is not None:
                                (got if m["providerId"] == drawn[i] else paced)[i].append((now, x))

    await asyncio.gather(*(one(i) for i in range(k)))
    return got


def dropped(url: str) -> int:
    """The console's count of WebSocket clients it cut (0 while it does not answer in time)."""
    try:
        return int(get_json(url + "/api/metrics")["wsClientsDropped"])
    except OSError:
        return 0


def fleet(clients_n: int, vehicles: int, seconds: float) -> dict:
    """`clients_n` clients and one that stops reading, on one console with `vehicles` vehicles, measured for `seconds`
    after the clients connected and warmed up (see the docstring)."""
    env = {"SEM_WS_CUT_SECONDS": str(FLEET_CUT_SECONDS)}
    with stack(sim_args=fleet_sim_args(vehicles), console_env=env) as st:
        wait_listed(st["url"], vehicles, timeout=60)
        counted_from = time.time() + clients_n * FLEET_STAGGER + FLEET_WARM_UP
        until = counted_from + seconds
        asleep: list[float] = []
        cut: list[float] = []

        def sleeper() -> None:  # connects when the measure starts, never reads; when the console cut it, by its counter
            time.sleep(max(0.0, counted_from - time.time()))
            sock = stalled_client(st["port"])
            asleep.append(time.time())
            while not cut and time.time() < until + 2 * FLEET_CUT_SECONDS:  # past the measure: the cut is a figure too
                if dropped(st["url"]) >= 1:
                    cut.append(time.time())
                time.sleep(0.25)
            sock.close()

        watcher = threading.Thread(target=sleeper, daemon=True)
        watcher.start()
        delivered = [0]
        closed: list[str] = []
        paced: list[list[tuple[float, float]]] = [[] for _ in range(clients_n)]
        own = [0.0]  # this process's CPU seconds when the measure started: the clients' own cost
        meter: CpuMeter | None = None

        async def run() -> list[list[tuple[float, float]]]:
            async def start_meter() -> None:
                nonlocal meter
                await asyncio.sleep(max(0.0, counted_from - time.time()))
                meter = CpuMeter(st["procs"]["console"])
                own[0] = time.process_time()

            got, _ = await asyncio.gather(
                fleet_clients(st["ws"], clients_n, until, counted_from, delivered, closed, paced), start_meter()
            )
            return got

        per_client = asyncio.run(run())
        assert meter is not None
        cpu_cores = meter.read()
        clients_cpu = time.process_time() - own[0]
        window = max(1e-9, min(time.time(), until) - counted_from)
        watcher.join(2 * FLEET_CUT_SECONDS + 5)
        health = get_json(st["url"] + "/api/health")
    cut_at = cut[0] if cut else None
    p99s = [v for v in (percentile([x for _, x in c], 99) for c in per_client) if not math.isnan(v)]
    before = [percentile([x for t, x in c if cut_at is None or t < cut_at], 99) for c in per_client]
    after = [percentile([x for t, x in c if cut_at is not None and t >= cut_at], 99) for c in per_client]
    real = [v for v in before if not math.isnan(v)]
    later = [v for v in after if not math.isnan(v)]
    return {
        "clients": clients_n,
        "vehicles": vehicles,
        "samples": sum(len(c) for c in per_client),
        "p50_ms": ms(percentile([x for c in per_client for _, x in c], 50)),
        # the vehicles a client does not draw: their reports' age as they arrive, the console's pace included
        "paced_p50_ms": ms(percentile([x for c in paced for _, x in c], 50)),
        "paced_p99_ms": ms(percentile([x for c in paced for _, x in c], 99)),
        "worst_client_p99_ms": ms(max(p99s)),
        "best_client_p99_ms": ms(min(p99s)),
        "worst_client_p99_sleeper_connected_ms": ms(max(real)) if real else None,
        "worst_client_p99_after_cut_ms": ms(max(later)) if later else None,
        "sleeper_cut_after_s": round(cut_at - asleep[0], 1) if cut_at is not None and asleep else None,
        "console_cpu_cores": round(cpu_cores, 2),
        "reports_delivered_per_s": round(delivered[0] / window),
        "cpu_us_per_delivered": round(cpu_cores * window / max(delivered[0], 1) * 1e6, 1),
        "clients_process_cpu_cores": round(clients_cpu / window, 2),
        "clients_cut_by_the_console": len(closed),
        "a_cut_client_told": closed[0] if closed else None,
        "console_behind_at_end": bool((health.get("load") or {}).get("behind")),
    }


def against_peer(vehicles: int, seconds: float) -> list[dict]:
    """The console and the peer on the same `vehicles`, one client each, at once."""
    with stack(sim_args=sim_args(vehicles)) as st, peer(st["domain"]) as (peer_proc, peer_url):
        wait_listed(st["url"], vehicles)
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
    ap.add_argument("--clients", type=int, default=100)
    ap.add_argument("--vehicles", type=int, default=250)
    ap.add_argument("--fleet-seconds", type=float, default=45.0, help="measured, after the clients' warm-up")
    ap.add_argument("--fleet-only", action="store_true", help="only the fleet run (100 clients, 250 vehicles)")
    args = ap.parse_args()
    many = fleet(args.clients, args.vehicles, args.fleet_seconds)
    keys = list(many)
    table(
        f"A fleet on many screens: {args.clients} clients and one that stops reading, {args.vehicles} vehicles at 1 Hz",
        ["figure", "value"],
        [[k, many[k]] for k in keys],
    )
    fleet_targets = [
        common.target(
            f"every client's p99, its selected vehicle ({args.clients} clients, {args.vehicles} vehicles)",
            many["worst_client_p99_ms"],
            "ms",
            "<=",
            250,
        ),
        common.target(
            "the worst client's p99 while a client that stops reading is connected, against after it was cut",
            many["worst_client_p99_sleeper_connected_ms"],
            "ms",
            "<=",
            None if many["worst_client_p99_after_cut_ms"] is None else round(1.2 * many["worst_client_p99_after_cut_ms"], 2),
            "after the cut, plus 20 %: this machine's run-to-run noise",
        ),
        common.target(
            "the client that stops reading cut, with its reason, after",
            many["sleeper_cut_after_s"],
            "s",
            "<=",
            3 * FLEET_CUT_SECONDS,
            "its bound, 10 s here, once its buffers filled",
        ),
    ]
    print(f"console CPU per report delivered: {many['cpu_us_per_delivered']} µs ({many['console_cpu_cores']} cores)")
    if args.fleet_only:
        emit("fanout", {"fleet": many, "targets": fleet_targets})
        return
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
    try:
        vs = against_peer(args.peer_vehicles, args.seconds)
    except RuntimeError as e:  # the peer's own process: the console's figures stand without it
        print(f"\nthe peer comparison did not run: {e}")
        emit("fanout", {"rows": rows, "fleet": many, "peer_error": str(e), "targets": fleet_targets})
        return
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
    emit("fanout", {"rows": rows, "peer": vs, "fleet": many, "targets": fleet_targets + targets})


if __name__ == "__main__":
    main()
