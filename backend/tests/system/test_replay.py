"""Replay in the console (`sem-console --replay FILE.mcap`): a live simulator run with a GPS fix command is
recorded through the recording feature, then a second console serves that file. It must show what the live
console showed (the same reports, byte for byte decoded alike, and the same command timeline), rebuild the
state when seeking, follow the speed, and refuse anything that would command or record."""

from __future__ import annotations

import json
import math
import random
import subprocess
import sys
import time
import uuid
from pathlib import Path
from typing import Any

import pytest
from cyclonedds.core import InstanceState
from mcap.exceptions import McapError

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as St
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Rs
from UMAA.SEM.GPSFixControl import GPSFixCommandStatusType

from sem_console.codec.decode import REPORT_TOPICS, Decoder
from sem_console.console.replay_source import Cursor, RecordedName
from sem_console.dds.topics import Sem
from sem_console.recording.reader import iter_messages, recorded_station, time_range
from sem_console.recording.recorder import Recorder
from sem_console.umaa.guid import to_guid
from sem_console.umaa.samples import now_datetime
from support import http, warm
from support.samplegen import random_sample
from test_console import HAPPY, V1, V2, WsClient, command, provider_ready, wait_command, wait_until
from test_recording import read, recorded

JSON = {"Content-Type": "application/json"}


def control(base: str, body: dict[str, Any]) -> dict[str, Any]:
    r = http.post(f"{base}/api/replay", json=body, timeout=30)
    assert r.status_code == 200, r.text
    return dict(r.json())


def replay_state(base: str) -> dict[str, Any]:
    return dict(http.get(f"{base}/api/replay").json())


@pytest.fixture
def recorded_run(sim, console, tmp_path: Path) -> dict[str, Any]:
    """A live run recorded to MCAP: the vehicle before and after a GPS fix command, what the live console
    showed at the end (REST), and the file."""
    sim()
    c = console("--record", str(tmp_path / "rec"))
    provider_ready(c.url, V1)
    time.sleep(1.0)
    session = http.post(f"{c.url}/api/providers/{V1}/gps-fix", json={}).json()["sessionId"]
    done = wait_command(c.url, session)
    assert [t["status"] for t in done["transitions"]] == HAPPY
    time.sleep(1.5)
    live = http.get(f"{c.url}/api/providers/{V1}").json()
    # a live console has no playback: GET gives null, the controls a 409
    assert http.get(f"{c.url}/api/replay").json() is None
    r = http.post(f"{c.url}/api/replay", json={"action": "pause"})
    assert r.status_code == 409 and "--replay" in r.json()["detail"]
    assert http.get(f"{c.url}/api/health").json()["replay"] is False
    path = recorded(c.url, tmp_path)
    c.stop()
    return {"path": path, "session": session, "live": live, "command": command_of(done)}


def command_of(c: dict[str, Any]) -> dict[str, Any]:
    """What a replay must reproduce of a command: everything but when the console applied each status."""
    return {**c, "transitions": [{k: v for k, v in t.items() if k != "receivedAt"} for t in c["transitions"]], "ackedAt": None}


