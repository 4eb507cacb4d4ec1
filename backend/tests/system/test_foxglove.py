"""The Foxglove gateway against a real console and sem-sim, read by a Foxglove WebSocket protocol client written from
the protocol's specification (tests/support/foxglove.py), not from the console's code."""

from __future__ import annotations

import asyncio
import base64
import dataclasses
import enum
import json
import random
import socket
import subprocess
import sys
import time
import uuid
from pathlib import Path
from typing import Any

import pytest

from conftest import free_port
from sem_console.umaa.samples import now_datetime
from support import http
from support.consumer import Consumer
from support.foxglove import FoxgloveClient, connect
from test_bad_starts import refused
from test_console import V1, V2, provider_ready, wait_command
from test_gateways import global_pose
from test_replay import synthetic_recording

FIX_PATH = ("position2DWithTime", "geodeticPosition")


def b64(data: bytes) -> str:
    return base64.b64encode(data).decode()


def gateway(base: str) -> dict[str, Any]:
    return {g["name"]: g for g in http.get(f"{base}/api/gateways").json()}["foxglove"]


async def until(client: FoxgloveClient, done: Any, seconds: float, what: str) -> None:
    """Read the client's messages (each to `done`, None for a text message) until `done` says True."""
    try:
        async with asyncio.timeout(seconds):
            async for m in client.messages():
                if done(m):
                    return
    except TimeoutError:
        raise AssertionError(f"no {what} within {seconds} s") from None


def latlon(report: dict[str, Any]) -> tuple[float, float]:
    p = report["position2DWithTime"]["geodeticPosition"]
    return p["geodeticLatitude"]["latitude"], p["geodeticLongitude"]["longitude"]


