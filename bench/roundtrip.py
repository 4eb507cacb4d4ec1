"""Command round trip: POST a GPS fix, time to ISSUED and to COMPLETED seen on the WebSocket,
against the same flow driven by a plain DDS consumer. The simulator answers at once
(--step-seconds 0, surfaced after the first command), so both measure the path, not the vehicle.
Usage: python bench/roundtrip.py [--commands 200]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import sys
import time
import urllib.request
import uuid

import common
from common import emit, ms, percentile, stack, table

SIM = ["--step-seconds", "0", "--surface-seconds", "0", "--fix-rate", "1", "--gps-rate", "0.2", "--ins-rate", "1"]


async def console_round_trips(st: dict, vehicle: str, n: int) -> tuple[list[float], list[float]]:
    import websockets

    issued, completed = [], []
    async with websockets.connect(st["ws"], max_size=2**26) as ws:
        seen: dict[str, dict[str, float]] = {}

        async def reader() -> None:
            async for text in ws:
                msg = json.loads(text)
                if msg["type"] == "transition":
                    seen.setdefault(msg["sessionId"], {}).setdefault(msg["transition"]["status"], time.perf_counter())

        task = asyncio.create_task(reader())
        loop = asyncio.get_running_loop()
        for _ in range(n + 5):
            req = urllib.request.Request(
                f"{st['url']}/api/providers/{vehicle}/gps-fix",
                method="POST",
                data=b"{}",
                headers={"Content-Type": "application/json"},
            )
            t0 = time.perf_counter()
            body = await loop.run_in_executor(None, lambda req=req: urllib.request.urlopen(req, timeout=10).read())
            session = json.loads(body)["sessionId"]
            deadline = time.monotonic() + 10
            while "COMPLETED" not in seen.get(session, {}) and time.monotonic() < deadline:
                await asyncio.sleep(0.0005)
            if "COMPLETED" in seen.get(session, {}):
                issued.append(seen[session]["ISSUED"] - t0)
                completed.append(seen[session]["COMPLETED"] - t0)
        task.cancel()
    return issued[5:], completed[5:]  # the first commands surface the vehicle


def plain_round_trips(domain: int, vehicle: uuid.UUID, n: int) -> tuple[list[float], list[float]]:
    sys.path.insert(0, str(common.ROOT / "backend" / "tests"))
    from cyclonedds.core import WaitSet
    from cyclonedds.util import duration

    from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S

    from sem_console.dds.bus import Bus, all_samples
    from sem_console.dds.topics import Service
    from sem_console.umaa.guid import to_guid
    from sem_console.umaa.samples import now_datetime

    bus = Bus(domain)
    writer, reader = bus.writer(Service.GPS_FIX.command), bus.reader(Service.GPS_FIX.status)
    cond = all_samples(reader)
    ws = WaitSet(bus.participant)
    ws.attach(cond)
    me = to_guid(uuid.uuid4())
    time.sleep(2.0)  # discovery settles
    issued, completed = [], []
    for _ in range(n + 5):
        session = uuid.uuid4()
        cmd = Service.GPS_FIX.command.spec.type(
            source=me, destination=to_guid(vehicle), sessionID=to_guid(session), timeStamp=now_datetime()
        )
        t0 = time.perf_counter()
        writer.write(cmd)
        got: dict[S, float] = {}
        deadline = time.monotonic() + 10
        while S.COMPLETED not in got and time.monotonic() < deadline:
            ws.wait(duration(milliseconds=50))
            for s in reader.take(N=64, condition=cond):
                if getattr(s, "sessionID", None) is not None and bytes(s.sessionID) == session.bytes:
                    got.setdefault(s.commandStatus, time.perf_counter())
        if S.COMPLETED in got:
            issued.append(got[S.ISSUED] - t0)
            completed.append(got[S.COMPLETED] - t0)
        writer.dispose(cmd)  # cleanup, as the console does
    return issued[5:], completed[5:]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--commands", type=int, default=200)
    args = ap.parse_args()
    from sem_console.sim.provider import vehicle_guid

    vehicle = vehicle_guid(1)
    with stack(sim_args=SIM) as st:
        common.wait_http(f"{st['url']}/api/providers/{vehicle}")
        c_iss, c_done = asyncio.run(console_round_trips(st, str(vehicle), args.commands))
        f_iss, f_done = plain_round_trips(st["domain"], vehicle, args.commands)
    rows = [
        [
            "console (REST -> WebSocket)",
            len(c_done),
            ms(percentile(c_iss, 50)),
            ms(percentile(c_iss, 99)),
            ms(percentile(c_done, 50)),
            ms(percentile(c_done, 99)),
        ],
        [
            "floor (plain DDS consumer)",
            len(f_done),
            ms(percentile(f_iss, 50)),
            ms(percentile(f_iss, 99)),
            ms(percentile(f_done, 50)),
            ms(percentile(f_done, 99)),
        ],
    ]
    table(
        "Command round trip (GPS fix, simulator answering at once)",
        ["path", "n", "ISSUED p50 ms", "ISSUED p99 ms", "COMPLETED p50 ms", "COMPLETED p99 ms"],
        rows,
    )
    figures = {
        "commands": len(c_done),
        "console_issued_p50_ms": rows[0][2],
        "console_issued_p99_ms": rows[0][3],
        "console_completed_p50_ms": rows[0][4],
        "console_completed_p99_ms": rows[0][5],
        "floor_issued_p50_ms": rows[1][2],
        "floor_issued_p99_ms": rows[1][3],
        "floor_completed_p50_ms": rows[1][4],
        "floor_completed_p99_ms": rows[1][5],
        "completed_overhead_p50_ms": round(rows[0][4] - rows[1][4], 2),
    }
    print(f"\ncommand to COMPLETED overhead over the plain-DDS floor, p50: {figures['completed_overhead_p50_ms']} ms")
    emit("roundtrip", figures)


if __name__ == "__main__":
    main()