def test_replay_shows_the_recorded_vehicle_and_command_and_seeks(recorded_run: dict[str, Any], console) -> None:
    session, live = recorded_run["session"], recorded_run["live"]
    r = console("--replay", str(recorded_run["path"]))
    assert http.get(f"{r.url}/api/health").json()["replay"] is True
    state = replay_state(r.url)
    assert state["file"] == recorded_run["path"].name and state["state"] == "playing" and state["speed"] == 1
    start, end = state["start"], state["end"]
    assert start < end and start <= state["position"] <= end
    ws = WsClient(r.ws_url)
    wait_until(lambda: ws.of("replay"), 5, "a replay message while playing")
    assert ws.messages[0]["type"] == "snapshot" and ws.messages[0]["replay"]["file"] == recorded_run["path"].name

    # at the instant the live console last took each report, the replay shows that very report
    for topic in ("GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"):
        at = live["reports"][topic]["receivedAt"]
        assert start <= at <= end
        control(r.url, {"action": "pause"})
        to = min(end, at + 0.0005)
        assert control(r.url, {"action": "seek", "position": to})["position"] == pytest.approx(to)
        shown = http.get(f"{r.url}/api/providers/{V1}").json()
        assert shown["reports"][topic] == live["reports"][topic], topic
    satellites = {s["satelliteId"] for s in live["reports"]["GPSReport"]["report"]["satellites"]}
    assert len(satellites) >= 20

    # the same command timeline, rebuilt from the recorded statuses (with their Figure 4 verdicts)
    control(r.url, {"action": "seek", "position": end})
    replayed = http.get(f"{r.url}/api/commands").json()
    assert [c["sessionId"] for c in replayed] == [session]
    assert command_of(replayed[0]) == recorded_run["command"]
    assert replayed[0]["ackedAt"] is not None and replayed[0]["cleanedUp"]
    times = [t["receivedAt"] for t in replayed[0]["transitions"]]
    assert times == sorted(times) and start <= times[0] and times[-1] <= end

    # the track and chart history played so far reach the end
    def history(kind: str) -> list[float]:
        got = http.get(f"{r.url}/api/providers/{V1}/{kind}")
        assert got.status_code == 200, got.text
        return [p["time"] for p in got.json()]

    assert max(history("track")) > replayed[0]["createdAt"] and max(history("series")) > replayed[0]["createdAt"]

    # seek back before the command: it is absent; between EXECUTING and COMPLETED: EXECUTING; at the end: done
    back = replayed[0]["createdAt"] - 0.2
    control(r.url, {"action": "seek", "position": back})
    assert http.get(f"{r.url}/api/commands").json() == []
    for kind in ("track", "series"):  # nothing after the instant shown, and what came before it is kept
        kept = history(kind)
        assert kept and max(kept) <= back, kind
    assert http.get(f"{r.url}/api/commands/{session}").status_code == 404
    assert http.get(f"{r.url}/api/providers/{V1}").status_code == 200
    control(r.url, {"action": "seek", "position": (times[2] + times[3]) / 2})
    midway = command(r.url, session)
    assert [t["status"] for t in midway["transitions"]] == HAPPY[:3] and not midway["terminal"]
    snapshot = wait_until(
        lambda: [m for m in ws.of("snapshot") if m["commands"] and m["commands"][0]["status"] == "EXECUTING"],
        5,
        "a fresh snapshot after the seek",
    )[-1]
    assert snapshot["replay"]["position"] == pytest.approx((times[2] + times[3]) / 2)
    control(r.url, {"action": "seek", "position": end + 100})  # beyond the end: the end
    assert replay_state(r.url)["position"] == end
    assert command(r.url, session)["status"] == "COMPLETED"
    for kind in ("track", "series"):  # played, sought back, rebuilt, played: still at most one point a second
        seconds = [math.floor(x) for x in history(kind)]
        assert seconds and len(seconds) == len(set(seconds)), kind
    assert ws.errors == []
    ws.close()