def test_a_foxglove_client_sees_the_fleet_and_decodes_its_fixes_logs_and_reports(sim, console) -> None:
    sim("--vehicles", "2")
    c = console("--foxglove-port", str(free_port()))
    provider_ready(c.url, V1, {"GPSFixReport"})
    provider_ready(c.url, V2, {"GPSFixReport"})
    state = gateway(c.url)
    assert state["enabled"] and state["lastError"] is None and state["endpoint"].startswith("ws://127.0.0.1:")
    me, other = f"/vehicles/{V1}/location", f"/vehicles/{V2}/location"
    fixes: dict[tuple[int, int], dict[str, Any]] = {}  # LocationFix by its time
    reports: dict[tuple[int, int], dict[str, Any]] = {}  # the GPSFixReport channel's messages of V1 by their time
    logs: list[dict[str, Any]] = []
    fleets: list[dict[str, Any]] = []
    senders: set[str] = set()

    async def session() -> dict[str, Any]:
        async with connect(state["endpoint"]) as client:
            wanted = {me, other, "/fleet/locations", "/console/log", "/reports/GPSFixReport", "/reports/GPSReport"}
            await until(client, lambda _m: wanted <= set(client.topics()), 10, f"advertisement of {wanted}")
            assert client.server_info["capabilities"] == []  # read-only: no clientPublish, services, parameters
            topics = client.topics()
            assert topics[me]["schemaName"] == "foxglove.LocationFix" and topics[me]["encoding"] == "json"
            assert topics["/fleet/locations"]["schemaName"] == "foxglove.LocationFixes"
            assert topics["/console/log"]["schemaName"] == "foxglove.Log"
            schema = json.loads(topics["/reports/GPSFixReport"]["schema"])
            assert schema["properties"]["report"]["title"] == "GPSFixReportType" and "$defs" not in schema
            # nobody subscribed yet: messages are only counted, none encoded
            await asyncio.sleep(1.5)
            idle = await asyncio.to_thread(gateway, c.url)
            assert idle["messagesOut"] == 0 and idle["counters"]["left out: no subscriber"] > 0, idle

            await client.subscribe([me, "/fleet/locations", "/console/log", "/reports/GPSFixReport"])
            # the protocol acknowledges no subscription: the first message on one of them says the server has taken the
            # request (one message for all four), before the command whose every transition the log must carry
            await until(client, lambda m: m is not None and m.topic in (me, "/fleet/locations"), 10, "a subscribed message")
            # the vehicle surfaces on a GPS fix command: its transitions are logged, and its fixes get a position
            session = (await asyncio.to_thread(http.post, f"{c.url}/api/providers/{V1}/gps-fix", json={})).json()["sessionId"]

            def take(m: Any) -> bool:
                if m is not None:
                    body = m.json()
                    if m.topic == me:
                        fixes[(body["timestamp"]["sec"], body["timestamp"]["nsec"])] = body
                    elif m.topic == "/console/log":
                        logs.append(body)
                    elif m.topic == "/fleet/locations":
                        fleets.append(body)
                    elif m.topic == "/reports/GPSFixReport":  # the fleet's, each with its vehicle (Plot filters by it)
                        senders.add(body["providerId"])
                        t = body["report"]["timeStamp"]
                        if body["providerId"] == V1:
                            reports[(t["seconds"], t["nanoseconds"])] = body
                return any("command completed" in x["message"] for x in logs) and len(fixes) >= 2 and len(fleets) >= 2

            await until(client, take, 30, "the command's completion in the log, two fixes and two fleet messages")
            command = await asyncio.to_thread(wait_command, c.url, session, 15, lambda x: x["status"] == "COMPLETED")
            # the fix the console holds now comes on the vehicle's channel with its position
            rest = (await asyncio.to_thread(http.get, f"{c.url}/api/providers/{V1}")).json()["reports"]["GPSFixReport"]
            t = rest["report"]["timeStamp"]
            key = (t["seconds"], t["nanoseconds"])
            await until(client, lambda m: take(m) and key in fixes and key in reports, 10, f"the fix of {key}")
            return {"rest": rest, "key": key, "command": command, "state": await asyncio.to_thread(gateway, c.url)}

    got = asyncio.run(session())
    rest, key = got["rest"], got["key"]
    fix = fixes[key]
    assert (fix["latitude"], fix["longitude"]) == latlon(rest["report"])
    assert fix["frame_id"] == V1 and len(fix["position_covariance"]) == 9
    assert fix["position_covariance_type"] in (0, 2)
    # the JSON report is what the dashboard gets: the same report, values flagged invalid and all
    assert reports[key]["report"] == rest["report"] and reports[key]["invalid"] == rest["invalid"]
    assert senders == {V1, V2}
    # the fleet: both vehicles, V2 submerged at its INS's position (GPSLatLongValid false), as the dashboard's map has it
    last = fleets[-1]["fixes"]
    assert sorted(f["frame_id"] for f in last) == sorted([V1, V2]) and all(isinstance(f["latitude"], float) for f in last)
    # one log line per transition of the command, at info level, named by its service
    said = [x for x in logs if x["name"] == f"command/{got['command']['service']}"]
    assert len(said) == len(got["command"]["transitions"]) and all(x["level"] == 2 for x in said), said
    last_log = got["command"]["transitions"][-1]["logMessage"]  # the vehicle's own words, after the console's
    assert said[-1]["message"] == f"{V1}: {got['command']['service']} command completed ({last_log})", said[-1]
    # V2's location channel has no subscriber: its fixes were never encoded, only counted
    assert got["state"]["counters"]["left out: no subscriber"] > 0
    assert got["state"]["messagesOut"] >= len(fixes) + len(logs) + len(fleets) + len(reports)


def test_a_6_0_vehicles_global_pose_is_its_location_fix(console, domain: int) -> None:
    """A UMAA 6.0 vehicle's GlobalPose is its position report in the console's model: its LocationFix comes on the
    vehicle's channel, with the report's time, and no covariance (GlobalPose gives no down variance)."""
    from sem_console.dds.topics import Sem60

    c = console("--foxglove-port", str(free_port()))
    bus = Consumer(domain, name="a-6.0-vehicle").bus
    vehicle, stamp = uuid.uuid4(), now_datetime()
    writer = bus.writer(Sem60.GLOBAL_POSE_REPORT)  # alive until the test ends
    writer.write(global_pose(vehicle, stamp))
    assert provider_ready(c.url, str(vehicle), {"GPSFixReport"})["umaaVersion"] == "6.0"
    topic = f"/vehicles/{vehicle}/location"

    async def session() -> dict[str, Any]:
        async with connect(gateway(c.url)["endpoint"]) as client:
            await until(client, lambda _m: topic in client.topics(), 10, f"the channel {topic}")
            await client.subscribe([topic])
            got: list[dict[str, Any]] = []

            async def writing() -> None:  # again, until the subscription has taken effect at the server
                while True:
                    writer.write(global_pose(vehicle, stamp))
                    await asyncio.sleep(0.5)

            again = asyncio.create_task(writing())
            try:
                await until(client, lambda m: m is not None and not got.append(m.json()), 10, "LocationFix of the 6.0 vehicle")
            finally:
                again.cancel()
            return got[0]

    fix = asyncio.run(session())
    assert fix == {
        "timestamp": {"sec": stamp.seconds, "nsec": stamp.nanoseconds},
        "frame_id": str(vehicle),
        "latitude": 36.85,
        "longitude": -75.98,
        "position_covariance": [0.0] * 9,
        "position_covariance_type": 0,
    }


