"""A mixed fleet: UMAA 3.0.1 and UMAA 6.0 vehicles (real `sem-sim` processes) on one bus, in one console."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys
import time
import uuid
from pathlib import Path
from typing import Any

import gpxpy
import httpx
from cyclonedds.core import InstanceState

from sem_console.codec.decode import Decoder
from sem_console.codec.jsonschema import report_schemas
from sem_console.dds.topics import Sem60
from sem_console.sim.provider import vehicle_guid
from sem_console.sim.umaa_6_0 import tfom
from sem_console.umaa.guid import satellite_label
from sem_console.versions import umaa_6_0
from test_console import WsClient, wait_until
from test_wire_layout import GOLDEN_6_0

V1, V2 = str(vehicle_guid(1)), str(vehicle_guid(2))
ALIVE = int(InstanceState.Alive)
HEALTH_6_0 = {"GPSReport", "GlobalPoseReportType", "InertialSensorReportType"}


def _detail(base: str, pid: str, topics: set[str]) -> dict[str, Any]:
    def ready() -> dict[str, Any] | None:
        r = httpx.get(f"{base}/api/providers/{pid}")
        return r.json() if r.status_code == 200 and topics <= set(r.json()["topics"]) else None
    return wait_until(ready, 30, f"provider {pid} with {topics}")


def test_a_mixed_fleet_in_one_console(sim: Any, console: Any, tmp_path: Path) -> None:
    sim("--vehicles", "1")
    six = sim("--umaa", "6.0", "--first-vehicle", "2", "--vehicles", "1", "--state-file", str(tmp_path / "sim-6.0.json"))
    c = console()
    ws = WsClient(c.ws_url)
    old = _detail(c.url, V1, {"GPSReport", "GPSFixReport", "InertialSensorReport"})
    new = _detail(c.url, V2, HEALTH_6_0)
    assert old["umaaVersion"] == "3.0.1" and new["umaaVersion"] == "6.0"
    assert {p["id"]: p["umaaVersion"] for p in httpx.get(f"{c.url}/api/providers").json()} == {V1: "3.0.1", V2: "6.0"}
    # the 6.0 vehicle's GPSReportType in the console's one model: the same GPSReport as a 3.0.1 vehicle's
    gps = new["reports"]["GPSReport"]["report"]
    assert set(gps) == set(old["reports"]["GPSReport"]["report"])
    assert gps["source"] == V2 and gps["numberSatellitesInView"] == len(gps["satellites"]) >= 20
    assert set(gps["satellites"][0]) == set(old["reports"]["GPSReport"]["report"]["satellites"][0])
    assert all(satellite_label(uuid.UUID(s["satelliteId"]).bytes)[0] in "GERCSJI" for s in gps["satellites"])
    assert gps["clock"]["biasUncertianty"] == 15 and "timeFigureOfMerit" not in gps["clock"]
    assert new["reports"]["GPSReport"]["invalid"] == []
    assert all(new["topics"][t]["alive"] and new["topics"][t]["samples"] > 0 for t in HEALTH_6_0)
    assert new["link"] == "live" and set(new["topics"]) == HEALTH_6_0
    # the WebSocket says each vehicle's version too (the snapshot and the provider events)
    wait_until(lambda: {p["provider"]["id"]: p["provider"]["umaaVersion"] for p in ws.of("provider")}.get(V2) == "6.0"
               or {p["id"]: p["umaaVersion"] for p in ws.messages[0]["providers"]}.get(V2) == "6.0", 10, "6.0 on the WebSocket")
    assert ws.errors == []
    ws.close()
    six.stop()  # its shutdown disposes its reports: the 6.0 vehicle's link is lost at once
    wait_until(lambda: httpx.get(f"{c.url}/api/providers/{V2}").json()["link"] == "lost", 10, "the 6.0 vehicle lost")


def test_6_0_reports_decode_into_the_model() -> None:
    """The golden 6.0 GPSReportType (tests/test_wire_layout.py) through the one decode path: the model's GPSReport,
    the satellite named by its constellation and number; the 6.0 reports the model has no place for yet count for the
    link only."""
    decoder = Decoder()
    sample, data = GOLDEN_6_0["UMAA::SEM::GPSStatus::GPSReportType"]()
    item = decoder.decode(Sem60.GPS_REPORT, data, True, ALIVE, 0.0)
    assert item is not None and item.topic == "GPSReport" and item.version == "6.0"  # type: ignore[union-attr]
    assert item.source == uuid.UUID(bytes=bytes(sample.source.id))
    report = item.report  # type: ignore[union-attr]
    assert report["source"] == str(uuid.UUID(bytes=bytes(sample.source.id)))
    assert satellite_label(uuid.UUID(report["satellites"][0]["satelliteId"]).bytes) == "E17"
    assert report["clock"]["biasUncertianty"] == 7 and report["clock"]["timeUncertainty"] is None
    # member for member the model's GPSReport, as the WebSocket schema has it (every member required, nullable)
    defs = report_schemas()
    for value, struct in ((report, "GPSReportType"), (report["clock"], "GPSClockType"),
                          (report["satellites"][0], "GPSSatelliteType")):
        assert sorted(value) == sorted(defs[struct]["required"]), struct
    for sem in (Sem60.GLOBAL_POSE_REPORT, Sem60.INS_REPORT):
        sample, data = GOLDEN_6_0[sem.spec.name]()
        item = decoder.decode(sem, data, True, ALIVE, 0.0)
        assert item is not None and item.report is None and item.alive  # type: ignore[union-attr]
        assert item.topic == sem.spec.name.rsplit("::", 1)[1]  # type: ignore[union-attr]
    assert decoder.undecodable == {}


def test_time_figure_of_merit() -> None:
    assert [tfom(x).name for x in (None, 0.5, 1, 1.5, 10, 20, 100, 101, 1e7, 1e9)] == [
        "TFOM_1", "TFOM_1", "TFOM_1", "TFOM_2", "TFOM_2", "TFOM_3", "TFOM_3", "TFOM_4", "TFOM_8", "TFOM_9"]


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
    live = {pid: httpx.get(f"{c.url}/api/providers/{pid}").json() for pid in (V1, V2)}
    six.stop()  # its shutdown disposes its reports: recorded as 6.0 instance events
    lost = wait_until(lambda: (d := httpx.get(f"{c.url}/api/providers/{V2}").json())["link"] == "lost" and d, 10,
                      "the 6.0 vehicle lost")
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
    assert poses == json.loads(json.dumps([_plain(Sem60.GLOBAL_POSE_REPORT.spec.type.deserialize(m.data))
                                           for m in messages[name]]))
    pose = poses[-1]  # the simulator's: the altitude above or the depth below the surface, no covariance
    assert (pose["altitude"] is None) != (pose["depth"] is None) and pose["positionCovariance"] is None
    assert -90 <= pose["position"]["geodeticLatitude"] <= 90
    assert messages["UMAA::SEM::GPSStatus::GPSReport"]  # the 3.0.1 vehicle beside it
    events = [json.loads(m.data) for m in messages["sem-console/instances"]]
    assert {(s.spec.name, V2) for s in umaa_6_0.REPORTS} <= {(e["topic"], e["source"]) for e in events
                                                             if e["state"] == "disposed"}

    # the console replaying it: at the instant the live console last took each GPSReport, that very report
    r = console("--replay", str(path))
    ws = WsClient(r.ws_url)
    state = replay_state(r.url)
    control(r.url, {"action": "pause"})
    for pid in (V2, V1):
        at = live[pid]["reports"]["GPSReport"]["receivedAt"]
        assert state["start"] <= at <= state["end"]
        control(r.url, {"action": "seek", "position": min(state["end"], at + 0.0005)})
        shown = httpx.get(f"{r.url}/api/providers/{pid}").json()
        assert shown["reports"]["GPSReport"] == live[pid]["reports"]["GPSReport"], pid
        assert shown["umaaVersion"] == live[pid]["umaaVersion"] and set(shown["topics"]) == set(live[pid]["topics"])
        assert shown["link"] == live[pid]["link"] == "live"
    assert {p["id"]: p["umaaVersion"] for p in httpx.get(f"{r.url}/api/providers").json()} == {V1: "3.0.1", V2: "6.0"}
    control(r.url, {"action": "seek", "position": state["start"]})  # back to before either vehicle, then to the end
    assert httpx.get(f"{r.url}/api/providers/{V2}").status_code == 404
    control(r.url, {"action": "seek", "position": state["end"]})
    at_end = httpx.get(f"{r.url}/api/providers/{V2}").json()  # its disposes replayed: lost, as live
    assert at_end["link"] == lost["link"] == "lost"
    assert {t: h["alive"] for t, h in at_end["topics"].items()} == {t: h["alive"] for t, h in lost["topics"].items()}
    snapshot = wait_until(lambda: [m for m in ws.of("snapshot") if any(p["id"] == V2 for p in m["providers"])], 5,
                          "a snapshot with the 6.0 vehicle")[-1]
    assert {p["id"]: p["umaaVersion"] for p in snapshot["providers"]} == {V1: "3.0.1", V2: "6.0"}
    assert ws.errors == []
    ws.close()
    # the exports say each vehicle's version
    for pid, version in ((V1, "3.0.1"), (V2, "6.0")):
        gpx = gpxpy.parse(httpx.get(f"{r.url}/api/providers/{pid}/track.gpx").text)
        assert gpx.tracks[0].description.startswith(f"a UMAA {version} vehicle; "), pid
        rows = list(csv.DictReader(io.StringIO(httpx.get(f"{r.url}/api/providers/{pid}/track.csv").text)))
        assert {row["umaa_version"] for row in rows} <= {version} and (rows or pid == V2), pid

    # sem-replay: the recorded 6.0 samples back on DDS, read by a console as a 6.0 vehicle
    other = free_domain(taken=domain)
    second = ConsoleProcess(other, tmp_path / "second.sqlite3", [], {}).start()
    try:
        out = subprocess.run([sys.executable, "-m", "sem_console.recording.sem_replay", str(path), "--domain", str(other),
                              "--speed", "4"], capture_output=True, text=True, timeout=60)
        assert out.returncode == 0, out.stderr
        again = _detail(second.url, V2, HEALTH_6_0)
        assert again["umaaVersion"] == "6.0"
        last = Decoder().decode(Sem60.GPS_REPORT, messages[Sem60.GPS_REPORT.spec.name][-1].data, True, ALIVE, 0.0)
        assert last is not None
        wait_until(lambda: httpx.get(f"{second.url}/api/providers/{V2}").json()["reports"]["GPSReport"]["report"]
                   == last.report, 10, "the last recorded 6.0 GPSReport on the second console")  # type: ignore[union-attr]
    finally:
        second.stop()
