"""Latency, sample to WebSocket, against the floor of a plain DDS reader in another process and
against a peer: the generic answer (a cyclonedds reader feeding Foxglove's WebSocket server, each
sample as JSON; bench/foxglove_peer.py), in the same run on the same samples.

A writer (a process of its own) publishes InertialSensorReport and GPSFixReport samples stamped with their send time
(5 sources x 2 topics at 10 Hz, written together every 100 ms: sparse input, so every sample is
shown); a WebSocket client of the console, a Foxglove WebSocket client of the peer and a plain
cyclonedds-python reader record arrival. Run with the default conflation window (report_interval
5 ms) and with 50 ms. Targets: overhead over the floor p50 < 1 ms and p99 < 5 ms; the
console beats the peer by at least 25 % at p50 and p99 (below 0.75 x the peer's, in the same run).
Usage: python bench/latency.py [--seconds 12]
"""

from __future__ import annotations

import argparse
import asyncio
import subprocess
import sys
import time
import uuid

import common
from common import emit, ms, percentile, stack, table, ws_collect
from foxglove_peer import foxglove_collect, peer, sample_latency

from UMAA.Common.MaritimeEnumeration.GPSFixEnumType import GPSFixEnumType
from UMAA.Common.MaritimeEnumeration.InertialSensorOpStatusEnumType import InertialSensorOpStatusEnumType as Op
from UMAA.Common.MaritimeEnumeration.InertialSensorStateEnumType import InertialSensorStateEnumType as Ins
from UMAA.Common.Measurement import (
    Altitude_MSL,
    GeodeticLatitude,
    GeodeticLongitude,
    Position2D,
    Position2DTime,
    Velocity3D_PlatformNED,
)
from UMAA.SEM.GPSFixStatus import GPSFixReportType
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from sem_console.dds.bus import Bus
from sem_console.dds.topics import Sem
from sem_console.umaa.guid import to_guid
from sem_console.umaa.samples import now_datetime

SOURCES, RATE = 5, 10.0


def publish(domain: int, seconds: float) -> int:
    bus = Bus(domain)
    ins_w, fix_w = bus.writer(Sem.INS_REPORT), bus.writer(Sem.GPS_FIX_REPORT)
    sources = [to_guid(uuid.uuid4()) for _ in range(SOURCES)]
    pos = Position2DTime(Position2D(GeodeticLatitude(36.8), GeodeticLongitude(-75.7)), None)
    print("ready", flush=True)
    if not sys.stdin.readline():  # go: the floor and the clients are ready (end of input: the run gave up, write nothing)
        return 0
    time.sleep(2.0)  # discovery settles both ways before the first timed sample
    sent, t_end = 0, time.monotonic() + seconds
    while time.monotonic() < t_end:
        t0 = time.monotonic()
        for src in sources:
            ins_w.write(InertialSensorReportType(state=Ins.ON, status=Op.OPERATIONAL, source=src, timeStamp=now_datetime()))
            fix_w.write(
                GPSFixReportType(
                    altitudeMSL=Altitude_MSL(0.0),
                    GPSFixCommandStatus=GPSFixEnumType.STABLE,
                    GPSLatLongValid=True,
                    magneticVariation=0.0,
                    position2DWithTime=pos,
                    SOG=1.0,
                    trueCourse=0.5,
                    velocity=Velocity3D_PlatformNED(0.0, 0.5, 0.8),
                    source=src,
                    timeStamp=now_datetime(),
                )
            )
            sent += 2
        time.sleep(max(0.0, 1 / RATE - (time.monotonic() - t0)))
    return sent