def test_a_replay_is_served_as_it_plays(console, tmp_path: Path) -> None:
    """With --replay the gateway reads the console's feed as it always does: the replayed reports come out, and what
    the gateway stamps itself (the fleet's LocationFixes) is at the replay's instant, not the machine's; the raw
    channels carry the recorded samples as they are played, the bytes and log times of the recording."""
    from sem_console.recording.reader import iter_messages

    raw = "UMAA::SEM::GPSFixStatus::GPSFixReport"
    recording = synthetic_recording(tmp_path / "rec", seconds=8)
    recorded = {(m.log_time, bytes(m.data)) for _topic, m in iter_messages(recording, {raw})}
    r = console("--replay", str(recording), "--replay-speed", "0.25", "--foxglove-port", str(free_port()))
    seen: list[dict[str, Any]] = []
    fleet: list[tuple[int, float]] = []  # each LocationFixes' log time (ns), and the latest report's receivedAt then
    played: list[tuple[int, bytes]] = []  # the raw channel's messages

    def take(m: Any) -> bool:
        if m is not None and m.topic == "/reports/GPSFixReport":
            seen.append(m.json())
        elif m is not None and m.topic == "/fleet/locations" and seen:
            fleet.append((m.log_time, seen[-1]["receivedAt"]))
        elif m is not None and m.topic == raw:
            played.append((m.log_time, m.data))
        return len(fleet) >= 2 and len(played) >= 2

    async def session() -> None:
        async with connect(gateway(r.url)["endpoint"]) as client:
            await until(client, lambda _m: "/reports/GPSFixReport" in client.topics(), 20, "the GPSFixReport channel")
            await client.subscribe(["/reports/GPSFixReport", "/fleet/locations", raw])
            await until(client, take, 20, "replayed GPSFixReports, two LocationFixes of the fleet, two raw samples")

    asyncio.run(session())
    assert seen[0]["providerId"] == V1
    assert set(played) <= recorded and len(set(played)) == len(played), played
    # the replay plays a report each second (a quarter of the recording's 4 a second)
    assert all(abs(log_time / 1e9 - received) < 1.5 for log_time, received in fleet), fleet


def test_a_foxglove_client_cannot_publish_call_a_service_or_set_a_parameter(sim, console) -> None:
    sim("--vehicles", "1")
    c = console("--foxglove-port", str(free_port()))
    provider_ready(c.url, V1, {"GPSFixReport"})
    endpoint = gateway(c.url)["endpoint"]

    async def session() -> list[dict[str, Any]]:
        async with connect(endpoint) as client:
            await until(client, lambda _m: "/console/log" in client.topics(), 10, "the log channel")
            command = {"op": "advertise", "channels": [{"id": 7, "topic": f"/vehicles/{V1}/gps-fix", "encoding": "json"}]}
            await client.send_json({**command, "channels": [{**command["channels"][0], "schemaName": "gps-fix"}]})
            await client.publish(7, json.dumps({"providerId": V1}).encode())
            await client.call_service(1, 1, "json", b"{}")
            await client.send_json({"op": "setParameters", "parameters": [{"name": "vehicle", "value": V1}]})
            await until(client, lambda _m: len(client.statuses) >= 4, 10, "four refusals")
            return client.statuses

    statuses = asyncio.run(session())
    said = [s.get("message", "") for s in statuses]
    assert any("does not support clientPublish" in x for x in said), said
    assert any(s["op"] == "serviceCallFailure" and "does not support services" in s["message"] for s in statuses), said
    assert any("does not support parameters" in x for x in said), said
    time.sleep(1)
    assert http.get(f"{c.url}/api/commands").json() == []  # nothing reached the console, nor any vehicle
    assert gateway(c.url)["lastError"] is None


