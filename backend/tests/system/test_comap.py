"""CoMap over IMC end to end: a real console and a real simulator talking IMC over UDP on
127.0.0.1 (and DDS on loopback), plus fuzzed datagrams against the console's IMC port."""

from __future__ import annotations

import math
import random
import socket
import struct
import time
import uuid
from dataclasses import asdict
from typing import Any

import pytest

from conftest import free_udp_port
from sem_console.comap.c2 import C2, FINAL, Task
from sem_console.comap.codec import crc16, decode_packet, encode_packet, msg
from sem_console.comap.geo import Local, contains
from sem_console.sim.options import vehicle_guid
from sem_console.storage.database import Database
from sem_console.storage.url import parse_database_url
from support import http, warm
from test_console import WsClient, wait_until

V1 = str(vehicle_guid(1))
FIN = frozenset(FINAL)


def comap_pair(sim: Any, console: Any, *sim_args: str) -> tuple[Any, int, int]:
    c_port, s_port = free_udp_port(), free_udp_port()
    sim(
        "--imc-port",
        str(s_port),
        "--imc-host",
        "127.0.0.1",
        "--imc-id",
        "0x2001",
        "--imc-peers",
        f"127.0.0.1:{c_port}",
        "--time-scale",
        "0.02",
        "--survey-spacing",
        "50",
        *sim_args,
    )
    c = console(
        "--imc-port",
        str(c_port),
        "--imc-host",
        "127.0.0.1",
        "--imc-peers",
        f"127.0.0.1:{s_port}",
        "--imc-id",
        "0x4001",
        "--imc-vehicles",
        f"{V1}=0x2001",
        # every second's track point stored: these tests read the track as where the vehicle is, and a thinned track
        # ends up to 5 m and 10 s short of it (a vehicle arriving at a point was seen there only 10 s later)
        *("--track-thin-metres", "0", "--track-thin-seconds", "0"),
    )
    return c, c_port, s_port


def capabilities(base: str) -> list[dict[str, Any]]:
    def get() -> list[dict[str, Any]] | None:
        return http.get(f"{base}/api/providers/{V1}/capabilities").json()["capabilities"]  # type: ignore[no-any-return]

    try:
        return wait_until(get, 20, "capabilities")  # type: ignore[no-any-return]
    except AssertionError:
        raise AssertionError(f"no capabilities; IMC node: {http.get(f'{base}/api/comap').json()}") from None


def last_position(base: str) -> tuple[float, float]:
    def get() -> tuple[float, float] | None:
        pts = (
            http.get(f"{base}/api/providers/{V1}/track").json()
            if http.get(f"{base}/api/providers/{V1}").status_code == 200
            else []
        )
        return (pts[-1]["latitude"], pts[-1]["longitude"]) if pts else None

    # a wait, not a timed assertion: the track is written once a second, and the whole test command loads the machine
    return wait_until(get, 60, "a track point of vehicle 1")  # type: ignore[no-any-return]


def square(center: tuple[float, float], north_m: float, size_m: float) -> list[tuple[float, float]]:
    loc = Local(*center)
    return [
        loc.latlon(x, north_m + y) for x, y in ((-size_m / 2, 0), (size_m / 2, 0), (size_m / 2, size_m), (-size_m / 2, size_m))
    ]


def polygon_feature(points: list[tuple[float, float]], fid: int | None) -> dict[str, Any]:
    ring = [[lon, lat] for lat, lon in points]
    return {
        "type": "Feature",
        "geometry": {"type": "Polygon", "coordinates": [[*ring, ring[0]]]},
        "properties": {"featureId": fid, "name": "box"},
    }


