"""The console knows when it is the one behind (console/load.py), against `sem-sim` vehicles over real DDS; and a
WebSocket client that stops reading is cut with a reason, slowing no one (console/hub.py)."""

from __future__ import annotations

import os
import signal
import socket
import threading
import time
from pathlib import Path
from typing import Any

import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from conftest import SimProcess
from sem_console.sim.provider import vehicle_guid
from support import http
from test_console import WsClient, wait_until

VEHICLES = 12


def alarms(url: str) -> list[dict[str, Any]]:
    result: list[dict[str, Any]] = http.get(f"{url}/api/alarms").json()
    return result


def all_live(url: str, n: int) -> bool:
    providers = http.get(f"{url}/api/providers").json()
    return len(providers) == n and all(p["link"] == "live" for p in providers)


def quiet(ws: WsClient, seconds: float) -> bool:
    """No report has come on `ws` for `seconds`."""
    count = len(ws.of("report"))
    time.sleep(seconds)
    return len(ws.of("report")) == count


@pytest.mark.slow
def test_a_starved_console_says_it_is_overloaded_once_and_blames_no_vehicle(sim, console) -> None:
    """The machine stalled for 3 s (saturated: the simulators and a browser took the cores; or its VM paused): the
    console and the vehicles' simulator stopped, the console ran again first. Every vehicle is silent by its clock
    then. It says it was behind, raises one console-overloaded alarm and no link-lost, shows the vehicles as not
    checked until they are heard, and clears when it keeps up."""
    vehicles = sim("--vehicles", str(VEHICLES))
    # a comms-lost timeout (and so a settle time) of 2 s: the vehicles silent before the stall for less than it, once
    # their last samples are handled, and the simulator given that long to be heard again after the console's judgement
    c = console("--comms-lost-timeout", "2")
    wait_until(lambda: all_live(c.url, VEHICLES), 30, "every vehicle live")
    wait_until(lambda: not http.get(f"{c.url}/api/health").json()["load"]["behind"], 30, "the console keeping up")
    ws = WsClient(c.ws_url)
    wait_until(lambda: ws.of("snapshot"), 10, "the snapshot")
    assert c.proc is not None and vehicles.proc is not None
    os.kill(vehicles.proc.pid, signal.SIGSTOP)
    # the samples the simulator sent before it stopped handled first: one still in the console's socket when it stops
    # is heard as it runs again, after the stall, and its vehicle is then silent while the console keeps up (lost)
    wait_until(lambda: quiet(ws, 0.3), 10, "the simulator's last reports handled")
    os.kill(c.proc.pid, signal.SIGSTOP)
    time.sleep(3)
    os.kill(c.proc.pid, signal.SIGCONT)
    # the vehicles again once the console has run and judged them, behind: the simulator's reports must not come
    # before the console's first tick, or nothing is late
    try:
        wait_until(lambda: "unchecked" in [m["event"] for m in ws.of("provider")], 10, "the console's vehicles unchecked")
    except AssertionError as e:
        seen = [(m["event"], m["provider"]["link"], m["provider"]["ageSeconds"]) for m in ws.of("provider")]
        raise AssertionError(f"{e}: provider events {seen}, load {[m['load'] for m in ws.of('load')]}") from None
    os.kill(vehicles.proc.pid, signal.SIGCONT)
    wait_until(lambda: any(m["load"]["behind"] for m in ws.of("load")), 10, "the console behind")
    wait_until(lambda: any(not m["load"]["behind"] for m in ws.of("load")), 15, "the console caught up")
    wait_until(lambda: all_live(c.url, VEHICLES), 15, "every vehicle live again")
    active = alarms(c.url)
    assert [a["kind"] for a in active] == ["console-overloaded"], active
    overload = active[0]
    assert overload["providerId"] is None and overload["state"] == "cleared-unacknowledged"
    assert overload["text"].startswith("this console is overloaded: it ran up to ")
    assert "run fewer vehicles on this console or give it a bigger machine" in overload["text"]
    events = [m["event"] for m in ws.of("provider")]
    assert "unchecked" in events and "lost" not in events, events
    assert ws.errors == []
    # and it keeps up again: a machine still saturated by others may hold it behind a while longer
    wait_until(
        lambda: (h := http.get(f"{c.url}/api/health").json()["load"])["behind"] is False and h["vehiclesNotChecked"] == 0,
        30,
        "the console keeping up, every vehicle checked",
    )