def test_a_foxglove_port_in_use_is_one_line(domain: int, tmp_path) -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        port = s.getsockname()[1]
        line = refused(["--db", str(tmp_path / "db"), "--foxglove-port", str(port)], domain)
    assert f"TCP 127.0.0.1:{port} is already in use" in line and "pass another --foxglove-port" in line, line


def test_a_foxglove_host_the_server_cannot_take_is_one_line(domain: int, tmp_path) -> None:
    """An empty address is every interface to the start's check of the port, and none to foxglove-sdk's server."""
    line = refused(["--db", str(tmp_path / "db"), "--foxglove-port", str(free_port()), "--foxglove-host", ""], domain)
    assert line.startswith("sem-console: error: --foxglove-host: an empty address: give one"), line


# A client that stopped reading (a laptop asleep at the end of an SSH tunnel): megabytes of reports wait for it in its
# socket. The gateway is run in a process of its own, so that a stop that never returns cannot hold the tests' process.
STALLED_CLIENT = """
import asyncio, os, sys, time, uuid
sys.path.insert(0, "tests")
from sem_console.console.feed import Feed
from sem_console.gateways.foxglove.gateway import FoxgloveGateway
from support.foxglove import connect

async def main() -> None:
    feed, vehicle = Feed(), str(uuid.uuid4())
    gateway = FoxgloveGateway(feed, int(sys.argv[1]))
    await gateway.start()
    def report() -> None:
        envelope = {"report": {"pad": "x" * 1000}, "invalid": [], "receivedAt": time.time()}
        feed.publish({"type": "report", "providerId": vehicle, "topic": "GPSReport", "report": envelope})
    report()
    async with connect(gateway.stats.endpoint) as client:
        async for _ in client.messages():
            if "/reports/GPSReport" in client.topics():
                break
        await client.subscribe(["/reports/GPSReport"])
        while not gateway.channels["/reports/GPSReport"].has_sinks():
            await asyncio.sleep(0.05)
        for _ in range(20000):  # 20 MB: more than the sockets between them hold; the client reads none of it
            report()
        started = time.monotonic()
        await gateway.stop()
        print(f"{time.monotonic() - started:.1f}", flush=True)
        os._exit(0)  # at once: closing the client that reads nothing would wait for its close handshake

asyncio.run(main())
"""


@pytest.mark.process
def test_a_client_that_stopped_reading_does_not_hold_the_consoles_shutdown() -> None:
    try:
        run = subprocess.run(
            [sys.executable, "-c", STALLED_CLIENT, str(free_port())],
            cwd=Path(__file__).resolve().parents[2],
            capture_output=True,
            text=True,
            timeout=30,
        )
    except subprocess.TimeoutExpired:
        raise AssertionError("the Foxglove gateway did not stop within 30 s") from None
    assert run.returncode == 0, run.stderr
    assert float(run.stdout.split()[-1]) < 10, run.stdout