def test_replay_speed_pause_and_play_from_the_end(recorded_run: dict[str, Any], console) -> None:
    r = console("--replay", str(recorded_run["path"]), "--replay-speed", "0.25")
    state = replay_state(r.url)
    start, end = state["start"], state["end"]
    assert end - start > 2.5 and state["speed"] == 0.25

    def advance(speed: float) -> float:
        control(r.url, {"action": "pause"})
        control(r.url, {"action": "seek", "position": start})
        control(r.url, {"action": "speed", "speed": speed})
        before = control(r.url, {"action": "play"})["position"]
        time.sleep(1.0)
        return float(control(r.url, {"action": "pause"})["position"] - before)

    slow, fast = advance(0.25), advance(2)
    assert 0 < slow < 0.6 and fast > 1.0 and fast / slow > 3, (slow, fast)
    paused = replay_state(r.url)
    time.sleep(0.5)
    assert replay_state(r.url) == paused and paused["state"] == "paused"
    # played to the end it pauses there; play starts again from the start
    control(r.url, {"action": "seek", "position": end - 0.2})
    control(r.url, {"action": "speed", "speed": 20})
    control(r.url, {"action": "play"})
    wait_until(lambda: replay_state(r.url)["state"] == "paused", 5, "the replay paused at the end")
    assert replay_state(r.url)["position"] == end
    again = control(r.url, {"action": "play"})
    assert again["state"] == "playing" and again["position"] < start + 2
    # bad controls: a clear 422, nothing changes
    for body in (
        {"action": "speed", "speed": 40},
        {"action": "rewind"},
        {"action": "seek"},
        {"action": "speed", "speed": "fast"},
    ):
        bad = http.post(f"{r.url}/api/replay", json=body)
        assert bad.status_code == 422 and bad.json()["detail"], body
    assert http.post(f"{r.url}/api/replay", content=b'{"action":"pause"}').status_code == 415
    assert (
        http.post(f"{r.url}/api/replay", json={"action": "pause"}, headers={"Origin": "http://evil.example"}).status_code == 403
    )


def test_replay_is_read_only(recorded_run: dict[str, Any], console) -> None:
    r = console("--replay", str(recorded_run["path"]))
    control(r.url, {"action": "seek", "position": replay_state(r.url)["end"]})
    session = recorded_run["session"]
    refused = [
        http.post(f"{r.url}/api/providers/{V1}/gps-fix", json={}),
        http.post(f"{r.url}/api/providers/{V1}/inertial-sensor", json={"state": "OFF"}),
        http.delete(f"{r.url}/api/commands/{session}"),
        http.post(f"{r.url}/api/recordings", json={"action": "start"}),
        http.put(
            f"{r.url}/api/providers/{V1}/link-config",
            json={"commsLostTimeout": 3, "regainedTime": 3, "policy": "STOP_MISSION", "regainedBehavior": 0},
        ),
        http.put(f"{r.url}/api/providers/{V1}/name", json={"name": "Bravo"}),
        http.put(f"{r.url}/api/worldmodel", json={"type": "FeatureCollection", "features": []}),
        http.post(f"{r.url}/api/tasks", json={"kind": "move", "vehicle": V1, "point": {"lat": 36.8, "lon": -75.7}}),
        http.post(f"{r.url}/api/tasks/1/synch", json={"action": "HOLD"}),
    ]
    for x in refused:
        assert x.status_code == 409 and x.json()["detail"].startswith("read-only: this console replays"), x.text
    assert http.get(f"{r.url}/api/recordings/status").json()["state"] == "off"
    assert [c["sessionId"] for c in http.get(f"{r.url}/api/commands").json()] == [session]
    audit = http.get(f"{r.url}/api/audit").json()
    assert [(a["outcome"], a["status"]) for a in audit] == [("refused", 409)] * len(refused)
    assert http.get(f"{r.url}/api/tasks").json() == []  # nothing assigned
    # the OpenAPI document of a replay says so
    doc = http.get(f"{r.url}/openapi.json").json()
    assert "read-only" in doc["paths"]["/api/providers/{provider_id}/gps-fix"]["post"]["responses"]["409"]["description"]
    assert "read-only" in doc["paths"]["/api/recordings"]["post"]["responses"]["409"]["description"]


def test_replay_options_are_checked(tmp_path: Path) -> None:
    not_mcap = tmp_path / "notes.mcap"
    not_mcap.write_text("hello")
    for args, needle in (
        (["--replay", str(tmp_path / "missing.mcap")], "cannot read"),
        (["--replay", str(not_mcap)], "is not an MCAP file"),
        (["--replay", str(not_mcap), "--sim", "1"], "does not go with --sim or --record"),
        (["--replay", str(not_mcap), "--imc-port", "4001"], "does not go with --imc-port"),
        (["--replay", str(not_mcap), "--replay-speed", "50"], "--replay-speed"),
    ):
        p = warm.run(warm.CONSOLE, args)
        assert p.returncode == 2 and needle in p.stderr and "Traceback" not in p.stderr, (args, p.stderr)


