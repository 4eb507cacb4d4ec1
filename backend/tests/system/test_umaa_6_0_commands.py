"""Commanding a UMAA 6.0 vehicle: InertialSensorCommandType through the whole flow on a real DDS domain (a `sem-sim
--umaa 6.0` vehicle and `sem-console`), cancel by dispose and cleanup, an update (ICD 6.0 4.1.4.2), a fault; and the
REST answers to a command of the other version."""

from __future__ import annotations

import ast
import csv
import io
import threading
import time
import uuid
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from cyclonedds.core import InstanceState
from cyclonedds.sub import DataReader
from fastapi.testclient import TestClient

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as R
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusReasonEnumModule import CommandStatusReasonEnumType as Reason60
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as InsCmd
from UMAA_6_0.Common.Measurement import DateTime

from sem_console.core.config import Settings
from sem_console.core.words import WORDS, word
from sem_console.dds.bus import Bus, take_each
from sem_console.dds.cyclone_private import InvalidSample
from sem_console.dds.qos import TopicClass, any_writer_reader_qos
from sem_console.dds.topics import Sem60
from sem_console.main import create_app
from sem_console.sim.umaa_6_0 import STAGES
from sem_console.umaa.flow import UPDATED, CommandFlow
from sem_console.versions import umaa_6_0
from support import http
from test_console import HAPPY, V1, WsClient, wait_command, wait_until
from test_umaa_versions import HEALTH_6_0, V2, _detail

ALIGN = ["BEST_ALIGN", "GPS_ALIGN", "INIT", "SNAP_ALIGN", "STATIONARY_ALIGN", "TRANSFER_ALIGN"]


class InsStages:
    """The 6.0 vehicle's InertialSensorReportType statuses, in the order they came: a reader of the test's own, taken
    every 20 ms (its history keeps the last report only)."""

    def __init__(self, domain: int) -> None:
        self.bus = Bus(domain)
        self.reader: DataReader[Any] = self.bus.reader(Sem60.INS_REPORT, any_writer_reader_qos(TopicClass.REPORT))
        self.seen: list[str] = []
        self.running = True
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        while self.running:
            for s in take_each(self.reader)[0]:
                if not isinstance(s, InvalidSample) and (not self.seen or self.seen[-1] != s.status.name):
                    self.seen.append(s.status.name)
            time.sleep(0.02)

    def take(self) -> list[str]:
        return list(self.seen)

    def close(self) -> None:
        self.running = False
        self.thread.join()
        self.bus.close()


@pytest.fixture
def stages(domain: int) -> Iterator[InsStages]:
    s = InsStages(domain)
    yield s
    s.close()


def post(base: str, state: str) -> dict[str, Any]:
    r = http.post(f"{base}/api/providers/{V1}/inertial-sensor", json={"state": state})
    assert r.status_code == 201, r.text
    assert r.json()["state"] == state
    return dict(r.json())


def test_every_6_0_command_completes_through_the_flow_and_the_ins_walks_its_stages(sim, console, stages) -> None:
    sim("--umaa", "6.0", "--align-seconds", "30")  # 0.5 s a stage at the tests' time scale
    c = console()
    _detail(c.url, V1, HEALTH_6_0)
    ws = WsClient(c.ws_url)
    for state in ALIGN:
        stages.seen.clear()
        session = post(c.url, state)["sessionId"]
        done = wait_command(c.url, session, timeout=20)
        assert [t["status"] for t in done["transitions"]] == HAPPY and done["violations"] == [], (state, done)
        assert done["ackedAt"] and done["cleanedUp"] and done["state"] == state
        wait_until(lambda s=session: ws.transitions(s) == HAPPY, 5, f"{state}: every transition on the WebSocket")
        # the vehicle's INS walked the stages of the kind commanded, and reports its aim once COMPLETED
        wait_until(lambda st=state: stages.take() and stages.seen[-1] == STAGES[st][-1], 5, f"{state}: its last stage")
        walked = [x for x in stages.seen if x in STAGES[state]]
        assert walked[-len(STAGES[state]) :] == list(STAGES[state]) or state == "SNAP_ALIGN", (state, stages.seen)
    assert ws.errors == []