@pytest.mark.process
def test_the_console_starts_without_foxglove_sdk_when_the_gateway_is_off() -> None:
    """foxglove-sdk (its native library, a few tens of milliseconds) is loaded only by a Foxglove gateway that runs."""
    run = subprocess.run(
        [sys.executable, "-c", "import sys, sem_console.main; print(' '.join(sorted(sys.modules)))"],
        cwd=Path(__file__).resolve().parents[2],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 0, run.stderr
    assert [m for m in run.stdout.split() if m == "foxglove" or m.startswith("foxglove.")] == []


# ---- raw SEM channels, decoded by Foxglove's own decoder ---------------------------------------------------------------
DECODER = Path(__file__).resolve().parents[1] / "support" / "omgidl_decode.cjs"
DOCS = Path(__file__).resolve().parents[3] / "docs" / "foxglove.md"


def plain(x: Any) -> Any:
    """A sample as Cyclone's Python binding deserializes it, in the plain JSON Foxglove's decoder gives (the support
    script's `plain`): enumerations as numbers, octets as arrays, absent optional members left out."""
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return {f.name: plain(v) for f in dataclasses.fields(x) if (v := getattr(x, f.name)) is not None}
    if isinstance(x, enum.Enum):
        return x.value
    if isinstance(x, (bytes, bytearray, list, tuple)):
        return [plain(v) for v in x]
    return x


def foxglove_decodes(channels: list[dict[str, Any]]) -> dict[str, Any]:
    """Foxglove's OMG IDL parser and CDR decoder, run by Node (tests/support/omgidl_decode.cjs)."""
    run = subprocess.run(["node", str(DECODER)], input=json.dumps(channels), capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    return dict(json.loads(run.stdout))


def documented_decoding() -> dict[tuple[str, str], bool]:
    """The decoder table of docs/foxglove.md: (topic, extensibility) -> whether Foxglove decodes it right."""
    rows: dict[tuple[str, str], bool] = {}
    for line in DOCS.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 4 and cells[0].startswith("`UMAA::") and cells[2] in ("final", "appendable"):
            rows[(cells[0].strip("`"), cells[2])] = cells[3].startswith("yes")
    return rows


@pytest.mark.parametrize("umaa", ["3.0.1", "6.0"])
def test_the_raw_sem_channels_decode_with_foxglove_s_own_decoder_as_the_docs_say(sim, console, umaa: str) -> None:
    """Every SEM topic of a UMAA version on its raw channel, CDR as it came off the wire with the recorder's OMG IDL:
    Foxglove's decoder (@foxglove/omgidl-serialization, as npm serves it) reads each sample as Cyclone reads it, or
    not, and docs/foxglove.md says which (its decoder table), measured here."""
    from sem_console.dds.qos import TopicClass
    from sem_console.dds.topics import Sem, Sem60, delimited

    sems = list(Sem if umaa == "3.0.1" else Sem60)
    sim("--vehicles", "1", "--umaa", umaa)
    c = console("--foxglove-port", str(free_port()))
    provider_ready(c.url, V1, {"GPSFixReport"})
    got: dict[str, list[Any]] = {s.spec.name: [] for s in sems}

    async def session() -> dict[str, dict[str, Any]]:
        async with connect(gateway(c.url)["endpoint"]) as client:
            await until(client, lambda _m: set(got) <= set(client.topics()), 10, "the raw channels")
            topics = client.topics()
            await client.subscribe(list(got))
            services = ["inertial-sensor"] if umaa == "6.0" else ["gps-fix", "inertial-sensor"]
            for service in services:  # the command, status and ack topics carry something
                body = {"state": "INIT" if umaa == "6.0" else "ON"} if service == "inertial-sensor" else {}
                r = await asyncio.to_thread(http.post, f"{c.url}/api/providers/{V1}/{service}", json=body)
                assert r.status_code < 300, r.text

            def take(m: Any) -> bool:
                if m is not None:
                    got[m.topic].append(m.data)
                return all(len(got[s.spec.name]) >= (5 if s.spec.cls is TopicClass.REPORT else 1) for s in sems)

            await until(client, take, 45, "samples on every raw channel")
            return topics

    topics = asyncio.run(session())
    by_name = {s.spec.name: s for s in sems}
    channels = []
    for name, samples in got.items():
        ad = topics[name]
        assert ad["encoding"] == "cdr" and ad["schemaEncoding"] == "omgidl", ad
        assert ad["schemaName"] == by_name[name].spec.type.__idl_typename__.replace(".", "::")
        channels.append({"schemaName": ad["schemaName"], "schema": ad["schema"], "messages": [b64(d) for d in samples]})
    out = foxglove_decodes(channels)
    measured: dict[tuple[str, str], bool] = {}
    how: dict[str, str] = {}  # what went wrong, for the message
    for (name, samples), decoded in zip(got.items(), out["channels"], strict=True):
        sem = by_name[name]
        wrong = errors = 0
        for data, d in zip(samples, decoded["decoded"], strict=True):
            assert not delimited(data)  # a Cyclone vehicle's, final: the topic's own channel
            errors += "error" in d
            wrong += "value" in d and d["value"] != plain(sem.spec.type.deserialize(data))
        measured[(name, "final")] = not wrong and not errors
        how[name] = f"{len(samples)} samples, {wrong} wrong, {errors} errors {decoded.get('error', '')}"
    documented = documented_decoding()
    table = {k: v for k, v in documented.items() if k in measured}
    assert table == measured, f"docs/foxglove.md says {table}, measured {how} (decoder {out['versions']})"


def test_comaps_world_model_is_a_geojson_channel(console) -> None:
    """The world model a console holds (here set over REST) comes on `/comap/world` as foxglove.GeoJSON, and again as
    it changes; a client subscribing late gets it within a second."""
    c = console("--foxglove-port", str(free_port()))
    square = [[-75.99, 36.85], [-75.98, 36.85], [-75.98, 36.86], [-75.99, 36.86], [-75.99, 36.85]]
    feature = {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [square]}, "properties": {"featureId": 7}}
    assert http.put(f"{c.url}/api/worldmodel", json={"type": "FeatureCollection", "features": [feature]}).status_code == 200
    worlds: list[dict[str, Any]] = []

    async def session() -> None:
        async with connect(gateway(c.url)["endpoint"]) as client:
            await until(client, lambda _m: "/comap/world" in client.topics(), 10, "the world model's channel")
            assert client.topics()["/comap/world"]["schemaName"] == "foxglove.GeoJSON"
            await client.subscribe(["/comap/world"])
            await until(client, lambda m: m is not None and not worlds.append(json.loads(m.json()["geojson"])), 5, "it")
            feature["properties"] = {"featureId": 8}
            put = {"type": "FeatureCollection", "features": [feature]}
            assert (await asyncio.to_thread(http.put, f"{c.url}/api/worldmodel", json=put)).status_code == 200

            def changed(m: Any) -> bool:
                if m is not None:
                    worlds.append(json.loads(m.json()["geojson"]))
                return worlds[-1]["features"][0]["properties"]["featureId"] == 8

            await until(client, changed, 5, "the changed world model")

    asyncio.run(session())
    first, last = worlds[0], worlds[-1]
    rest = http.get(f"{c.url}/api/worldmodel").json()
    assert first["type"] == "FeatureCollection" and first["features"][0]["properties"]["featureId"] == 7
    assert first["features"][0]["geometry"] == {"type": "Polygon", "coordinates": [square]}
    assert last == {"type": "FeatureCollection", "features": rest["features"]}


def test_foxglove_s_playback_control_drives_the_consoles_replay(console, tmp_path: Path) -> None:
    """With --replay the server offers playback control over the recording's span: a client's pause and seek move the
    console's replay (what REST and the dashboard show), its speed too; the dashboard's seek comes back to the
    client as the playback state, as a seek: both views at one instant."""
    from support.foxglove import PAUSE, PAUSED, PLAY

    recording = synthetic_recording(tmp_path / "rec", seconds=20, rate=2)
    r = console("--replay", str(recording), "--foxglove-port", str(free_port()))
    status = http.get(f"{r.url}/api/replay").json()
    start, end = status["start"], status["end"]
    middle = round((start + (end - start) / 2) * 1e9)

    async def session() -> dict[str, Any]:
        async with connect(gateway(r.url)["endpoint"]) as client:
            await until(client, lambda _m: bool(client.server_info), 10, "the server's info")
            info = client.server_info
            await client.playback_control(PAUSE, 1.0, middle, "seek-1")
            await until(client, lambda _m: any(s.request_id == "seek-1" for s in client.playback), 10, "the seek's state")
            sought = await asyncio.to_thread(lambda: http.get(f"{r.url}/api/replay").json())
            answer = next(s for s in client.playback if s.request_id == "seek-1")
            await client.playback_control(PLAY, 2.0, None, "play-2")
            await until(client, lambda _m: any(s.request_id == "play-2" for s in client.playback), 10, "the play's state")
            playing = await asyncio.to_thread(lambda: http.get(f"{r.url}/api/replay").json())
            # the dashboard seeks back to the start, paused: the client is told
            await asyncio.to_thread(http.post, f"{r.url}/api/replay", json={"action": "pause"})
            mark = len(client.playback)
            await asyncio.to_thread(http.post, f"{r.url}/api/replay", json={"action": "seek", "position": start}, timeout=30)
            back = round(start * 1e9)
            await until(client, lambda _m: client.playback[-1].time == back, 10, "the dashboard's seek")
            there = next(s for s in client.playback[mark:] if s.time == back)
            return {"info": info, "sought": sought, "answer": answer, "playing": playing, "last": there}

    got = asyncio.run(session())
    assert "playbackControl" in got["info"]["capabilities"], got["info"]
    assert got["sought"]["state"] == "paused" and abs(got["sought"]["position"] - middle / 1e9) < 1e-6, got["sought"]
    assert got["answer"].status == PAUSED and got["answer"].did_seek and abs(got["answer"].time - middle) < 1000
    assert got["playing"]["state"] == "playing" and got["playing"]["speed"] == 2.0, got["playing"]
    assert got["last"].status == PAUSED and got["last"].did_seek, got["last"]  # a seek, whoever asked: Foxglove is told


@pytest.mark.parametrize("umaa", ["3.0.1", "6.0"])
def test_an_appendable_writers_samples_have_their_own_raw_channel_as_the_docs_say(console, domain: int, umaa: str) -> None:
    """An RTI vehicle's GPSReport, GPSFixReport and GlobalPose (an appendable writer: delimited XCDR2) come on a raw
    channel of their own topic (`<DDS name>/appendable`: Foxglove's player takes one channel a topic), whose schema has
    every struct @appendable (as in a recording); Foxglove's decoder reads them as the docs' decoder table says (random
    samples: every optional member set or not)."""
    from sem_console.dds.bus import Bus
    from sem_console.dds.topics import Sem, Sem60, delimited
    from sem_console.gateways.foxglove.gateway import APPENDABLE_TOPIC
    from support.samplegen import random_sample

    sems = [Sem.GPS_REPORT, Sem.GPS_FIX_REPORT] if umaa == "3.0.1" else [Sem60.GLOBAL_POSE_REPORT]
    c = console("--foxglove-port", str(free_port()))
    bus = Bus(domain)
    rng = random.Random(5)
    try:
        writers = {sem: bus.writer(sem, appendable=True) for sem in sems}

        def write() -> None:
            for sem, w in writers.items():
                for _ in range(3):
                    assert sem.spec.appendable is not None
                    w.write(random_sample(sem.spec.appendable, rng))

        got: dict[str, list[bytes]] = {s.spec.name: [] for s in sems}

        async def session() -> dict[str, dict[str, Any]]:
            async with connect(gateway(c.url)["endpoint"]) as client:
                write()  # the first sample of each opens its appendable channel

                def appendable() -> dict[int, dict[str, Any]]:
                    return {i: ch for i, ch in client.channels.items() if ch.get("metadata", {}).get("extensibility")}

                await until(client, lambda _m: len(appendable()) == len(sems), 10, "the appendable channels")
                channels = appendable()
                advertised = [ch["topic"] for ch in client.channels.values()]
                # one channel a topic: Foxglove's player shows none of a second channel of a topic
                assert len(advertised) == len(set(advertised)), sorted(advertised)
                assert {ch["topic"] for ch in channels.values()} == {name + APPENDABLE_TOPIC for name in got}
                dds = {i: ch["topic"].removesuffix(APPENDABLE_TOPIC) for i, ch in channels.items()}
                await client.subscribe_channels(dds)

                async def writing() -> None:  # until enough came (the subscription takes effect at some point)
                    while True:
                        write()
                        await asyncio.sleep(0.5)

                def take(m: Any) -> bool:
                    if m is not None:
                        got[m.topic].append(m.data)
                    return all(len(v) >= 6 for v in got.values())

                writer = asyncio.create_task(writing())
                try:
                    await until(client, take, 20, "six samples on each appendable channel")
                except AssertionError:
                    raise AssertionError(({k: len(v) for k, v in got.items()}, client.statuses)) from None
                finally:
                    writer.cancel()
                return {dds[i]: ch for i, ch in channels.items()}

        topics = asyncio.run(session())
    finally:
        bus.close()
    by_name = {s.spec.name: s for s in sems}
    channels = []
    for name, samples in got.items():
        ad = topics[name]
        assert ad["encoding"] == "cdr" and "@appendable" in ad["schema"] and "@final" not in ad["schema"], name
        assert all(delimited(d) for d in samples)
        channels.append({"schemaName": ad["schemaName"], "schema": ad["schema"], "messages": [b64(d) for d in samples]})
    out = foxglove_decodes(channels)
    measured: dict[tuple[str, str], bool] = {}
    how: dict[str, str] = {}
    for (name, samples), decoded in zip(got.items(), out["channels"], strict=True):
        appendable_type = by_name[name].spec.appendable
        assert appendable_type is not None
        errors = sum("error" in d for d in decoded["decoded"])
        wrong = sum(
            "value" in d and d["value"] != plain(appendable_type.deserialize(data))
            for data, d in zip(samples, decoded["decoded"], strict=True)
        )
        measured[(name, "appendable")] = not wrong and not errors
        how[name] = f"{len(samples)} samples, {wrong} wrong, {errors} errors {decoded.get('error', '')}"
    table = {k: v for k, v in documented_decoding().items() if k in measured}
    assert table == measured, f"docs/foxglove.md says {table}, measured {how} (decoder {out['versions']})"
