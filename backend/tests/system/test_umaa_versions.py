"""A mixed fleet: UMAA 3.0.1 and UMAA 6.0 vehicles (real `sem-sim` processes) on one bus, in one console."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys
import time
import uuid
from dataclasses import replace
from pathlib import Path
from typing import Any

import gpxpy
from cyclonedds.core import InstanceState

from sem_console.codec import fastcdr
from sem_console.codec.convert import to_json
from sem_console.codec.decode import Decoder, ReportItem
from sem_console.codec.jsonschema import report_schemas
from sem_console.console.history import track_point
from sem_console.dds.topics import Sem, Sem60, delimited, to_appendable
from sem_console.sim import umaa_6_0 as sim60
from sem_console.sim.models import SUBMERGED_DEPTH_M
from sem_console.sim.options import SimOptions
from sem_console.sim.provider import vehicle_guid
from sem_console.sim.reports import Sensors
from sem_console.sim.umaa_6_0 import tfom
from sem_console.umaa.guid import satellite_label
from sem_console.versions import umaa_6_0
from support import http
from test_console import WsClient, wait_until
from unit.test_wire_layout import GOLDEN_6_0

V1, V2 = str(vehicle_guid(1)), str(vehicle_guid(2))
ALIVE = int(InstanceState.Alive)
HEALTH_6_0 = {"GPSReport", "GPSFixReport", "InertialSensorReport"}  # the model's topics, whatever the version


def _detail(base: str, pid: str, topics: set[str]) -> dict[str, Any]:
    def ready() -> dict[str, Any] | None:
        r = http.get(f"{base}/api/providers/{pid}")
        return r.json() if r.status_code == 200 and topics <= set(r.json()["topics"]) else None

    return wait_until(ready, 30, f"provider {pid} with {topics}")


def test_a_mixed_fleet_in_one_console(sim: Any, console: Any, tmp_path: Path) -> None:
    sim("--vehicles", "1")
    six = sim("--umaa", "6.0", "--first-vehicle", "2", "--vehicles", "1", "--state-file", str(tmp_path / "sim-6.0.json"))
    c = console()
    ws = WsClient(c.ws_url)
    old = _detail(c.url, V1, {"GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"})
    new = _detail(c.url, V2, HEALTH_6_0)
    assert old["umaaVersion"] == "3.0.1" and new["umaaVersion"] == "6.0"
    assert {p["id"]: p["umaaVersion"] for p in http.get(f"{c.url}/api/providers").json()} == {V1: "3.0.1", V2: "6.0"}
    # the 6.0 vehicle's GPSReportType in the console's one model: the same GPSReport as a 3.0.1 vehicle's
    gps = new["reports"]["GPSReport"]["report"]
    assert set(gps) == set(old["reports"]["GPSReport"]["report"])
    assert gps["source"] == V2 and gps["numberSatellitesInView"] == len(gps["satellites"]) >= 20
    assert set(gps["satellites"][0]) == set(old["reports"]["GPSReport"]["report"]["satellites"][0])
    assert all(satellite_label(uuid.UUID(s["satelliteId"]).bytes)[0] in "GERCSJI" for s in gps["satellites"])
    assert gps["clock"]["biasUncertianty"] == 15
    # time quality: each version what it reports (3.0.1 its time uncertainty, 6.0 its figure of merit)
    assert gps["clock"]["timeFigureOfMerit"] == tfom(old["reports"]["GPSReport"]["report"]["clock"]["timeUncertainty"]).name
    assert gps["clock"]["timeUncertainty"] is None and "timeFigureOfMerit" not in old["reports"]["GPSReport"]["report"]["clock"]
    assert new["reports"]["GPSReport"]["invalid"] == []
    # its GlobalPose: the model's position report, as a 3.0.1 vehicle's GPSFixReport, with what 6.0 adds
    pose, fix = new["reports"]["GPSFixReport"]["report"], old["reports"]["GPSFixReport"]["report"]
    assert set(fix) < set(pose) and pose["source"] == V2 and new["reports"]["GPSFixReport"]["invalid"] == []
    at = pose["position2DWithTime"]["geodeticPosition"]
    assert -90 <= at["geodeticLatitude"]["latitude"] <= 90 and -180 <= at["geodeticLongitude"]["longitude"] <= 180
    assert 0 <= pose["trueCourse"] < 7 and pose["attitude"]["yaw"]["yaw"] == pose["trueCourse"]
    # on the surface (6.0 has no GPS fix command to surface it): a measured position, as a working 6.0 vehicle's
    assert pose["navigationSolution"] == "MEASURED" and pose["GPSLatLongValid"] is True and pose["SOG"] is None
    assert pose["altitudeMSL"] == {"altitude": 0.0} and pose["depth"] is None
    assert any(s["usedInFix"] for s in gps["satellites"])
    # its INS: the model's InertialSensorReport, the status a 6.0 literal, no power state
    ins = new["reports"]["InertialSensorReport"]["report"]
    assert ins["state"] is None and ins["status"] in report_schemas()["InertialSensorOpStatusEnumType"]["enum"]
    assert ins["status"] not in ("OPERATIONAL", "COURSE_GPS_ALIGNMENT", "COURSE_STATIONARY_ALIGNMENT")
    assert "GPSFixStatusReport" not in new["reports"] or new["reports"]["GPSFixStatusReport"] is None
    # its track: the map's and the exports' history take its positions as a 3.0.1 vehicle's
    wait_until(lambda: http.get(f"{c.url}/api/providers/{V2}/track").json(), 10, "the 6.0 vehicle's track")
    assert all(new["topics"][t]["alive"] and new["topics"][t]["samples"] > 0 for t in HEALTH_6_0)
    assert new["link"] == "live" and set(new["topics"]) == HEALTH_6_0
    # the WebSocket says each vehicle's version too (the snapshot and the provider events)
    wait_until(
        lambda: (
            {p["provider"]["id"]: p["provider"]["umaaVersion"] for p in ws.of("provider")}.get(V2) == "6.0"
            or {p["id"]: p["umaaVersion"] for p in ws.messages[0]["providers"]}.get(V2) == "6.0"
        ),
        10,
        "6.0 on the WebSocket",
    )
    # and its reports in the model's topics, each valid against the published schema (WsClient checks every message)
    wait_until(
        lambda: (
            {"GPSFixReport", "InertialSensorReport", "GPSReport"}
            <= {m["topic"] for m in ws.of("report") if m["providerId"] == V2}
        ),
        10,
        "the 6.0 vehicle's reports on the WebSocket",
    )
    assert ws.errors == []
    ws.close()
    six.stop()  # its shutdown disposes its reports: the 6.0 vehicle's link is lost at once
    wait_until(lambda: http.get(f"{c.url}/api/providers/{V2}").json()["link"] == "lost", 10, "the 6.0 vehicle lost")


def _model(sem: Sem60, data: bytes | None = None) -> tuple[Any, dict[str, Any], list[str]]:
    """A golden 6.0 sample (tests/test_wire_layout.py), or `data` on its topic, through the one decode path."""
    decoder = Decoder()
    sample, golden = GOLDEN_6_0[sem.spec.name]()
    item = decoder.decode(sem, golden if data is None else data, True, ALIVE, 0.0)
    assert isinstance(item, ReportItem) and item.version == "6.0" and item.report is not None
    assert item.source == uuid.UUID(bytes=bytes(sample.source.id)) and decoder.undecodable == {}
    assert item.report["source"] == str(item.source)
    return sample, item.report, item.invalid


def _schema_members(value: dict[str, Any], struct: str, defs: dict[str, Any]) -> None:
    """`value` is the model's `struct` member for member, as the WebSocket schema has it: every required member, and
    no member the schema lacks (those 6.0 adds are optional)."""
    assert set(defs[struct]["required"]) <= set(value) <= set(defs[struct]["properties"]), struct


def test_6_0_reports_decode_into_the_model() -> None:
    """The golden 6.0 reports through the one decode path into the console's one model: the GPSReport (the satellite
    named by its constellation and number, the clock's time figure of merit), the position report from GlobalPose
    (position, course, attitude, navigation solution, the optional members present or null) and the INS status."""
    defs = report_schemas()
    _, gps, invalid = _model(Sem60.GPS_REPORT)
    assert satellite_label(uuid.UUID(gps["satellites"][0]["satelliteId"]).bytes) == "E17" and invalid == []
    assert gps["clock"]["biasUncertianty"] == 7 and gps["clock"]["timeUncertainty"] is None
    assert gps["clock"]["timeFigureOfMerit"] == "TFOM_3"
    for value, struct in ((gps, "GPSReportType"), (gps["clock"], "GPSClockType"), (gps["satellites"][0], "GPSSatelliteType")):
        _schema_members(value, struct, defs)

    _, pose, invalid = _model(Sem60.GLOBAL_POSE_REPORT)
    assert invalid == []
    assert pose["position2DWithTime"] == {
        "geodeticPosition": {"geodeticLatitude": {"latitude": 36.85}, "geodeticLongitude": {"longitude": -75.98}},
        "timeAtPosition": 1_790_000_004.00000025,
    }
    assert pose["trueCourse"] == 3.0 and pose["GPSLatLongValid"] is True and pose["navigationSolution"] == "MEASURED"
    assert pose["attitude"] == {"pitch": {"pitch": 0.1}, "roll": {"roll": -0.2}, "yaw": {"yaw": 1.5}}
    assert pose["positionCovariance"] == {"pdPd": None, "pePd": None, "pePe": 2.0, "pnPd": None, "pnPe": 0.5, "pnPn": 3.0}
    assert pose["altitudeGeodetic"] == 12.5 and pose["altitudeMSL"] is None and pose["depth"] is None
    assert pose["attitudeCovariance"] is None and pose["altitudeAGL"] is None and pose["altitudeASF"] is None
    # what GlobalPose does not report is null, not made up
    assert pose["SOG"] is None and pose["velocity"] is None and pose["magneticVariation"] is None
    assert pose["GPSFixCommandStatus"] is None
    _schema_members(pose, "GPSFixReportType", defs)

    _, ins, invalid = _model(Sem60.INS_REPORT)
    assert (
        ins
        == {
            "state": None,
            "status": "FINE_GPS_ALIGNMENT_STARTED",
            "source": ins["source"],
            "timeStamp": {"seconds": 1, "nanoseconds": 2},
        }
        and invalid == []
    )
    assert "FINE_GPS_ALIGNMENT_STARTED" in defs["InertialSensorOpStatusEnumType"]["enum"]
    _schema_members(ins, "InertialSensorReportType", defs)


def test_a_6_0_position_flagged_invalid_is_named_by_the_models_path() -> None:
    """An impossible latitude and an estimated position: the model's track and gateways read the flag by the model's
    path, and an estimated position is no measurement (GPSLatLongValid false, as a 3.0.1 INS position)."""
    sample, _ = GOLDEN_6_0["UMAA::SA::GlobalPoseStatus::GlobalPoseReportType"]()
    sample.position.geodeticLatitude = 95.0
    sample.course = float("nan")
    sample.navigationSolution = type(sample.navigationSolution)["ESTIMATED"]
    _, pose, invalid = _model(Sem60.GLOBAL_POSE_REPORT, type(sample).serialize(sample, use_version_2=True))
    assert sorted(invalid) == [
        "position2DWithTime.geodeticPosition.geodeticLatitude.latitude: 95.0 outside -90..90",
        "trueCourse: nan is not a number",
    ]
    assert pose["GPSLatLongValid"] is False and pose["navigationSolution"] == "ESTIMATED" and pose["trueCourse"] is None
    assert track_point(pose["source"], 0.0, pose, invalid, None) is None  # no valid position, no track point


def test_a_6_0_sim_vehicle_reports_a_measured_position_on_the_surface() -> None:
    """UMAA 6.0 has no GPS fix command to surface a vehicle: a 6.0 sem-sim vehicle is on the surface, its GlobalPose
    MEASURED and its satellites used in the fix; under water its position would be ESTIMATED, with its depth."""
    sensors = Sensors(SimOptions(umaa="6.0"), 1, vehicle_guid(1), set())
    now = time.monotonic()
    sats = sensors.satellites(now)
    pose = sim60.global_pose(sensors.fix_reports(now, sats)[0])
    assert pose.navigationSolution.name == "MEASURED" and pose.altitude == 0.0 and pose.depth is None
    assert any(s.usedInFix for s in sim60.gps_report(sensors.gps_report(now, sats)).satellites)
    sensors.depth = SUBMERGED_DEPTH_M
    pose = sim60.global_pose(sensors.fix_reports(now, sensors.satellites(now))[0])
    assert pose.navigationSolution.name == "ESTIMATED" and pose.depth == -SUBMERGED_DEPTH_M and pose.altitude is None
    # one simulator's mixed fleet: its 6.0 vehicles on the surface, its 3.0.1 ones submerged until a GPS fix
    mixed = SimOptions(vehicles=2, umaa_6_0_vehicles={2})
    assert Sensors(mixed, 2, vehicle_guid(2), set()).depth == 0.0
    assert Sensors(mixed, 1, vehicle_guid(1), set()).depth == SUBMERGED_DEPTH_M


def test_a_6_0_satellite_number_no_satellite_has_is_flagged() -> None:
    """A 6.0 satellite's number becomes the console's satellite GUID; one no satellite has (17.5, 300) cannot, and is
    listed as invalid, as a 3.0.1 satellite GUID of the wrong length is, not left null unsaid."""
    sample, _ = GOLDEN_6_0["UMAA::SEM::GPSStatus::GPSReportType"]()
    first = sample.satellites[0]
    sample.satellites = [replace(first, satelliteID=17.5), replace(first, satelliteID=300.0), first]
    _, gps, invalid = _model(Sem60.GPS_REPORT, type(sample).serialize(sample))
    assert [s["satelliteId"] is None for s in gps["satellites"]] == [True, True, False]
    assert invalid == [
        "satellites[0].satelliteId: 17.5 is no satellite number (a whole number 1..255)",
        "satellites[1].satelliteId: 300.0 is no satellite number (a whole number 1..255)",
    ]


def test_a_6_0_course_west_of_north_is_valid() -> None:
    """UMAA 6.0's course (CourseTrueNorth, SA ICD 6.0) is -2 pi..2 pi, where 3.0.1's is 0..2 pi: a 6.0 vehicle reporting
    -1 rad is on course 302.7°, not an invalid course the track, the map and the gateways leave out."""
    sample, _ = GOLDEN_6_0["UMAA::SA::GlobalPoseStatus::GlobalPoseReportType"]()
    sample.course = -1.0
    _, pose, invalid = _model(Sem60.GLOBAL_POSE_REPORT, type(sample).serialize(sample, use_version_2=True))
    assert invalid == [] and pose["trueCourse"] == -1.0
    point = track_point(pose["source"], 0.0, pose, invalid, None)
    assert point is not None and round(point["course"], 1) == 302.7


def test_time_figure_of_merit() -> None:
    assert [tfom(x).name for x in (None, 0.5, 1, 1.5, 10, 20, 100, 101, 1e7, 1e9)] == [
        "TFOM_1",
        "TFOM_1",
        "TFOM_1",
        "TFOM_2",
        "TFOM_2",
        "TFOM_3",
        "TFOM_3",
        "TFOM_4",
        "TFOM_8",
        "TFOM_9",
    ]


def test_the_generated_decoder_and_cyclonedds_give_the_same_model() -> None:
    """A 6.0 report said as data (versions/shape.py) is decoded by the generated code straight to the model's JSON,
    and one cyclonedds decodes (the fallback) is adapted to the same JSON: the same members, values and invalid
    values, for the golden samples and a sample with impossible values and every optional member present."""
    for sem in (Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT):
        r = umaa_6_0.REPORTS[sem]
        assert r.spec is not None
        sample, golden = GOLDEN_6_0[sem.spec.name]()
        datas = [golden]
        if sem is Sem60.GLOBAL_POSE_REPORT:
            sample.position.geodeticLongitude, sample.course, sample.altitude, sample.depth = 181.0, -7.0, 5.0, 2.0
            sample.altitudeAGL, sample.altitudeASF = 7.0, 8.0
            sample.attitudeCovariance = _attitude_covariance()
            datas.append(type(sample).serialize(sample, use_version_2=True))
        for data in datas:
            generated = fastcdr.decoder(sem.spec.type, r.spec, umaa_6_0.model_path, r.model).json(data)
            assert generated == r.model(*to_json(sem.spec.type.deserialize(data)))
        if sem is Sem60.GLOBAL_POSE_REPORT:
            pose = generated
    assert sorted(pose[1]) == [
        "position2DWithTime.geodeticPosition.geodeticLongitude.longitude: 181.0 outside -180..180",
        "trueCourse: -7.0 outside -6.28319..6.28319",
    ]
    assert pose[0]["altitudeMSL"] == {"altitude": 5.0} and pose[0]["attitudeCovariance"]["rrRy"] is None


def test_a_6_0_report_from_an_appendable_writer_decodes_into_the_same_model() -> None:
    """A 6.0 report as an appendable writer sends it (an RTI vehicle, `sem-sim --gps-extensibility appendable`):
    the one decode path gives the same model as for the final type, and cyclonedds' decoding of the appendable copy,
    adapted, the same again."""
    sems = [sem for sem in umaa_6_0.REPORTS if sem.spec.appendable is not None]
    assert Sem60.GLOBAL_POSE_REPORT in sems
    for sem in sems:
        sample, golden = GOLDEN_6_0[sem.spec.name]()
        data = to_appendable(sample).serialize(use_version_2=True)
        assert delimited(data) and not delimited(golden)
        final, appendable = (Decoder().decode(sem, d, True, ALIVE, 0.0) for d in (golden, data))
        assert isinstance(final, ReportItem) and isinstance(appendable, ReportItem) and final.report is not None
        assert (appendable.topic, appendable.source, appendable.version) == (final.topic, final.source, "6.0")
        assert (appendable.report, appendable.invalid) == (final.report, final.invalid)
        assert sem.spec.appendable is not None
        cyclonedds = to_json(sem.spec.appendable.deserialize(data))
        assert umaa_6_0.REPORTS[sem].model(*cyclonedds) == (final.report, final.invalid)


def _attitude_covariance() -> Any:
    from UMAA_6_0.Common.Measurement import CovarianceOrientationNEDType

    return CovarianceOrientationNEDType(rpRp=0.01, rpRy=None, rrRp=0.002, rrRr=0.02, rrRy=None, ryRy=0.03)


def test_a_mixed_fleet_recorded_replays_as_live(sim: Any, console: Any, domain: int, tmp_path: Path) -> None:
    """A 3.0.1 and a 6.0 `sem-sim` vehicle on one bus, recorded by the console: the file holds both versions' channels,
    the 6.0 samples decoded with types idlc builds from their schema text alone. `sem-console --replay` then shows each
    vehicle as the live console did (the same report at the same instant, its version, its link), sought back and
    forth; `sem-replay` puts the 6.0 vehicle back on another domain, where a console sees it as 6.0."""
    from conftest import ConsoleProcess, free_domain
    from test_recording import _plain, decode_with_schema, read, recorded
    from test_replay import control, replay_state

    sim("--vehicles", "1")
    six = sim("--umaa", "6.0", "--first-vehicle", "2", "--vehicles", "1", "--state-file", str(tmp_path / "sim-6.0.json"))
    c = console("--record", str(tmp_path / "rec"))
    _detail(c.url, V1, {"GPSReport", "GPSFixReport", "InertialSensorReport"})
    _detail(c.url, V2, HEALTH_6_0)
    time.sleep(1.0)
    live = {pid: http.get(f"{c.url}/api/providers/{pid}").json() for pid in (V1, V2)}
    six.stop()  # its shutdown disposes its reports: recorded as 6.0 instance events
    lost = wait_until(
        lambda: (d := http.get(f"{c.url}/api/providers/{V2}").json())["link"] == "lost" and d, 10, "the 6.0 vehicle lost"
    )
    path = recorded(c.url, tmp_path)
    c.stop()

    # the file: each vehicle on its version's channels
    channels, messages = read(path)
    for sem in Sem60:
        assert channels[sem.spec.name][1].metadata == {"umaaVersion": "6.0"}
    assert all(m.data[:2] == b"\x00\x01" for m in messages[Sem60.GPS_REPORT.spec.name])  # XCDR1
    assert all(m.data[:2] == b"\x00\x07" for m in messages[Sem60.GLOBAL_POSE_REPORT.spec.name])  # XCDR2: optional members
    for sem in (Sem60.GPS_REPORT, Sem60.INS_REPORT):
        assert len(messages[sem.spec.name]) >= 3, sem.name
    # the one with optional members decoded with the schema's own types (each 6.0 schema: test_recording.py), member
    # for member what the console's 6.0 types read from the same bytes
    name = Sem60.GLOBAL_POSE_REPORT.spec.name
    poses = decode_with_schema(channels[name][0].name, channels[name][0].data.decode(), name, path, tmp_path)
    assert len(poses) == len(messages[name]) >= 3 and {str(uuid.UUID(hex=x["source"]["id"])) for x in poses} == {V2}
    assert poses == json.loads(
        json.dumps([_plain(Sem60.GLOBAL_POSE_REPORT.spec.type.deserialize(m.data)) for m in messages[name]])
    )
    pose = poses[-1]  # the simulator's: the altitude above or the depth below the surface, no covariance
    assert (pose["altitude"] is None) != (pose["depth"] is None) and pose["positionCovariance"] is None
    assert -90 <= pose["position"]["geodeticLatitude"] <= 90
    assert messages["UMAA::SEM::GPSStatus::GPSReport"]  # the 3.0.1 vehicle beside it
    events = [json.loads(m.data) for m in messages["sem-console/instances"]]
    assert {(s.spec.name, V2) for s in umaa_6_0.REPORTS} <= {
        (e["topic"], e["source"]) for e in events if e["state"] == "disposed"
    }

    # the console replaying it: at the instant the live console last took each GPSReport, that very report
    r = console("--replay", str(path))
    ws = WsClient(r.ws_url)
    state = replay_state(r.url)
    control(r.url, {"action": "pause"})
    for pid in (V2, V1):
        at = live[pid]["reports"]["GPSReport"]["receivedAt"]
        assert state["start"] <= at <= state["end"]
        control(r.url, {"action": "seek", "position": min(state["end"], at + 0.0005)})
        shown = http.get(f"{r.url}/api/providers/{pid}").json()
        assert shown["reports"]["GPSReport"] == live[pid]["reports"]["GPSReport"], pid
        assert shown["umaaVersion"] == live[pid]["umaaVersion"] and set(shown["topics"]) == set(live[pid]["topics"])
        assert shown["link"] == live[pid]["link"] == "live"
    assert {p["id"]: p["umaaVersion"] for p in http.get(f"{r.url}/api/providers").json()} == {V1: "3.0.1", V2: "6.0"}
    # back to the recording's first instant, where only the vehicle heard first is (each vehicle on its version's
    # channels; either may come first), then to the end
    first = {
        pid: min(m.log_time for s in sems for m in messages.get(s.spec.name, []))
        for pid, sems in ((V1, list(Sem)), (V2, list(Sem60)))
    }
    control(r.url, {"action": "seek", "position": state["start"]})
    later = V2 if first[V2] > first[V1] else V1
    assert http.get(f"{r.url}/api/providers/{later}").status_code == 404
    control(r.url, {"action": "seek", "position": state["end"]})
    at_end = http.get(f"{r.url}/api/providers/{V2}").json()  # its disposes replayed: lost, as live
    assert at_end["link"] == lost["link"] == "lost"
    assert {t: h["alive"] for t, h in at_end["topics"].items()} == {t: h["alive"] for t, h in lost["topics"].items()}
    snapshot = wait_until(
        lambda: [m for m in ws.of("snapshot") if any(p["id"] == V2 for p in m["providers"])], 5, "a snapshot with the 6.0 vehicle"
    )[-1]
    assert {p["id"]: p["umaaVersion"] for p in snapshot["providers"]} == {V1: "3.0.1", V2: "6.0"}
    assert ws.errors == []
    ws.close()
    # the exports say each vehicle's version
    for pid, version in ((V1, "3.0.1"), (V2, "6.0")):
        gpx = gpxpy.parse(http.get(f"{r.url}/api/providers/{pid}/track.gpx").text)
        assert gpx.tracks[0].description.startswith(f"a UMAA {version} vehicle; "), pid
        rows = list(csv.DictReader(io.StringIO(http.get(f"{r.url}/api/providers/{pid}/track.csv").text)))
        assert {row["umaa_version"] for row in rows} <= {version} and (rows or pid == V2), pid

    # sem-replay: the recorded 6.0 samples back on DDS, read by a console as a 6.0 vehicle
    other = free_domain(taken=domain)
    second = ConsoleProcess(other, tmp_path / "second.sqlite3", [], {}).start()
    try:
        out = subprocess.run(
            [sys.executable, "-m", "sem_console.recording.sem_replay", str(path), "--domain", str(other), "--speed", "4"],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert out.returncode == 0, out.stderr
        again = _detail(second.url, V2, HEALTH_6_0)
        assert again["umaaVersion"] == "6.0"
        last = Decoder().decode(Sem60.GPS_REPORT, messages[Sem60.GPS_REPORT.spec.name][-1].data, True, ALIVE, 0.0)
        assert last is not None
        wait_until(
            lambda: http.get(f"{second.url}/api/providers/{V2}").json()["reports"]["GPSReport"]["report"] == last.report,
            10,
            "the last recorded 6.0 GPSReport on the second console",
        )  # type: ignore[union-attr]
    finally:
        second.stop()
