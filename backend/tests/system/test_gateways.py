"""The gateways against real processes: ASPN-23 read back from a real LCM log with LCM's EventLog and
the published aspn23-lcm classes, JAUS over real UDP decoded by a decoder written here from the
field-type table (README, "Gateways"), never by the console's code."""

from __future__ import annotations

import hashlib
import math
import random
import socket
import struct
import threading
import time
import uuid
from pathlib import Path
from typing import Any

import aspn23_lcm
import lcm
import pytest

from UMAA.Common.MaritimeEnumeration.GPSConstellationEnumType import GPSConstellationEnumType as Constellation
from UMAA.SEM.GPSStatus import GPSClockType, GPSReportType, GPSSatelliteType

from conftest import free_udp_port
from sem_console.dds.topics import Sem
from sem_console.umaa.guid import satellite_guid, to_guid
from sem_console.umaa.samples import make, now_datetime
from support import http
from support.consumer import Consumer
from test_console import V1, WsClient, _valid_fix, provider_ready, wait_command, wait_until

FIX_MEASUREMENTS = {
    "measurement_position",
    "measurement_altitude",
    "measurement_velocity",
    "measurement_speed",
    "measurement_direction_of_motion_2d",
}


def nsec(report: Any) -> int:
    return report.timeStamp.seconds * 1_000_000_000 + report.timeStamp.nanoseconds


def read_log(path: Path) -> list[tuple[str, Any]]:
    """(channel, decoded aspn23_lcm message) for every event of an LCM log file."""
    out = []
    for event in lcm.EventLog(str(path), "r"):
        measurement = event.channel.rsplit("/", 1)[1]
        out.append((event.channel, getattr(aspn23_lcm, measurement).decode(event.data)))
    return out


def lcm_vehicle(vehicle: str) -> str:
    """A vehicle's part of its ASPN channel names, by the recipe of docs/gateways.md (not the console's code)."""
    return hashlib.blake2b(uuid.UUID(vehicle).bytes, digest_size=8).hexdigest()


def surface(base: str) -> None:
    provider_ready(base, V1, {"GPSFixReport", "GPSReport"})
    session = http.post(f"{base}/api/providers/{V1}/gps-fix", json={}).json()["sessionId"]
    wait_command(base, session, done=lambda x: x["status"] == "COMPLETED")