@pytest.mark.slow
def test_survey_task_runs_on_a_simulated_vehicle(sim, console) -> None:
    # at 1 m/s before the time scale (50 m/s), about 10 s on the lanes over the polygon (a 150 m square, lanes 50 m
    # apart), where the console keeps a track point a second: at the default 2 m/s a starved simulator may leave fewer
    # than three there
    c, _c_port, _s_port = comap_pair(sim, console, "--survey-speed", "1")
    here = last_position(c.url)
    caps = capabilities(c.url)
    assert {x["kind"] for x in caps} == {"AREA_SURVEY", "POINT_SURVEY", "MOVE"}
    assert any(x["sensor"] == "SIDESCAN" for x in caps if x["kind"] == "AREA_SURVEY")

    box = square(here, 100, 150)
    ws = WsClient(c.ws_url)
    put = http.put(f"{c.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [polygon_feature(box, 7)]})
    assert put.status_code == 200, put.text
    (f,) = put.json()["features"]
    assert f["properties"]["featureId"] == 7 and f["properties"]["coverage"] is None and f["properties"]["name"] == "box"
    assert len(f["geometry"]["coordinates"][0]) == 5  # closed ring out, 4 vertices over IMC

    r = http.post(
        f"{c.url}/api/tasks",
        json={
            "kind": "survey",
            "vehicle": V1,
            "featureId": 7,
            "sensor": "SIDESCAN",
            "resolution": 5.0,
            "deadline": "2099-01-01T00:00:00Z",
        },
    )
    assert r.status_code == 201, r.text
    task = r.json()
    assert task["state"] == "ASSIGNED" and task["kind"] == "survey" and task["deadline"] == 4070908800.0
    tid = task["taskId"]
    done = wait_until(
        lambda: (lambda t: t if t["state"] == "COMPLETED" else None)(http.get(f"{c.url}/api/tasks/{tid}").json()),
        60,
        "the survey to complete",
    )
    assert done["progress"] == 100 and done["quality"] == 100
    time.sleep(0.5)
    ws.close()
    assert not ws.errors
    states = [m["task"]["state"] for m in ws.of("task") if m["task"]["taskId"] == tid]
    assert states[:2] == ["ASSIGNED", "ACCEPTED"] and "IN_PROGRESS" in states and states[-1] == "COMPLETED", states
    progress = [m["task"]["progress"] for m in ws.of("task") if m["task"]["taskId"] == tid]
    assert progress == sorted(progress) and len(set(progress)) > 3, progress
    coverage = [m["worldModel"]["features"][0]["properties"]["coverage"] for m in ws.of("worldmodel")]
    assert coverage[0] is None and coverage[-2:] == ["PARTIAL", "COMPLETED"], coverage
    assert http.get(f"{c.url}/api/worldmodel").json()["features"][0]["properties"]["coverage"] == "COMPLETED"

    # the UMAA track (GPSFixReport positions the console stored) really went over the polygon
    def inside() -> list[Any] | None:
        pts = http.get(f"{c.url}/api/providers/{V1}/track").json()
        hits = [p for p in pts if contains(box, p["latitude"], p["longitude"])]
        return hits if len(hits) >= 3 else None

    wait_until(inside, 5, "track points inside the polygon")


@pytest.mark.slow
def test_reject_hold_resume_interrupt_and_move(sim, console) -> None:
    c, _c_port, _s_port = comap_pair(sim, console, "--survey-speed", "1")
    here = last_position(c.url)
    box = square(here, 50, 400)
    assert (
        http.put(
            f"{c.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [polygon_feature(box, None)]}
        ).status_code
        == 200
    )
    fid = http.get(f"{c.url}/api/worldmodel").json()["features"][0]["properties"]["featureId"]
    capabilities(c.url)

    def state(tid: int, want: str) -> dict[str, Any]:
        return wait_until(
            lambda: (lambda t: t if t["state"] == want else None)(http.get(f"{c.url}/api/tasks/{tid}").json()),
            20,
            f"task {tid} {want}",
        )

    # a sensor it lacks: REJECT
    r = http.post(f"{c.url}/api/tasks", json={"kind": "survey", "vehicle": V1, "featureId": fid, "sensor": "CAMERA"}).json()
    state(r["taskId"], "REJECTED")
    assert http.post(f"{c.url}/api/tasks/{r['taskId']}/synch", json={"action": "HOLD"}).status_code == 409

    t = http.post(f"{c.url}/api/tasks", json={"kind": "survey", "vehicle": V1, "featureId": fid}).json()
    state(t["taskId"], "IN_PROGRESS")
    wait_until(lambda: http.get(f"{c.url}/api/tasks/{t['taskId']}").json()["progress"] >= 2, 20, "progress")
    assert http.post(f"{c.url}/api/tasks/{t['taskId']}/synch", json={"action": "HOLD"}).json()["state"] == "HELD"
    time.sleep(2.5)  # the track takes a point a second and is written a second later
    p1 = last_position(c.url)
    held = http.get(f"{c.url}/api/tasks/{t['taskId']}").json()
    time.sleep(2.5)
    assert Local(*p1).xy(*last_position(c.url)) == (0.0, 0.0)  # held: the track stands still
    assert http.get(f"{c.url}/api/tasks/{t['taskId']}").json()["progress"] == held["progress"] < 100
    assert http.post(f"{c.url}/api/tasks/{t['taskId']}/synch", json={"action": "RESUME"}).json()["state"] == "IN_PROGRESS"
    wait_until(lambda: Local(*p1).xy(*last_position(c.url)) != (0.0, 0.0), 10, "moving again")
    assert http.post(f"{c.url}/api/tasks/{t['taskId']}/synch", json={"action": "INTERRUPT"}).json()["state"] == "INTERRUPTED"

    dest = Local(*here).latlon(-60.0, -40.0)
    m = http.post(f"{c.url}/api/tasks", json={"kind": "move", "vehicle": V1, "point": {"lat": dest[0], "lon": dest[1]}}).json()
    wait_until(
        lambda: (lambda x: x if x["state"] == "COMPLETED" else None)(http.get(f"{c.url}/api/tasks/{m['taskId']}").json()),
        40,
        "the move task to complete",
    )
    wait_until(lambda: math.hypot(*Local(*dest).xy(*last_position(c.url))) < 1.0, 10, "the vehicle at the destination")


@pytest.mark.slow
def test_task_routes_refuse_bad_requests(console) -> None:
    c = console("--imc-port", str(free_udp_port()), "--imc-host", "127.0.0.1", "--imc-vehicles", f"{V1}=0x2001")
    fc = {"type": "FeatureCollection", "features": []}
    other = "00000000-0000-0000-0000-000000000001"
    cases = [
        (http.post, "/api/tasks", {"kind": "survey", "vehicle": other, "featureId": 1}, 404),
        (http.post, "/api/tasks", {"kind": "survey", "vehicle": V1, "featureId": 1}, 409),
        (http.post, "/api/tasks", {"kind": "survey", "vehicle": V1}, 422),
        (http.post, "/api/tasks", {"kind": "move", "vehicle": V1, "point": {"lat": 91, "lon": 0}}, 422),
        (http.post, "/api/tasks/99/synch", {"action": "HOLD"}, 404),
        (
            http.put,
            "/api/worldmodel",
            {
                **fc,
                "features": [
                    {
                        "type": "Feature",
                        "properties": {},
                        "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1], [2, 2]]},
                    }
                ],
            },
            422,
        ),
        (
            http.put,
            "/api/worldmodel",
            {
                **fc,
                "features": [
                    {
                        "type": "Feature",
                        "properties": {},  # a bow tie crosses itself
                        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 1], [1, 0], [0, 1]]]},
                    }
                ],
            },
            409,
        ),
        (
            http.put,
            "/api/worldmodel",
            {
                **fc,
                "features": [
                    {
                        "type": "Feature",
                        "properties": {},  # 3 vertices, 2 distinct
                        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 1], [0, 0], [0, 0]]]},
                    }
                ],
            },
            409,
        ),
        (
            http.put,
            "/api/worldmodel",
            {
                **fc,
                "features": [
                    {"type": "Feature", "properties": {"featureId": 3}, "geometry": {"type": "Point", "coordinates": [0, 0]}}
                ]
                * 2,
            },
            409,
        ),
        (
            http.put,
            "/api/worldmodel",
            {
                **fc,
                "features": [
                    {"type": "Feature", "properties": {"featureId": True}, "geometry": {"type": "Point", "coordinates": [0, 0]}}
                ],
            },
            422,
        ),
        (
            http.put,
            "/api/worldmodel",
            {**fc, "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [200, 0]}}]},
            422,
        ),
    ]
    for call, path, body, want in cases:
        r = call(c.url + path, json=body)
        assert r.status_code == want, (path, body, r.text)
    audit = http.get(f"{c.url}/api/audit").json()
    assert sum(
        1 for a in audit if a["outcome"] == "refused" and a["path"] in ("/api/tasks", "/api/worldmodel", "/api/tasks/99/synch")
    ) == len(cases)
    c.stop()  # one console per SQLite file
    off = console("--console-name", "comap-off")  # a console without CoMap on the same database
    assert (
        http.post(f"{off.url}/api/tasks", json={"kind": "move", "vehicle": V1, "point": {"lat": 1, "lon": 2}}).status_code == 409
    )
    assert http.get(f"{off.url}/api/comap").json()["enabled"] is False


