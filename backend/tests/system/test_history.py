"""Track and chart history in the console's database, and the GPX and CSV exports: a real `sem-console`
and `sem-sim` over DDS on loopback."""

from __future__ import annotations

import csv
import io
import itertools
import math
import signal
import time
import uuid
from collections import Counter
from collections.abc import Callable
from datetime import UTC, datetime
from typing import Any

import gpxpy
import pytest

from sem_console.comap.geo import Local
from sem_console.dds.bus import Bus
from sem_console.dds.topics import Sem
from sem_console.umaa.guid import to_guid
from sem_console.umaa.samples import now_datetime
from support import http
from test_console import HAPPY, V1, V2, _valid_fix, command, provider_ready, wait_command, wait_until

UNTHINNED = ("--track-thin-metres", "0", "--track-thin-seconds", "0")  # every second's track point stored
TRACK_HEADER = [
    "time_utc",
    "latitude_deg",
    "longitude_deg",
    "altitude_msl_m",
    "course_deg",
    "sog_mps",
    "fix_valid",
    "gps_lat_long_valid",
    "position_time_utc",
    "umaa_version",
]


def iso(t: float) -> str:
    return datetime.fromtimestamp(t, UTC).isoformat().replace("+00:00", "Z")


def parse_utc(s: str) -> float:
    assert s.endswith("Z"), s
    return datetime.fromisoformat(s).timestamp()


def get(base: str, path: str, **params: Any) -> Any:
    r = http.get(base + path, params=params)
    assert r.status_code == 200, r.text
    return r.json()


def at_most_one_per_second(points: list[dict[str, Any]]) -> None:
    times = [p["time"] for p in points]
    assert times == sorted(times) and len(set(times)) == len(times)
    seconds = [math.floor(t) for t in times]
    assert len(set(seconds)) == len(seconds), "two points in one UTC second"  # so over n seconds, at most n + 1


@pytest.mark.slow
def test_track_and_series_at_most_1_hz_survive_a_restart(sim, console) -> None:
    vehicle = sim("--vehicles", "2")  # GPSFixReport at 10 Hz, GPSReport at 4 Hz (conftest FAST)
    first = console(*UNTHINNED)
    provider_ready(first.url, V1)
    start = time.time()
    wait_until(lambda: len(get(first.url, f"/api/providers/{V1}/track")) >= 6, 20, "six track points")
    track = get(first.url, f"/api/providers/{V1}/track")
    series = get(first.url, f"/api/providers/{V1}/series")
    at_most_one_per_second(track)
    at_most_one_per_second(series)
    assert len(series) >= 4
    latest = get(first.url, f"/api/providers/{V1}")["reports"]
    p = track[-1]
    assert p["providerId"] == V1 and -90 <= p["latitude"] <= 90 and -180 <= p["longitude"] <= 180
    assert 0 <= p["course"] < 360 and p["sog"] >= 0 and isinstance(p["latLongValid"], bool)
    assert p["altitudeMsl"] == latest["GPSFixReport"]["report"]["altitudeMSL"]["altitude"]
    assert p["fixValid"] is False  # submerged: no fix yet
    assert abs(p["positionTime"] - p["time"]) < 5 and p["time"] >= start - 5
    s = series[-1]
    assert s["satellitesInView"] == latest["GPSReport"]["report"]["numberSatellitesInView"] >= 20
    assert s["satellitesUsed"] == 0 and 0 < s["cn0Mean"] < 60  # submerged: nothing used in the fix
    # per vehicle, and a time range selects
    assert {x["providerId"] for x in get(first.url, f"/api/providers/{V2}/track")} == {V2}
    middle = get(first.url, f"/api/providers/{V1}/track", since=iso(track[1]["time"] - 1e-3), until=iso(track[-2]["time"] + 1e-3))
    assert [x["time"] for x in middle] == [x["time"] for x in track[1:-1]]
    assert get(first.url, f"/api/providers/{V1}/track", since=iso(track[-1]["time"]), until=iso(track[0]["time"])) == []

    first.stop(signal.SIGINT)
    vehicle.stop()
    second = console(*UNTHINNED)  # the vehicles are gone: the track is still there
    again = get(second.url, f"/api/providers/{V1}/track")
    assert [x["time"] for x in again[: len(track)]] == [x["time"] for x in track]
    assert again[: len(track)] == track
    assert len(get(second.url, f"/api/providers/{V1}/series")) >= len(series)


