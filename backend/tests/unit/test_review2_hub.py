"""Review of the `interest` merge: the hub's budgets and pace told, failing where they do not hold."""

from __future__ import annotations

import asyncio
import json
import time
from typing import Any

import pytest

from sem_console.console import hub as hub_module
from sem_console.console.hub import Hub


def test_a_seek_while_a_pages_snapshot_is_in_flight_does_not_lose_its_pace() -> None:
    """A replay's seek (`resync`) clears what waits for each client; the `pace` message told with its `select` waited
    there behind the snapshot in flight: the page never learns the pace it is sent at, and judges every vehicle it does
    not draw by 3 s (at 1,000 vehicles, paced at 10 s, all 'stale' between their reports)."""

    async def scenario() -> None:
        hub = Hub()
        got: list[dict[str, Any]] = []
        gate = asyncio.Event()

        async def send(text: str) -> None:
            if not got:
                await gate.wait()  # its first snapshot (hundreds of kB) still going out
            got.append(json.loads(text))

        client = hub.attach(send, {"type": "snapshot", "n": 1}, vehicle="sel")  # /ws?vehicle=sel
        await asyncio.sleep(0.01)
        hub.resync({"type": "snapshot", "n": 2})  # another viewer of the replay seeks
        gate.set()
        await asyncio.sleep(0.05)
        assert client.selecting and [m["type"] for m in got][:2] == ["snapshot", "snapshot"]
        assert [m["othersEvery"] for m in got if m["type"] == "pace"] == [client.pace]

    asyncio.run(scenario())


def test_the_whole_gps_reports_budget_holds_in_wall_time_in_a_replay_at_20x(monkeypatch: pytest.MonkeyPatch) -> None:
    """WHOLE_BUDGET is whole GPSReports a second to a page (their bytes: 10 kB each); in a replay the hub's clock is the
    recording's (20x: 20 s of it each second), and each vehicle's whole one is due by that clock, so a page gets 20
    times the budget: at 1,000 vehicles 200 whole GPSReports (2 MB) a second, what the budget was made to stop."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 0.0)
    monkeypatch.setattr(hub_module, "FULL_EVERY", 1.0)
    monkeypatch.setattr(hub_module, "WHOLE_BUDGET", 2)  # 10 other vehicles: each one's whole every 5 s

    async def scenario() -> None:
        start = time.monotonic()
        hub = Hub(clock=lambda: 20 * (time.monotonic() - start))  # a replay at 20x
        got: list[dict[str, Any]] = []

        async def send(text: str) -> None:
            got.append(json.loads(text))

        hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        vehicles = ["sel"] + [f"v{i}" for i in range(10)]

        def gps() -> None:
            for p in vehicles:
                whole = {"type": "report", "providerId": p, "topic": "GPSReport", "report": {"satellites": [1]}}
                hub.publish(whole, key=(p, "GPSReport"), thin={**whole, "partial": True, "report": {"satellites": []}})

        gps()
        hub.sweep(0.0)
        hub.sweep(hub_module.STREAMS_EVERY)  # 11 vehicles with a GPSReport counted
        got.clear()
        began = time.monotonic()
        while time.monotonic() - began < 2.0:
            gps()
            await asyncio.sleep(0.05)
        wall = time.monotonic() - began
        whole = [m for m in got if m["type"] == "report" and m["providerId"] != "sel" and not m.get("partial")]
        # within the budget: 2 a second, and each vehicle's first spread over its period (at most one each)
        assert len(whole) <= hub_module.WHOLE_BUDGET * wall + 10, len(whole)

    asyncio.run(scenario())


def test_a_report_that_raises_an_alarm_is_not_held_a_pace_behind_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """The console publishes a vehicle's report, then the alarm it raised (service.py: `report_changed`, then
    `_update_alarms`): the alarm, ordered, goes at once; the report of a vehicle the page does not draw waits up to its
    pace (10 s at 1,000 vehicles), so the fleet bar's chip and the vehicle list say 'INS operational' for seconds beside
    'Bravo: INS failed' in the alarms."""
    monkeypatch.setattr(hub_module, "OTHERS_BUDGET", 1)  # the others' two streams: a pace of 2 s

    async def scenario() -> None:
        hub = Hub()
        got: list[dict[str, Any]] = []

        async def send(text: str) -> None:
            got.append(json.loads(text))

        def ins(status: str) -> None:
            message = {"type": "report", "providerId": "bravo", "topic": "InertialSensorReport", "status": status}
            hub.publish(message, key=("bravo", "InertialSensorReport"))

        hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        ins("OPERATIONAL")
        hub.publish({"type": "report", "providerId": "bravo", "topic": "GPSFixReport"}, key=("bravo", "GPSFixReport"))
        hub.sweep(0.0)
        hub.sweep(hub_module.STREAMS_EVERY)
        client = next(iter(hub.clients))
        assert client.pace == 2.0
        sent = len([m for m in got if m.get("topic") == "InertialSensorReport"])
        while len([m for m in got if m.get("topic") == "InertialSensorReport"]) == sent:  # until one just went
            ins("OPERATIONAL")
            await asyncio.sleep(0.02)
        ins("FAILED")
        hub.publish({"type": "alarms", "alarms": [{"text": "bravo: INS failed"}]})
        await asyncio.sleep(0.3)
        kinds = [m.get("status") or m["type"] for m in got[-2:]]
        assert "alarms" in kinds and "FAILED" in kinds, kinds

    asyncio.run(scenario())
