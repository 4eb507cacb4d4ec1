"""Track and chart history in the console's database, and the GPX and CSV exports: a real `sem-console`
and `sem-sim` over DDS on loopback."""

from __future__ import annotations

import csv
import io
import itertools
import math
import signal
import time
from datetime import UTC, datetime
from typing import Any

import gpxpy
import httpx
import pytest

from test_console import HAPPY, V1, V2, provider_ready, wait_command, wait_until

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
    r = httpx.get(base + path, params=params)
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
    first = console()
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
    second = console()  # the vehicles are gone: the track is still there
    again = get(second.url, f"/api/providers/{V1}/track")
    assert [x["time"] for x in again[: len(track)]] == [x["time"] for x in track]
    assert again[: len(track)] == track
    assert len(get(second.url, f"/api/providers/{V1}/series")) >= len(series)


def test_retention_prunes_old_points(sim, console) -> None:
    sim()
    c = console("--track-retention-hours", "0.0005")  # 1.8 s, pruned every second
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

    r = httpx.get(f"{c.url}/api/providers/{V1}/track.gpx", params={"until": until})
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

    r = httpx.get(f"{c.url}/api/providers/{V1}/track.csv", params={"until": until})
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
    empty = httpx.get(f"{c.url}/api/providers/{V1}/track.gpx", params={"until": "2001-01-01T00:00:00Z"})
    assert empty.status_code == 200 and gpxpy.parse(empty.text).tracks[0].segments[0].points == []
    assert httpx.get(f"{c.url}/api/providers/{V1}/track.csv", params={"until": "2001-01-01"}).text.strip() == ",".join(
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
        sessions.append(httpx.post(f"{c.url}/api/providers/{v}/gps-fix", json={}).json()["sessionId"])
        wait_command(c.url, sessions[-1])

    r = httpx.get(f"{c.url}/api/commands.csv")
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

    only_v2 = list(csv.DictReader(io.StringIO(httpx.get(f"{c.url}/api/commands.csv", params={"provider_id": V2}).text)))
    assert {x["session_id"] for x in only_v2} == {sessions[1]}
    later = httpx.get(f"{c.url}/api/commands.csv", params={"since": mine[0]["created_utc"]}).text
    assert {x["session_id"] for x in csv.DictReader(io.StringIO(later))} == {sessions[2]}

    # the dashboard's pager: a vehicle's older commands, page by page
    page1 = get(c.url, "/api/commands", provider_id=V1, limit=1, offset=0)
    page2 = get(c.url, "/api/commands", provider_id=V1, limit=1, offset=1)
    assert [x["sessionId"] for x in page1 + page2] == [sessions[2], sessions[0]]
    assert get(c.url, "/api/commands", provider_id=V1, limit=1, offset=2) == []