def off_path(p: tuple[float, float], path: list[tuple[float, float]]) -> float:
    """Metres from p to the nearest segment of the polyline `path` (local x, y in metres)."""

    def to_segment(a: tuple[float, float], b: tuple[float, float]) -> float:
        dx, dy = b[0] - a[0], b[1] - a[1]
        k = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy or 1.0)))
        return math.hypot(p[0] - a[0] - k * dx, p[1] - a[1] - k * dy)

    return min(to_segment(a, b) for a, b in itertools.pairwise([path[0], *path]))


def test_the_track_keeps_a_moving_vehicles_turn_and_drops_a_stationary_vehicles_repeats(
    console, new_bus: Callable[[int], Bus], domain: int
) -> None:
    c = console("--track-thin-metres", "5", "--track-thin-seconds", "6")
    writer = new_bus(domain).writer(Sem.GPS_FIX_REPORT)
    moving, still = uuid.uuid4(), uuid.uuid4()
    origin = Local(10.0, 20.0)

    def write(vehicle: uuid.UUID, x: float, y: float, valid: bool = True) -> None:
        fix = _valid_fix()
        lat, lon = origin.latlon(x, y)
        fix.position2DWithTime.geodeticPosition.geodeticLatitude.latitude = lat
        fix.position2DWithTime.geodeticPosition.geodeticLongitude.longitude = lon
        fix.GPSLatLongValid, fix.source, fix.timeStamp = valid, to_guid(vehicle), now_datetime()
        writer.write(fix)

    def listed() -> bool:
        for v in (moving, still):
            write(v, 0.0, 0.0)
        time.sleep(0.2)
        return all(http.get(f"{c.url}/api/providers/{v}").status_code == 200 for v in (moving, still))

    wait_until(listed, 20, "both vehicles listed")
    # one report a second, each in a second of its own: 2 m/s east for 8 s, a right angle, 2 m/s north for 8 s; the
    # other vehicle stays put, one report of it from the INS (GPSLatLongValid false)
    path = [(2.0 * k, 0.0) if k <= 8 else (16.0, 2.0 * (k - 8)) for k in range(17)]
    start = math.floor(time.time()) + 1.5
    for k, (x, y) in enumerate(path):
        time.sleep(max(0.0, start + k - time.time()))
        write(moving, x, y)
        write(still, 0.0, 0.0, valid=k != 9)
    end = time.time()

    track = get(c.url, f"/api/providers/{moving}/track")
    stored = [origin.xy(p["latitude"], p["longitude"]) for p in track]
    assert 4 <= len(stored) < len(path) / 2, stored  # one in 2.5 s at 2 m/s, not every second's
    assert all(math.dist(a, b) >= 5 - 1e-6 for a, b in itertools.pairwise(stored[-7:])), stored  # the path: 5 m apart
    assert max(off_path(p, stored) for p in path[:-1]) <= 5.0, stored  # the turn too: no report's position 5 m off
    assert min(math.dist((16.0, 0.0), p) for p in stored) <= 5.0, stored

    here = get(c.url, f"/api/providers/{still}/track")
    assert {(round(p["latitude"], 9), round(p["longitude"], 9)) for p in here} == {(10.0, 20.0)}
    times = [p["time"] for p in here if p["time"] >= start - 1]
    assert len(times) <= math.ceil((end - start) / 6) + 3, times  # every 6 s and the change there and back
    from_ins = [i for i, p in enumerate(here) if not p["latLongValid"]]
    assert len(from_ins) == 1 and here[from_ins[0] + 1]["latLongValid"], here  # each change kept at once
    assert here[from_ins[0] + 1]["time"] - here[from_ins[0]]["time"] < 1.5 and abs(here[from_ins[0]]["time"] - start - 9) < 1