def test_a_6_0_ins_aligned_at_once_reports_the_stationary_alignment_it_did(sim, stages) -> None:
    # --align-seconds 0: the simulated INS is aligned from the start, never seen completing a stage; it aligns
    # stationary, and says so, not a GPS-aided alignment it never did
    sim("--umaa", "6.0", "--align-seconds", "0")
    wait_until(stages.take, 10, "an INS report")
    time.sleep(0.5)
    assert set(stages.take()) == {"FINE_STATIONARY_ALIGNMENT_COMPLETE"}, stages.seen


def test_a_6_0_vehicle_first_heard_on_its_command_status_speaks_6_0(console, domain: int) -> None:
    # a status on the bus (transient-local) before the vehicle's first report: the vehicle is a 6.0 one from the start
    vehicle = uuid.uuid4()
    bus = Bus(domain)
    try:
        command = umaa_6_0.ins_command(uuid.uuid4(), vehicle, uuid.uuid4(), "GPS_ALIGN", (1, 0))
        writer = bus.writer(Sem60.INS_COMMAND_STATUS)  # kept: the status stays on the bus while it lives
        writer.write(umaa_6_0.ins_status(vehicle, command, S.ISSUED, R.SUCCEEDED, "", (1, 0)))
        c = console()
        seen = wait_until(
            lambda: (r := http.get(f"{c.url}/api/providers/{vehicle}")).status_code == 200 and r.json(),
            15,
            "the vehicle of the status",
        )
        assert seen["umaaVersion"] == "6.0", seen
    finally:
        bus.close()


def test_a_vehicle_heard_on_the_other_versions_topics_is_shown_in_its_new_version(console, domain: int) -> None:
    """A vehicle first heard on a 3.0.1 topic and then on 6.0 ones: every station is told its new version at once (a
    `configured` provider message, which the dashboard applies), not only a page opened after it."""
    from sem_console.dds.topics import Service
    from sem_console.versions.commands import commanding

    vehicle, console_id = uuid.uuid4(), uuid.uuid4()
    c = console()
    ws = WsClient(c.ws_url)
    bus = Bus(domain)
    writers = []  # kept: a status stays on the bus (transient-local) while its writer lives
    try:
        for version in ("3.0.1", "6.0"):
            found = commanding(version, Service.INERTIAL_SENSOR)
            assert found is not None
            command = found.build(console_id, vehicle, uuid.uuid4(), found.states[0], (1, 0))
            writers.append(bus.writer(found.status))
            writers[-1].write(found.build_status(vehicle, command, S.ISSUED, R.SUCCEEDED, "", (1, 0)))
            wait_until(
                lambda v=version: any(
                    m["provider"]["id"] == str(vehicle) and m["provider"]["umaaVersion"] == v for m in ws.of("provider")
                ),
                15,
                f"the vehicle shown as UMAA {version}",
            )
        told = [m["event"] for m in ws.of("provider") if m["provider"]["id"] == str(vehicle)]
        assert told[:1] == ["appeared"] and "configured" in told, told
        assert http.get(f"{c.url}/api/providers/{vehicle}").json()["umaaVersion"] == "6.0"
    finally:
        ws.close()
        bus.close()


def _console_command(domain: int, session: str) -> tuple[Bus, Any]:
    """The console's InertialSensorCommandType of `session`, as it is on the bus (transient-local)."""
    bus = Bus(domain)
    reader = bus.reader(Sem60.INS_COMMAND)
    found = wait_until(
        lambda: next(
            (
                s
                for s in take_each(reader)[0]
                if not isinstance(s, InvalidSample) and str(uuid.UUID(bytes=bytes(s.sessionID))) == session
            ),
            None,
        ),
        10,
        "the command",
    )
    return bus, found