def synthetic_recording(directory: Path, seconds: float = 4.0, rate: float = 4.0) -> Path:
    """A small recording written by the console's own recorder from random report samples of one vehicle and
    a GPS fix command it never answered (no DDS): for tests of the replay's HTTP contract."""
    rng = random.Random(11)
    recorder = Recorder(directory, 1 << 30, 3600)
    recorder.start()
    t0 = time.time_ns()
    recorder.on_message(
        {
            "type": "command",
            "command": {
                "sessionId": str(uuid.UUID(int=rng.getrandbits(128), version=4)),
                "service": "GPSFix",
                "providerId": V1,
                "state": None,
                "operator": None,
                "createdAt": t0 / 1e9,
                "status": None,
                "terminal": False,
                "unanswered": False,
                "cancelRequested": False,
                "canceledBy": None,
                "ackedAt": None,
                "cleanedUp": False,
                "violations": [],
                "transitions": [],
            },
        }
    )
    for i in range(int(seconds * rate)):
        at = t0 + int(i * 1e9 / rate)
        for sem in REPORT_TOPICS:
            sample = random_sample(sem.spec.type, rng)
            sample.source = to_guid(uuid.UUID(V1))
            recorder.on_samples(sem, [(sample.serialize(use_version_2=sem.spec.xcdr2_only), True, InstanceState.Alive, at)], at)
    recorder.stop()
    (path,) = directory.glob("*.mcap")
    return path


def test_a_recording_cut_short_replays_up_to_where_it_stops(console, tmp_path: Path) -> None:
    """A console killed while recording leaves a file without its summary (`incomplete`). Its time span was read
    in log time order, which the reader sorts only at the end of the file, never reached: the replay showed
    0.0 s of recording and nothing. Here a file cut after its last chunk (before its summary), as a kill leaves it."""
    path = synthetic_recording(tmp_path / "rec")
    data = path.read_bytes()
    at = 8  # the magic; then records: opcode (1 byte), length (u64 LE), body
    while data[at] != 0x0F:  # DataEnd: everything after it is the summary a killed console never writes
        at += 9 + int.from_bytes(data[at + 1 : at + 9], "little")
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[:at])
    r = console("--replay", str(cut), "--replay-speed", "20")
    playback = replay_state(r.url)
    assert playback["start"] > 0 and playback["end"] - playback["start"] > 3  # the 4 s of reports written
    wait_until(lambda: replay_state(r.url)["state"] == "paused", 10, "the end of the replay")
    assert http.get(f"{r.url}/api/metrics").json()["samplesDecoded"] == 64


def test_a_synthetic_recording_replays(console, tmp_path: Path) -> None:
    r = console("--replay", str(synthetic_recording(tmp_path / "rec")), "--replay-speed", "20")
    wait_until(lambda: replay_state(r.url)["state"] == "paused", 10, "the end of the replay")
    detail = http.get(f"{r.url}/api/providers/{V1}").json()
    assert all(detail["reports"][t] for t in ("GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"))
    assert http.get(f"{r.url}/api/metrics").json()["samplesDecoded"] == 64
    (cmd,) = http.get(f"{r.url}/api/commands").json()
    assert cmd["service"] == "GPSFix" and cmd["unanswered"] and cmd["transitions"] == []  # no ISSUED within 2 s


