"""Reports wake the push path per arrival while input is sparse and are conflated only under load:
the report thread's pacing (a controllable clock), the hub's per-client conflation (counting
sends), and the console on real Cyclone DDS with a conflation window far longer than any wait."""

from __future__ import annotations

import asyncio
import json
import time

import pytest

from sem_console.console.hub import Hub
from sem_console.console.pace import Pacer
from sem_console.dds.bus import Bus
from support import http
from test_console import WsClient, wait_until
from test_ingest import Provider, S


class Clock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_sparse_takes_never_wait_for_the_window() -> None:
    clock = Clock()
    pace = Pacer(window=0.005, burst=8, clock=clock)
    for _ in range(50):  # 10 Hz: every arrival is taken as it comes
        pace.took()
        assert pace.delay() == 0.0
        clock.t += 0.1


def test_a_burst_is_taken_at_once_then_the_window_applies() -> None:
    clock = Clock()
    pace = Pacer(window=0.005, burst=8, clock=clock)
    delays = []
    for _ in range(8):  # eight takes in the same instant (several vehicles' samples written together)
        pace.took()
        delays.append(pace.delay())
    assert delays[:7] == [0.0] * 7 and abs(delays[7] - 0.005) < 1e-12
    clock.t += 1.0  # idle: the bucket refills, to `burst` and no more
    for _ in range(7):
        pace.took()
        assert pace.delay() == 0.0
    pace.took()
    assert pace.delay() > 0


def test_sustained_load_takes_once_per_window() -> None:
    clock = Clock()
    pace = Pacer(window=0.005, burst=8, clock=clock)
    start, takes = clock.t, 0
    while clock.t - start < 1.0:  # input always waiting: the thread takes whenever it may
        pace.took()
        takes += 1
        clock.t += pace.delay()
        if pace.delay() == 0:
            clock.t += 1e-6  # a take costs a little time
    assert 200 <= takes <= 200 + 8 + 1  # one per 5 ms, plus the initial burst


def test_no_window_never_waits() -> None:
    clock = Clock()
    pace = Pacer(window=0.0, burst=1, clock=clock)
    for _ in range(20):
        pace.took()
        assert pace.delay() == 0.0


def test_hub_sends_a_lone_report_at_once_and_conflates_while_a_send_is_in_flight() -> None:
    async def scenario() -> None:
        hub = Hub()
        sent: list[dict] = []
        gate = asyncio.Event()
        gate.set()

        async def send(text: str) -> None:
            await gate.wait()
            sent.append(json.loads(text))

        hub.attach(send, {"type": "snapshot"})
        for _ in range(3):
            await asyncio.sleep(0)
        hub.publish({"type": "report", "n": 0}, key=("p", "GPSFixReport"))
        for _ in range(3):  # no timer: the client's task sends it on its next turn
            await asyncio.sleep(0)
        assert [m.get("n") for m in sent] == [None, 0]
        gate.clear()  # the socket is busy: the next send stays in flight
        hub.publish({"type": "report", "n": 1}, key=("p", "GPSFixReport"))
        await asyncio.sleep(0)
        for i in range(2, 6):
            hub.publish({"type": "report", "n": i}, key=("p", "GPSFixReport"))
            hub.publish({"type": "report", "n": 10 + i}, key=("q", "GPSFixReport"))
        gate.set()
        for _ in range(10):
            await asyncio.sleep(0)
        # the one in flight, then the latest per key: oldest key first
        assert [m.get("n") for m in sent] == [None, 0, 1, 5, 15]

    asyncio.run(scenario())


@pytest.mark.slow
def test_sparse_reports_reach_the_websocket_without_waiting_for_a_long_window(console, domain: int) -> None:
    """A 10 s conflation window: sparse reports still arrive at once; a dense stream is conflated."""
    c = console(env={"SEM_REPORT_INTERVAL": "10", "SEM_REPORT_BURST": "8"})
    bus = Bus(domain)
    p = Provider(bus.participant, bus=bus)
    ws = WsClient(c.ws_url)
    base = time.time_ns()

    def shown() -> list[int]:
        return [
            m["report"]["report"]["timeStamp"]["seconds"] * S + m["report"]["report"]["timeStamp"]["nanoseconds"] - base
            for m in ws.of("report")
            if m["providerId"] == str(p.id) and m["topic"] == "InertialSensorReport"
        ]

    time.sleep(2.5)  # idle: the thread's wakeups by its 200 ms timeout take nothing and must not empty the bucket
    for i in (1, 2):
        p.report(base + i * S)
        wait_until(lambda i=i: i * S in shown(), 30, f"sparse report {i}")
    # taken as they came: no take waited for the window
    assert http.get(f"{c.url}/api/metrics").json()["reportWindowWaits"] == 0
    before = len(shown())
    for i in range(3, 203):  # 200 reports 2 ms apart: each wakes the thread until the bucket is empty, then the window applies
        p.report(base + i * S)
        time.sleep(0.002)
    wait_until(lambda: shown() and shown()[-1] == 202 * S, 40, "the latest of the dense reports")
    dense = shown()[before:]
    assert len(dense) <= 9, dense  # the bucket's takes and the one after the window, not one per sample
    assert http.get(f"{c.url}/api/metrics").json()["reportWindowWaits"] >= 1  # the dense stream was batched
    assert dense == sorted(dense)
    ws.close()


def test_websocket_compression_only_when_configured(console) -> None:
    """permessage-deflate costs CPU and latency on every message: off unless SEM_WS_COMPRESSION asks for it."""
    from websockets.sync.client import connect

    for env, want in (({}, []), ({"SEM_WS_COMPRESSION": "true"}, ["PerMessageDeflate"])):
        c = console(env=env)
        with connect(c.ws_url, open_timeout=10, max_size=2**24) as ws:  # offers permessage-deflate, as browsers do
            assert [type(e).__name__ for e in ws.protocol.extensions] == want
            assert json.loads(ws.recv())["type"] == "snapshot"
        c.stop()