def test_a_6_0_command_is_addressed_to_the_providers_identifier_its_parent_too(console, domain: int) -> None:
    """A 6.0 command's destination is the provider's IdentifierType as the provider reports it in its source, parentID
    included (ICD 6.0 4.1: a provider answers the commands whose destination is its identifier; 5.2.9: parentID is its
    parent's, the nil UUID only when it has none), not the vehicle's id with a nil parent."""
    from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorOpStatusEnumModule import InertialSensorOpStatusEnumType

    vehicle, parent = uuid.uuid4(), uuid.uuid4()
    c = console()
    bus = Bus(domain)
    try:
        report = Sem60.INS_REPORT.spec.type(
            status=InertialSensorOpStatusEnumType.INIT,
            timeStamp=DateTime(seconds=1, nanoseconds=0),
            source=umaa_6_0.identifier(vehicle, parent),
        )
        writer = bus.writer(Sem60.INS_REPORT)  # kept: the vehicle lives while its writer does
        writer.write(report)
        wait_until(lambda: http.get(f"{c.url}/api/providers/{vehicle}").status_code == 200, 15, "the vehicle")
        r = http.post(f"{c.url}/api/providers/{vehicle}/inertial-sensor", json={"state": "GPS_ALIGN"})
        assert r.status_code == 201, r.text
        reader = bus.reader(Sem60.INS_COMMAND)
        session = r.json()["sessionId"]
        command = wait_until(
            lambda: next(
                (
                    s
                    for s in take_each(reader)[0]
                    if not isinstance(s, InvalidSample) and str(uuid.UUID(bytes=bytes(s.sessionID))) == session
                ),
                None,
            ),
            10,
            "the command",
        )
        assert uuid.UUID(bytes=bytes(command.destination.id)) == vehicle
        assert uuid.UUID(bytes=bytes(command.destination.parentID)) == parent
        assert bytes(command.source.parentID) == bytes(16)  # the console has no parent: the nil UUID

        # the vehicle given another parent: the next command goes to the identifier its reports now say
        other = uuid.uuid4()
        heard = http.get(f"{c.url}/api/providers/{vehicle}").json()["reports"]["InertialSensorReport"]["receivedAt"]
        report.source, report.timeStamp = umaa_6_0.identifier(vehicle, other), DateTime(seconds=2, nanoseconds=0)
        writer.write(report)
        wait_until(
            lambda: http.get(f"{c.url}/api/providers/{vehicle}").json()["reports"]["InertialSensorReport"]["receivedAt"] != heard,
            15,
            "the report with the new parent",
        )
        r = http.post(f"{c.url}/api/providers/{vehicle}/inertial-sensor", json={"state": "GPS_ALIGN"})
        assert r.status_code == 201, r.text
        session = r.json()["sessionId"]
        command = wait_until(
            lambda: next(
                (
                    s
                    for s in take_each(reader)[0]
                    if not isinstance(s, InvalidSample) and str(uuid.UUID(bytes=bytes(s.sessionID))) == session
                ),
                None,
            ),
            10,
            "the command",
        )
        assert uuid.UUID(bytes=bytes(command.destination.parentID)) == other
    finally:
        bus.close()


def test_a_6_0_command_updated_starts_over_and_the_monitor_follows(sim, console, domain: int) -> None:
    sim("--umaa", "6.0", "--align-seconds", "600")  # 10 s a stage: still aligning when updated
    c = console()
    _detail(c.url, V1, HEALTH_6_0)
    ws = WsClient(c.ws_url)
    session = post(c.url, "GPS_ALIGN")["sessionId"]
    wait_command(c.url, session, done=lambda x: x["status"] == "EXECUTING")
    bus, command = _console_command(domain, session)
    try:
        # the same source and sessionID, a newer time stamp: an update, here to INIT (done at once)
        command.timeStamp = DateTime(seconds=command.timeStamp.seconds + 1, nanoseconds=command.timeStamp.nanoseconds)
        command.state = type(command.state)["INIT"]
        bus.writer(Sem60.INS_COMMAND).write(command)
        done = wait_command(c.url, session, timeout=20)
    finally:
        bus.close()
    assert [(t["status"], t["reason"]) for t in done["transitions"]] == [
        ("ISSUED", "SUCCEEDED"),
        ("COMMANDED", "SUCCEEDED"),
        ("EXECUTING", "SUCCEEDED"),
        ("ISSUED", "UPDATED"),
        ("COMMANDED", "SUCCEEDED"),
        ("EXECUTING", "SUCCEEDED"),
        ("COMPLETED", "SUCCEEDED"),
    ]
    assert done["violations"] == [] and done["cleanedUp"]
    wait_until(
        lambda: [m["transition"]["reason"] for m in ws.of("transition") if m["sessionId"] == session].count("UPDATED") == 1,
        5,
        "UPDATED on the WebSocket",
    )
    assert ws.errors == []


