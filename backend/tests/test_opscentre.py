"""An operations centre: two real `sem-console` processes on one DDS domain and one real PostgreSQL database
(tests/pg.py), with a simulated vehicle. Each console is its own UMAA consumer; what one does reaches the other's
WebSocket through LISTEN/NOTIFY; a command issued on one can be canceled from the other, running or not."""

from __future__ import annotations

import signal
from collections.abc import Callable
from typing import Any

import httpx

from conftest import ConsoleProcess
from test_console import WsClient, command, gps_fix_executing, wait_command, wait_until


def health(c: ConsoleProcess) -> dict[str, Any]:
    return httpx.get(f"{c.url}/api/health").json()


def heard(ws: WsClient, session: str, status: str) -> dict[str, Any] | None:
    """The newest `command` message of `session` on this WebSocket, once its status is `status`."""
    for m in reversed(ws.of("command")):
        if m["command"]["sessionId"] == session:
            return m["command"] if m["command"]["status"] == status else None
    return None


def test_two_consoles_distinct_identities_shared_commands_and_hand_over(
        sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str) -> None:
    sim("--surface-seconds", "400")  # a GPS fix stays EXECUTING until canceled
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    id_a, id_b = health(a)["consoleId"], health(b)["consoleId"]
    assert id_a != id_b  # two UMAA consumers on one domain, told apart by the vehicle
    ws_b = WsClient(b.ws_url)
    try:
        session = gps_fix_executing(a.url)
        on_b = wait_until(lambda: heard(ws_b, session, "EXECUTING"), 10, "A's command on B's WebSocket")
        assert on_b["console"] == "watch" and [t["status"] for t in on_b["transitions"]] == ["ISSUED", "COMMANDED",
                                                                                              "EXECUTING"]
        assert command(b.url, session)["console"] == "watch"  # and in B's history
        r = httpx.delete(f"{b.url}/api/commands/{session}")  # B cancels A's command
        assert r.status_code == 200 and r.json()["cancelRequested"], r.text
        statuses = ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]
        for c in (a, b):
            done = wait_command(c.url, session, done=lambda x: x["terminal"])
            assert [t["status"] for t in done["transitions"]] == statuses
        wait_until(lambda: heard(ws_b, session, "CANCELED"), 10, "CANCELED on B's WebSocket")
        assert not ws_b.errors, ws_b.errors
    finally:
        ws_b.close()
    a.stop()
    again = console("--database-url", pg_url, "--console-name", "watch")
    assert health(again)["consoleId"] == id_a  # a restart keeps its identity


def test_a_command_of_a_console_that_stopped_is_canceled_from_another(
        sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str) -> None:
    sim("--surface-seconds", "400")
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    session = gps_fix_executing(a.url)
    a.stop(signal.SIGKILL)  # gone without its shutdown sequence: the command still runs on the vehicle
    r = httpx.delete(f"{b.url}/api/commands/{session}")
    assert r.status_code == 200 and r.json()["cancelRequested"], r.text
    done = wait_command(b.url, session, done=lambda x: x["terminal"])
    assert [t["status"] for t in done["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]