@pytest.mark.parametrize("recorded_by", ["watch", "relief", None])
def test_another_stations_command_recorded_after_its_statuses_replays_as_it_went(
    console, tmp_path: Path, recorded_by: str | None
) -> None:
    """Another station's command reaches the recording console by the database's notification, after the vehicle's
    first statuses (long after them when that station's write was held in an outage). The replay applies those
    statuses when the command comes: FAILED as live, not a command with no status and an 'unanswered' alarm that
    the live console never raised. Its alarm ('command-failed') only where the live console had it: a replay of
    watch's recording raised alarms for relief's commands, which watch showed but never alarmed on; the file names
    its station (a file without one, from before: every command counts as the recording console's)."""
    directory = tmp_path / "rec"
    recorder = Recorder(directory, 1 << 30, 3600, station=recorded_by)
    recorder.start()
    session = uuid.uuid4()
    t0 = time.time_ns() - 3_000_000_000
    for i, (status, reason) in enumerate(((St.ISSUED, Rs.SUCCEEDED), (St.FAILED, Rs.RESOURCE_REJECTED))):
        sample = GPSFixCommandStatusType(
            source=to_guid(uuid.UUID(V1)),
            sessionID=to_guid(session),
            commandStatus=status,
            commandStatusReason=reason,
            logMessage="rejected",
            timeStamp=now_datetime(),
        )
        at = t0 + i * 20_000_000
        recorder.on_samples(Sem.GPS_FIX_COMMAND_STATUS, [(sample.serialize(), True, InstanceState.Alive, at)], at)
    recorder.on_message(
        {
            "type": "command",
            "command": {  # as relief's command reached watch, with what relief saw
                "sessionId": str(session),
                "service": "GPSFix",
                "providerId": V1,
                "state": None,
                "operator": None,
                "createdAt": t0 / 1e9 - 0.01,
                "status": "FAILED",
                "terminal": True,
                "unanswered": False,
                "cancelRequested": False,
                "canceledBy": None,
                "ackedAt": None,
                "cleanedUp": False,
                "console": "relief",
                "violations": [],
                "transitions": [],
            },
        }
    )
    recorder.stop()
    (path,) = directory.glob("*.mcap")
    r = console("--replay", str(path), "--replay-speed", "20")
    wait_until(lambda: replay_state(r.url)["state"] == "paused", 10, "the end of the replay")
    (cmd,) = http.get(f"{r.url}/api/commands").json()
    assert [t["status"] for t in cmd["transitions"]] == ["ISSUED", "FAILED"] and cmd["console"] == "relief"
    assert not cmd["unanswered"]
    kinds = [a["kind"] for a in http.get(f"{r.url}/api/alarms").json()]  # and link-lost: the recording ends 3 s later
    assert ("command-failed" in kinds) == (recorded_by != "watch") and "command-unanswered" not in kinds
    assert recorded_station(path) == recorded_by