def test_a_6_0_command_canceled_by_dispose_stops_the_alignment_and_is_cleaned_up(sim, console, stages) -> None:
    sim("--umaa", "6.0", "--align-seconds", "600")
    c = console()
    _detail(c.url, V1, HEALTH_6_0)
    session = post(c.url, "STATIONARY_ALIGN")["sessionId"]
    wait_command(c.url, session, done=lambda x: x["status"] == "EXECUTING")
    wait_until(lambda: stages.take() and stages.seen[-1] == "COARSE_STATIONARY_ALIGNMENT", 5, "coarse alignment")
    r = http.delete(f"{c.url}/api/commands/{session}")
    assert r.status_code == 200 and r.json()["cancelRequested"]
    done = wait_command(c.url, session, done=lambda x: x["terminal"])
    assert [(t["status"], t["reason"]) for t in done["transitions"]][-1] == ("CANCELED", "CANCELED")
    assert [t["status"] for t in done["transitions"]] == ["ISSUED", "COMMANDED", "EXECUTING", "CANCELED"]
    assert done["cleanedUp"] and done["violations"] == []
    time.sleep(1)  # the alignment stays where the cancel found it
    assert stages.take()[-1] == "COARSE_STATIONARY_ALIGNMENT"
    assert http.delete(f"{c.url}/api/commands/{session}").status_code == 409


def test_a_6_0_vehicle_disposes_its_status_and_ack_when_the_console_cleans_up(sim, console, domain: int) -> None:
    sim("--umaa", "6.0")
    c = console()
    _detail(c.url, V1, HEALTH_6_0)
    bus = Bus(domain)
    try:
        status, ack = bus.reader(Sem60.INS_COMMAND_STATUS), bus.reader(Sem60.INS_COMMAND_ACK)
        session = post(c.url, "INIT")["sessionId"]
        wait_command(c.url, session)

        def disposed(reader: DataReader[Any]) -> bool:  # a dispose after an untaken sample shows in its instance state
            return any(s.sample_info.instance_state == InstanceState.NotAliveDisposed for s in take_each(reader)[0])

        wait_until(lambda: disposed(status), 10, "the status disposed")
        wait_until(lambda: disposed(ack), 10, "the ack disposed")
    finally:
        bus.close()


def test_a_6_0_alignment_that_fails_shows_its_kind_s_failure_and_the_command_failed(sim, console, stages) -> None:
    sim("--umaa", "6.0", "--align-seconds", "60", "--fault", "fail-midway")
    c = console()
    _detail(c.url, V1, HEALTH_6_0)
    session = post(c.url, "GPS_ALIGN")["sessionId"]
    done = wait_command(c.url, session, timeout=20)
    assert [(t["status"], t["reason"]) for t in done["transitions"]][-1] == ("FAILED", "RESOURCE_FAILED")
    assert done["violations"] == []
    wait_until(lambda: stages.take() and stages.seen[-1] == "GPS_ALIGNMENT_FAILURE", 5, "GPS_ALIGNMENT_FAILURE")
    # the alarm names the command in the operator's words
    alarms = wait_until(
        lambda: [a for a in http.get(f"{c.url}/api/alarms").json() if a["kind"] == "command-failed"],
        5,
        "the command-failed alarm",
    )
    assert "INS GPS-aided alignment failed" in alarms[0]["text"], alarms


def test_the_6_0_commands_and_the_update_have_words() -> None:
    assert set(WORDS["InertialSensorCmdEnumType"]) == set(InsCmd.__members__) == set(ALIGN)
    assert all(w.strip() for w in WORDS["InertialSensorCmdEnumType"].values())
    assert word("CommandStatusReasonEnumType", "UPDATED") == "Again, updated: it starts over"
    assert {m.name for m in Reason60} <= set(WORDS["CommandStatusReasonEnumType"])