def test_old_history_is_rolled_up_to_one_point_per_interval_and_commands_audit_and_alarms_are_not(
    sim, console, database_url: str
) -> None:
    sim("--fault", "ins-failure")  # an alarm per vehicle, and no position from the INS: a track once surfaced
    c = console(
        "--database-url",
        database_url,
        *("--track-thin-metres", "0", "--track-thin-seconds", "0"),  # every second's point: 3 in an interval
        *("--track-rollup-after-hours", "0.002", "--track-rollup-seconds", "3"),  # older than 7.2 s: 1 in 3 s
    )
    provider_ready(c.url, V1, {"GPSFixReport", "GPSReport"})
    session = http.post(f"{c.url}/api/providers/{V1}/gps-fix", json={}).json()["sessionId"]
    wait_command(c.url, session)
    alarms = wait_until(lambda: get(c.url, "/api/alarms"), 20, "an alarm")
    start = time.time()
    wait_until(lambda: time.time() - start > 24 and get(c.url, "/api/metrics")["historyRowsRolledUp"] > 0, 30, "a rollup")
    now = time.time()
    for kind in ("track", "series"):
        points = get(c.url, f"/api/providers/{V1}/{kind}")
        # a track point whose GPSLatLongValid or fixValid differs from the one before is kept besides (fixValid is
        # null until the first GPSFixStatusReport)
        changed = {
            b["time"]
            for a, b in itertools.pairwise(points)
            if kind == "track" and (a["latLongValid"], a["fixValid"]) != (b["latLongValid"], b["fixValid"])
        }
        aged = [p for p in points if p["time"] < now - 7.2 - 3 - 2.8]  # the rollup's lag
        old = Counter(math.floor(p["time"] / 3) for p in aged if p["time"] not in changed)
        recent = Counter(math.floor(p["time"] / 3) for p in points if p["time"] > now - 6)
        assert len(old) >= 3 and set(old.values()) == {1}, (kind, old)
        intervals = sorted({math.floor(p["time"] / 3) for p in aged})
        assert intervals == list(range(intervals[0], intervals[-1] + 1)), (kind, old)  # not one left without its point
        assert max(recent.values()) >= 2, (kind, recent)  # the last 7.2 s as written: one a second
    assert [t["status"] for t in command(c.url, session)["transitions"]] == HAPPY
    assert [a["id"] for a in get(c.url, "/api/alarms")] == [a["id"] for a in alarms]
    assert any(x.get("sessionId") == session for x in get(c.url, "/api/audit"))


def test_retention_prunes_old_points(sim, console) -> None:
    sim()
    c = console("--track-retention-hours", "0.0005", *UNTHINNED)  # 1.8 s, pruned every second
    provider_ready(c.url, V1)
    wait_until(lambda: get(c.url, "/api/metrics")["historyRowsPruned"] >= 4, 20, "pruned points")
    oldest = get(c.url, f"/api/providers/{V1}/track")[0]["time"]
    assert time.time() - oldest < 1.8 + 2.5  # the retention, plus up to a flush and a prune interval
    assert time.time() - get(c.url, f"/api/providers/{V1}/series")[0]["time"] < 1.8 + 2.5