def test_a_damaged_recording_is_one_line_not_a_traceback(domain: int, tmp_path: Path) -> None:
    """A chunk whose zstd data is damaged raised ZstdError through the readers: a traceback from sem-replay, and
    `sem-console --replay` failed its start-up. It ends the reading with one McapError that says so."""
    path = synthetic_recording(tmp_path / "rec")
    raw = bytearray(path.read_bytes())
    frame = raw.index(b"\x28\xb5\x2f\xfd")  # the first chunk's zstd frame
    raw[frame + 40 : frame + 120] = bytes(80)
    damaged = tmp_path / "damaged.mcap"
    damaged.write_bytes(raw[:-200])  # without its summary, as after a crash: read from the start
    with pytest.raises(McapError, match=r"a damaged chunk or record \("):
        list(iter_messages(damaged, {"sem-console/commands", *(sem.spec.name for sem in REPORT_TOPICS)}))
    whole, read = time_range(path), time_range(damaged)  # what reads before the damage (file order), if anything
    assert whole is not None and (read is None or whole[0] <= read[0] <= read[1] <= whole[1])
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(path.read_bytes()[:frame])
    with pytest.raises(McapError, match="the file is cut short"):
        list(iter_messages(cut, {"sem-console/commands"}))
    p = subprocess.run(
        [sys.executable, "-m", "sem_console.recording.sem_replay", "--domain", str(domain), "--wait", "0", str(damaged)],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    assert "the recording ends early: a damaged chunk or record (" in p.stderr


@pytest.mark.parametrize(
    "args, says",
    [
        (["--speed", "inf"], "--speed: inf is outside 0.01..1000"),
        (["--wait", "nan"], "--wait: nan is outside 0..3600"),
        (["--domain", "233"], "--domain: 233 is outside 0..232"),
    ],
)
def test_sem_replay_refuses_a_value_out_of_range_in_one_line(args: list[str], says: str, tmp_path: Path) -> None:
    """--speed inf published the whole file at once and --wait nan waited on; both were taken."""
    p = subprocess.run(
        [sys.executable, "-m", "sem_console.recording.sem_replay", str(tmp_path / "x.mcap"), "--domain", "1", *args],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and says in p.stderr, p.stderr


def names_recorded(path: Path) -> list[tuple[int, dict[str, Any]]]:
    """(log time, message) of the file's `sem-console/names`, read with the mcap library."""
    return [(m.log_time, json.loads(m.data)) for m in read(path)[1]["sem-console/names"]]


def recorded_messages(base: str) -> int:
    return int(http.get(f"{base}/api/recordings/status").json()["messages"])


@pytest.mark.slow
def test_a_replay_names_the_vehicles_as_the_recording_station_did(sim, console, tmp_path: Path) -> None:
    """A replay named the vehicles by the replaying console's own --vehicle-names only: the names an operator set from
    the dashboard (before the recording started, or while it ran) were not in the file, so a live 'Tug Two: link lost'
    replayed as '<short id>: link lost'. The file holds the names in force at its start and each rename; a replay
    applies them at their instants (a seek gives the names of the instant sought), over its own --vehicle-names."""
    first = sim()
    sim("--first-vehicle", "2", "--state-file", str(tmp_path / "sim2.json"))  # V2 goes on when V1 is lost
    c = console("--vehicle-names", f"{V1}=Alpha")
    provider_ready(c.url, V1)
    provider_ready(c.url, V2)
    assert http.put(f"{c.url}/api/providers/{V1}/name", json={"name": "Tug One"}).json()["name"] == "Tug One"
    assert http.post(f"{c.url}/api/recordings", json={"action": "start"}).json()["state"] == "recording"
    wait_until(lambda: recorded_messages(c.url) > 50, 15, "samples recorded")
    before_rename = time.time()
    assert http.put(f"{c.url}/api/providers/{V1}/name", json={"name": "Tug Two"}).json()["name"] == "Tug Two"
    first.kill()
    lost = wait_until(
        lambda: [a for a in http.get(f"{c.url}/api/alarms").json() if a["kind"] == "link-lost"], 15, "V1's link lost"
    )
    assert [a["text"] for a in lost] == ["Tug Two: link lost"]
    then = recorded_messages(c.url)  # V2's samples a while longer: the replay's tick finds V1 lost before the end
    wait_until(lambda: recorded_messages(c.url) > then + 100, 15, "more samples recorded")
    path = recorded(c.url, tmp_path)
    c.stop()
    names = names_recorded(path)
    assert [(n["providerId"], n["name"], n["initial"]) for _at, n in names] == [(V1, "Tug One", True), (V1, "Tug Two", False)]
    assert names[0][0] < before_rename * 1e9 < names[1][0]

    r = console("--replay", str(path), "--vehicle-names", f"{V1}=Zulu,{V2}=Yankee")
    control(r.url, {"action": "pause"})
    ws = WsClient(r.ws_url)

    def shown() -> tuple[dict[str, Any], list[str]]:
        return (
            {v: http.get(f"{r.url}/api/providers/{v}").json()["name"] for v in (V1, V2)},
            [a["text"] for a in http.get(f"{r.url}/api/alarms").json()],
        )

    control(r.url, {"action": "seek", "position": before_rename})
    assert shown() == ({V1: "Tug One", V2: "Yankee"}, [])  # V2 has no name in the recording: the replay's own
    end = replay_state(r.url)["end"]
    control(r.url, {"action": "seek", "position": end})
    assert shown() == ({V1: "Tug Two", V2: "Yankee"}, ["Tug Two: link lost"])
    snapshot = wait_until(lambda: [m for m in ws.of("snapshot") if m["replay"]["position"] == end], 5, "the end's snapshot")
    assert {p["id"]: p["name"] for p in snapshot[-1]["providers"]} == {V1: "Tug Two", V2: "Yankee"}
    control(r.url, {"action": "seek", "position": before_rename})  # back: the names of that instant again
    assert shown() == ({V1: "Tug One", V2: "Yankee"}, [])
    assert ws.errors == []
    ws.close()


@pytest.mark.slow
def test_each_file_starts_with_the_names_in_force(console, tmp_path: Path) -> None:
    """A file the recording rolled over to starts with the names in force then (those at the start and the renames
    since), so that it replays alone with them."""
    names = {V1: "Tug One", V2: "Barge"}
    recorder = Recorder(tmp_path / "rec", 1 << 30, 0.5, names=lambda: names)
    recorder.start()
    rng = random.Random(5)

    def files() -> list[Path]:
        return sorted((tmp_path / "rec").glob("*.mcap"))

    def report(n: int) -> None:  # a GPSFixReport of V1: a vehicle to name in the replay
        sample = random_sample(Sem.GPS_FIX_REPORT.spec.type, rng)
        sample.source = to_guid(uuid.UUID(V1))
        at = time.time_ns()
        recorder.on_samples(Sem.GPS_FIX_REPORT, [(sample.serialize(use_version_2=True), True, InstanceState.Alive, at)], at)

    report(0)
    recorder.on_message({"type": "vehicle-name", "providerId": V1, "name": "Tug Two", "initial": False})
    recorder.on_message({"type": "vehicle-name", "providerId": V2, "name": None, "initial": False})
    wait_until(lambda: len(files()) >= 3, 10, "two rollovers")
    report(1)
    recorder.stop()
    first, *_ = files()
    last = next(f for f in reversed(files()) if read(f)[1][Sem.GPS_FIX_REPORT.spec.name])  # the one with report(1)
    assert last != first
    assert [(n["providerId"], n["name"], n["initial"]) for _at, n in names_recorded(first)] == [
        *((v, name, True) for v, name in sorted(names.items())),
        (V1, "Tug Two", False),
        (V2, None, False),
    ]
    assert [(n["providerId"], n["name"], n["initial"]) for _at, n in names_recorded(last)] == [(V1, "Tug Two", True)]

    r = console("--replay", str(last), "--vehicle-names", f"{V1}=Zulu")
    control(r.url, {"action": "seek", "position": replay_state(r.url)["end"]})
    assert http.get(f"{r.url}/api/providers/{V1}").json()["name"] == "Tug Two"


@pytest.mark.slow
def test_a_name_before_the_vehicle_appeared_a_recorded_null_and_a_file_without_names(console, tmp_path: Path) -> None:
    """A vehicle named before it appeared is named so when it does; a recorded null (renamed back to no name) leaves it
    to the replaying console's --vehicle-names from that instant; a file without names (its recorder wrote none)
    names the vehicles by --vehicle-names only."""
    rng = random.Random(7)

    def recording(directory: Path, names: dict[str, str] | None) -> tuple[Path, int]:
        """V2 reported, renamed back to no name, reported again; the file and the first report's log time."""
        recorder = Recorder(directory, 1 << 30, 3600, names=None if names is None else lambda: names)
        recorder.start()
        times = []
        for n in range(2):
            sample = random_sample(Sem.GPS_FIX_REPORT.spec.type, rng)
            sample.source = to_guid(uuid.UUID(V2))
            times.append(time.time_ns())
            recorder.on_samples(
                Sem.GPS_FIX_REPORT, [(sample.serialize(use_version_2=True), True, InstanceState.Alive, times[-1])], times[-1]
            )
            time.sleep(0.01)  # the rename apart from both reports, so that a seek between them falls between
            if n == 0 and names is not None:
                recorder.on_message({"type": "vehicle-name", "providerId": V2, "name": None, "initial": False})
                time.sleep(0.01)
        recorder.stop()
        (path,) = directory.glob("*.mcap")
        return path, times[0]

    def name(r: Any) -> Any:
        return http.get(f"{r.url}/api/providers/{V2}").json()["name"]

    path, first = recording(tmp_path / "named", {V2: "Barge"})
    (_start, initial), (renamed_at, renamed) = names_recorded(path)
    assert (initial["name"], initial["initial"], renamed["name"], renamed["initial"]) == ("Barge", True, None, False)
    r = console("--replay", str(path), "--vehicle-names", f"{V2}=Yankee")
    control(r.url, {"action": "pause"})
    control(r.url, {"action": "seek", "position": (first + renamed_at) / 2e9})  # V2 seen, not yet renamed
    assert name(r) == "Barge"
    control(r.url, {"action": "seek", "position": replay_state(r.url)["end"]})
    assert name(r) == "Yankee"
    r.stop()

    old, _first = recording(tmp_path / "old", None)
    assert names_recorded(old) == []
    r = console("--replay", str(old), "--vehicle-names", f"{V2}=Yankee")
    control(r.url, {"action": "seek", "position": replay_state(r.url)["end"]})
    assert name(r) == "Yankee"


def test_a_rename_is_recorded_even_with_the_buffer_full(tmp_path: Path) -> None:
    """A full buffer drops takes (counted in `dropped`); it dropped a rename as well, and a replay then named the vehicle
    as before it for the rest of the recording (each file the recording rolled over to started so too). A rename is
    never dropped."""
    recorder = Recorder(tmp_path / "rec", 1 << 30, 3600, queue_size=0)  # full from the start: every take is dropped
    recorder.start()
    sample = random_sample(Sem.GPS_FIX_REPORT.spec.type, random.Random(3))
    at = time.time_ns()
    recorder.on_samples(Sem.GPS_FIX_REPORT, [(sample.serialize(use_version_2=True), True, InstanceState.Alive, at)], at)
    recorder.on_message({"type": "vehicle-name", "providerId": V1, "name": "Tug Two", "initial": False})
    assert recorder.stop()["dropped"] == 1
    (path,) = (tmp_path / "rec").glob("*.mcap")
    assert [(n["providerId"], n["name"]) for _at, n in names_recorded(path)] == [(V1, "Tug Two")]


def test_a_recorded_name_of_the_wrong_shape_is_skipped(tmp_path: Path) -> None:
    """A names message whose providerId is not a string (a file another tool wrote) raised an AttributeError out of the
    replay's read: the batch read with it was lost while playing, and a seek answered 500. It is skipped, counted and
    logged, as a message of the wrong shape on the other JSON channels is."""
    recorder = Recorder(tmp_path / "rec", 1 << 30, 3600)
    recorder.start()
    recorder.on_message({"type": "vehicle-name", "providerId": 5, "name": "Tug One", "initial": False})
    recorder.on_message({"type": "vehicle-name", "providerId": V1, "name": "Tug Two", "initial": False})
    recorder.stop()
    (path,) = (tmp_path / "rec").glob("*.mcap")
    cursor = Cursor(path, Decoder())
    try:
        read_items = [item for _at, item in cursor.read_until(2**63)]
    finally:
        cursor.close()
    assert read_items == [RecordedName(uuid.UUID(V1), "Tug Two")] and cursor.skipped == 1