def test_fuzzed_imc_datagrams_are_counted_and_dropped(console) -> None:
    port = free_udp_port()
    c = console("--imc-port", str(port), "--imc-host", "127.0.0.1")
    rng = random.Random(1212)
    good = encode_packet(msg("CoverageState", feature_id=1, state=2), src=5)

    def packet(mgid: int, payload: bytes) -> bytes:
        body = struct.pack("<HHHdHBHB", 0xFE55, mgid, len(payload), 0.0, 5, 0, 0xFFFF, 0xFF) + payload
        return body + struct.pack("<H", crc16(body))

    datagrams = [bytes(rng.randbytes(rng.randint(0, 300))) for _ in range(300)]
    datagrams += [good[:-1] + bytes([good[-1] ^ 0xFF])] * 20  # bad CRC
    datagrams += [packet(3001, b"\xff\xff")] * 20  # a list of 65535 features in no bytes
    datagrams += [packet(3001, struct.pack("<HHHH", 1, 3002, 9, 60000) + b"\x5c\x02" * 10)] * 20  # points that are not there
    datagrams += [packet(3002, struct.pack("<HH", 1, 0) + b"\x00" * 500)] * 20  # oversized: bytes beyond its fields
    datagrams += [good[:10]] * 20
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        for d in datagrams:
            s.sendto(d, ("127.0.0.1", port))
            time.sleep(0.001)
        s.sendto(encode_packet(msg("TaskStatus", task_id=1, status=2, progress=3, quality=4), src=5), ("127.0.0.1", port))
    counters = wait_until(
        lambda: (lambda x: x if x["received"] == len(datagrams) + 1 else None)(http.get(f"{c.url}/api/comap").json()["counters"]),
        10,
        "every datagram counted",
    )
    assert (
        counters["accepted"] == 1 and counters["bad_crc"] >= 20 and counters["bad_size"] >= 40 and counters["truncated"] >= 40
    ), counters
    dropped = sum(counters[k] for k in ("truncated", "bad_sync", "bad_size", "bad_crc", "unknown_id", "bad_message"))
    assert dropped == len(datagrams), counters
    assert http.get(f"{c.url}/api/health").status_code == 200 and c.proc.poll() is None
    assert decode_packet(good)[1]["state"] == 2