def test_gpx_and_csv_exports_of_the_track(sim, console) -> None:
    sim()
    c = console()
    provider_ready(c.url, V1)
    wait_until(lambda: len(get(c.url, f"/api/providers/{V1}/track")) >= 5, 20, "five track points")
    until = iso(time.time() - 0.01)
    track = get(c.url, f"/api/providers/{V1}/track", until=until)

    r = http.get(f"{c.url}/api/providers/{V1}/track.gpx", params={"until": until})
    assert r.status_code == 200 and r.headers["content-type"] == "application/gpx+xml"
    assert r.headers["content-disposition"].startswith("attachment; filename=")
    gpx = gpxpy.parse(r.text)
    assert gpx.version == "1.1" and len(gpx.tracks) == 1 and len(gpx.tracks[0].segments) == 1
    assert gpx.tracks[0].description.startswith("a UMAA 3.0.1 vehicle; ")
    points = gpx.tracks[0].segments[0].points
    assert len(points) == len(track)
    times = [p.time.timestamp() for p in points]
    assert len(times) >= 3 and all(a < b for a, b in itertools.pairwise(times))  # in time order, one per instant
    assert len({math.floor(t) for t in times}) == len(times)  # at most one a second (1 Hz)
    assert len({(p.latitude, p.longitude) for p in points}) > 1  # the vehicle's track, not one point repeated
    for p, t in zip(points, track, strict=True):
        assert abs(p.time.timestamp() - t["time"]) < 1e-3
        assert (p.latitude, p.longitude, p.elevation) == (t["latitude"], t["longitude"], t["altitudeMsl"])
        ext = {e.tag.split("}")[1]: float(e.text) for e in p.extensions}
        assert ext == {"course": t["course"], "speed": t["sog"]}

    r = http.get(f"{c.url}/api/providers/{V1}/track.csv", params={"until": until})
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    rows = list(csv.reader(io.StringIO(r.text)))
    assert rows[0] == TRACK_HEADER and len(rows) == len(track) + 1
    for row, t in zip(rows[1:], track, strict=True):
        rec = dict(zip(TRACK_HEADER, row, strict=True))
        assert abs(parse_utc(rec["time_utc"]) - t["time"]) < 1e-3
        assert (float(rec["latitude_deg"]), float(rec["longitude_deg"]), float(rec["altitude_msl_m"])) == (
            t["latitude"],
            t["longitude"],
            t["altitudeMsl"],
        )
        assert (float(rec["course_deg"]), float(rec["sog_mps"])) == (t["course"], t["sog"])
        assert rec["fix_valid"] in ("true", "false", "") and rec["gps_lat_long_valid"] == str(t["latLongValid"]).lower()
        assert rec["umaa_version"] == "3.0.1"  # the vehicle's version, as REST says it

    # an empty range is an empty file, not an error
    empty = http.get(f"{c.url}/api/providers/{V1}/track.gpx", params={"until": "2001-01-01T00:00:00Z"})
    assert empty.status_code == 200 and gpxpy.parse(empty.text).tracks[0].segments[0].points == []
    assert http.get(f"{c.url}/api/providers/{V1}/track.csv", params={"until": "2001-01-01"}).text.strip() == ",".join(
        TRACK_HEADER
    )


@pytest.mark.slow
def test_commands_csv_has_every_transition_and_the_pager_filters_by_vehicle(sim, console) -> None:
    sim("--vehicles", "2")
    c = console()
    provider_ready(c.url, V1, {"GPSFixReport"})
    provider_ready(c.url, V2, {"GPSFixReport"})
    sessions = []
    for v in (V1, V2, V1):  # one after the other (a newer GPS fix command supersedes a running one)
        sessions.append(http.post(f"{c.url}/api/providers/{v}/gps-fix", json={}).json()["sessionId"])
        wait_command(c.url, sessions[-1])

    r = http.get(f"{c.url}/api/commands.csv")
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    rows = list(csv.DictReader(io.StringIO(r.text)))
    by_session: dict[str, list[dict[str, str]]] = {}
    for row in rows:
        by_session.setdefault(row["session_id"], []).append(row)
    assert list(by_session) == sessions  # oldest first
    for s, v in zip(sessions, (V1, V2, V1), strict=True):
        mine = by_session[s]
        assert [x["status"] for x in mine] == HAPPY and [x["seq"] for x in mine] == ["1", "2", "3", "4"]
        assert {
            (x["provider_id"], x["service"], x["final_status"], x["created_utc"], x["station"], x["umaa_version"]) for x in mine
        } == {(v, "GPSFix", "COMPLETED", mine[0]["created_utc"], "test-console", "3.0.1")}
        received = [parse_utc(x["received_utc"]) for x in mine]
        assert received == sorted(received) and parse_utc(mine[0]["created_utc"]) <= received[0]

    only_v2 = list(csv.DictReader(io.StringIO(http.get(f"{c.url}/api/commands.csv", params={"provider_id": V2}).text)))
    assert {x["session_id"] for x in only_v2} == {sessions[1]}
    later = http.get(f"{c.url}/api/commands.csv", params={"since": mine[0]["created_utc"]}).text
    assert {x["session_id"] for x in csv.DictReader(io.StringIO(later))} == {sessions[2]}

    # the dashboard's pager: a vehicle's older commands, page by page
    page1 = get(c.url, "/api/commands", provider_id=V1, limit=1, offset=0)
    page2 = get(c.url, "/api/commands", provider_id=V1, limit=1, offset=1)
    assert [x["sessionId"] for x in page1 + page2] == [sessions[2], sessions[0]]
    assert get(c.url, "/api/commands", provider_id=V1, limit=1, offset=2) == []
