"""An operations centre: two real `sem-console` processes on one DDS domain and one real PostgreSQL database
(tests/pg.py), with a simulated vehicle. Each console is its own UMAA consumer; what one does reaches the other's
WebSocket through LISTEN/NOTIFY; a command issued on one can be canceled from the other, running or not."""

from __future__ import annotations

import csv
import io
import json
import signal
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import psycopg
import pytest

from conftest import ConsoleProcess
from support import http
from support.pg import Cluster
from test_console import (
    V1,
    V2,
    WsClient,
    command,
    gps_fix_executing,
    lost_vehicle_command_canceled_unanswered,
    provider_ready,
    wait_command,
    wait_until,
)
from test_history import UNTHINNED, at_most_one_per_second
from test_names import rename_heard
from test_recording import read, recorded


def health(c: ConsoleProcess) -> dict[str, Any]:
    return http.get(f"{c.url}/api/health").json()


def heard(ws: WsClient, session: str, status: str) -> dict[str, Any] | None:
    """The newest `command` message of `session` on this WebSocket, once its status is `status`."""
    for m in reversed(ws.of("command")):
        if m["command"]["sessionId"] == session:
            return m["command"] if m["command"]["status"] == status else None
    return None


@pytest.mark.slow
def test_two_consoles_distinct_identities_shared_commands_and_hand_over(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    sim("--surface-seconds", "400")  # a GPS fix stays EXECUTING until canceled
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    id_a, id_b = health(a)["consoleId"], health(b)["consoleId"]
    assert id_a != id_b  # two UMAA consumers on one domain, told apart by the vehicle
    ws_b = WsClient(b.ws_url)
    try:
        session = gps_fix_executing(a.url)
        on_b = wait_until(lambda: heard(ws_b, session, "EXECUTING"), 10, "A's command on B's WebSocket")
        assert on_b["console"] == "watch" and [t["status"] for t in on_b["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING"]
        assert command(b.url, session)["console"] == "watch"  # and in B's history
        r = http.delete(f"{b.url}/api/commands/{session}")  # B cancels A's command
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


@pytest.mark.slow
def test_the_canceller_and_the_station_are_named_on_every_station_in_history_and_the_csv(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    """Bob on relief cancels Alice's command from watch: both stations, their histories and their CSV exports say who
    cancelled it and where, not only while the cancel is on its way (the API had the operator, no station)."""
    sim("--surface-seconds", "400")
    a = console("--database-url", pg_url, "--console-name", "watch", "--operator-tokens", "alice:tok-a")
    b = console("--database-url", pg_url, "--console-name", "relief", "--operator-tokens", "bob:tok-b")
    alice, bob = {"Authorization": "Bearer tok-a"}, {"Authorization": "Bearer tok-b"}
    ws_a = WsClient(a.ws_url)
    try:
        provider_ready(a.url, V1, {"GPSFixReport"})
        session = http.post(f"{a.url}/api/providers/{V1}/gps-fix", json={}, headers=alice).json()["sessionId"]
        wait_command(a.url, session, done=lambda x: x["status"] == "EXECUTING")
        # relief knows the command before bob cancels it there (it hears it a moment after watch: a loaded run's relief
        # had not yet, and answered the cancel 404)
        wait_command(b.url, session, done=lambda x: x.get("status") == "EXECUTING")
        asked = time.time()
        r = http.delete(f"{b.url}/api/commands/{session}", headers=bob)
        assert r.status_code == 200 and (r.json()["canceledBy"], r.json()["canceledOn"]) == ("bob", "relief"), r.text
        for c in (a, b):
            done = wait_command(c.url, session, done=lambda x: x["terminal"] and x["status"] == "CANCELED")
            assert (done["operator"], done["console"], done["canceledBy"], done["canceledOn"]) == (
                "alice",
                "watch",
                "bob",
                "relief",
            ), done
            assert abs(done["canceledAt"] - asked) < 5
            listed = next(x for x in http.get(f"{c.url}/api/commands").json() if x["sessionId"] == session)
            assert (listed["canceledBy"], listed["canceledOn"]) == ("bob", "relief")  # the history page
            rows = [
                x for x in csv.DictReader(io.StringIO(http.get(f"{c.url}/api/commands.csv").text)) if x["session_id"] == session
            ]
            assert {(x["operator"], x["station"], x["canceled_by"], x["canceled_on"]) for x in rows} == {
                ("alice", "watch", "bob", "relief")
            }, rows
        # Alice's own WebSocket: the finished command as her station's clients have it
        on_a = wait_until(lambda: heard(ws_a, session, "CANCELED"), 10, "CANCELED on A's WebSocket")
        assert (on_a["canceledBy"], on_a["canceledOn"]) == ("bob", "relief"), on_a
    finally:
        ws_a.close()
    a.stop()
    again = console("--database-url", pg_url, "--console-name", "watch", "--operator-tokens", "alice:tok-a")
    reloaded = command(again.url, session)  # after a restart, from the database
    assert (reloaded["canceledBy"], reloaded["canceledOn"]) == ("bob", "relief"), reloaded


def test_the_database_banner_s_message_comes_within_2_s_of_the_console_knowing(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_cluster: Cluster, pg_url: str
) -> None:
    """The dashboard asked GET /api/health every 15 s: the banner came about 12 s after the console knew. The console
    now pushes a `database` message at the tick that finds the outage (and its end), as it does an alarm."""
    sim()
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    provider_ready(a.url, V1)
    sockets = [WsClient(a.ws_url), WsClient(b.ws_url)]
    try:
        for ws in sockets:
            snapshot = wait_until(lambda ws=ws: ws.of("snapshot"), 10, "the snapshot")[0]
            assert snapshot["database"] == {"unavailableSince": None, "writesHeld": 0, "writesDropped": 0}
        pg_cluster.stop()
        try:
            for ws in sockets:

                def down(ws: WsClient = ws) -> tuple[float, dict[str, Any]] | None:
                    m = next((m for m in ws.of("database") if m["database"]["unavailableSince"] is not None), None)
                    return (time.time(), m["database"]) if m else None

                seen, state = wait_until(down, 20, "the outage on the WebSocket")
                assert seen - state["unavailableSince"] < 2.0, (seen, state)
        finally:
            pg_cluster.start()
        for ws in sockets:
            wait_until(
                lambda ws=ws: (x := ws.of("database")) and x[-1]["database"]["unavailableSince"] is None,
                20,
                "the end of the outage on the WebSocket",
            )
            assert not ws.errors, ws.errors
    finally:
        for ws in sockets:
            ws.close()


def test_a_command_of_a_console_that_stopped_is_canceled_from_another(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    # no orphan grace to speak of: the vehicle would cancel a command that lost its writer (A) by itself after 10 s,
    # and this test would pass without B's dispose reaching it
    sim("--surface-seconds", "400", "--orphan-grace", "3600")
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    session = gps_fix_executing(a.url)
    wait_command(b.url, session, done=lambda x: x.get("status") == "EXECUTING")  # relief has heard it (a moment after)
    a.stop(signal.SIGKILL)  # gone without its shutdown sequence: the command still runs on the vehicle
    r = http.delete(f"{b.url}/api/commands/{session}")
    assert r.status_code == 200 and r.json()["cancelRequested"], r.text
    done = wait_command(b.url, session, done=lambda x: x["terminal"])
    assert [t["status"] for t in done["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]


@pytest.mark.slow
def test_a_command_canceled_unanswered_on_a_station_stopped_for_good_is_ended_by_another(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    """Watch cancels a command its lost vehicle never answered, then stops for good: relief showed it counting up for
    ever, in its history and on its dashboard. Relief ends it once it has heard the vehicle back without a word of it."""
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    session = lost_vehicle_command_canceled_unanswered(a, sim())
    a.stop()
    ws_b = WsClient(b.ws_url)
    try:
        assert not command(b.url, session)["terminal"]
        sim()  # the vehicle back, without the command (the cancel disposed it)
        done = wait_command(b.url, session, done=lambda x: x["terminal"], timeout=30)
        assert (done["closedUnheard"], done["status"], done["transitions"], done["cleanedUp"]) == ("heard", None, [], True)
        listed = next(x for x in http.get(f"{b.url}/api/commands").json() if x["sessionId"] == session)  # history
        assert (listed["terminal"], listed["closedUnheard"], listed["closedAt"]) == (True, "heard", done["closedAt"])
        wait_until(
            lambda: any(m["command"]["sessionId"] == session and m["command"]["terminal"] for m in ws_b.of("command")),
            10,
            "the end on relief's WebSocket",
        )
        assert not ws_b.errors, ws_b.errors
    finally:
        ws_b.close()


@pytest.mark.slow
def test_a_command_taken_over_replays_with_the_alarms_the_station_raised_for_it(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str, tmp_path: Path
) -> None:
    """Relief records; it shows watch's command, raising no alarm for it, then takes it over (to cancel it) and from
    then on raises its alarms: here the Figure 4 violation of a vehicle that skips COMMANDED. A replay of relief's
    recording raised none: the file did not say which commands were taken over, so this one counted as watch's."""
    sim("--surface-seconds", "400", "--fault", "skip-commanded")  # ISSUED -> EXECUTING, and EXECUTING until canceled
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief", "--record", str(tmp_path / "rec"))
    ws_b = WsClient(b.ws_url)
    try:
        session = gps_fix_executing(a.url)
        wait_until(lambda: heard(ws_b, session, "EXECUTING"), 10, "A's command on B's WebSocket")
    finally:
        ws_b.close()

    def violations(c: ConsoleProcess) -> list[dict[str, Any]]:
        return [x for x in http.get(f"{c.url}/api/alarms").json() if x["kind"] == "flow-violation" and x["sessionId"] == session]

    assert violations(a) and not violations(b)  # watch's own; relief only shows it
    r = http.delete(f"{b.url}/api/commands/{session}")  # relief takes it over to cancel it
    assert r.status_code == 200 and r.json()["cancelRequested"], r.text
    wait_command(b.url, session, done=lambda x: x["terminal"])
    assert violations(b)  # from the take-over on, relief's too
    path = recorded(b.url, tmp_path)
    followed = [json.loads(m.data)["followed"] for m in read(path)[1]["sem-console/commands"]]
    assert followed[0] is False and followed[-1] is True, followed  # shown, then taken over
    replay = console("--replay", str(path), "--replay-speed", "20")
    wait_until(lambda: http.get(f"{replay.url}/api/replay").json()["state"] == "paused", 30, "the end of the replay")
    (shown,) = violations(replay)
    assert shown["vehicle"] is not None and shown["state"] == "active-unacknowledged"


@pytest.mark.slow
def test_a_database_outage_loses_nothing_and_stops_no_console(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_cluster: Cluster, pg_url: str
) -> None:
    """PostgreSQL stopped: both consoles keep monitoring, A commands and cancels, its health says since when the
    shared history is unavailable, reads of the database answer 503 in one line, an alarm raised meanwhile can be
    acknowledged; started again: what A held is written, B reads it all from the database and its WebSocket hears
    what it missed (A's command, the acknowledgement)."""
    vehicle = sim("--surface-seconds", "400")
    a = console("--database-url", pg_url, "--console-name", "watch", *UNTHINNED)
    b = console("--database-url", pg_url, "--console-name", "relief", *UNTHINNED)
    provider_ready(a.url, V1, {"GPSFixReport"})
    provider_ready(b.url, V1, {"GPSFixReport"})
    ws_b = WsClient(b.ws_url)
    pg_cluster.stop()
    try:
        r = http.post(f"{a.url}/api/providers/{V1}/gps-fix", json={})
        assert r.status_code == 201, r.text
        session = r.json()["sessionId"]
        wait_command(a.url, session, done=lambda x: x["status"] == "EXECUTING")
        assert http.delete(f"{a.url}/api/commands/{session}").status_code == 200
        wait_command(a.url, session, done=lambda x: x["terminal"])
        down = health(a)
        assert down["databaseUnavailableSince"] is not None and down["databaseWritesHeld"] > 0, down
        for c in (a, b):  # monitoring goes on
            assert http.get(f"{c.url}/api/providers/{V1}").json()["link"] != "lost"
        for c in (a, b):  # the shared history: one line, not a traceback
            r = http.get(f"{c.url}/api/audit")
            assert r.status_code == 503 and r.json()["detail"].startswith("shared history unavailable since"), r.text
            assert "\n" not in r.json()["detail"] and "pg-test-s3cret" not in r.text
        vehicle.kill()  # an alarm raised during the outage: its row's id, taken ahead, acknowledged by it
        on_a = wait_until(lambda: lost(a), 15, "link-lost on A")
        wait_until(lambda: lost(b), 15, "link-lost on B")
        assert on_a["id"] > 0, on_a
        r = http.post(f"{a.url}/api/alarms/{on_a['id']}/ack", json={})
        assert r.status_code == 200, r.text
        for c, name in ((a, "Night A"), (b, "Night B")):  # both rename it: both held, written one after the other
            assert http.put(f"{c.url}/api/providers/{V1}/name", json={"name": name}).json()["name"] == name
    finally:
        pg_cluster.start()
    try:
        wait_until(lambda: health(a)["databaseUnavailableSince"] is None, 20, "the held writes written")
        assert health(a)["databaseWritesHeld"] == 0
        # B finds the server back at its own next check (every 2 s); until then its reads answer 503
        wait_until(lambda: health(b)["databaseUnavailableSince"] is None, 20, "B back on the database")
        done = command(b.url, session)  # from the database: everything A did meanwhile
        assert [t["status"] for t in done["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"], done
        assert done["cancelRequested"] and done["console"] == "watch"
        paths = {(e["method"], e["path"]) for e in http.get(f"{b.url}/api/audit").json()}
        assert ("POST", f"/api/providers/{V1}/gps-fix") in paths and ("DELETE", f"/api/commands/{session}") in paths
        wait_until(lambda: heard(ws_b, session, "CANCELED"), 20, "A's command, made during the outage, on B's WebSocket")
        wait_until(lambda: (x := lost(b)) is not None and x["state"] != "active-unacknowledged", 20, "A's ack on B")
        assert not ws_b.errors, ws_b.errors
        with psycopg.connect(pg_url) as db:  # the name written last is the one both consoles show
            stored = db.execute("SELECT name FROM vehicle_names WHERE provider_id = %s", (V1,)).fetchone()
            acked = db.execute("SELECT acked_at FROM alarms WHERE id = %s AND console = 'watch'", (on_a["id"],)).fetchone()
        assert acked is not None and acked[0] is not None, f"no row {on_a['id']} of A's alarm, acknowledged"
        assert stored is not None and stored[0] in ("Night A", "Night B"), stored
        wait_until(
            lambda: all(http.get(f"{c.url}/api/providers/{V1}").json()["name"] == stored[0] for c in (a, b)),
            10,
            f"{stored[0]!r} on both consoles",
        )
    finally:
        ws_b.close()
    assert a.proc is not None and b.proc is not None and a.proc.poll() is None and b.proc.poll() is None


def lost(c: ConsoleProcess) -> dict[str, Any] | None:
    """The console's link-lost alarm, when it has one."""
    return next((x for x in http.get(f"{c.url}/api/alarms").json() if x["kind"] == "link-lost"), None)


@pytest.mark.slow
def test_an_alarm_acknowledged_on_one_console_is_acknowledged_on_the_other(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    vehicle = sim()
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    for c in (a, b):
        provider_ready(c.url, V1, {"GPSFixReport"})
    vehicle.kill()  # both lose it: each raises its own link-lost alarm
    on_a = wait_until(lambda: lost(a), 15, "link-lost on A")
    wait_until(lambda: lost(b), 15, "link-lost on B")
    assert http.post(f"{a.url}/api/alarms/{on_a['id']}/ack", json={}).status_code == 200
    wait_until(lambda: (x := lost(b)) is not None and x["state"] == "active-acknowledged", 10, "the ack on B")


@pytest.mark.slow
def test_a_replay_shows_the_alarms_acknowledged_as_they_were_on_this_station_and_the_other(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str, tmp_path: Path
) -> None:
    """Relief records; bob acknowledges on watch its alarm of one lost vehicle (so relief's is acknowledged too),
    relief's own operator relief's of the other. A replay derives the alarms again: it showed every one as never
    acknowledged, as if nobody had seen them; it shows them acknowledged when, by whom and where they were."""
    vehicles = sim("--vehicles", "2")
    a = console("--database-url", pg_url, "--console-name", "watch", env={"SEM_OPERATOR_TOKENS": "bob:t0ken"})
    b = console("--database-url", pg_url, "--console-name", "relief", "--record", str(tmp_path / "rec"))
    for c, v in ((a, V1), (b, V1), (b, V2)):
        provider_ready(c.url, v, {"GPSFixReport"})
    vehicles.kill()

    def lost_of(c: ConsoleProcess, v: str) -> dict[str, Any] | None:
        return next(
            (x for x in http.get(f"{c.url}/api/alarms").json() if x["kind"] == "link-lost" and x["providerId"] == v), None
        )

    on_a = wait_until(lambda: lost_of(a, V1), 15, "V1's link-lost on watch")
    for v in (V1, V2):
        wait_until(lambda v=v: lost_of(b, v), 15, f"{v}'s link-lost on relief")
    r = http.post(f"{a.url}/api/alarms/{on_a['id']}/ack", json={}, headers={"Authorization": "Bearer t0ken"})
    assert r.status_code == 200, r.text
    wait_until(lambda: (x := lost_of(b, V1)) is not None and x["ackedBy"] == "bob", 10, "bob's ack on relief")
    own = lost_of(b, V2)
    assert own is not None and http.post(f"{b.url}/api/alarms/{own['id']}/ack", json={}).status_code == 200
    live = {v: lost_of(b, v) for v in (V1, V2)}
    path = recorded(b.url, tmp_path)
    acks = [json.loads(m.data) for m in read(path)[1]["sem-console/alarm-acks"]]
    assert [(x["providerId"], x["ackedBy"], x["station"]) for x in acks] == [(V1, "bob", "watch"), (V2, None, "relief")]
    replay = console("--replay", str(path), "--replay-speed", "20")
    wait_until(lambda: http.get(f"{replay.url}/api/replay").json()["state"] == "paused", 30, "the end of the replay")
    for v in (V1, V2):
        shown, was = lost_of(replay, v), live[v]
        assert shown is not None and was is not None
        assert (shown["state"], shown["ackedAt"], shown["ackedBy"]) == ("active-acknowledged", was["ackedAt"], was["ackedBy"])


def test_a_rename_on_one_console_shows_on_the_others_websocket_and_a_later_console_loads_it(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    sim()
    a = console("--database-url", pg_url, "--console-name", "watch")
    b = console("--database-url", pg_url, "--console-name", "relief")
    provider_ready(b.url, V1, {"GPSFixReport"})
    rename_heard(f"{a.url}/api/providers/{V1}/name", "Bravo", WsClient(b.ws_url))  # on A, heard on B's WebSocket
    assert http.get(f"{b.url}/api/providers/{V1}").json()["name"] == "Bravo"
    with psycopg.connect(pg_url, autocommit=True) as db:  # the listening connections lost: a rename meanwhile is
        db.execute("SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE query LIKE 'LISTEN%'")  # not heard
    assert http.put(f"{a.url}/api/providers/{V1}/name", json={"name": "Charlie"}).status_code == 200
    wait_until(
        lambda: http.get(f"{b.url}/api/providers/{V1}").json()["name"] == "Charlie",
        10,
        "B reloads the names when it listens again",
    )
    later = console("--database-url", pg_url, "--console-name", "night")
    assert provider_ready(later.url, V1, {"GPSFixReport"})["name"] == "Charlie"


def test_each_vehicles_track_is_written_once_and_handed_over(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    """Two consoles hear the vehicle, one writes its track (at most one point a second in the shared database);
    when that one stops, the other goes on writing it."""
    sim()
    a = console("--database-url", pg_url, "--console-name", "watch", *UNTHINNED)
    b = console("--database-url", pg_url, "--console-name", "relief", *UNTHINNED)
    provider_ready(a.url, V1, {"GPSFixReport"})
    provider_ready(b.url, V1, {"GPSFixReport"})

    def track() -> list[dict[str, Any]]:
        return http.get(f"{b.url}/api/providers/{V1}/track").json()

    wait_until(lambda: len(track()) >= 6, 20, "six track points")
    at_most_one_per_second(track())
    a.stop()  # whichever of the two wrote it, B writes it from now on
    stopped = len(track())
    wait_until(lambda: len(track()) >= stopped + 4, 20, "the track going on after A stopped")
    at_most_one_per_second(track())