def test_the_flow_takes_an_update_back_to_issued_from_a_running_state_only() -> None:
    flow = CommandFlow()
    for status in (S.ISSUED, S.COMMANDED, S.EXECUTING):
        flow.observe(status, R.SUCCEEDED)
    assert flow.observe(S.ISSUED, UPDATED).violation is None  # type: ignore[union-attr]
    assert flow.status is S.ISSUED and not flow.terminal
    for status in (S.COMMANDED, S.EXECUTING, S.COMPLETED):
        flow.observe(status, R.SUCCEEDED)
    assert flow.violations == []
    late = flow.observe(S.ISSUED, UPDATED)
    assert late is not None and late.violation == "COMPLETED -> ISSUED is not a Figure 4 transition"
    first = CommandFlow().observe(S.ISSUED, UPDATED)
    assert first is not None and first.violation == "reason UPDATED is not valid for ISSUED"
    wrong = CommandFlow()
    wrong.observe(S.ISSUED, R.SUCCEEDED)
    assert wrong.observe(S.COMMANDED, UPDATED).violation == "reason UPDATED is not valid for COMMANDED"  # type: ignore[union-attr]


# ---- REST: the vehicle's version decides the choices (no DDS under test) ---------------------------------------------
def test_a_literal_of_the_other_version_and_a_gps_fix_to_a_6_0_vehicle_get_422s(domain: int, tmp_path: Path) -> None:
    six, old = uuid.uuid4(), uuid.uuid4()
    settings = Settings(
        domain=domain, db_path=tmp_path / "db", recordings_dir=tmp_path / "recordings", vehicle_names=f"{six}=Six,{old}=Old"
    )
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        console = client.app.state.console  # type: ignore[attr-defined]

        def heard() -> None:
            now, wall = console.clock.monotonic(), console.clock.wall()
            console.providers.seen("GPSReport", six, {"report": {}, "invalid": [], "receivedAt": wall}, now, wall, True, "6.0")
            console.providers.seen("GPSReport", old, {"report": {}, "invalid": [], "receivedAt": wall}, now, wall, True, "3.0.1")

        client.portal.call(heard)
        r = client.post(f"/api/providers/{six}/inertial-sensor", json={"state": "ON"})
        assert r.status_code == 422 and r.json()["errors"] == [
            "body.state: Six speaks UMAA 6.0: its inertial sensor takes BEST_ALIGN, GPS_ALIGN, INIT, SNAP_ALIGN, "
            "STATIONARY_ALIGN, TRANSFER_ALIGN; ON is a UMAA 3.0.1 state"
        ], r.text
        r = client.post(f"/api/providers/{old}/inertial-sensor", json={"state": "GPS_ALIGN"})
        assert r.status_code == 422 and r.json()["detail"] == (
            "body.state: Old speaks UMAA 3.0.1: its inertial sensor takes OFF, ON, RESTARTING; GPS_ALIGN is a UMAA 6.0 state"
        ), r.text
        r = client.post(f"/api/providers/{six}/gps-fix", json={})
        assert r.status_code == 422 and r.json()["detail"] == (
            "path.provider_id: Six speaks UMAA 6.0, which has no GPS fix service (GPSFixControl)"
        ), r.text
        assert client.get("/api/commands").json() == []  # nothing was published

        # a lost vehicle: a command its version has not is refused as such, not held for a confirmation it could not use
        def lose(lost: bool) -> None:
            for v in (six, old):
                console.providers.by_id[v].link = "lost" if lost else "live"

        client.portal.call(lose, True)
        r = client.post(f"/api/providers/{six}/inertial-sensor", json={"state": "ON"})
        assert r.status_code == 422 and r.json()["detail"].startswith("body.state: Six speaks UMAA 6.0: "), r.text
        r = client.post(f"/api/providers/{old}/inertial-sensor", json={"state": "GPS_ALIGN", "confirmLost": False})
        assert r.status_code == 422 and r.json()["detail"].startswith("body.state: Old speaks UMAA 3.0.1: "), r.text
        assert client.post(f"/api/providers/{six}/gps-fix", json={}).status_code == 422
        r = client.post(f"/api/providers/{six}/inertial-sensor", json={"state": "GPS_ALIGN"})
        assert r.status_code == 409 and r.json()["detail"].startswith("Six is lost (nothing heard for "), r.text
        client.portal.call(lose, False)
        r = client.post(f"/api/providers/{six}/inertial-sensor", json={"state": "GPS_ALIGN"})
        assert r.status_code == 201 and r.json()["state"] == "GPS_ALIGN", r.text
        r = client.post(f"/api/providers/{old}/inertial-sensor", json={"state": "ON"})
        assert r.status_code == 201 and r.json()["state"] == "ON", r.text
        assert [c["state"] for c in client.get("/api/commands").json()] == ["ON", "GPS_ALIGN"]
    # the console restarted, neither vehicle heard since: the commands CSV still says each command's version
    with TestClient(create_app(settings), base_url="http://localhost") as client:
        rows = list(csv.DictReader(io.StringIO(client.get("/api/commands.csv").text)))
        assert [(r["ins_state"], r["umaa_version"]) for r in rows] == [("GPS_ALIGN", "6.0"), ("ON", "3.0.1")], rows


