"""Alarms derived on the server (console/alarms.py): the derivation and ISA-18.2 states without a network
(a real SQLite store, the console's Commands and Providers), the routes through FastAPI's TestClient, and one
vehicle with a failed INS over real DDS."""

from __future__ import annotations

import re
import uuid
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import text

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as R

from sem_console.console.alarms import NO_FIX_GRACE, Alarms
from sem_console.console.clock import RecordingClock
from sem_console.console.commands import Command, Commands
from sem_console.console.providers import Providers
from sem_console.core.config import Settings
from sem_console.dds.topics import Service
from sem_console.main import create_app
from sem_console.storage.database import Database
from sem_console.versions.commands import COMMANDING
from support import http
from test_console import V1, WsClient, provider_ready, wait_until

OK = R.SUCCEEDED
ALPHA, CHARLIE, UNNAMED = uuid.uuid4(), uuid.uuid4(), uuid.UUID("3f2a9c01-0000-4000-8000-000000000000")
NAMES = {str(ALPHA): "Alpha", str(CHARLIE): "Charlie"}
T0 = 1_800_000_000.0

GPS_FIX_3_0_1, INS_3_0_1 = COMMANDING["3.0.1", Service.GPS_FIX], COMMANDING["3.0.1", Service.INERTIAL_SENSOR]


class World:
    """A console's state without DDS: its store, commands and providers on a clock the test moves."""

    def __init__(self, db: Path) -> None:
        self.clock = RecordingClock(T0)
        self.store = Database(db)
        self.written: list[Any] = []
        self.disposed: list[Any] = []
        self.commands = Commands(
            self.store.claim("test", hold=False),
            self.store,
            lambda _s, x: self.written.append(x),
            lambda _s, x: self.disposed.append(x),
            lambda _m: None,
            2.0,
            self.clock,
        )
        self.providers = Providers(3.0, 1.0, NAMES)  # lost after 3 s, regained after 1 s
        self.alarms = Alarms(self.store, NAMES)
        assert self.store.flush(30)  # as a console started: alarm ids taken ahead
        self.alarms.baseline(self.commands.by_session.values())
        self.recording_error: str | None = None

    def at(self, t: float) -> World:
        self.clock.at = T0 + t
        return self

    def report(self, vehicle: uuid.UUID, topic: str, **fields: Any) -> bool:
        now = self.clock.at
        self.providers.seen(topic, vehicle, {"report": fields, "invalid": [], "receivedAt": now}, now, now, True)
        return self.alarms.report_changed(vehicle, topic, fields)

    def status(self, cmd: Command, *steps: tuple[S, R] | tuple[S, R, str]) -> None:
        for st, reason, *message in steps:
            self.commands.on_status(
                cmd.service, cmd.session_id, cmd.provider_id, st, reason, message[0] if message else "", self.clock.at
            )

    def update(self) -> list[dict[str, Any]]:
        self.providers.tick(self.clock.at)
        self.commands.tick(self.clock.at, lambda p: x.last_seen() if (x := self.providers.by_id.get(p)) else None)
        self.alarms.update(self.clock.at, self.providers.by_id, self.commands.by_session.values(), self.recording_error)
        return self.alarms.active()

    def ack(self, alarm_id: int, operator: str | None = "alice") -> bool:
        return self.alarms.acknowledge(alarm_id, operator, self.clock.at) is not None


def kinds(active: list[dict[str, Any]]) -> list[tuple[str, str]]:
    return [(a["kind"], a["state"]) for a in active]