def collect(consumer: Consumer, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        consumer.pump()
        time.sleep(0.01)


# ---- ASPN-23 over LCM ------------------------------------------------------------------------------
def test_aspn_log_matches_the_umaa_reports(sim, console, consumer, tmp_path: Path) -> None:
    log_file = tmp_path / "aspn.lcm"
    sim("--vehicles", "1")
    c = console("--aspn-lcm", f"file://{log_file}", "--aspn-prefix", "fleet")

    def submerged_fixes() -> bool:  # without a valid position, seen by the test's reader and by the console
        seen = consumer.reports[Sem.GPS_FIX_REPORT].get(uuid.UUID(V1), [])
        if sum(not r.GPSLatLongValid for r in seen) < 3:
            return False
        fix = (http.get(f"{c.url}/api/providers/{V1}").json().get("reports") or {}).get("GPSFixReport")
        return fix is not None and fix["report"]["GPSLatLongValid"] is False

    # a console ready sooner than the bus had brought the vehicle's fixes to both: the check below had none to check
    consumer.wait(submerged_fixes, 30, "submerged fixes, at the test's reader and at the console")
    surface(c.url)
    collect(consumer, 1.5)
    recorded = http.get(f"{c.url}/api/providers/{V1}/aspn-log", params={"seconds": 60})
    assert recorded.status_code == 200 and recorded.headers["content-type"] == "application/octet-stream"
    assert (
        recorded.headers["content-disposition"].startswith("attachment; filename=")
        and ".lcm" in recorded.headers["content-disposition"]
    )
    (tmp_path / "recorded.lcm").write_bytes(recorded.content)
    # `since` is ISO 8601 as everywhere else in the API (it took seconds since the epoch, which the docs never said)
    since = http.get(f"{c.url}/api/providers/{V1}/aspn-log", params={"since": "2000-01-01T00:00:00Z"})
    assert since.status_code == 200 and len(since.content) >= len(recorded.content) > 0
    later = http.get(f"{c.url}/api/providers/{V1}/aspn-log", params={"since": "2100-01-01T00:00:00+01:00"})
    assert later.status_code == 200 and later.content == b""  # nothing kept from then: `since` is applied
    assert http.get(f"{c.url}/api/providers/{V1}/aspn-log", params={"since": "1700000000"}).status_code == 422
    state = {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}
    assert state["aspn"]["enabled"] and state["aspn"]["messagesOut"] > 0 and state["aspn"]["lastError"] is None
    assert not state["jaus"]["enabled"]
    c.stop()

    fixes = {nsec(r): r for r in consumer.reports[Sem.GPS_FIX_REPORT][uuid.UUID(V1)]}
    gps = {nsec(r): r for r in consumer.reports[Sem.GPS_REPORT][uuid.UUID(V1)]}
    events = read_log(log_file)
    assert {ch for ch, _ in events} == {f"fleet/{lcm_vehicle(V1)}/{m}" for m in FIX_MEASUREMENTS | {"measurement_satnav"}}
    # the dashboard's recording holds the same messages (a window of them)
    recorded_events = read_log(tmp_path / "recorded.lcm")
    assert recorded_events and {ch for ch, _ in recorded_events} <= {ch for ch, _ in events}

    by_channel: dict[str, list[Any]] = {}
    for ch, msg in events:
        by_channel.setdefault(ch, []).append(msg)
    devices = {m.header.device_id for _, m in events}
    assert len(devices) == 1
    contexts = {ch: {m.header.context_id for m in msgs} for ch, msgs in by_channel.items()}
    assert all(len(x) == 1 for x in contexts.values()) and len({next(iter(x)) for x in contexts.values()}) == len(contexts)
    for ch, msgs in by_channel.items():  # sequence_id counts up by one per stream
        assert [m.header.sequence_id for m in msgs] == list(range(len(msgs))), ch

    matched = {m: 0 for m in FIX_MEASUREMENTS | {"measurement_satnav"}}
    positions_at = set()
    for ch, m in events:
        measurement = ch.rsplit("/", 1)[1]
        t = m.time_of_validity.elapsed_nsec
        if measurement == "measurement_satnav":
            r = gps.get(t)
            if r is None:
                continue
            matched[measurement] += 1
            assert m.num_signals_tracked == len(r.satellites) == len(m.obs)
            for o, s in zip(m.obs, r.satellites, strict=True):
                assert o.prn == bytes(s.satelliteId)[15]
                assert (
                    o.satellite_system.satellite_system
                    == {
                        Constellation.GPS: 0,
                        Constellation.GALILEO: 1,
                        Constellation.GLONASS: 2,
                        Constellation.BEIDOU: 3,
                        Constellation.SBAS: 4,
                    }[s.constellationType]
                )
                assert o.frequency == s.carrierFrequency
                if s.antennaCarrierNoiseDensity is None:
                    assert math.isnan(o.c_n0)
                else:
                    assert o.c_n0 == pytest.approx(s.antennaCarrierNoiseDensity)
                for absent in (
                    o.pseudorange,
                    o.pseudorange_variance,
                    o.pseudorange_rate,
                    o.carrier_phase,
                    o.carrier_phase_variance,
                ):
                    assert math.isnan(absent)  # UMAA has none of these: NaN, never a stand-in 0
                assert o.lock_count == -1
            continue
        r = fixes.get(t)
        if r is None:
            continue
        matched[measurement] += 1
        if measurement == "measurement_position":
            assert r.GPSLatLongValid
            positions_at.add(t)
            assert m.reference_frame == aspn23_lcm.measurement_position.REFERENCE_FRAME_GEODETIC
            assert m.term1 == pytest.approx(
                math.radians(r.position2DWithTime.geodeticPosition.geodeticLatitude.latitude), abs=1e-12
            )
            assert m.term2 == pytest.approx(
                math.radians(r.position2DWithTime.geodeticPosition.geodeticLongitude.longitude), abs=1e-12
            )
            assert math.isnan(m.term3)  # UMAA gives MSL, not height above the ellipsoid
            assert m.num_meas == 2 and all(math.isnan(x) for row in m.covariance for x in row)
        elif measurement == "measurement_altitude":
            assert m.reference == aspn23_lcm.measurement_altitude.REFERENCE_MSL
            assert m.altitude == pytest.approx(r.altitudeMSL.altitude) and math.isnan(m.variance)
        elif measurement == "measurement_velocity":
            assert m.reference_frame == aspn23_lcm.measurement_velocity.REFERENCE_FRAME_NED
            assert (m.x, m.y, m.z) == pytest.approx((r.velocity.northSpeed, r.velocity.eastSpeed, r.velocity.downSpeed))
            assert all(math.isnan(x) for row in m.covariance for x in row)
        elif measurement == "measurement_speed":
            assert m.reference == aspn23_lcm.measurement_speed.REFERENCE_GROUND
            assert m.speed == pytest.approx(r.SOG) and math.isnan(m.variance)
        else:
            assert m.reference == aspn23_lcm.measurement_direction_of_motion_2d.REFERENCE_NE
            assert m.obs == pytest.approx(r.trueCourse) and math.isnan(m.variance)
    assert all(n >= 3 for k, n in matched.items() if k != "measurement_satnav") and matched["measurement_satnav"] >= 1, matched
    # submerged (GPSLatLongValid false: the INS's solution) nothing of the fix goes out, so a fusion engine never takes
    # the INS's own values back as GPS measurements
    submerged = {t for t, r in fixes.items() if not r.GPSLatLongValid}
    fix_at = {m.time_of_validity.elapsed_nsec for ch, m in events if ch.rsplit("/", 1)[1] in FIX_MEASUREMENTS}
    assert submerged and positions_at and not fix_at & submerged


def test_aspn_over_udp_multicast_sends_every_measurement(sim, console, tmp_path: Path) -> None:
    """LCM over UDP (the listeners' usual transport, unlike a log file) refuses a channel name over 63 characters: with
    the vehicle's whole GUID in it, position, altitude, velocity and direction of motion were never sent (only speed and
    satnav). A real LCM subscriber on the multicast group gets all six, decoded by the published aspn23_lcm types."""
    url = f"udpm://239.255.76.67:{free_udp_port()}?ttl=0"
    got: dict[str, Any] = {}
    listener = lcm.LCM(url)
    listener.subscribe("nav/.*", lambda ch, data: got.setdefault(ch, getattr(aspn23_lcm, ch.rsplit("/", 1)[1]).decode(data)))
    sim("--vehicles", "1")
    c = console("--aspn-lcm", url, "--aspn-prefix", "nav")
    surface(c.url)  # a valid position
    wanted = {f"nav/{lcm_vehicle(V1)}/{m}" for m in FIX_MEASUREMENTS | {"measurement_satnav"}}
    deadline = time.monotonic() + 30
    while not wanted <= set(got) and time.monotonic() < deadline:
        listener.handle_timeout(100)
    assert set(got) == wanted, sorted(set(got))
    assert {m.header.device_id for m in got.values()} == {int(lcm_vehicle(V1), 16) >> 1}
    state = {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}
    assert state["aspn"]["lastError"] is None, state["aspn"]


def test_every_aspn_channel_fits_lcm_over_udp() -> None:
    """Whatever the vehicle and measurement, a channel stays within LCM's 63 characters with the longest prefix the
    settings take (core/config.py: 11)."""
    from sem_console.gateways.aspn.encode import CONTEXT_IDS
    from sem_console.gateways.aspn.gateway import LCM_MAX_CHANNEL, channel_vehicle

    assert max(len(f"{'p' * 11}/{channel_vehicle(uuid.uuid4())}/{m}") for m in CONTEXT_IDS) <= LCM_MAX_CHANNEL


def test_aspn_leaves_out_invalid_values(console, domain: int, tmp_path: Path) -> None:
    c = console("--aspn-lcm", f"file://{tmp_path / 'aspn.lcm'}")
    bus = Consumer(domain, name="bad-aspn-provider").bus
    source = uuid.uuid4()
    fix = _valid_fix()
    fix.source = to_guid(source)
    fix.SOG = math.nan
    fix.position2DWithTime.geodeticPosition.geodeticLatitude.latitude = 200.0
    fix.velocity.downSpeed = math.nan
    good = make(
        GPSSatelliteType,
        constellationType=Constellation.GPS,
        satelliteId=satellite_guid(Constellation.GPS, 7),
        carrierFrequency=1575.42e6,
    )
    no_frequency = make(GPSSatelliteType, constellationType=Constellation.GPS, satelliteId=satellite_guid(Constellation.GPS, 8))
    gps = make(
        GPSReportType,
        clock=make(GPSClockType),
        numberSatellitesInView=2,
        satellites=[good, no_frequency],
        source=to_guid(source),
        timeStamp=now_datetime(),
    )
    writers = {sem: bus.writer(sem) for sem in (Sem.GPS_FIX_REPORT, Sem.GPS_REPORT)}  # alive until the test ends
    writers[Sem.GPS_FIX_REPORT].write(fix)
    writers[Sem.GPS_REPORT].write(gps)
    provider_ready(c.url, str(source), {"GPSFixReport", "GPSReport"})

    def log() -> dict[str, Any] | None:
        r = http.get(f"{c.url}/api/providers/{source}/aspn-log")
        if r.status_code != 200:
            return None
        (tmp_path / "got.lcm").write_bytes(r.content)
        got = {ch.rsplit("/", 1)[1]: m for ch, m in read_log(tmp_path / "got.lcm")}
        return got if {"measurement_velocity", "measurement_satnav"} <= set(got) else None

    got = wait_until(log, 10, "the ASPN messages of the bad reports")
    assert "measurement_position" not in got and "measurement_speed" not in got  # latitude 200, SOG NaN: left out
    v = got["measurement_velocity"]
    assert (v.x, v.y) == (1.0, 0.0) and math.isnan(v.z)  # north, east as sent (0.0 kept); the NaN down never sent as 0
    assert got["measurement_altitude"].altitude == 0.0 and got["measurement_direction_of_motion_2d"].obs == 1.0
    sat = got["measurement_satnav"]
    assert [o.prn for o in sat.obs] == [7] and math.isnan(sat.obs[0].c_n0)
    counters = {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}["aspn"]["counters"]
    assert counters["left out: position: latitude or longitude invalid"] >= 1
    assert counters["left out: speed: SOG invalid"] >= 1
    assert counters["left out: satellite: carrier frequency absent or in no known band"] >= 1


def test_aspn_log_route_needs_the_gateway(sim, console) -> None:
    sim("--vehicles", "1")
    c = console()
    provider_ready(c.url, V1, {"GPSFixReport"})
    r = http.get(f"{c.url}/api/providers/{V1}/aspn-log")
    assert r.status_code == 409 and "--aspn-lcm" in r.json()["detail"]
    assert http.get(f"{c.url}/api/providers/{uuid.uuid4()}/aspn-log").status_code == 404


def test_bad_aspn_url_is_a_one_line_error(tmp_path: Path) -> None:
    import subprocess
    import sys

    r = subprocess.run(
        [sys.executable, "-m", "sem_console.cli", "--aspn-lcm", f"file://{tmp_path}/no/such/dir/x.lcm"],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert r.returncode == 2 and "--aspn-lcm" in r.stderr and "Traceback" not in r.stderr


# ---- JAUS over JUDP, decoded from the table ------------------------------------------------------
# (bits, lo, hi): value = raw * (hi - lo) / (2**bits - 1) + lo; lo None: a plain unsigned integer
TABLE: dict[str, tuple[int, float | None, float | None]] = {
    "TimeSeconds": (32, None, None),
    "TimeNanoSeconds": (32, None, None),
    "Latitude": (32, -90, 90),
    "Longitude": (32, -180, 180),
    **{k: (32, -10000, 35000) for k in ("AltitudeAGL", "AltitudeMSL", "AltitudeASF", "Depth")},
    "XYPositionRMS": (32, 0, 100),
    "ZPositionRMS": (32, 0, 100),
    **{k: (16, -math.pi, math.pi) for k in ("Roll", "Pitch", "Heading", "Course")},
    **{k: (32, -327.68, 327.68) for k in ("Velocity_N", "Velocity_E", "Velocity_D")},
    "SpeedOverGround": (16, 0, 327.67),
}
GLOBAL = [
    "Latitude",
    "Longitude",
    "AltitudeAGL",
    "AltitudeMSL",
    "AltitudeASF",
    "Depth",
    "XYPositionRMS",
    "ZPositionRMS",
    "Roll",
    "Pitch",
    "Heading",
    "Attitude_RMS",
    "Course",
    "TimeSeconds",
    "TimeNanoSeconds",
]
LOCAL = [
    "X",
    "Y",
    "AltitudeAGL",
    "AltitudeMSL",
    "AltitudeASF",
    "Depth",
    "ZLocal",
    "XYPositionRMS",
    "ZPositionRMS",
    "Roll",
    "Pitch",
    "Heading",
    "Attitude_RMS",
    "Course",
    "TimeSeconds",
    "TimeNanoSeconds",
]
NED = ["Velocity_N", "Velocity_E", "Velocity_D"]
VSTATE = [
    "Velocity_RMS",
    "RollRate",
    "PitchRate",
    "YawRate",
    "Rate_RMS",
    "SpeedOverGround",
    "SpeedRelativeToMedium",
    "RotationsPerMinute",
    "IndicatedSpeed",
    "TimeSeconds",
    "TimeNanoSeconds",
]
ACCEL = [
    "Acceleration_X",
    "Acceleration_Y",
    "Acceleration_Z",
    "Acceleration_RMS",
    "RollAcceleration",
    "PitchAcceleration",
    "YawAcceleration",
    "RotationalAcceleration_RMS",
    "TimeSeconds",
    "TimeNanoSeconds",
]
ME = (7, 3, 900)  # the test station: component, node, subsystem


def step(name: str) -> float:
    bits, lo, hi = TABLE[name]
    return 1.0 if lo is None else (hi - lo) / (2**bits - 1)


def judp(dest: tuple[int, int, int], message_id: int, body: bytes, seq: int = 1, flags: int = 1) -> bytes:
    size = 14 + 2 + len(body)
    return (
        struct.pack("<BBHB", 2, 0, size, flags)
        + struct.pack("<BBH", *dest)
        + struct.pack("<BBH", *ME)
        + struct.pack("<H", message_id)
        + body
        + struct.pack("<H", seq)
    )


def unjudp(data: bytes) -> tuple[tuple[int, int, int], tuple[int, int, int], int, bytes]:
    version, kind, size, _flags = struct.unpack_from("<BBHB", data)
    assert (version, kind, size) == (2, 0, len(data) - 1)
    dest, src = struct.unpack_from("<BBH", data, 5), struct.unpack_from("<BBH", data, 9)
    (message_id,) = struct.unpack_from("<H", data, 13)
    return dest, src, message_id, data[15:-2]


def read_record(body: bytes, at: int, names: list[str], pv_bits: int) -> tuple[int, dict[str, float], int]:
    pv_fmt = "<B" if pv_bits == 8 else "<H"
    (pv,) = struct.unpack_from(pv_fmt, body, at)
    at += struct.calcsize(pv_fmt)
    values = {}
    for i, name in enumerate(names):
        if pv >> i & 1:
            bits, lo, hi = TABLE[name]  # a field the table lacks must never be present
            fmt = "<I" if bits == 32 else "<H"
            (raw,) = struct.unpack_from(fmt, body, at)
            at += struct.calcsize(fmt)
            values[name] = float(raw) if lo is None else raw * (hi - lo) / (2**bits - 1) + lo
    return pv, values, at


def decode_navigation(body: bytes) -> dict[str, Any]:
    sec, nsec_ = struct.unpack_from("<II", body, 0)
    at = 8
    g_pv, g, at = read_record(body, at, GLOBAL, 16)
    l_pv, _, at = read_record(body, at, LOCAL, 16)
    (tag,) = struct.unpack_from("<B", body, at)
    n_pv, n, at = read_record(body, at + 1, NED, 8)
    v_pv, v, at = read_record(body, at, VSTATE, 16)
    a_pv, _, at = read_record(body, at, ACCEL, 16)
    assert at == len(body)
    return {
        "sync": (sec, nsec_),
        "global": g,
        "globalPv": g_pv,
        "localPv": l_pv,
        "tag": tag,
        "ned": n,
        "nedPv": n_pv,
        "state": v,
        "statePv": v_pv,
        "accelPv": a_pv,
    }


def ask(sock: socket.socket, port: int, packet: bytes) -> bytes:
    sock.sendto(packet, ("127.0.0.1", port))
    return sock.recvfrom(65536)[0]


@pytest.fixture
def station() -> Any:
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    # in the DDS gaps of this worker, as the gateway's port: an ephemeral port (32768 up) can be a DDS port of a domain
    # id from 102 up, and the station then received that domain's RTPS datagrams (seen once in CI: 'RT' as a version)
    s.bind(("127.0.0.1", free_udp_port()))
    s.settimeout(5)
    yield s
    s.close()


def test_jaus_report_navigation_matches_the_simulator(sim, console, consumer, station) -> None:
    port = free_udp_port()  # a UDP port in the DDS gaps of this worker, not an ephemeral one
    sim("--vehicles", "1")
    c = console("--jaus-port", str(port), "--jaus-subsystem", "42")
    surface(c.url)
    assert http.get(f"{c.url}/api/providers/{V1}").json()["jausId"] == "42.1.1"
    me = (1, 1, 42)  # component, node, subsystem
    collect(consumer, 0.5)
    everything = struct.pack("<HHHH", 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF)
    checked = 0
    for _ in range(20):
        consumer.pump()
        dest, src, message_id, body = unjudp(ask(station, port, judp(me, 0x2421, everything)))
        assert (dest, src, message_id) == (ME, me, 0x4421)
        nav = decode_navigation(body)
        assert nav["globalPv"] == sum(
            1 << GLOBAL.index(k) for k in ("Latitude", "Longitude", "AltitudeMSL", "Course", "TimeSeconds", "TimeNanoSeconds")
        )
        assert nav["localPv"] == 0 and nav["accelPv"] == 0 and nav["tag"] == 2 and nav["nedPv"] == 0b111
        assert nav["statePv"] == sum(1 << VSTATE.index(k) for k in ("SpeedOverGround", "TimeSeconds", "TimeNanoSeconds"))
        g, t = nav["global"], int(nav["global"]["TimeSeconds"]) * 10**9 + int(nav["global"]["TimeNanoSeconds"])
        r = next((x for x in consumer.reports[Sem.GPS_FIX_REPORT][uuid.UUID(V1)] if nsec(x) == t), None)
        time.sleep(0.05)
        if r is None:
            continue
        checked += 1
        assert nav["sync"] == (r.timeStamp.seconds, r.timeStamp.nanoseconds)
        pos = r.position2DWithTime.geodeticPosition
        assert abs(g["Latitude"] - pos.geodeticLatitude.latitude) <= step("Latitude")
        assert abs(g["Longitude"] - pos.geodeticLongitude.longitude) <= step("Longitude")
        assert abs(g["AltitudeMSL"] - r.altitudeMSL.altitude) <= step("AltitudeMSL")
        course = (r.trueCourse + math.pi) % (2 * math.pi) - math.pi
        assert abs(g["Course"] - course) <= step("Course")
        for name, want in zip(NED, (r.velocity.northSpeed, r.velocity.eastSpeed, r.velocity.downSpeed), strict=True):
            assert abs(nav["ned"][name] - want) <= step(name)
        assert abs(nav["state"]["SpeedOverGround"] - r.SOG) <= step("SpeedOverGround")
    assert checked >= 3
    # only what is asked for: latitude alone
    nav = decode_navigation(unjudp(ask(station, port, judp(me, 0x2421, struct.pack("<HHHH", 1, 0, 0, 0))))[3])
    assert nav["globalPv"] == 1 and set(nav["global"]) == {"Latitude"} and nav["nedPv"] == 0 and nav["statePv"] == 0
    state = {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}["jaus"]
    assert state["enabled"] and state["messagesOut"] >= 21 and state["counters"]["received"] >= 21
    assert state["endpoint"] == f"udp://127.0.0.1:{port} subsystem 42"
    ws = WsClient(c.ws_url)  # every message checked against the published schema
    wait_until(lambda: ws.messages, 5, "the snapshot")
    assert {g["name"]: g["enabled"] for g in ws.messages[0]["gateways"]} == {"aspn": False, "jaus": True, "foxglove": False}
    ask(station, port, judp(me, 0x2421, everything))

    # a gateways message sent before the answer (at most one a second) may still carry the old count: wait for the
    # one that counts the answer
    def jaus_out(m: dict[str, Any]) -> int:
        return int(next(g for g in m["gateways"] if g["name"] == "jaus")["messagesOut"])

    wait_until(
        lambda: [m for m in ws.of("gateways") if jaus_out(m) > state["messagesOut"]], 5, "a gateways message counting the answer"
    )
    assert ws.errors == []
    ws.close()


def test_jaus_comms_lost_configuration_follows_the_api(sim, console, station) -> None:
    port = free_udp_port()  # a UDP port in the DDS gaps of this worker, not an ephemeral one
    sim("--vehicles", "1")
    c = console("--jaus-port", str(port), "--jaus-subsystem", "42", "--operator-tokens", "alice:secret-1")
    provider_ready(c.url, V1, {"GPSFixReport"})
    me = (1, 1, 42)

    def config() -> tuple[int, ...]:
        dest, src, message_id, body = unjudp(ask(station, port, judp(me, 0x2C03, b"")))
        assert (dest, src, message_id) == (ME, me, 0x4C03) and len(body) == 7
        return struct.unpack("<HBBHB", body)  # lost timeout, policy tag, its u8, regained timeout, regained behaviour

    assert config() == (1, 0, 1, 1, 0)  # the console's --comms-lost-timeout 1 --regained-time 1, StopMission
    body = {"commsLostTimeout": 7.5, "regainedTime": 2, "policy": "CONTINUE_MISSION", "regainedBehavior": 3}
    url = f"{c.url}/api/providers/{V1}/link-config"
    assert http.put(url, json=body).status_code == 401
    assert (
        http.put(url, content="{}", headers={"Authorization": "Bearer secret-1", "Content-Type": "text/plain"}).status_code == 415
    )
    bad = http.put(url, json={**body, "policy": "RETROTRAVERSE"}, headers={"Authorization": "Bearer secret-1"})
    assert bad.status_code == 422 and "policy" in bad.json()["detail"]
    r = http.put(url, json=body, headers={"Authorization": "Bearer secret-1"})
    assert r.status_code == 200 and r.json() == {**body, "regainedTime": 2.0}
    assert config() == (8, 1, 1, 2, 3)  # 7.5 s rounded up to whole seconds
    assert http.get(f"{c.url}/api/providers/{V1}").json()["linkConfig"] == {**body, "regainedTime": 2.0}
    audit = http.get(f"{c.url}/api/audit").json()
    assert any(a["path"].endswith("/link-config") and a["outcome"] == "accepted" and a["operator"] == "alice" for a in audit)
    # a command route of the auditor: the refused attempts are in the audit too (no token, not JSON, a bad body)
    assert {401, 415, 422} <= {a["status"] for a in audit if a["path"].endswith("/link-config") and a["outcome"] == "refused"}
    c.stop()
    again = console("--jaus-port", str(port), "--jaus-subsystem", "42", "--operator-tokens", "alice:secret-1")
    provider_ready(again.url, V1, {"GPSFixReport"})
    assert http.get(f"{again.url}/api/providers/{V1}").json()["linkConfig"] == {**body, "regainedTime": 2.0}
    assert config() == (8, 1, 1, 2, 3)  # kept in the database


def test_jaus_answers_every_message_of_a_packed_datagram(sim, console, station) -> None:
    """AS5669A lets a station pack several messages after one version byte (JUDP stacks that batch their sends do):
    the gateway took the datagram's size for one message's, counted it `malformed: wrong size` and answered nothing."""
    port = free_udp_port()  # a UDP port in the DDS gaps of this worker, not an ephemeral one
    sim("--vehicles", "1")
    c = console("--jaus-port", str(port), "--jaus-subsystem", "42")
    provider_ready(c.url, V1, {"GPSFixReport"})
    me = (1, 1, 42)
    packed = (
        b"\x02"
        + judp(me, 0x2421, struct.pack("<HHHH", 1, 0, 0, 0))[1:]
        + judp(me, 0x2C03, b"", seq=2)[1:]
        + judp((9, 1, 42), 0x2C03, b"", seq=3)[1:]
    )  # the third for a component no vehicle has
    station.sendto(packed, ("127.0.0.1", port))
    answers = [unjudp(station.recvfrom(65536)[0]) for _ in range(2)]
    assert [(dest, src, message_id) for dest, src, message_id, _ in answers] == [(ME, me, 0x4421), (ME, me, 0x4C03)]
    state = wait_until(
        lambda: (lambda s: s if s["messagesOut"] == 2 else None)(
            {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}["jaus"]
        ),
        5,
        "both answers counted",
    )
    assert state["counters"] == {"received": 1, "malformed": 1, "malformed: no such component": 1}


def test_jaus_malformed_input_is_counted_and_dropped(sim, console, station) -> None:
    port = free_udp_port()  # a UDP port in the DDS gaps of this worker, not an ephemeral one
    sim("--vehicles", "1")
    c = console("--jaus-port", str(port), "--jaus-subsystem", "42")
    provider_ready(c.url, V1, {"GPSFixReport"})
    me = (1, 1, 42)
    query = judp(me, 0x2421, struct.pack("<HHHH", 1, 0, 0, 0))
    bad = [
        b"",
        b"\x02",
        query[:10],
        b"\x01" + query[1:],
        query[:1] + b"\x01" + query[2:],
        query + b"\x00",
        query[:-3] + query[-2:],
        judp(me, 0x2421, b"\x00\x00"),
        judp((2, 1, 42), 0x2421, b"\0" * 8),
        judp((1, 1, 43), 0x2C03, b""),
        judp(me, 0x2C03, b"x"),
        judp(me, 0x2421, b"\0" * 8, flags=0x40),
    ]
    rng = random.Random(13)
    bad += [bytes(rng.randrange(256) for _ in range(rng.randrange(0, 80))) for _ in range(200)]
    bad += [bytearray(query) for _ in range(100)]
    for b in bad[-100:]:  # a valid query with one byte flipped in its header
        i = rng.randrange(0, 15)
        b[i] ^= 1 << rng.randrange(8)
    sent_bad = 0
    for b in bad:
        station.sendto(bytes(b), ("127.0.0.1", port))
        sent_bad += 1
        if sent_bad % 10 == 0:
            time.sleep(0.02)  # UDP: a burst beyond the socket's buffer would be lost in the kernel, uncounted
    # everything above is dropped, never answered; a good query still is
    station.settimeout(0.5)
    got = []
    with pytest.raises(socket.timeout):
        while True:
            got.append(station.recvfrom(65536)[0])
    # a flipped bit of flags' priority or broadcast bits leaves a valid query: those are answered
    answered = len(got)
    assert all(unjudp(g)[2] == 0x4421 for g in got)
    station.settimeout(5)
    assert unjudp(ask(station, port, query))[2] == 0x4421
    state = wait_until(
        lambda: (lambda s: s if s["counters"].get("received", 0) >= sent_bad + 1 else None)(
            {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}["jaus"]
        ),
        5,
        "every datagram counted",
    )
    counters = state["counters"]
    assert counters["received"] == sent_bad + 1
    unsupported = counters.get("unsupported message id", 0)  # a bit flipped in a message id: legal, not answered
    assert counters["malformed"] + unsupported == sent_bad - answered
    for reason in (
        "short",
        "wrong version",
        "header compression",
        "wrong size",
        "wrong body size",
        "no such component",
        "multi-packet",
    ):
        assert counters[f"malformed: {reason}"] >= 1, reason
    assert http.get(f"{c.url}/api/health").status_code == 200
    # a legal JAUS message the gateway does not answer (QueryIdentification, QueryServices) is not malformed
    for message_id in (0x2B00, 0x2B03):
        station.sendto(judp(me, message_id, b"\x02" if message_id == 0x2B00 else b""), ("127.0.0.1", port))
    after = wait_until(
        lambda: (lambda s: s if s.get("unsupported message id") == unsupported + 2 else None)(
            {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}["jaus"]["counters"]
        ),
        5,
        "both counted",
    )
    assert after["malformed"] == counters["malformed"]


class _HeldLcm:
    """An LCM whose publish waits until the test lets it go: a slow network or a full disk."""

    def __init__(self, inner: lcm.LCM) -> None:
        self.inner, self.go, self.channels = inner, threading.Event(), []

    def publish(self, channel: str, data: bytes) -> None:
        self.go.wait(30)
        self.inner.publish(channel, data)
        self.channels.append(channel)


def _speed_report(vehicle: uuid.UUID, seconds: int) -> dict[str, Any]:
    # GPSLatLongValid: a surfaced vehicle's fix (a submerged one's, the INS's solution, sends nothing)
    report = {"timeStamp": {"seconds": seconds, "nanoseconds": 0}, "SOG": float(seconds), "GPSLatLongValid": True}
    return {"type": "report", "topic": "GPSFixReport", "providerId": str(vehicle), "report": {"report": report, "invalid": []}}


def test_a_slow_aspn_gateway_never_stalls_the_feed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from sem_console.console.feed import Feed
    from sem_console.gateways.aspn import gateway as aspn

    monkeypatch.setattr(aspn, "QUEUE_SIZE", 5)
    feed = Feed()
    gw = aspn.AspnGateway(feed, f"file://{tmp_path / 'aspn.lcm'}")
    held = _HeldLcm(gw.lcm)
    gw.lcm = held  # type: ignore[assignment]
    vehicle = uuid.uuid4()
    try:
        for second in range(1, 21):  # with publish on the loop this would hang on the first report
            feed.publish(_speed_report(vehicle, second))
        counters = gw.state()["counters"]
        assert feed.errors == {}
        # one report taken by the held worker, five waiting, the rest dropped and counted
        assert 14 <= counters["dropped: queue full"] <= 15
        held.go.set()
        kept = wait_until(
            lambda: (lambda e: e if len(e) == 20 - counters["dropped: queue full"] else None)(gw.events(vehicle)),
            10,
            "the queued reports published",
        )
        speeds = [aspn23_lcm.measurement_speed.decode(data).speed for _, _, data in kept]
        assert speeds == sorted(speeds) and speeds[0] == 1.0  # in arrival order
        assert len(held.channels) == len(kept) and gw.state()["messagesOut"] == len(kept)
    finally:
        held.go.set()
        gw.close()


def test_aspn_vehicles_whose_guids_share_their_first_half_stay_apart() -> None:
    """GUIDs given by hand or by a counter share their first 64 bits: with those as the channel's vehicle part and the
    device_id, two such vehicles were one device on one channel to an LCM listener (sequence ids interleaved)."""
    from sem_console.console.feed import Feed
    from sem_console.gateways.aspn.gateway import AspnGateway

    url = f"udpm://239.255.76.67:{free_udp_port()}?ttl=0"
    got: list[tuple[str, Any]] = []
    listener = lcm.LCM(url)
    listener.subscribe("aspn23/.*", lambda ch, data: got.append((ch, aspn23_lcm.measurement_speed.decode(data))))
    feed = Feed()
    gw = AspnGateway(feed, url)
    v1, v2 = uuid.UUID(int=1), uuid.UUID(int=2)
    try:
        feed.publish(_speed_report(v1, 1))
        feed.publish(_speed_report(v2, 2))
        deadline = time.monotonic() + 10
        while len(got) < 2 and time.monotonic() < deadline:
            listener.handle_timeout(100)
    finally:
        gw.close()
    by_speed = {m.speed: (ch, m.header.device_id, m.header.sequence_id) for ch, m in got}
    assert by_speed == {
        1.0: (f"aspn23/{lcm_vehicle(str(v1))}/measurement_speed", int(lcm_vehicle(str(v1)), 16) >> 1, 0),
        2.0: (f"aspn23/{lcm_vehicle(str(v2))}/measurement_speed", int(lcm_vehicle(str(v2)), 16) >> 1, 0),
    }


def test_aspn_file_log_survives_a_restart(tmp_path: Path) -> None:
    from sem_console.console.feed import Feed
    from sem_console.gateways.aspn.gateway import AspnGateway, check_url

    log_file = tmp_path / "aspn.lcm"
    vehicle = uuid.uuid4()
    for run in (1, 2):  # two console runs on the same file:// URL
        feed = Feed()
        gw = AspnGateway(feed, f"file://{log_file}")
        feed.publish(_speed_report(vehicle, run))
        wait_until(lambda gw=gw: gw.state()["messagesOut"] == 1 or None, 10, "the report published")
        gw.close()
    speeds = [m.speed for _, m in read_log(log_file)]
    assert speeds == [1.0, 2.0]  # the first run's message is still there
    check_url(f"file://{log_file}")  # an existing, writable log passes the start check
    with pytest.raises(RuntimeError):
        check_url(f"file://{tmp_path}/no/such/dir/x.lcm")
    with pytest.raises(RuntimeError):
        check_url(f"file://{tmp_path}")
    with pytest.raises(RuntimeError, match=r"on the line above\): give e.g. udpm://"):  # liblcm's reason is on stderr
        check_url("bogus://x")


def test_aspn_kept_messages_are_bounded_in_memory_and_forgotten_when_quiet(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import sys

    from sem_console.console.feed import Feed
    from sem_console.gateways.aspn import gateway as aspn

    monkeypatch.setattr(aspn, "MAX_LOG_BYTES", 20_000)
    feed = Feed()
    gw = aspn.AspnGateway(feed, "memq://", log_seconds=1.0)
    v1, v2 = uuid.uuid4(), uuid.uuid4()
    try:
        for second in range(1, 401):
            feed.publish(_speed_report(v1, second))
        wait_until(lambda: gw.state()["messagesOut"] == 400 or None, 20, "the reports published")
        with gw._lock:
            rec = gw.recordings[v1]
            events = list(rec.events)
            # what the events really take (tuple, int, bytes object, deque slot) is inside what was counted
            real = sum(sys.getsizeof(e) + sys.getsizeof(e[0]) + sys.getsizeof(e[2]) + 8 for e in events)
            assert real <= rec.size == sum(len(e[2]) + aspn.EVENT_OVERHEAD for e in events) <= aspn.MAX_LOG_BYTES
            assert 0 < len(events) < 400  # the byte bound, not the window, let the oldest go
            assert len({id(e[1]) for e in events}) == 1  # the stream's channel string held once
        time.sleep(1.2)  # v1 quiet for longer than the kept window
        feed.publish(_speed_report(v2, 1))
        wait_until(lambda: gw.state()["messagesOut"] == 401 or None, 10, "v2's report published")
        assert gw.events(v1) == [] and v1 not in gw.recordings and len(gw.events(v2)) == 1
    finally:
        gw.close()


def test_jaus_sync_time_never_wraps(monkeypatch: pytest.MonkeyPatch) -> None:
    from sem_console.console.feed import Feed
    from sem_console.gateways.jaus.gateway import JausGateway, report_navigation
    from sem_console.gateways.jaus.judp import parse

    everything = (0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF)
    now = 1_700_000_000.25

    def fix(seconds: int) -> dict[str, Any]:
        return {"report": {"timeStamp": {"seconds": seconds, "nanoseconds": 7}, "SOG": 1.0}, "invalid": []}

    body, unfit = report_navigation(fix(1_600_000_000), everything, now)
    assert decode_navigation(body)["sync"] == (1_600_000_000, 7) and not unfit
    for bad in (2**32 + 5, -1):  # wrapped, 2**32 + 5 would read as 5 s after 1970: the console's time instead
        body, unfit = report_navigation(fix(bad), everything, now)
        nav = decode_navigation(body)
        assert nav["sync"] == (1_700_000_000, 250_000_000) and unfit
        assert "TimeSeconds" not in nav["global"]  # the records leave the unfit time out, as before
    body, unfit = report_navigation(None, everything, now)
    assert decode_navigation(body)["sync"] == (1_700_000_000, 250_000_000) and not unfit
    gw = JausGateway(Feed(), 1, 42)  # answer() alone: no socket is opened without start()
    vehicle = uuid.uuid4()
    gw.vehicles[1], gw.fixes[vehicle] = vehicle, fix(2**32 + 5)
    gw.answer(parse(judp((1, 1, 42), 0x2421, struct.pack("<HHHH", *everything)))[0])
    assert gw.stats.counters["report time outside u32: console time sent"] == 1
    gw.close()


def test_stored_link_configs_are_validated(caplog: pytest.LogCaptureFixture) -> None:
    from sem_console.console.service import stored_link_configs
    from sem_console.core.contract import LinkConfig

    good = {"commsLostTimeout": 2.5, "regainedTime": 1, "policy": "CONTINUE_MISSION", "regainedBehavior": 3}
    rows = {
        "a": good,
        "old": {"commsLostTimeout": 4, "regainedTime": 2},  # a row from before the policy: its defaults
        "negative": {**good, "commsLostTimeout": -1},
        "nan": {**good, "regainedTime": float("nan")},
        "text": {**good, "commsLostTimeout": "5"},
        "policy": {**good, "policy": "EXPLODE"},
        "extra": {**good, "colour": "red"},
        "list": [1, 2],
        "not json": "{oops",
    }
    with caplog.at_level("WARNING", logger="sem-console"):
        configs = stored_link_configs(rows)
    assert configs == {
        "a": LinkConfig(commsLostTimeout=2.5, regainedTime=1.0, policy="CONTINUE_MISSION", regainedBehavior=3),
        "old": LinkConfig(commsLostTimeout=4.0, regainedTime=2.0, policy="STOP_MISSION", regainedBehavior=0),
    }
    warnings = [r for r in caplog.records if r.levelname == "WARNING"]
    assert len(warnings) == 1 and all(
        k in warnings[0].getMessage() for k in ("negative", "nan", "text", "policy", "extra", "list", "not json")
    )


def global_pose(vehicle: uuid.UUID, stamp: Any) -> Any:
    """A UMAA 6.0 vehicle's GlobalPose at 36.85 N 75.98 W, at `stamp` (its DateTime's seconds and nanoseconds): course
    4.2, yaw 4.0, depth 3.5, altitude ASF 12, a horizontal position covariance of north 16 and east 9, no down."""
    from UMAA_6_0.Common import IdentifierType
    from UMAA_6_0.Common.MaritimeEnumeration.NavigationSolutionEnumModule import NavigationSolutionEnumType
    from UMAA_6_0.Common.Measurement import CovariancePositionNEDType, DateTime, GeoPosition2D
    from UMAA_6_0.Common.Orientation import Orientation3DNEDType, PitchYNEDType, RollXNEDType, YawZNEDType
    from UMAA_6_0.SA.GlobalPoseStatus import GlobalPoseReportType

    return GlobalPoseReportType(
        altitude=None,
        altitudeAGL=None,
        altitudeASF=12.0,
        altitudeGeodetic=None,
        attitude=Orientation3DNEDType(pitch=PitchYNEDType(0.05), roll=RollXNEDType(-0.1), yaw=YawZNEDType(4.0)),
        attitudeCovariance=None,
        course=4.2,
        depth=3.5,
        navigationSolution=NavigationSolutionEnumType.MEASURED,
        position=GeoPosition2D(geodeticLatitude=36.85, geodeticLongitude=-75.98),
        positionCovariance=CovariancePositionNEDType(pdPd=None, pePd=None, pePe=9.0, pnPd=None, pnPe=None, pnPn=16.0),
        timeStamp=DateTime(seconds=stamp.seconds, nanoseconds=stamp.nanoseconds),
        source=IdentifierType(id=to_guid(vehicle), parentID=bytes(16)),
    )


def test_a_6_0_vehicles_global_pose_comes_out_of_both_gateways(console, domain: int, station, tmp_path: Path) -> None:
    """A UMAA 6.0 vehicle's GlobalPose reaches the gateways through the console's one model, as a 3.0.1 vehicle's
    GPSFixReport does: ASPN-23's position and direction of motion; JAUS's ReportNavigation with the position, course,
    attitude, depth and horizontal position error 6.0 adds. Written with the 3.0.1 ICD's report QoS (reliable,
    transient-local), which the console's 6.0 readers match as they match RTI's best-effort writers (sem-sim)."""
    from sem_console.dds.topics import Sem60

    port = free_udp_port()
    c = console("--aspn-lcm", f"file://{tmp_path / 'aspn.lcm'}", "--jaus-port", str(port), "--jaus-subsystem", "42")
    bus = Consumer(domain, name="a-6.0-vehicle").bus
    vehicle = uuid.uuid4()
    stamp = now_datetime()
    pose = global_pose(vehicle, stamp)
    writer = bus.writer(Sem60.GLOBAL_POSE_REPORT)  # alive until the test ends
    writer.write(pose)
    detail = provider_ready(c.url, str(vehicle), {"GPSFixReport"})
    assert detail["umaaVersion"] == "6.0"

    def log() -> dict[str, Any] | None:
        r = http.get(f"{c.url}/api/providers/{vehicle}/aspn-log")
        if r.status_code != 200 or not r.content:
            return None
        (tmp_path / "got.lcm").write_bytes(r.content)
        got = {ch.rsplit("/", 1)[1]: m for ch, m in read_log(tmp_path / "got.lcm")}
        return got if "measurement_position" in got else None

    got = wait_until(log, 10, "the 6.0 vehicle's ASPN position")
    position = got["measurement_position"]
    assert (position.term1, position.term2) == (math.radians(36.85), math.radians(-75.98))
    assert position.time_of_validity.elapsed_nsec == stamp.seconds * 10**9 + stamp.nanoseconds
    assert got["measurement_direction_of_motion_2d"].obs == 4.2
    assert "measurement_speed" not in got and "measurement_velocity" not in got  # GlobalPose has none: nothing made up
    # ... and counted as not reported, not as invalid
    counters = {g["name"]: g for g in http.get(f"{c.url}/api/gateways").json()}["aspn"]["counters"]
    assert counters["left out: speed: SOG not reported"] >= 1 and counters["left out: velocity: not reported"] >= 1
    assert counters["left out: altitude: not reported"] >= 1 and not any(k.endswith("invalid") for k in counters)

    me = (1, 1, 42)
    nav = decode_navigation(unjudp(ask(station, port, judp(me, 0x2421, struct.pack("<HHHH", 0xFFFF, 0, 0xFFFF, 0))))[3])
    g = nav["global"]
    assert set(g) == {
        "Latitude",
        "Longitude",
        "AltitudeASF",
        "Depth",
        "XYPositionRMS",
        "Roll",
        "Pitch",
        "Heading",
        "Course",
        "TimeSeconds",
        "TimeNanoSeconds",
    }
    assert abs(g["Latitude"] - 36.85) <= step("Latitude") and abs(g["Longitude"] + 75.98) <= step("Longitude")
    assert abs(g["Depth"] - 3.5) <= step("Depth") and abs(g["AltitudeASF"] - 12.0) <= step("AltitudeASF")
    assert abs(g["XYPositionRMS"] - 5.0) <= step("XYPositionRMS")  # sqrt(16 + 9)
    assert abs(g["Roll"] + 0.1) <= step("Roll") and abs(g["Pitch"] - 0.05) <= step("Pitch")
    assert abs(g["Heading"] - (4.0 - 2 * math.pi)) <= step("Heading") and abs(g["Course"] - (4.2 - 2 * math.pi)) <= step("Course")
    assert nav["statePv"] == sum(1 << VSTATE.index(k) for k in ("TimeSeconds", "TimeNanoSeconds"))  # no speed reported
