"""A mixed fleet: UMAA 3.0.1 and UMAA 6.0 vehicles (real `sem-sim` processes) on one bus, in one console."""

from __future__ import annotations

import uuid
from pathlib import Path
from typing import Any

import httpx
from cyclonedds.core import InstanceState

from sem_console.codec.decode import Decoder
from sem_console.codec.jsonschema import report_schemas
from sem_console.dds.topics import Sem60
from sem_console.sim.provider import vehicle_guid
from sem_console.sim.umaa_6_0 import tfom
from sem_console.umaa.guid import satellite_label
from test_console import WsClient, wait_until
from unit.test_wire_layout import GOLDEN_6_0

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