# ---- conditions --------------------------------------------------------------------------------
def test_each_failed_alignment_of_a_6_0_ins_is_an_ins_failure_in_its_words(tmp_path: Path) -> None:
    """UMAA 6.0 says which alignment failed: each raises the INS alarm, its text the status's words."""
    w = World(tmp_path / "db")
    said = {}
    for t, status in enumerate(
        (
            "GPS_ALIGNMENT_FAILURE",
            "STATIONARY_ALIGNMENT_FAILURE",
            "BEST_ALIGNMENT_FAILURE",
            "TRANSFER_ALIGNMENT_FAILURE",
            "SNAP_ALIGNMENT_FAILURE",
        )
    ):
        w.at(2 * t).report(ALPHA, "InertialSensorReport", status=status)
        [failed] = w.update()
        assert (failed["kind"], failed["severity"], failed["state"]) == ("ins-failure", "alarm", "active-unacknowledged")
        said[status] = failed["text"]
        w.at(2 * t + 1).report(ALPHA, "InertialSensorReport", status="FINE_GPS_ALIGNMENT_COMPLETE")  # aligned: it clears
        assert kinds(w.update()) == [("ins-failure", "cleared-unacknowledged")]
        w.ack(failed["id"])
        assert w.update() == []
    assert said["GPS_ALIGNMENT_FAILURE"] == "Alpha: INS GPS-aided alignment failed"
    assert said["SNAP_ALIGNMENT_FAILURE"] == "Alpha: INS snap alignment failed"
    w.report(ALPHA, "InertialSensorReport", status="COARSE_GPS_ALIGNMENT")  # a stage is no failure
    assert w.update() == []