def test_one_simulator_runs_a_mixed_fleet_each_vehicle_commanded_in_its_version(sim, console) -> None:
    """One `sem-sim` of a 3.0.1 and a 6.0 vehicle (--umaa-6-0-vehicles), one console: each vehicle reports on its
    version's topics and takes its version's command, at once."""
    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2", "--align-seconds", "30")
    c = console()
    assert _detail(c.url, V1, {"GPSReport", "GPSFixReport", "InertialSensorReport"})["umaaVersion"] == "3.0.1"
    six_detail = _detail(c.url, V2, HEALTH_6_0)
    assert six_detail["umaaVersion"] == "6.0" and set(six_detail["topics"]) == HEALTH_6_0  # none of the 3.0.1 topics
    old = http.post(f"{c.url}/api/providers/{V1}/inertial-sensor", json={"state": "RESTARTING"})
    six = http.post(f"{c.url}/api/providers/{V2}/inertial-sensor", json={"state": "GPS_ALIGN"})
    assert old.status_code == six.status_code == 201, (old.text, six.text)
    for r in (old, six):
        done = wait_command(c.url, r.json()["sessionId"], timeout=20)
        assert [t["status"] for t in done["transitions"]] == HAPPY and done["violations"] == [] and done["ackedAt"]
    # and neither takes the other's: the console refuses before anything reaches the bus
    assert http.post(f"{c.url}/api/providers/{V2}/inertial-sensor", json={"state": "ON"}).status_code == 422
    assert http.post(f"{c.url}/api/providers/{V1}/inertial-sensor", json={"state": "INIT"}).status_code == 422


# ---- the versions room ----------------------------------------------------------------------------------------------
def test_nothing_outside_the_versions_room_asks_which_version_a_vehicle_speaks() -> None:
    """The versions room (`versions/`) and the simulator's 6.0 writer (`sim/umaa_6_0.py`) know what each version has;
    elsewhere none compares a version (sem-check's detector, `check/observe.py`, names the one it found)."""
    import sem_console

    root = Path(sem_console.__file__).parent
    allowed = {"versions", "sim/umaa_6_0.py", "check/observe.py"}

    def a_version(n: ast.expr) -> bool:
        return (isinstance(n, ast.Constant) and n.value in ("3.0.1", "6.0")) or (
            isinstance(n, ast.Name) and n.id in ("UMAA_3_0_1", "UMAA_6_0")
        )

    asked = [
        f"{f.relative_to(root)}:{n.lineno}: {ast.unparse(n)}"
        for f in sorted(root.rglob("*.py"))
        if not any(str(f.relative_to(root)).startswith(a) for a in allowed)
        for n in ast.walk(ast.parse(f.read_text()))
        if isinstance(n, ast.Compare) and any(a_version(x) for x in (n.left, *n.comparators))
    ]
    assert asked == []