def test_a_silent_vehicle_is_lost_while_the_console_keeps_up(sim, console, domain: int, tmp_path: Path) -> None:
    """The console not behind: a vehicle that goes silent (its process stopped) is link-lost as ever, and the console
    says nothing of itself."""
    sim("--vehicles", "2")
    silent = SimProcess(domain, ["--vehicles", "1", "--first-vehicle", "3"], tmp_path / "third.json").start()
    c = console()
    wait_until(lambda: all_live(c.url, 3), 30, "every vehicle live")
    assert silent.proc is not None
    os.kill(silent.proc.pid, signal.SIGSTOP)
    try:
        lost = str(vehicle_guid(3))
        wait_until(lambda: any(a["kind"] == "link-lost" for a in alarms(c.url)), 15, "a link-lost alarm")
        active = alarms(c.url)
        assert [(a["kind"], a["providerId"]) for a in active] == [("link-lost", lost)], active
        assert http.get(f"{c.url}/api/health").json()["load"]["behind"] is False
    finally:
        os.kill(silent.proc.pid, signal.SIGCONT)
        silent.end()


@pytest.mark.slow
def test_a_client_that_stops_reading_is_cut_with_a_reason_and_slows_no_one(sim, console) -> None:
    """A real client that stops reading (its socket's buffers full: a laptop asleep) is cut after the bound, told why
    in the close frame; another client's reports keep arriving meanwhile."""
    sim("--vehicles", "6")
    c = console(env={"SEM_WS_CUT_SECONDS": "2"})
    wait_until(lambda: all_live(c.url, 6), 30, "every vehicle live")
    reading = WsClient(c.ws_url)
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # before connecting: a small window from the start
    sock.connect(("127.0.0.1", c.port))
    with connect(c.ws_url, sock=sock, open_timeout=10, max_size=2**24) as sleeper:
        closed: list[tuple[int | None, str | None]] = []

        def wake_later() -> None:
            try:
                while True:
                    sleeper.recv()
            except ConnectionClosed as e:
                closed.append((e.rcvd.code if e.rcvd else None, e.rcvd.reason if e.rcvd else None))

        # the sleeper's buffers fill, and it is cut after the bound; meanwhile the reading client's reports stay fresh
        start = time.monotonic()
        time.sleep(1)
        before = len(reading.of("report"))
        ages: list[float] = []

        def cut() -> bool:
            newest = reading.of("report")[-1]["report"]["report"]["timeStamp"]
            ages.append(time.time() - (newest["seconds"] + newest["nanoseconds"] / 1e9))
            return bool(http.get(f"{c.url}/api/metrics").json()["wsClientsDropped"] >= 1)

        wait_until(cut, 30, "the sleeper cut")
        cut_after = time.monotonic() - start
        reader = threading.Thread(target=wake_later, daemon=True)
        # the laptop wakes a moment later (or a loaded machine runs this test late): it reads what was sent to it, then
        # the close frame with its reason, which waits for it (ws.CLOSE_WAIT)
        time.sleep(2)
        reader.start()
        reader.join(15)
    assert closed and closed[0][0] == 1013, closed
    assert closed[0][1] is not None and closed[0][1].startswith("stopped reading: nothing taken for "), closed
    assert closed[0][1].endswith("the console cut it so no other screen waits. Reconnect")
    assert len(reading.of("report")) - before > 50 * cut_after, "the reading client kept receiving"
    # its newest report, looked at every 50 ms while the sleeper stalled: fresh at the median (held behind the sleeper,
    # it would age from 0 to the cut, a median of half the bound or more); a loaded machine's own stall of a second or
    # two shows in its maximum, not in its median
    assert sorted(ages)[len(ages) // 2] < 0.5, ages
    assert http.get(f"{c.url}/api/metrics").json()["wsClients"] == 1
    out = c.stop()
    assert "closed the WebSocket of 127.0.0.1" in out and "stopped reading" in out