def run(window: float, seconds: float) -> dict[str, float]:
    with stack(console_env={"SEM_REPORT_INTERVAL": str(window)}) as st, peer(st["domain"]) as (_peer, peer_url):
        console: list[float] = []
        generic: list[float] = []
        # the writer in a process of its own, as the floor's reader: in this one it would hold the clients' GIL while it
        # writes each burst, and delay their arrival stamps by its own work
        writer = subprocess.Popen(
            [sys.executable, __file__, "--seconds", str(seconds), "--publish", str(st["domain"])],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        floor = subprocess.Popen(
            [
                sys.executable,
                str(common.ROOT / "bench" / "floor_reader.py"),
                str(st["domain"]),
                str(seconds + 4),
                "INS_REPORT",
                "GPS_FIX_REPORT",
            ],
            stdout=subprocess.PIPE,
            text=True,
        )
        for p in (writer, floor):
            assert p.stdout is not None and p.stdout.readline().strip() == "ready"
        assert writer.stdin is not None
        writer.stdin.write("go\n")  # it waits 2 s for discovery, then writes for `seconds`
        writer.stdin.flush()

        def on(msg: dict, now: float) -> None:
            lat = common.report_latency(msg, now)
            if lat is not None and msg["topic"] in ("InertialSensorReport", "GPSFixReport"):
                console.append(lat)

        def on_peer(topic: str, sample: dict, now: float) -> None:
            lat = sample_latency(sample, now)
            if lat is not None and topic in ("InertialSensorReport", "GPSFixReport"):
                generic.append(lat)

        async def both() -> None:  # both clients in this one process, on the same loop
            await asyncio.gather(ws_collect(st["ws"], seconds + 3, on), foxglove_collect(peer_url, seconds + 3, on_peer))

        asyncio.run(both())
        sent = int(writer.communicate(timeout=30)[0].strip().splitlines()[-1])  # it has written everything by now
        floor_lat = [float(x) for x in __import__("json").loads(floor.communicate(timeout=30)[0].strip().splitlines()[-1])]
    c50, c99, f50, f99 = percentile(console, 50), percentile(console, 99), percentile(floor_lat, 50), percentile(floor_lat, 99)
    g50, g99 = percentile(generic, 50), percentile(generic, 99)
    return {
        "window_ms": window * 1000,
        "published": sent,
        "console_n": len(console),
        "peer_n": len(generic),
        "floor_n": len(floor_lat),
        "console_p50_ms": ms(c50),
        "console_p99_ms": ms(c99),
        "console_max_ms": ms(max(console, default=float("nan"))),
        "peer_p50_ms": ms(g50),
        "peer_p99_ms": ms(g99),
        "floor_p50_ms": ms(f50),
        "floor_p99_ms": ms(f99),
        "overhead_p50_ms": ms(c50 - f50),
        "overhead_p99_ms": ms(c99 - f99),
        "peer_overhead_p50_ms": ms(g50 - f50),
        "peer_overhead_p99_ms": ms(g99 - f99),
        "ratio_p50": round(c50 / f50, 1) if f50 > 0 else None,
        "ratio_p99": round(c99 / f99, 1) if f99 > 0 else None,
    }


def _quarter_less(peer_ms: float) -> float:
    """What beating the peer by at least 25 % means: below 0.75 x its figure."""
    return round(0.75 * peer_ms, 2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=12.0)
    ap.add_argument("--publish", type=int, metavar="DOMAIN", help=argparse.SUPPRESS)  # the writer's process (run())
    args = ap.parse_args()
    if args.publish is not None:
        print(publish(args.publish, args.seconds), flush=True)
        return
    runs = [run(w, args.seconds) for w in (0.005, 0.05)]  # the default window, and a wider one
    keys = [
        "window_ms",
        "published",
        "console_n",
        "peer_n",
        "floor_n",
        "console_p50_ms",
        "console_p99_ms",
        "console_max_ms",
        "peer_p50_ms",
        "peer_p99_ms",
        "floor_p50_ms",
        "floor_p99_ms",
        "overhead_p50_ms",
        "overhead_p99_ms",
        "peer_overhead_p50_ms",
        "peer_overhead_p99_ms",
        "ratio_p50",
        "ratio_p99",
    ]
    table(
        "Latency, sample to WebSocket: console, peer (cyclonedds + Foxglove WebSocket server), raw DDS floor",
        keys,
        [[r[k] for k in keys] for r in runs],
    )
    d = runs[0]  # the default window
    targets = [
        common.target("overhead over the floor, p50 (5 ms window)", d["overhead_p50_ms"], "ms", "<", 1.0),
        common.target("overhead over the floor, p99 (5 ms window)", d["overhead_p99_ms"], "ms", "<", 5.0),
        common.target(
            "console p50 against the peer's", d["console_p50_ms"], "ms", "<", _quarter_less(d["peer_p50_ms"]), "0.75 x the peer's"
        ),
        common.target(
            "console p99 against the peer's", d["console_p99_ms"], "ms", "<", _quarter_less(d["peer_p99_ms"]), "0.75 x the peer's"
        ),
    ]
    emit("latency", {"runs": runs, "targets": targets})


if __name__ == "__main__":
    main()