def test_link_lost_is_active_until_regained_and_leaves_once_acknowledged(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.report(CHARLIE, "GPSReport")
    assert w.update() == []
    [lost] = w.at(5).update()
    assert (lost["kind"], lost["severity"], lost["state"], lost["text"]) == (
        "link-lost",
        "alarm",
        "active-unacknowledged",
        "Charlie: link lost",
    )
    assert lost["vehicle"] == "Charlie" and lost["providerId"] == str(CHARLIE) and lost["since"] == T0 + 5
    assert w.ack(lost["id"]) and kinds(w.update()) == [("link-lost", "active-acknowledged")]
    assert w.alarms.active()[0]["ackedBy"] == "alice"
    for t in (6, 6.5, 7, 7.5):  # samples again for the regained time
        w.at(t).report(CHARLIE, "GPSReport")
        w.update()
    assert w.providers.by_id[CHARLIE].link == "regained" and w.alarms.active() == []
    assert w.store.flush(30)
    with w.store.engine.connect() as c:
        [row] = c.execute(text("SELECT * FROM alarms")).mappings().all()
    assert row["normal_at"] == row["cleared_at"] == T0 + 7 and row["acked_by"] == "alice"


@pytest.mark.postgres
def test_an_acknowledgement_is_told_the_other_stations_once_not_again_at_each_later_save(pg_url: str) -> None:
    """Relief's link-lost alarm acknowledged by Alice, then saved again as the vehicle is back (normal): the other
    stations are told of the acknowledgement once. Told again at each later save, it acknowledged an alarm of that key
    another station had raised since (the vehicle lost again there) that nobody had seen."""
    import time

    from sem_console.storage.url import parse_database_url

    store = Database(parse_database_url(pg_url))
    heard: list[dict[str, Any]] = []
    listener = store.listen(heard.append)
    assert listener is not None and listener.connected.wait(30)
    try:
        store.claim("relief", hold=False)
        providers = Providers(3.0, 1.0, NAMES)
        alarms = Alarms(store, NAMES, station="relief")
        assert store.flush(30)
        providers.seen("GPSReport", CHARLIE, {"report": {}, "invalid": [], "receivedAt": T0}, T0, T0, True)
        for t in (5.0, 6.0):  # silent: lost, its alarm raised, then another second of it
            providers.tick(T0 + t)
            alarms.update(T0 + t, providers.by_id, (), None)
        [lost] = alarms.open.values()
        assert alarms.acknowledge(lost.id, "alice", T0 + 7, "relief") is lost
        for t in (8.0, 8.5, 9.0, 9.5, 10.0):  # samples again for the regained time: back to normal, saved again
            providers.seen("GPSReport", CHARLIE, {"report": {}, "invalid": [], "receivedAt": T0 + t}, T0 + t, T0 + t, True)
            providers.tick(T0 + t)
            alarms.update(T0 + t, providers.by_id, (), None)
        assert alarms.open == {} and store.flush(30)
        deadline = time.monotonic() + 5  # what the database delivers after the commit
        while time.monotonic() < deadline and not any(m["kind"] == "alarm-ack" for m in heard):
            time.sleep(0.05)
        time.sleep(1)  # and whatever a later save would have told
        acks = [m for m in heard if m["kind"] == "alarm-ack"]
        assert [(m["key"], m["at"], m["by"], m["console"]) for m in acks] == [(lost.key, T0 + 7, "alice", "relief")], heard
    finally:
        listener.stop()


def test_a_cleared_alarm_waits_for_acknowledge_and_comes_back_active(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    assert w.report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
    assert not w.report(ALPHA, "InertialSensorReport", status="OPERATIONAL")  # the same: nothing to re-derive
    assert w.update() == []
    assert w.at(1).report(ALPHA, "InertialSensorReport", status="INERTIAL_SENSOR_FAILURE")
    [failed] = w.update()
    assert (failed["kind"], failed["severity"], failed["text"]) == ("ins-failure", "alarm", "Alpha: INS failed")
    w.at(2).report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
    assert kinds(w.update()) == [("ins-failure", "cleared-unacknowledged")] and w.alarms.active()[0]["clearedAt"] == T0 + 2
    w.at(3).report(ALPHA, "InertialSensorReport", status="INERTIAL_SENSOR_FAILURE")
    [again] = w.update()
    assert (again["id"], again["state"], again["clearedAt"]) == (failed["id"], "active-unacknowledged", None)
    w.at(4).report(ALPHA, "InertialSensorReport", status="OPERATIONAL")
    w.update()
    assert w.ack(failed["id"]) and w.update() == []
    assert not w.ack(failed["id"])  # back to normal: no longer in the set


def test_fix_lost_only_after_a_valid_fix(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.report(UNNAMED, "GPSFixStatusReport", fixValid=False)  # submerged from the start: nothing lost
    assert w.update() == []
    w.at(1).report(UNNAMED, "GPSFixStatusReport", fixValid=True)
    assert w.update() == []
    w.at(1.5).report(UNNAMED, "GPSFixStatusReport", fixValid=False)
    [lost] = w.update()
    assert (lost["kind"], lost["severity"], lost["text"], lost["vehicle"]) == (
        "fix-lost",
        "warning",
        "3f2a9c01: GPS fix lost",
        "3f2a9c01",
    )
    w.at(2).report(UNNAMED, "GPSFixStatusReport", fixValid=True)
    assert kinds(w.update()) == [("fix-lost", "cleared-unacknowledged")]


def test_no_fix_a_few_seconds_after_a_completed_gps_fix_command(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.report(ALPHA, "GPSFixStatusReport", fixValid=False)
    cmd = w.commands.issue(GPS_FIX_3_0_1, ALPHA, None, "alice")
    w.status(cmd, (S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK), (S.COMPLETED, OK))
    w.at(NO_FIX_GRACE - 2).report(ALPHA, "GPSFixStatusReport", fixValid=False)  # the vehicle keeps reporting
    assert w.at(NO_FIX_GRACE - 1).update() == []
    [nofix] = w.at(NO_FIX_GRACE + 1).update()
    assert (nofix["kind"], nofix["severity"], nofix["sessionId"]) == ("no-fix-after-command", "warning", str(cmd.session_id))
    assert nofix["text"] == "Alpha: no valid GPS fix 6 s after the fix command completed"
    w.at(NO_FIX_GRACE + 2).report(ALPHA, "GPSFixStatusReport", fixValid=True)
    assert kinds(w.update()) == [("no-fix-after-command", "cleared-unacknowledged")]


def test_a_fix_that_came_and_went_after_the_command_is_fix_lost_only_also_after_a_restart(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.report(ALPHA, "GPSFixStatusReport", fixValid=False)
    cmd = w.commands.issue(GPS_FIX_3_0_1, ALPHA, None, "alice")
    w.status(cmd, (S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK))
    w.at(1).report(ALPHA, "GPSFixStatusReport", fixValid=True)
    w.status(cmd, (S.COMPLETED, OK))
    assert w.update() == []
    w.at(60).report(ALPHA, "GPSFixStatusReport", fixValid=False)  # its work is under water: the vehicle dives again
    w.at(60 + NO_FIX_GRACE + 1).report(ALPHA, "GPSFixStatusReport", fixValid=False)
    assert kinds(w.update()) == [("fix-lost", "active-unacknowledged")]  # not also "no fix after the command"
    w.store.close()

    again = World(tmp_path / "db").at(120)  # restarted: the completed command is in the history, the fix is invalid
    again.report(ALPHA, "GPSFixStatusReport", fixValid=False)
    assert kinds(again.update()) == [("fix-lost", "active-unacknowledged")]


def test_unanswered_command_can_be_canceled_and_a_late_start_is_an_alarm(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    cmd = w.commands.issue(INS_3_0_1, ALPHA, "RESTARTING", "alice")
    assert w.at(1).update() == []
    [unanswered] = w.at(3).update()
    assert (unanswered["kind"], unanswered["severity"], unanswered["text"]) == (
        "command-unanswered",
        "warning",
        "Alpha: INS RESTART: no answer",
    )
    w.commands.cancel(cmd.session_id, "alice")  # an UNANSWERED command can be canceled: it is disposed
    assert w.disposed == [cmd.sample] and cmd.cancel_requested
    assert kinds(w.update()) == [("command-unanswered", "cleared-unacknowledged")]
    w.at(12).status(cmd, (S.ISSUED, OK))  # the vehicle comes back and takes it up anyway
    late, cleared = w.update()
    assert (late["kind"], late["severity"], late["state"]) == ("executed-late", "alarm", "active-unacknowledged")
    assert late["text"] == "Alpha: INS RESTART executed late (no answer for 12 s)" and cleared["kind"] == "command-unanswered"


# ---- events ------------------------------------------------------------------------------------
def test_failed_command_is_latched_until_acknowledged_then_never_raised_again(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    cmd = w.commands.issue(GPS_FIX_3_0_1, UNNAMED, None, "alice")
    w.status(cmd, (S.ISSUED, OK), (S.FAILED, R.VALIDATION_FAILED, "timeStamp out of range"))
    [failed] = w.at(1).update()
    assert (failed["kind"], failed["severity"], failed["state"], failed["clearedAt"]) == (
        "command-failed",
        "alarm",
        "active-unacknowledged",
        None,
    )
    # the reason in the words the command's card says it (core/words.py)
    assert failed["text"] == "3f2a9c01: GPS fix command failed: the vehicle found the request invalid"
    assert kinds(w.at(30).update()) == [("command-failed", "active-unacknowledged")]  # it does not clear by itself
    assert w.ack(failed["id"]) and w.update() == []
    assert w.at(40).update() == []  # the command is still FAILED in memory: not raised twice


def test_own_supersession_is_not_an_alarm_another_operators_interruption_is(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    first = w.commands.issue(INS_3_0_1, ALPHA, "OFF", "alice")
    w.status(first, (S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK))
    second = w.at(1).commands.issue(INS_3_0_1, ALPHA, "RESTARTING", "alice")
    w.status(first, (S.FAILED, R.INTERRUPTED, f"superseded by command {second.session_id}"))
    w.status(second, (S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK))
    assert w.update() == []
    w.at(2).status(second, (S.FAILED, R.INTERRUPTED, "superseded by command 0b9f5c2e-6c1d-4a7e-9f00-000000000000"))
    [interrupted] = w.update()  # no newer command of this console explains it: another operator's
    assert (interrupted["kind"], interrupted["severity"], interrupted["sessionId"]) == (
        "command-interrupted",
        "alarm",
        str(second.session_id),
    )
    assert interrupted["text"] == "Alpha: INS RESTART interrupted by a command not from this console"


def test_flow_violation_and_recording_failure(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    cmd = w.commands.issue(GPS_FIX_3_0_1, CHARLIE, None, None)
    w.status(cmd, (S.ISSUED, OK), (S.EXECUTING, OK))  # COMMANDED skipped
    w.recording_error = "recording stopped: the disk is full (/var/recordings/x.mcap)"
    recording, violation = w.at(1).update()
    assert (violation["kind"], violation["severity"], violation["text"]) == (
        "flow-violation",
        "alarm",
        "Charlie: GPS fix command: the vehicle reported an invalid status sequence",
    )
    assert (recording["kind"], recording["providerId"], recording["vehicle"], recording["text"]) == (
        "recording-failed",
        None,
        None,
        "Recording failed: the disk is full (/var/recordings/x.mcap)",
    )
    assert w.ack(recording["id"]) and kinds(w.at(2).update()) == [("flow-violation", "active-unacknowledged")]


# ---- persistence -------------------------------------------------------------------------------
def test_a_restart_keeps_the_alarms_not_back_to_normal(tmp_path: Path) -> None:
    w = World(tmp_path / "db")
    w.report(CHARLIE, "GPSReport")
    old = w.commands.issue(GPS_FIX_3_0_1, ALPHA, None, None)
    w.status(old, (S.ISSUED, OK), (S.FAILED, R.RESOURCE_FAILED))
    w.at(1).update()
    acked = w.alarms.active()[0]
    assert acked["text"] == "Alpha: GPS fix command failed: the equipment failed"  # as its card says it
    assert acked["kind"] == "command-failed" and w.ack(acked["id"])  # back to normal: gone for good
    cmd = w.commands.issue(GPS_FIX_3_0_1, ALPHA, None, None)
    w.status(cmd, (S.ISSUED, OK), (S.FAILED, R.TIMEOUT))
    before = w.at(5).update()
    assert kinds(before) == [("link-lost", "active-unacknowledged"), ("command-failed", "active-unacknowledged")]
    w.store.close()

    again = World(tmp_path / "db").at(6)
    assert again.alarms.active() == before  # loaded from the database; Charlie not heard from yet is no evidence
    assert again.update() == before  # the failed commands in the loaded history are not raised again


def test_an_alarm_has_its_rows_id_at_once_the_id_it_keeps_over_a_restart(tmp_path: Path) -> None:
    """An alarm's id is given at once (the loop does not wait for its row) and is its row's: the id the dashboard, the
    audit trail and a restarted console name it by."""
    w = World(tmp_path / "db")
    w.report(CHARLIE, "GPSReport")
    [lost] = w.at(5).update()
    assert lost["kind"] == "link-lost" and w.ack(lost["id"]) and w.store.flush(30)
    with w.store.engine.connect() as c:
        [row_id] = c.execute(text("SELECT id FROM alarms")).scalars().all()
    assert lost["id"] == row_id, f"the alarm is shown as {lost['id']}, its row is {row_id}"
    w.store.close()
    [again] = World(tmp_path / "db").at(7).alarms.active()
    assert (again["id"], again["ackedBy"]) == (row_id, "alice")


# ---- REST and WebSocket ------------------------------------------------------------------------
def test_routes_acknowledge_audited_and_no_silent_command_to_a_lost_vehicle(domain: int, tmp_path: Path) -> None:
    settings = Settings(
        domain=domain,
        db_path=tmp_path / "db",
        recordings_dir=tmp_path / "recordings",
        operator_tokens="alice:s3cret",
        vehicle_names=f"{CHARLIE}=Charlie",
        unanswered_timeout=2.0,
    )
    auth = {"Authorization": "Bearer s3cret"}
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        console = client.app.state.console  # type: ignore[attr-defined]

        def heard_a_minute_ago() -> None:  # on the console's loop, like every change of its state
            now, wall = console.clock.monotonic(), console.clock.wall()
            console.providers.seen(
                "GPSReport", CHARLIE, {"report": {}, "invalid": [], "receivedAt": wall - 60}, now - 60, wall - 60, True
            )
            console.tick(now)

        client.portal.call(heard_a_minute_ago)
        gps_fix = f"/api/providers/{CHARLIE}/gps-fix"
        r = client.post(gps_fix, json={}, headers=auth)
        # at least the minute set above: a loaded machine may take a few seconds more between there and here
        lost_for = re.match(r"Charlie is lost \(nothing heard for (\d+) s\)", r.json()["detail"])
        assert r.status_code == 409 and lost_for and 60 <= int(lost_for[1]) < 120, r.text
        assert client.post(f"/api/providers/{CHARLIE}/inertial-sensor", json={"state": "OFF"}, headers=auth).status_code == 409
        r = client.post(gps_fix, json={"confirmLost": True}, headers=auth)
        assert r.status_code == 201, r.text
        session = r.json()["sessionId"]
        client.portal.call(lambda: console.tick(console.clock.monotonic() + 3))  # past the unanswered timeout
        unanswered, lost = client.get("/api/alarms").json()
        assert (unanswered["kind"], unanswered["text"], unanswered["sessionId"]) == (
            "command-unanswered",
            "Charlie: GPS fix command: no answer",
            session,
        )
        assert (lost["kind"], lost["text"], lost["state"]) == ("link-lost", "Charlie: link lost", "active-unacknowledged")

        r = client.delete(f"/api/commands/{session}", headers=auth)  # an UNANSWERED command can be canceled
        assert r.status_code == 200 and r.json()["cancelRequested"] and r.json()["unanswered"]
        assert client.get("/api/alarms").json()[0]["state"] == "cleared-unacknowledged"

        ack = f"/api/alarms/{lost['id']}/ack"
        assert client.post(ack, json={}).status_code == 401
        assert client.post(ack, headers=auth).status_code == 415  # a JSON body ({}) like every command route
        r = client.post(ack, json={}, headers=auth)
        assert r.status_code == 200 and r.json()[1]["state"] == "active-acknowledged" and r.json()[1]["ackedBy"] == "alice"
        assert client.post(ack, json={}, headers=auth).json() == r.json()  # again: no change
        assert client.post("/api/alarms/99999/ack", json={}, headers=auth).status_code == 404
        with client.websocket_connect("ws://localhost/ws") as ws:
            assert [a["id"] for a in ws.receive_json()["alarms"]] == [unanswered["id"], lost["id"]]
            assert client.post(f"/api/alarms/{unanswered['id']}/ack", json={}, headers=auth).status_code == 200
            message = ws.receive_json()
            while message["type"] != "alarms":
                message = ws.receive_json()
            assert [a["id"] for a in message["alarms"]] == [lost["id"]]  # cleared and acknowledged: back to normal
        audit = [(e["path"], e["outcome"], e["status"], e["operator"]) for e in client.get("/api/audit").json()]
        assert (ack, "accepted", 200, "alice") in audit and (ack, "refused", 401, None) in audit
        assert (gps_fix, "refused", 409, "alice") in audit and (gps_fix, "accepted", 201, "alice") in audit
        # Charlie takes the canceled command up at last, then cancels it: it was executed late all the same
        for st, reason in ((S.ISSUED, OK), (S.CANCELED, R.CANCELED)):
            client.portal.call(console.commands.on_status, Service.GPS_FIX, uuid.UUID(session), CHARLIE, st, reason, "", None)
        late = client.get("/api/alarms").json()[0]
        assert (late["kind"], late["sessionId"]) == ("executed-late", session)
        assert late["text"].startswith("Charlie: GPS fix command executed late (no answer for ")


@pytest.mark.parametrize("umaa", ["3.0.1", "6.0"])
def test_a_vehicle_with_a_failed_ins_shows_in_rest_and_a_fresh_snapshot(sim, console, umaa: str) -> None:
    sim("--fault", "ins-failure", "--umaa", umaa)
    c = console("--vehicle-names", f"{V1}=Alpha")
    provider_ready(c.url, V1, {"InertialSensorReport"})
    [alarm] = wait_until(
        lambda: [a for a in http.get(f"{c.url}/api/alarms").json() if a["kind"] == "ins-failure"], 10, "an ins-failure alarm"
    )
    assert (alarm["text"], alarm["providerId"], alarm["severity"], alarm["state"]) == (
        "Alpha: INS failed",
        V1,
        "alarm",
        "active-unacknowledged",
    )
    ws = WsClient(c.ws_url)
    snapshot = wait_until(lambda: ws.messages and ws.messages[0], 10, "the snapshot")
    assert snapshot["type"] == "snapshot" and alarm in snapshot["alarms"] and ws.errors == []
    ws.close()


def test_a_renamed_vehicles_alarms_name_it_as_it_is_named_now_and_the_rows_keep_what_was_said(
    domain: int, tmp_path: Path
) -> None:
    settings = Settings(
        domain=domain,
        db_path=tmp_path / "db",
        recordings_dir=tmp_path / "recordings",
        operator_tokens="alice:s3cret",
        vehicle_names=f"{CHARLIE}=Charlie",
    )
    auth = {"Authorization": "Bearer s3cret"}
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        console = client.app.state.console  # type: ignore[attr-defined]

        def heard_a_minute_ago() -> None:
            now, wall = console.clock.monotonic(), console.clock.wall()
            console.providers.seen(
                "GPSReport", CHARLIE, {"report": {}, "invalid": [], "receivedAt": wall - 60}, now - 60, wall - 60, True
            )
            console.tick(now)

        client.portal.call(heard_a_minute_ago)
        [lost] = client.get("/api/alarms").json()
        assert (lost["kind"], lost["vehicle"], lost["text"]) == ("link-lost", "Charlie", "Charlie: link lost")
        with client.websocket_connect("ws://localhost/ws") as ws:
            ws.receive_json()  # the snapshot
            r = client.put(f"/api/providers/{CHARLIE}/name", json={"name": "Delta"}, headers=auth)
            assert r.status_code == 200, r.text
            assert [(a["vehicle"], a["text"]) for a in client.get("/api/alarms").json()] == [("Delta", "Delta: link lost")]
            message = ws.receive_json()
            while message["type"] != "alarms":  # the set is sent again, not only the provider's new name
                message = ws.receive_json()
            assert [(a["vehicle"], a["text"]) for a in message["alarms"]] == [("Delta", "Delta: link lost")]
        assert console.store.flush(30)
        with console.store.engine.connect() as c:  # what was said when raised stays as recorded
            [row] = c.execute(text("SELECT vehicle, text FROM alarms")).mappings().all()
        assert (row["vehicle"], row["text"]) == ("Charlie", "Charlie: link lost")
        client.put(f"/api/providers/{CHARLIE}/name", json={"name": None}, headers=auth)  # back to --vehicle-names
        assert client.get("/api/alarms").json()[0]["text"] == "Charlie: link lost"


def test_a_silent_relay_is_one_alarm_naming_it_and_its_vehicles_not_one_per_vehicle(tmp_path: Path) -> None:
    """Three vehicles through relay ship-1 (console/hops.py): its link goes quiet, every vehicle is lost with it, and the
    set holds one relay-silent alarm, of the console; the link back with two of them, the third is lost on its own."""
    from sem_console.console.hops import Hops
    from sem_console.dds.hops import RelayLink

    w = World(tmp_path / "db")
    w.alarms.relay_silent_after = 3.0
    fleet = [ALPHA, CHARLIE, UNNAMED]
    hops = Hops()

    def heard(t: float, vehicles: list[uuid.UUID]) -> list[dict[str, Any]]:
        w.at(t)
        stamp = {"seconds": int(w.clock.at), "nanoseconds": 0}
        for v in vehicles:
            w.report(v, "GPSFixReport", timeStamp=stamp)
            w.providers.by_id[v].relay = "ship-1"
        hops.seen(RelayLink("ship-1", [str(v) for v in fleet], 0), w.clock.at)  # data over the link just now
        w.providers.tick(w.clock.at, w.clock.at)
        w.alarms.update(w.clock.at, w.providers.by_id, (), None, hops.by_relay)
        return w.alarms.active()

    assert heard(0, fleet) == []
    w.at(10).providers.tick(w.clock.at, w.clock.at)  # the relay's link quiet since T0: all three lost
    w.alarms.update(w.clock.at, w.providers.by_id, (), None, hops.by_relay)
    [silent] = w.alarms.active()
    assert (silent["kind"], silent["providerId"], silent["severity"]) == ("relay-silent", None, "alarm")
    assert silent["text"] == "relay ship-1 silent: 3 vehicles" and silent["cause"] == "Relay silent"
    # the link back with Alpha and Charlie: the relay's alarm clears; the unnamed vehicle, still silent while the link
    # carries the others' data, is lost on its own
    for t in (11, 12, 13, 14, 15, 16):
        active = heard(t, [ALPHA, CHARLIE])
    assert sorted(kinds(active)) == [("link-lost", "active-unacknowledged"), ("relay-silent", "cleared-unacknowledged")]
    assert next(a for a in active if a["kind"] == "link-lost")["providerId"] == str(UNNAMED)


def test_a_silent_relay_whose_name_holds_a_bar_clears_when_its_link_is_back(tmp_path: Path) -> None:
    """A relay's --name is free text: "ship|1" (a bar, as the alarms' keys join their parts with) raises its
    relay-silent alarm and clears it when data comes over its link again."""
    from sem_console.console.hops import Hops
    from sem_console.dds.hops import RelayLink

    w = World(tmp_path / "db")
    w.alarms.relay_silent_after = 3.0
    hops = Hops()
    hops.seen(RelayLink("ship|1", [str(ALPHA)], 0), w.clock.at)
    w.at(10)
    w.alarms.update(w.clock.at, w.providers.by_id, (), None, hops.by_relay)
    [silent] = w.alarms.active()
    assert (silent["kind"], silent["text"]) == ("relay-silent", "relay ship|1 silent: 1 vehicle")
    hops.seen(RelayLink("ship|1", [str(ALPHA)], 0), w.at(11).clock.at)  # data over the link again
    w.alarms.update(w.clock.at, w.providers.by_id, (), None, hops.by_relay)
    assert kinds(w.alarms.active()) == [("relay-silent", "cleared-unacknowledged")]


def test_a_relay_silent_while_every_vehicle_it_carries_is_in_a_planned_silence_raises_no_relay_alarm(
    tmp_path: Path,
) -> None:
    """The watch planned the ship's satellite outage: both vehicles of relay ship-1 out of comms until T0 + 600. The
    relay's link going quiet then is expected, as each vehicle's loss is: no alarm; one vehicle not planned: the alarm."""
    from sem_console.console.hops import Hops
    from sem_console.dds.hops import RelayLink

    w = World(tmp_path / "db")
    w.alarms.relay_silent_after = 3.0
    hops = Hops()
    hops.seen(RelayLink("ship-1", [str(ALPHA), str(CHARLIE)], 0), w.clock.at)
    for v in (ALPHA, CHARLIE):
        w.alarms.silence(str(v), T0 + 600, "satellite outage", "alice", w.clock.at)
    w.at(10)
    w.alarms.update(w.clock.at, w.providers.by_id, (), None, hops.by_relay)
    assert w.alarms.active() == []
    w.alarms.cancel_silence(str(CHARLIE), "alice", w.clock.at)
    w.alarms.update(w.clock.at, w.providers.by_id, (), None, hops.by_relay)
    assert kinds(w.alarms.active()) == [("relay-silent", "active-unacknowledged")]


def test_the_console_overloaded_alarm_says_how_many_vehicles_it_did_not_check_now_not_when_raised(
    tmp_path: Path,
) -> None:
    """The console falls behind and vehicles go unchecked one after another: its one alarm's words follow the count
    and the worst delay while it holds (one alarm, not one per change), and keep the last when it clears."""
    from sem_console.console.alarms import overloaded_text

    w = World(tmp_path / "db")
    w.at(1).alarms.update(w.clock.at, w.providers.by_id, (), None, None, overloaded_text(0.7, 1))
    [first] = w.alarms.active()
    assert (
        first["text"] == "this console is overloaded: it ran up to 0.7 s behind and did not check 1 vehicle (no "
        "link-lost alarm for a silence its delay may explain); run fewer vehicles on this console or give it a bigger machine"
    )
    assert w.at(2).alarms.update(w.clock.at, w.providers.by_id, (), None, None, overloaded_text(3.2, 130))
    [grown] = w.alarms.active()
    assert grown["id"] == first["id"] and grown["state"] == "active-unacknowledged"
    assert grown["text"].startswith("this console is overloaded: it ran up to 3.2 s behind and did not check 130 vehicles")
    assert not w.at(3).alarms.update(w.clock.at, w.providers.by_id, (), None, None, overloaded_text(3.2, 130))
    assert w.at(4).alarms.update(w.clock.at, w.providers.by_id, (), None, None, None)
    [cleared] = w.alarms.active()
    assert cleared["state"] == "cleared-unacknowledged" and "130 vehicles" in cleared["text"]


def test_one_stations_overload_acknowledged_or_shelved_is_not_another_stations(tmp_path: Path) -> None:
    """Acknowledgements and shelves are shared by key between the stations of one database; a console's overload is
    its own: an operator at ops-2 acknowledging or shelving ops-2's leaves ops-1's in view, unacknowledged."""
    from sem_console.console.alarms import overloaded_text

    store = Database(tmp_path / "db")
    one, two = Alarms(store, NAMES, station="ops-1"), Alarms(store, NAMES, station="ops-2")
    for alarms in (one, two):
        alarms.update(T0, {}, (), None, None, overloaded_text(2.0, 3))
    [theirs] = two.open.values()
    assert two.acknowledge(theirs.id, "bob", T0 + 1, "ops-2") is not None
    assert not one.acknowledged_elsewhere(theirs.key, "bob", T0 + 1, "ops-2")
    assert two.shelve(theirs.id, "known slow machine", 3600, "bob", T0 + 1, "ops-2") is not None
    assert not one.shared_shelf(two.shelves[theirs.key].model_dump())
    [ours] = one.active()
    assert (ours["state"], ours["shelf"]) == ("active-unacknowledged", None)
