"""Alarm management for a watch (console/alarms.py): shelving, planned silences, chattering and the causes floods are
grouped by. The derivation over a real SQLite store without a network (test_alarms.World), then real `sem-console` and
`sem-sim` processes: a shelf over a restart, a planned silence that ends in an alarm, a flood of 20 vehicles, and two
stations on one PostgreSQL database."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import text

from conftest import ConsoleProcess
from sem_console import cli
from sem_console.console.alarms import Alarms
from sem_console.sim.provider import vehicle_guid
from support import http
from test_alarms import ALPHA, CHARLIE, NAMES, T0, World
from test_console import V1, provider_ready, wait_until

OPERATOR = {"SEM_OPERATOR_TOKENS": "alice:s3cret"}
AUTH = {"Authorization": "Bearer s3cret"}
SHARED = 10  # seconds for a change on one station to reach the other (its write queued behind the others, NOTIFY, the
# listener): a bound for a loaded machine, not a latency test


def by_kind(active: list[dict[str, Any]], kind: str) -> dict[str, Any]:
    [a] = [x for x in active if x["kind"] == kind]
    return a


# ---- the derivation ----------------------------------------------------------------------------------
def test_a_shelved_alarm_is_out_of_view_until_its_time_ends_and_a_worse_one_brings_it_back_at_once(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.report(ALPHA, "GPSFixStatusReport", fixValid=True)
    w.report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
    w.update()
    w.at(1).report(ALPHA, "GPSFixStatusReport", fixValid=False)
    fix = by_kind(w.update(), "fix-lost")
    assert fix["cause"] == "GPS fix lost" and fix["shelf"] is None and fix["returned"] is None
    assert w.alarms.shelve(fix["id"], "diving", 900, "alice", T0 + 2, "watch") is not None
    shelf = by_kind(w.update(), "fix-lost")["shelf"]
    assert (shelf["reason"], shelf["by"], shelf["station"], shelf["until"]) == ("diving", "alice", "watch", T0 + 902)
    # a warning of another vehicle, or the fix coming and going, is not worse
    w.at(3).report(ALPHA, "GPSFixStatusReport", fixValid=True)
    w.update()
    w.at(4).report(ALPHA, "GPSFixStatusReport", fixValid=False)
    assert by_kind(w.update(), "fix-lost")["shelf"] is not None
    # the time ends: back in view, saying why
    back = by_kind(w.at(902).update(), "fix-lost")
    assert back["shelf"] is None and back["returned"] == "back from shelving: its time ended"
    # shelved again, then the same vehicle's INS fails (an alarm, more severe than the warning): back at once
    w.alarms.shelve(fix["id"], "diving", 3600, "alice", T0 + 903)
    assert by_kind(w.update(), "fix-lost")["returned"] is None
    w.at(904).report(ALPHA, "InertialSensorReport", status="INERTIAL_SENSOR_FAILURE")
    active = w.update()
    assert by_kind(active, "fix-lost")["shelf"] is None
    assert by_kind(active, "fix-lost")["returned"] == "back from shelving at once, worse: Alpha: INS failed"
    assert w.store.flush(30)
    with w.store.engine.connect() as c:
        ends = c.execute(text("SELECT end_reason FROM alarm_shelves ORDER BY shelved_at")).scalars().all()
    assert ends == ["expired", "worse: Alpha: INS failed"]
    assert w.ack(fix["id"]) and by_kind(w.alarms.active(), "fix-lost")["returned"] is None  # seen


def test_an_alarm_that_clears_and_returns_n_times_in_m_minutes_is_chattering_until_acknowledged(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.alarms = Alarms(w.store, NAMES, chatter=(3, 600.0))  # 3 returns within 10 min
    w.report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
    w.update()
    t = 0.0

    def flap() -> dict[str, Any]:
        nonlocal t
        t += 60
        w.at(t).report(ALPHA, "InertialSensorReport", status="INERTIAL_SENSOR_FAILURE")
        w.update()
        w.at(t + 1).report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
        w.update()
        w.at(t + 2).report(ALPHA, "InertialSensorReport", status="INERTIAL_SENSOR_FAILURE")
        return by_kind(w.update(), "ins-failure")

    assert not flap()["chattering"]  # raised, cleared, back once
    assert not flap()["chattering"]  # back twice (the raise at t=120 is the same alarm returning)
    chattering = flap()
    assert chattering["chattering"] and chattering["state"] == "active-unacknowledged"
    assert w.ack(chattering["id"]) and not by_kind(w.update(), "ins-failure")["chattering"]  # seen: sounds again
    # returns spread wider than the window are not chattering
    w2 = World(tmp_path / "db2")
    w2.alarms = Alarms(w2.store, NAMES, chatter=(3, 120.0))
    w2.report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
    for k in range(5):
        w2.at(100 * k).report(ALPHA, "InertialSensorReport", status="INERTIAL_SENSOR_FAILURE")
        w2.update()
        w2.at(100 * k + 1).report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
        w2.update()
    assert not by_kind(w2.alarms.active(), "ins-failure")["chattering"]


def test_a_planned_silence_holds_the_loss_back_then_is_overdue_heard_or_cancelled(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.alarms = Alarms(w.store, NAMES, silence_grace=30.0)
    w.report(CHARLIE, "GPSReport")
    w.update()
    w.alarms.silence(str(CHARLIE), T0 + 60, "diving", "alice", T0)
    assert w.at(10).update() == [] and w.providers.by_id[CHARLIE].link == "lost"
    assert [s["until"] for s in w.alarms.planned_silences()] == [T0 + 60]
    assert w.at(89).update() == []  # within the grace
    [overdue] = w.at(90).update()
    assert (overdue["kind"], overdue["severity"], overdue["cause"]) == (
        "silence-overdue",
        "alarm",
        "Not heard after a planned silence",
    )
    assert (
        overdue["text"] == f"Charlie: not heard by {time.strftime('%H:%M', time.gmtime(T0 + 60))} UTC, the end of its "
        "planned silence (30 s grace)"
    )
    assert w.alarms.planned_silences() == []
    for t in (91, 91.5, 92):  # heard again: cleared, and a later loss is link-lost again
        w.at(t).report(CHARLIE, "GPSReport")
        w.update()
    assert [(a["kind"], a["state"]) for a in w.alarms.active()] == [("silence-overdue", "cleared-unacknowledged")]
    w.ack(overdue["id"])
    assert [a["kind"] for a in w.at(100).update()] == ["link-lost"]
    # a silence declared while it is lost clears the loss; heard back by its end, it ends without an alarm
    w.alarms.silence(str(CHARLIE), T0 + 200, "relay down", "alice", T0 + 100)
    assert [a["state"] for a in w.at(101).update()] == ["cleared-unacknowledged"]
    for t in (150, 150.5, 151, 230):
        w.at(t).report(CHARLIE, "GPSReport")
        w.update()
    assert w.alarms.planned_silences() == [] and all(a["kind"] == "link-lost" for a in w.alarms.active())
    # cancelled: the loss is an alarm again at once
    w.alarms.silence(str(CHARLIE), T0 + 900, "diving", "alice", T0 + 231)
    w.at(240).update()
    assert w.alarms.cancel_silence(str(CHARLIE), "bob", T0 + 241) is not None
    assert any(a["kind"] == "link-lost" and a["state"] == "active-unacknowledged" for a in w.at(242).update())
    assert w.store.flush(30)
    with w.store.engine.connect() as c:
        ends = c.execute(text("SELECT end_reason, ended_by FROM planned_silences ORDER BY set_at")).all()
    assert [tuple(e) for e in ends] == [("overdue", None), ("heard", None), ("cancelled", "bob")]


# ---- real processes ----------------------------------------------------------------------------------
def alarm_of(c: ConsoleProcess, kind: str) -> dict[str, Any] | None:
    return next((a for a in http.get(f"{c.url}/api/alarms").json() if a["kind"] == kind), None)


@pytest.mark.slow
def test_a_shelf_is_kept_over_a_console_restart_and_ends_in_time_or_when_unshelved(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess]
) -> None:
    env = {**OPERATOR, "SEM_SHELVE_MIN_MINUTES": "0.1"}
    vehicle = sim()
    c = console(env=env)
    provider_ready(c.url, V1, {"GPSFixReport"})
    vehicle.kill()
    lost = wait_until(lambda: alarm_of(c, "link-lost"), 15, "link-lost")
    shelve = f"{c.url}/api/alarms/{lost['id']}/shelve"
    r = http.post(shelve, json={"reason": "relay down", "minutes": 600}, headers=AUTH)
    assert r.status_code == 409 and r.json()["detail"] == (
        "600 minutes is outside this console's shelving bounds, 0.1 to 480 minutes: shelve for a time within them"
    )
    assert http.post(shelve, json={"reason": "  ", "minutes": 30}, headers=AUTH).status_code == 422
    assert http.post(shelve, json={"reason": "relay down", "minutes": 30}).status_code == 401
    r = http.post(shelve, json={"reason": "relay down", "minutes": 0.4}, headers=AUTH)  # 24 s
    assert r.status_code == 200, r.text
    shelf = by_kind(r.json(), "link-lost")["shelf"]
    assert (shelf["reason"], shelf["by"], shelf["station"]) == ("relay down", "alice", "test-console")
    assert shelf["until"] - shelf["at"] == 24

    c.stop()
    c = console(env=env)  # the shelf and the alarm are kept
    again = alarm_of(c, "link-lost")
    assert again is not None and again["id"] == lost["id"] and again["shelf"] == shelf
    assert time.time() < shelf["until"]  # the test saw the restart within the shelf: not a trivial pass
    back = wait_until(lambda: (a := alarm_of(c, "link-lost")) and a["shelf"] is None and a, 40, "the shelf's end")
    assert back["returned"] == "back from shelving: its time ended" and time.time() >= shelf["until"]

    shelve = f"{c.url}/api/alarms/{lost['id']}/shelve"
    assert http.post(shelve, json={"reason": "known", "minutes": 60}, headers=AUTH).status_code == 200
    c.stop()
    c = console(env=env)
    assert (alarm_of(c, "link-lost") or {}).get("shelf", {})["reason"] == "known"  # type: ignore[index]
    unshelve = f"{c.url}/api/alarms/{lost['id']}/unshelve"
    r = http.post(unshelve, json={}, headers=AUTH)
    assert r.status_code == 200 and by_kind(r.json(), "link-lost")["returned"] == "back from shelving: unshelved by alice"
    assert http.post(unshelve, json={}, headers=AUTH).status_code == 409
    audit = [(e["path"], e["outcome"], e["status"], e["operator"], e["sessionId"]) for e in http.get(f"{c.url}/api/audit").json()]
    path = f"/api/alarms/{lost['id']}/shelve"
    assert (path, "accepted", 200, "alice", "shelved for 0.4 min: relay down") in audit
    assert (path, "refused", 409, "alice", None) in audit and (path, "refused", 401, None, None) in audit
    assert (f"/api/alarms/{lost['id']}/unshelve", "accepted", 200, "alice", None) in audit


@pytest.mark.slow
def test_a_planned_silence_is_kept_over_a_restart_and_ends_in_an_alarm_when_the_vehicle_is_not_back(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess]
) -> None:
    env = {**OPERATOR, "SEM_SILENCE_GRACE": "2"}
    vehicle = sim()
    started = time.monotonic()
    c = console(env=env)
    provider_ready(c.url, V1, {"GPSFixReport"})
    # the silence outlasts a restart and a loss: a console start and its vehicle ready took `start` s here (longer on a
    # loaded machine), the restart below takes about as long, the loss 1-2 s more
    start = time.monotonic() - started
    silence = f"{c.url}/api/providers/{V1}/silence"
    assert http.put(silence, json={"until": time.time() - 5, "reason": "dive"}, headers=AUTH).status_code == 409
    until = time.time() + max(20.0, 3 * start + 10)
    r = http.put(silence, json={"until": until, "reason": "dive to 40 m"}, headers=AUTH)
    assert r.status_code == 200, r.text
    [planned] = r.json()
    assert (planned["providerId"], planned["reason"], planned["by"], planned["until"]) == (V1, "dive to 40 m", "alice", until)
    c.stop()
    c = console(env=env)
    assert http.get(f"{c.url}/api/silences").json() == [planned]
    provider_ready(c.url, V1, {"GPSFixReport"})
    vehicle.kill()
    wait_until(lambda: http.get(f"{c.url}/api/providers/{V1}").json()["link"] == "lost", 15, "the loss")
    assert alarm_of(c, "link-lost") is None and alarm_of(c, "silence-overdue") is None
    assert time.time() < until  # lost within the silence: no alarm, not a trivial pass
    overdue = wait_until(lambda: alarm_of(c, "silence-overdue"), until - time.time() + 20, "the overdue alarm")
    assert time.time() >= until + 2
    assert overdue["text"].endswith(
        f"not heard by {time.strftime('%H:%M', time.gmtime(until))} UTC, the end of its planned silence (2 s grace)"
    )
    assert overdue["severity"] == "alarm" and alarm_of(c, "link-lost") is None
    assert http.get(f"{c.url}/api/silences").json() == []
    sim()  # back: cleared, waiting for acknowledgement
    wait_until(lambda: (a := alarm_of(c, "silence-overdue")) and a["state"] == "cleared-unacknowledged", 20, "cleared")
    audit = [(e["path"], e["operator"], e["sessionId"]) for e in http.get(f"{c.url}/api/audit").json()]
    assert (
        f"/api/providers/{V1}/silence",
        "alice",
        f"out of comms until {time.strftime('%H:%M', time.gmtime(until))} UTC: dive to 40 m",
    ) in audit


def test_a_flood_of_20_vehicles_lost_at_once_shares_one_cause(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess]
) -> None:
    vehicles = sim("--vehicles", "20")
    c = console()
    ids = {str(vehicle_guid(n)) for n in range(1, 21)}
    wait_until(lambda: {p["id"] for p in http.get(f"{c.url}/api/providers").json()} == ids, 60, "20 vehicles")
    vehicles.kill()  # the relay fails
    flood = wait_until(
        lambda: len(a := [x for x in http.get(f"{c.url}/api/alarms").json() if x["kind"] == "link-lost"]) == 20 and a,
        30,
        "20 link-lost alarms",
    )
    assert {a["providerId"] for a in flood} == ids and {a["cause"] for a in flood} == {"Link lost"}
    assert not any(a["chattering"] or a["shelf"] for a in flood)


@pytest.mark.slow
def test_two_stations_share_shelves_and_planned_silences(
    sim: Callable[..., Any], console: Callable[..., ConsoleProcess], pg_url: str
) -> None:
    vehicle = sim()
    a = console("--database-url", pg_url, "--console-name", "watch", env=OPERATOR)
    b = console("--database-url", pg_url, "--console-name", "relief", env=OPERATOR)
    for c in (a, b):
        provider_ready(c.url, V1, {"GPSFixReport"})
    until = time.time() + 600
    assert (
        http.put(f"{a.url}/api/providers/{V1}/silence", json={"until": until, "reason": "dive"}, headers=AUTH).status_code == 200
    )
    wait_until(lambda: [s["until"] for s in http.get(f"{b.url}/api/silences").json()] == [until], SHARED, "the silence on B")
    assert http.delete(f"{b.url}/api/providers/{V1}/silence", headers=AUTH).status_code == 200
    wait_until(lambda: http.get(f"{a.url}/api/silences").json() == [], SHARED, "the cancel on A")
    vehicle.kill()
    on_a = wait_until(lambda: alarm_of(a, "link-lost"), 15, "link-lost on A")
    wait_until(lambda: alarm_of(b, "link-lost"), 15, "link-lost on B")
    r = http.post(f"{a.url}/api/alarms/{on_a['id']}/shelve", json={"reason": "relay down", "minutes": 60}, headers=AUTH)
    assert r.status_code == 200
    shelf = by_kind(r.json(), "link-lost")["shelf"]
    on_b = wait_until(lambda: (x := alarm_of(b, "link-lost")) and x["shelf"] and x, SHARED, "the shelf on B")
    assert on_b["shelf"] == shelf and shelf["station"] == "watch"
    assert http.post(f"{b.url}/api/alarms/{on_b['id']}/unshelve", json={}, headers=AUTH).status_code == 200
    back = wait_until(lambda: (x := alarm_of(a, "link-lost")) and x["shelf"] is None and x, SHARED, "the unshelve on A")
    assert back["returned"] == "back from shelving: unshelved by alice"


def test_shelving_bounds_the_wrong_way_round_stop_sem_console_with_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        cli.main(["--shelve-min-minutes", "600"])
    assert e.value.code == 2
    assert capsys.readouterr().err == (
        "sem-console: error: --shelve-min-minutes 600 is above --shelve-max-minutes 480: the shortest shelf must not be "
        "longer than the longest\n"
    )