def test_a_world_model_that_cannot_be_used_is_counted_not_taken_for_accepted(console) -> None:
    """A well-formed WorldModel whose feature has no vertices (or one out of range) was ignored with a log line only:
    /api/comap counted it `accepted` and nothing said the model was refused."""
    from sem_console.comap.geo import Feature, world_model_message

    port = free_udp_port()
    c = console("--imc-port", str(port), "--imc-host", "127.0.0.1")
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.sendto(encode_packet(world_model_message([Feature(4, [])]), src=5), ("127.0.0.1", port))
        s.sendto(encode_packet(world_model_message([Feature(5, [(95.0, 0.0)])]), src=5), ("127.0.0.1", port))
    counters = wait_until(
        lambda: (lambda x: x if x.get("accepted") == 2 else None)(http.get(f"{c.url}/api/comap").json()["counters"]),
        10,
        "both datagrams",
    )
    assert counters["refusedWorldModels"] == 2, counters
    assert http.get(f"{c.url}/api/worldmodel").json()["features"] == []  # no model taken from them


def test_a_peer_given_by_host_name_is_sent_to(console) -> None:
    """--imc-peers localhost:N: every send raised ValueError in the event loop's transport (it takes addresses
    only), so PUT /api/worldmodel answered 500 and nothing was sent or counted."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as vehicle:
        # a port no DDS datagram reaches (an ephemeral one took a participant's discovery ping: 'RTPS', not IMC)
        vehicle.bind(("127.0.0.1", free_udp_port()))
        vehicle.settimeout(10)
        port = vehicle.getsockname()[1]
        c = console("--imc-port", str(free_udp_port()), "--imc-host", "127.0.0.1", "--imc-peers", f"localhost:{port}")
        model = {"type": "FeatureCollection", "features": [polygon_feature(square((36.8, -75.7), 0, 100), 1)]}
        r = http.put(f"{c.url}/api/worldmodel", json=model)
        assert r.status_code == 200, r.text
        assert decode_packet(vehicle.recvfrom(65535)[0])[1].name == "WorldModel"
    assert http.get(f"{c.url}/api/comap").json()["peers"] == [f"127.0.0.1:{port}"]


def test_bad_imc_options_are_one_line_errors(tmp_path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)  # the commands' working directory (warm.run's is this process's)
    cases = [
        ((warm.CONSOLE, ["--imc-vehicles", "not-a-guid=5"]), "is not a GUID"),
        ((warm.CONSOLE, ["--imc-vehicles", f"{V1}=0x10000"]), "not in 0..0xFFFE"),
        ((warm.CONSOLE, ["--imc-peers", "localhost"]), "is not host:port"),
        ((warm.CONSOLE, ["--imc-id", "x"]), "is not an IMC system id"),
        ((warm.SIM, ["--imc-port", "1", "--imc-sensors", "SONAR"]), "unknown sensor SONAR"),
        ((warm.SIM, ["--imc-peers", "h:99999"]), "is not host:port"),
        (
            (warm.CONSOLE, ["--imc-port", "6002", "--imc-peers", "no-such-host.invalid:6002"]),
            "is not an IPv4 address or a host name",
        ),
    ]
    for (module, args), text in cases:
        p = warm.run(module, args)
        assert p.returncode == 2 and text in p.stderr and len(p.stderr.strip().splitlines()) <= 2, (args, p.stderr)


def test_imc_peers_of_a_console_without_comap_are_not_resolved() -> None:
    """Without --imc-port nothing is sent to them: a name that does not resolve (a vehicle's, off the network) must
    not stop a console that does not use CoMap; their form is still checked."""
    from sem_console.core.config import Settings

    assert Settings(imc_peers="no-such-host.invalid:6002").imc_peers == "no-such-host.invalid:6002"
    with pytest.raises(ValueError, match="is not an IPv4 address or a host name"):
        Settings(imc_peers="no-such-host.invalid:6002", imc_port=6002)
    with pytest.raises(ValueError, match="is not host:port"):
        Settings(imc_peers="no-such-host.invalid")
    # the simulator's plain socket resolves a name at each send: kept as given (it stopped sem-sim without CoMap)
    from sem_console.sim.sem_sim import _peers

    assert _peers("no-such-host.invalid:6002") == [("no-such-host.invalid", 6002)]
    # with CoMap on it would be sent to: one line at the start (its sends failed unseen, counted in sendErrors only)
    from sem_console.sim.sem_sim import build_parser, options_from

    assert options_from(build_parser().parse_args(["--imc-peers", "no-such-host.invalid:6002"])).imc_peers
    with pytest.raises(SystemExit) as stopped:
        options_from(build_parser().parse_args(["--imc-port", "6003", "--imc-peers", "no-such-host.invalid:6002"]))
    assert stopped.value.code == 2


def test_new_feature_ids_are_not_reused_after_a_delete() -> None:
    """A feature PUT without an id is numbered above every id the C2 has seen (not the lowest free one):
    a deleted feature's id, whose survey may still report CoverageState, is not given to a new feature."""
    from sem_console.comap.c2 import C2
    from sem_console.comap.codec import Header
    from sem_console.comap.geo import Feature, world_model_message

    sent: list[Any] = []
    c2 = C2({}, lambda m, dst: sent.append(m), lambda ws: None)
    pt = [(1.0, 2.0)]
    c2.put_world_model([Feature(1, pt), Feature(2, pt), Feature(-1, pt)])
    assert [f.feature_id for f in c2.features] == [1, 2, 3]
    c2.put_world_model([Feature(1, pt)])  # #2 and #3 deleted
    c2.put_world_model([Feature(1, pt), Feature(-1, pt), Feature(-1, pt)])
    assert [f.feature_id for f in c2.features] == [1, 4, 5]
    # ids in a world model a peer sent count too
    c2.on_message(
        Header(mgid=0, size=0, timestamp=0.0, src=0x2001, src_ent=0, dst=0xFFFF, dst_ent=0), world_model_message([Feature(9, pt)])
    )
    c2.put_world_model([Feature(-1, pt)])
    assert [f.feature_id for f in c2.features] == [10]
    assert len(sent) == 4 and sent[-1].name == "WorldModel"


def test_a_progress_report_keeps_another_stations_newer_state(database_url: str) -> None:
    """Station A (which assigned the task) stores the vehicle's progress while its copy of the task is stale: station B
    has just stored HOLD. The stored task keeps HELD with A's progress, and A takes it on its next read. Without the
    rule, A's IN_PROGRESS went over B's HOLD on every station (test_comap_shared saw it under load)."""
    db = Database(parse_database_url(database_url))
    try:
        db.claim("watch", hold=False)
        vehicle = uuid.uuid4()
        at_a = Task(
            1,
            "move",
            vehicle,
            0x2001,
            None,
            point={"lat": 36.8, "lon": -75.7},
            state="IN_PROGRESS",
            created_at=100.0,
            updated_at=101.0,
            station="watch",
            state_at=101.0,
        )
        db.set_comap_task(asdict(at_a), FIN)
        at_b = Task(**{**asdict(at_a), "state": "HELD", "last_synch": "HOLD", "updated_at": 102.0, "state_at": 102.0})
        db.set_comap_task(asdict(at_b), FIN)  # B's HOLD
        progressed = Task(**{**asdict(at_a), "progress": 40, "updated_at": 103.0})  # A's stale copy, newer progress
        db.set_comap_task(asdict(progressed), FIN)
        (row,) = db.comap_tasks(1)
        assert (row["state"], row["last_synch"], row["progress"], row["updated_at"], row["state_at"]) == (
            "HELD",
            "HOLD",
            40,
            103.0,
            102.0,
        )

        shown: list[dict[str, object]] = []
        a = C2({vehicle: 0x2001}, lambda m, dst: None, shown.append, station="watch")
        a.tasks[1] = progressed
        a.load_task({**row, "point": row["point"]})  # the same progress as A's own, a state decided after A's: taken
        assert (a.tasks[1].state, a.tasks[1].last_synch, a.tasks[1].progress) == ("HELD", "HOLD", 40)
        assert shown[-1]["task"]["state"] == "HELD"  # type: ignore[index]
        shown.clear()
        a.load_task({**row, "point": row["point"]})  # the same row again: nothing new
        assert not shown

        # A's copy already newer than the row (its vehicle reports faster than the notifications come: each progress
        # report stamped anew before the row was read): B's HOLD is taken all the same, A's newer progress kept
        a.tasks[1] = Task(**{**asdict(progressed), "progress": 55, "updated_at": 105.0})
        a.load_task({**row, "point": row["point"]})
        assert (a.tasks[1].state, a.tasks[1].last_synch, a.tasks[1].progress) == ("HELD", "HOLD", 55)
        # but not over a state A decided after that row was stamped (its own RESUME)
        a.linked = True
        a.tasks[1].state = "IN_PROGRESS"
        a.tasks[1].last_synch = None
        a.synch(1, "RESUME")
        a.load_task({**row, "point": row["point"]})
        assert (a.tasks[1].state, a.tasks[1].last_synch) == ("IN_PROGRESS", "RESUME")

        # a HOLD held through an outage (B's database connection lost at 104) is stored when B's write comes at last,
        # though A stored newer progress meanwhile (110); that progress stays. One stamp for both (updated_at) lost it
        db.set_comap_task(asdict(Task(**{**asdict(at_a), "progress": 80, "updated_at": 110.0})), FIN)
        held = Task(
            **{**asdict(at_a), "state": "HELD", "last_synch": "HOLD", "progress": 60, "updated_at": 104.0, "state_at": 104.0}
        )
        db.set_comap_task(asdict(held), FIN)
        (row,) = db.comap_tasks(1)
        assert (row["state"], row["last_synch"], row["progress"], row["updated_at"], row["state_at"]) == (
            "HELD",
            "HOLD",
            80,
            110.0,
            104.0,
        )
        db.set_comap_task(asdict(Task(**{**asdict(at_a), "state": "COMPLETED", "updated_at": 111.0, "state_at": 111.0})), FIN)
        assert db.comap_tasks(1)[0]["state"] == "COMPLETED"  # a change of state is stored as before
        # never over another task of that id (a stale station's write of the finished task the id had before)
        db.set_comap_task(
            asdict(Task(**{**asdict(at_a), "created_at": 50.0, "state": "ERROR", "updated_at": 200.0, "state_at": 200.0})), FIN
        )
        assert db.comap_tasks(1)[0]["state"] == "COMPLETED"

        # nor over a state A's vehicle reported after that row was stamped (its COMPLETED: C2._set stamps it)
        from sem_console.comap.codec import Header
        from sem_console.comap.messages import TaskStatusEnum

        c = C2({vehicle: 0x2001}, lambda m, dst: None, lambda ws: None, station="watch")
        c.tasks[1] = Task(**asdict(progressed))
        c.on_message(
            Header(mgid=0, size=0, timestamp=0.0, src=0x2001, src_ent=0, dst=0x4001, dst_ent=0),
            msg("TaskStatus", task_id=1, status=TaskStatusEnum.COMPLETED.value, progress=100, quality=100),
        )
        stale = {**row, "point": row["point"], "updated_at": c.tasks[1].updated_at - 0.001}  # read before it came
        c.load_task(stale)
        assert c.tasks[1].state == "COMPLETED"
    finally:
        db.close()


def test_a_finished_task_stays_finished_whatever_a_stale_station_decides_after(database_url: str) -> None:
    """Watch's vehicle completes its task; relief, which has not read that yet (the notification on its way, or its
    database connection lost), sends a HOLD. The task stays COMPLETED at 100 %, in the database and on both consoles:
    HELD, stamped after it, left a completed task held on every station for good (the vehicle reports nothing more,
    and its id was never free again), and relief's write, stamped as progress too, put its stale progress over the
    vehicle's last. The same when watch's writes, held through an outage of its own, come after relief's HOLD."""
    from sem_console.comap.codec import Header
    from sem_console.comap.messages import TaskStatusEnum
    from sem_console.console.service import SharedComap

    db = Database(parse_database_url(database_url))
    try:
        db.claim("watch", hold=False)
        vehicle = uuid.uuid4()
        held_writes: list[Task] = []

        class Held:  # watch's writes during its outage, written when the database is back
            def world(self, world: dict[str, Any]) -> None: ...
            def task(self, task: Task) -> None:
                held_writes.append(Task(**asdict(task)))

        def station(name: str, save: Any = None) -> C2:
            c = C2({vehicle: 0x2001}, lambda m, dst: None, lambda ws: None, save or SharedComap(db), station=name)
            c.linked = True
            return c

        def status(c: C2, tid: int, state: TaskStatusEnum, progress: int) -> None:
            c.on_message(
                Header(mgid=0, size=0, timestamp=0.0, src=0x2001, src_ent=0, dst=0x4001, dst_ent=0),
                msg("TaskStatus", task_id=tid, status=state.value, progress=progress, quality=90),
            )

        def stored(tid: int) -> tuple[str, str | None, int]:
            (row,) = db.comap_tasks(tid)
            return row["state"], row["last_synch"], row["progress"]

        for outage in (False, True):
            watch, relief = station("watch", Held() if outage else None), station("relief")
            planned = watch.plan("move", vehicle, None, point={"lat": 36.8, "lon": -75.7})
            tid = db.new_comap_task(asdict(planned), FIN)
            assert tid is not None
            planned.task_id = tid
            watch.assign(planned)
            status(watch, tid, TaskStatusEnum.IN_PROGRESS, 40)
            relief.load_task(db.comap_tasks(tid)[0])  # relief has read the task at 40 %
            status(watch, tid, TaskStatusEnum.IN_PROGRESS, 80)
            status(watch, tid, TaskStatusEnum.COMPLETED, 100)
            relief.synch(tid, "HOLD")  # before it read the COMPLETED
            for t in held_writes:  # watch's database back: its writes after relief's
                db.set_comap_task(asdict(t), FIN)
            assert stored(tid) == ("COMPLETED", None, 100), outage
            for c in (watch, relief):
                c.load_task(db.comap_tasks(tid)[0])
                assert (c.tasks[tid].state, c.tasks[tid].progress) == ("COMPLETED", 100), (outage, c.station)

        # of two final states the first decided stands (a stale INTERRUPT of a task its vehicle had completed)
        row = db.comap_tasks(tid)[0]
        db.set_comap_task({**row, "state": "INTERRUPTED", "last_synch": "INTERRUPT", "state_at": row["state_at"] + 5}, FIN)
        assert stored(tid) == ("COMPLETED", None, 100)
    finally:
        db.close()


def test_a_task_stored_before_state_at_keeps_its_state_after_the_upgrade(database_url: str) -> None:
    """A database of schema 0005 with a task HELD on it: upgraded (migration 0006), the task's state is stamped when
    its last change was (its `updated_at`, the best known), so the assigning station's progress report, which carries
    the older stamp of the IN_PROGRESS it had read, does not undo the HOLD; a state decided after it is stored."""
    from alembic import command
    from sqlalchemy import text

    from sem_console.storage.engine import alembic_config, open_engine

    url = parse_database_url(database_url)
    engine = open_engine(url)
    try:
        with engine.begin() as c:
            command.upgrade(alembic_config(c), "0005")
            c.execute(
                text(
                    "INSERT INTO comap_tasks (task_id, kind, vehicle, imc_id, state, progress, created_at, "
                    "updated_at, last_synch, station) VALUES (7, 'move', :v, 8193, 'HELD', 40, 100.0, 102.0, "
                    "'HOLD', 'relief')"
                ),
                {"v": V1},
            )
    finally:
        engine.dispose()
    db = Database(url)
    try:
        (row,) = db.comap_tasks(7)
        assert (row["state"], row["state_at"], row["updated_at"]) == ("HELD", 102.0, 102.0)
        watch = Task(
            7,
            "move",
            uuid.UUID(V1),
            0x2001,
            None,
            state="IN_PROGRESS",
            progress=60,
            created_at=100.0,
            updated_at=103.0,
            state_at=101.0,
            station="watch",
        )  # its copy from before the HOLD
        db.set_comap_task(asdict(watch), FIN)
        (row,) = db.comap_tasks(7)
        assert (row["state"], row["last_synch"], row["progress"]) == ("HELD", "HOLD", 60)
        db.set_comap_task(
            asdict(Task(**{**asdict(watch), "state": "IN_PROGRESS", "last_synch": "RESUME", "state_at": 104.0})), FIN
        )
        assert db.comap_tasks(7)[0]["state"] == "IN_PROGRESS"
    finally:
        db.close()


@pytest.mark.slow
def test_a_6_0_vehicle_moves_for_comap_and_its_position_follows(sim, console) -> None:
    """A UMAA 6.0 vehicle (sem-sim --umaa 6.0) under CoMap: its position, from its GlobalPose through the console's one
    model, is CoMap's vehicle position and the track's; a move task takes it to the point, as a 3.0.1 vehicle."""
    c, _c_port, _s_port = comap_pair(sim, console, "--umaa", "6.0", "--survey-speed", "1")
    here = last_position(c.url)
    assert http.get(f"{c.url}/api/providers/{V1}").json()["umaaVersion"] == "6.0"
    capabilities(c.url)
    dest = Local(*here).latlon(-60.0, -40.0)
    m = http.post(f"{c.url}/api/tasks", json={"kind": "move", "vehicle": V1, "point": {"lat": dest[0], "lon": dest[1]}}).json()
    wait_until(
        lambda: (lambda x: x if x["state"] == "COMPLETED" else None)(http.get(f"{c.url}/api/tasks/{m['taskId']}").json()),
        40,
        "the move task to complete",
    )
    wait_until(lambda: math.hypot(*Local(*dest).xy(*last_position(c.url))) < 1.0, 10, "the vehicle at the destination")
    pose = http.get(f"{c.url}/api/providers/{V1}").json()["reports"]["GPSFixReport"]["report"]
    at = pose["position2DWithTime"]["geodeticPosition"]
    assert math.hypot(*Local(*dest).xy(at["geodeticLatitude"]["latitude"], at["geodeticLongitude"]["longitude"])) < 1.0
