"""Recording to MCAP and `sem-replay`, over real DDS with real `sem-sim` and `sem-console` processes.

The files are read back with the `mcap` library and decoded with Python types that Cyclone's idlc
builds from the schema text in the file, never with the recorder's code.
"""

from __future__ import annotations

import base64
import json
import os
import random
import re
import signal
import subprocess
import sys
import textwrap
import threading
import time
import uuid
from collections import defaultdict
from pathlib import Path
from typing import Any

import pytest
from cyclonedds.core import InstanceState
from mcap.reader import make_reader

from conftest import ConsoleProcess, free_domain
from sem_console import idlgen
from sem_console.dds.topics import Sem, Sem60
from support import http
from test_console import HAPPY, V1, WsClient, provider_ready, wait_command, wait_until

SEM_TOPICS = {s.spec.name: s for s in Sem}
BOTH_VERSIONS = {s.spec.name for s in (*Sem, *Sem60)}  # every file has a channel of each, recorded or not
JSON_TOPICS = {
    "sem-console/commands",
    "sem-console/transitions",
    "sem-console/links",
    "sem-console/instances",
    "sem-console/alarm-acks",
    "sem-console/names",
}


def post(base: str, action: str) -> dict[str, Any]:
    r = http.post(f"{base}/api/recordings", json={"action": action}, timeout=15)
    assert r.status_code == 200, r.text
    return dict(r.json())


def recorded(base: str, tmp: Path) -> Path:
    """Stop the recording and download its one file through the REST API."""
    post(base, "stop")
    files = http.get(f"{base}/api/recordings").json()
    assert len(files) == 1 and files[0]["state"] == "complete" and files[0]["end"] >= files[0]["start"], files
    r = http.get(f"{base}/api/recordings/{files[0]['name']}")
    assert r.status_code == 200 and r.headers["content-type"] == "application/octet-stream"
    assert len(r.content) == files[0]["size"]
    path = tmp / files[0]["name"]
    path.write_bytes(r.content)
    return path


def read(path: Path) -> tuple[dict[str, Any], dict[str, list[Any]]]:
    """(channel topic -> (schema, channel)), (topic -> messages) with the mcap library."""
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        assert summary is not None
        channels = {c.topic: (summary.schemas[c.schema_id], c) for c in summary.channels.values()}
        messages: dict[str, list[Any]] = defaultdict(list)
        for _schema, channel, message in reader.iter_messages(log_time_order=True):
            messages[channel.topic].append(message)
    return channels, messages


DECODE = textwrap.dedent("""
    import importlib, json, sys
    gen, module, name, path = sys.argv[1:5]
    channel = int(sys.argv[6]) if len(sys.argv) > 6 else None  # only that channel of the topic
    sys.path.insert(0, gen)
    t = getattr(importlib.import_module(module), name)
    assert importlib.import_module("UMAA").__file__.startswith(gen), "decoded with the project's own types"
    from mcap.reader import make_reader
    from cyclonedds.idl import IdlEnum
    def plain(v):
        if isinstance(v, IdlEnum): return v.name
        if isinstance(v, (bytes, bytearray)): return v.hex()
        if isinstance(v, list): return [plain(x) for x in v]
        if hasattr(v, "__dataclass_fields__"): return {k: plain(getattr(v, k)) for k in v.__dataclass_fields__}
        return v
    out = []
    with open(path, "rb") as f:
        for _s, ch, m in make_reader(f).iter_messages(topics=[sys.argv[5]]):
            if channel is None or ch.id == channel:
                out.append(plain(t.deserialize(m.data)))
    print(json.dumps(out))
""")


def decode_with_schema(
    schema_name: str, idl: str, topic: str, path: Path, tmp: Path, channel: int | None = None
) -> list[dict[str, Any]]:
    """Every message of `topic` (of its channel `channel` only, if given) decoded with types that idlc builds from the
    schema text alone."""
    work = tmp / (schema_name.replace("::", "_") + ("" if channel is None else f"-{channel}"))
    (work / "idl").mkdir(parents=True)
    (work / "idl" / "schema.idl").write_text(idl)
    idlgen.generate(work / "gen", idl_dir=work / "idl", extensibility=None)  # the text says @final itself
    module, name = schema_name.replace("::", ".").rsplit(".", 1)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    out = subprocess.run(
        [
            sys.executable,
            "-c",
            DECODE,
            str(work / "gen"),
            module,
            name,
            str(path),
            topic,
            *([] if channel is None else [str(channel)]),
        ],
        capture_output=True,
        text=True,
        cwd=work,
        env=env,
        timeout=60,
    )
    assert out.returncode == 0, out.stderr
    return list(json.loads(out.stdout))


def _plain(v: Any) -> Any:
    """A sample as DECODE prints it."""
    from cyclonedds.idl import IdlEnum

    if isinstance(v, IdlEnum):
        return v.name
    if isinstance(v, (bytes, bytearray)):
        return v.hex()
    if isinstance(v, list):
        return [_plain(x) for x in v]
    if hasattr(v, "__dataclass_fields__"):
        return {k: _plain(getattr(v, k)) for k in v.__dataclass_fields__}
    return v


def guid(hex_bytes: str) -> str:
    return str(uuid.UUID(hex=hex_bytes))


def test_a_recorded_run_reads_back_with_its_own_schemas(sim, console, tmp_path: Path) -> None:
    sim()
    c = console("--record", str(tmp_path / "rec"))
    status = http.get(f"{c.url}/api/recordings/status").json()
    assert status["state"] == "recording" and status["directory"] == str(tmp_path / "rec")
    ws = WsClient(c.ws_url)
    provider_ready(c.url, V1)
    session = http.post(f"{c.url}/api/providers/{V1}/gps-fix", json={}).json()["sessionId"]
    done = wait_command(c.url, session)  # COMPLETED, then cleaned up (the provider disposes status and ack)
    assert [t["status"] for t in done["transitions"]] == HAPPY
    time.sleep(0.5)
    live = http.get(f"{c.url}/api/recordings").json()
    assert [f["state"] for f in live] == ["recording"]
    assert http.get(f"{c.url}/api/recordings/{live[0]['name']}").status_code == 409  # still being written
    path = recorded(c.url, tmp_path)
    assert path.parent != tmp_path / "rec" and (tmp_path / "rec" / path.name).is_file()
    wait_until(lambda: any(m["recording"]["state"] == "off" for m in ws.of("recording")), 5, "the recording's stop on /ws")
    assert ws.messages[0]["recording"]["state"] == "recording" and ws.errors == []
    ws.close()

    channels, messages = read(path)
    # a channel per SEM topic, named by the DDS topic, with the OMG IDL of its type; the console's own JSON channels
    assert set(channels) == BOTH_VERSIONS | JSON_TOPICS
    for topic, sem in SEM_TOPICS.items():
        schema, channel = channels[topic]
        assert channel.message_encoding == "cdr" and schema.encoding == "omgidl"
        assert schema.name == str(sem.spec.type.__idl_typename__).replace(".", "::")
        assert "#include" not in schema.data.decode() and f"struct {schema.name.rsplit('::', 1)[1]} {{" in schema.data.decode()
    for topic in JSON_TOPICS:
        schema, channel = channels[topic]
        assert channel.message_encoding == "json" and schema.encoding == "jsonschema" and json.loads(schema.data)["properties"]
    # the recording console's station, for a replay to tell its commands from other stations' (test_replay.py)
    assert channels["sem-console/commands"][1].metadata == {"station": http.get(f"{c.url}/api/health").json()["consoleName"]}

    # the raw CDR from the wire: an encapsulation header, a receive time and the writer's source timestamp
    fix_reports = messages["UMAA::SEM::GPSFixStatus::GPSFixReport"]
    assert len(fix_reports) >= 10
    assert all(m.data[:2] == b"\x00\x07" for m in fix_reports)  # XCDR2 little endian: the type has @optional members
    assert all(m.data[:2] == b"\x00\x01" for m in messages["UMAA::SEM::GPSFixControl::GPSFixCommandStatus"])  # XCDR1
    assert all(0 < m.log_time - m.publish_time < 5e9 for m in fix_reports)

    # decoded with types built by idlc from the schema text in the file
    status_schema, _ = channels["UMAA::SEM::GPSFixControl::GPSFixCommandStatus"]
    statuses = decode_with_schema(
        status_schema.name, status_schema.data.decode(), "UMAA::SEM::GPSFixControl::GPSFixCommandStatus", path, tmp_path
    )
    ours = [s for s in statuses if guid(s["sessionID"]) == session]
    assert [s["commandStatus"] for s in ours] == HAPPY and {guid(s["source"]) for s in ours} == {V1}
    assert ours[-1]["commandStatusReason"] == "SUCCEEDED"
    fix_schema, _ = channels["UMAA::SEM::GPSFixStatus::GPSFixReport"]
    fixes = decode_with_schema(fix_schema.name, fix_schema.data.decode(), "UMAA::SEM::GPSFixStatus::GPSFixReport", path, tmp_path)
    assert len(fixes) == len(fix_reports) and {guid(f["source"]) for f in fixes} == {V1}
    lats = [f["position2DWithTime"]["geodeticPosition"]["geodeticLatitude"]["latitude"] for f in fixes]
    assert all(-90 <= x <= 90 for x in lats) and len(set(lats)) > 1  # the vehicle moves
    assert fixes[-1]["GPSFixCommandStatus"] == "STABLE" and fixes[-1]["GPSLatLongValid"] is True
    cmd_schema, _ = channels["UMAA::SEM::GPSFixControl::GPSFixCommand"]
    commands = decode_with_schema(
        cmd_schema.name, cmd_schema.data.decode(), "UMAA::SEM::GPSFixControl::GPSFixCommand", path, tmp_path
    )
    assert [guid(x["sessionID"]) for x in commands] == [session] and guid(commands[0]["destination"]) == V1
    # the other topics the run carried, each with the types built from its own schema text
    for topic in (
        "UMAA::SEM::GPSStatus::GPSReport",
        "UMAA::SEM::GPSFixStatus::GPSFixStatusReport",
        "UMAA::SEM::InertialSensorStatus::InertialSensorReport",
        "UMAA::SEM::GPSFixControl::GPSFixCommandAckReport",
    ):
        schema, _ = channels[topic]
        decoded = decode_with_schema(schema.name, schema.data.decode(), topic, path, tmp_path)
        assert decoded and len(decoded) == len(messages[topic]) and {guid(x["source"]) for x in decoded} == {V1}, topic
        if topic.endswith("GPSReport"):
            assert all(len(x["satellites"]) >= 20 and x["satellites"][0]["satelliteId"] for x in decoded)

    # the console's view: the transitions with their Figure 4 verdicts, the command, the provider's appearance
    transitions = [json.loads(m.data) for m in messages["sem-console/transitions"]]
    assert [t["transition"]["status"] for t in transitions if t["sessionId"] == session] == HAPPY
    assert all(t["transition"]["violation"] is None for t in transitions)
    assert any(json.loads(m.data)["command"]["sessionId"] == session for m in messages["sem-console/commands"])
    assert all(json.loads(m.data)["followed"] is True for m in messages["sem-console/commands"])  # its own: its alarms
    assert any(json.loads(m.data)["event"] == "appeared" for m in messages["sem-console/links"])
    # the cleanup's disposes: the console's command, then the provider's status and ack
    disposed = [json.loads(m.data) for m in messages["sem-console/instances"]]
    assert {(d["topic"].rsplit("::", 1)[1], d["state"]) for d in disposed if d["sessionId"] == session} == {
        ("GPSFixCommand", "disposed"),
        ("GPSFixCommandStatus", "disposed"),
        ("GPSFixCommandAckReport", "disposed"),
    }
    key = next(d for d in disposed if d["topic"].endswith("GPSFixCommandStatus"))["key"]
    assert len(base64.b64decode(key)) >= 4 + 32  # header, source and sessionID


def test_sem_replay_republishes_a_recording_that_another_console_shows(sim, console, domain: int, tmp_path: Path) -> None:
    s = sim()
    c = console()
    assert post(c.url, "start")["state"] == "recording"
    provider_ready(c.url, V1)
    time.sleep(1.5)
    s.stop()  # the simulator's shutdown disposes every report: recorded as disposes
    wait_until(
        lambda: not http.get(f"{c.url}/api/providers/{V1}").json()["topics"]["GPSFixReport"]["alive"],
        10,
        "the disposed GPSFixReport",
    )
    path = recorded(c.url, tmp_path)
    _channels, messages = read(path)
    recorded_fixes = messages["UMAA::SEM::GPSFixStatus::GPSFixReport"]
    assert recorded_fixes

    other = free_domain(taken=domain)
    second = ConsoleProcess(other, tmp_path / "second.sqlite3", [], {}).start()
    try:
        from cyclonedds.core import InstanceState

        from sem_console.dds.bus import Bus, all_samples
        from sem_console.dds.qos import reader_qos

        bus = Bus(other)
        reader = bus.reader(Sem.GPS_FIX_REPORT, reader_qos(Sem.GPS_FIX_REPORT.spec.cls, durable=True))
        seen_ts: list[int] = []
        arrived: dict[int, float] = {}  # source timestamp -> when the test took it (monotonic)
        disposed: list[Any] = []
        cond = all_samples(reader)
        stop = threading.Event()

        def take() -> None:  # every sample the replay publishes (keep last 1: take often)
            while not stop.is_set():
                for x in reader.take(N=100, condition=cond):
                    if x.sample_info.instance_state == InstanceState.NotAliveDisposed:
                        disposed.append(x)
                    elif x.sample_info.valid_data:
                        seen_ts.append(x.sample_info.source_timestamp)
                        arrived.setdefault(x.sample_info.source_timestamp, time.monotonic())
                time.sleep(0.005)

        taker = threading.Thread(target=take, daemon=True)
        taker.start()
        replay = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "sem_console.recording.sem_replay",
                str(path),
                "--domain",
                str(other),
                "--speed",
                "2",
                "--log-level",
                "info",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )

        def live_with_reports() -> bool:
            r = http.get(f"{second.url}/api/providers/{V1}")
            return r.status_code == 200 and all(
                r.json()["reports"][t] for t in ("GPSReport", "GPSFixReport", "InertialSensorReport")
            )

        wait_until(live_with_reports, 15, "the replayed vehicle on the second console")
        out, _ = replay.communicate(timeout=30)
        assert replay.returncode == 0, out
        assert "replayed" in out and "disposes" in out
        wait_until(lambda: disposed, 10, "the replayed dispose")
        stop.set()
        taker.join()
        detail = http.get(f"{second.url}/api/providers/{V1}").json()
        assert not detail["topics"]["GPSFixReport"]["alive"]  # disposed, as when it was recorded
        # the original source timestamps
        assert set(seen_ts) <= {m.publish_time for m in recorded_fixes} and len(seen_ts) >= len(recorded_fixes) // 2, (
            sorted(seen_ts),
            sorted(m.publish_time for m in recorded_fixes),
        )
        # with the recorded timing at twice the speed: never faster (its own count of the time it took, from the
        # first sample to the last, against the recording's span), and the fixes arrive about as spaced as recorded
        logged = {m.publish_time: m.log_time for m in recorded_fixes}
        sem_times = [m.log_time for topic, ms in messages.items() if topic in SEM_TOPICS for m in ms]
        took = float(re.search(r"replayed \d+ samples.* in ([\d.]+) s", out).group(1))  # type: ignore[union-attr]
        assert took >= (max(sem_times) - min(sem_times)) / 1e9 / 2 - 0.1, (took, max(sem_times) - min(sem_times))
        first, last = min(arrived, key=arrived.__getitem__), max(arrived, key=arrived.__getitem__)
        recorded_span, replayed_span = (logged[last] - logged[first]) / 1e9, arrived[last] - arrived[first]
        assert recorded_span > 0.5 and replayed_span <= recorded_span / 2 + 2.0, (recorded_span, replayed_span)
        # the second console got the recorded positions (the last report is the last recorded one)
        last = detail["reports"]["GPSFixReport"]["report"]
        wire = Sem.GPS_FIX_REPORT.spec.type.deserialize(recorded_fixes[-1].data)
        assert last["position2DWithTime"]["geodeticPosition"]["geodeticLatitude"]["latitude"] == pytest.approx(
            wire.position2DWithTime.geodeticPosition.geodeticLatitude.latitude
        )
        assert http.get(f"{second.url}/api/commands").json() == []  # commands are not republished by default

        # --loop --retime: again and again, stamped with the replay's time, until interrupted
        seen_ts.clear()
        stop.clear()
        taker = threading.Thread(target=take, daemon=True)
        taker.start()
        began = time.time_ns()
        looping = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "sem_console.recording.sem_replay",
                str(path),
                "--domain",
                str(other),
                "--speed",
                "20",
                "--loop",
                "--retime",
                "--wait",
                "0",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        try:
            wait_until(lambda: len(seen_ts) > 2 * len(recorded_fixes), 30, "the recording replayed more than twice")
            looping.send_signal(signal.SIGINT)
            out, _ = looping.communicate(timeout=30)
        finally:
            if looping.poll() is None:  # a failure above: never leave it publishing
                looping.kill()
                looping.wait()
        assert looping.returncode == 0, out
        assert all(ts >= began for ts in seen_ts) and not set(seen_ts) & set(logged)  # retimed: none of the recorded stamps
    finally:
        stop.set()
        second.stop()


@pytest.mark.slow
def test_a_full_disk_stops_the_recording_not_the_console(sim, console, tmp_path: Path) -> None:
    """A real full disk: a 192 KiB tmpfs (we run as root here). Where mounting is not permitted, the
    console process gets a file size limit instead (RLIMIT_FSIZE: writes past it fail with EFBIG)."""
    small = tmp_path / "small"
    small.mkdir()
    mounted = (
        subprocess.run(["mount", "-t", "tmpfs", "-o", "size=192k", "tmpfs", str(small)], capture_output=True).returncode == 0
    )
    try:
        sim("--vehicles", "3", "--satellites", "40")
        c = console("--record", str(small))
        if not mounted:
            import resource

            assert c.proc is not None
            resource.prlimit(c.proc.pid, resource.RLIMIT_FSIZE, (192 * 1024, 192 * 1024))
        ws = WsClient(c.ws_url)
        status = wait_until(
            lambda: (lambda s: s if s["state"] == "failed" else None)(http.get(f"{c.url}/api/recordings/status").json()),
            90,
            "the recording to fail",
        )
        assert ("the disk is full" if mounted else "too large") in status["error"].lower()
        wait_until(lambda: any(m["recording"]["state"] == "failed" for m in ws.of("recording")), 5, "the failure on /ws")
        # the console goes on: health, fresh reports, and a recording that can be tried again
        assert http.get(f"{c.url}/api/health").status_code == 200
        applied = http.get(f"{c.url}/api/metrics").json()["reportsApplied"]
        wait_until(lambda: http.get(f"{c.url}/api/metrics").json()["reportsApplied"] > applied + 10, 10, "more reports")
        files = http.get(f"{c.url}/api/recordings").json()
        assert files and files[0]["state"] == "incomplete"
        assert c.proc is not None and c.proc.poll() is None
        ws.close()
        c.stop()
    finally:
        if mounted:
            subprocess.run(["umount", str(small)], check=False)


def test_recording_control_is_a_command_and_downloads_stay_in_the_directory(console, tmp_path: Path) -> None:
    c = console(env={"SEM_OPERATOR_TOKENS": "alice:s3cret"})
    url, token = f"{c.url}/api/recordings", {"Authorization": "Bearer s3cret"}
    assert http.post(url, json={"action": "start"}).status_code == 401  # the operator auth of commands
    assert http.post(url, content='{"action": "start"}', headers={**token, "Content-Type": "text/plain"}).status_code == 415
    foreign = http.post(url, json={"action": "start"}, headers={**token, "Origin": "http://evil.example"})
    assert foreign.status_code == 403
    assert http.post(url, json={"action": "record"}, headers=token).status_code == 422
    assert http.get(f"{url}/status").json()["state"] == "off"
    started = http.post(url, json={"action": "start"}, headers=token).json()
    assert started["state"] == "recording" and started["directory"] == str(tmp_path / "recordings")
    assert http.post(url, json={"action": "start"}, headers=token).json()["file"] == started["file"]  # no second file
    stopped = http.post(url, json={"action": "stop"}, headers=token).json()
    assert stopped["state"] == "off" and stopped["error"] is None
    (tmp_path / "secret.mcap").write_bytes(b"not yours")
    for name in ("..%2Fsecret.mcap", "%2E%2E%2Fconsole.sqlite3", "secret.mcap", "20261122T101530.123Z.mcap.."):
        assert http.get(f"{url}/{name}").status_code in (404, 422), name
    assert http.get(f"{url}/20000101T000000.000Z.mcap").status_code == 404
    assert http.get(f"{url}/{started['file']}").content[:8] == b"\x89MCAP0\r\n"
    audit = http.get(f"{c.url}/api/audit").json()
    assert [(a["outcome"], a["operator"], a["reason"]) for a in audit if a["path"] == "/api/recordings"][:3] == [
        ("accepted", "alice", "recording stop"),
        ("accepted", "alice", "recording start"),
        ("accepted", "alice", "recording start"),
    ]


def test_files_roll_over_and_each_stands_alone(sim, console, tmp_path: Path) -> None:
    sim()
    c = console("--record", str(tmp_path / "rec"), "--record-max-seconds", "1")
    provider_ready(c.url, V1)
    wait_until(lambda: len(http.get(f"{c.url}/api/recordings").json()) >= 3, 20, "three files")
    post(c.url, "stop")
    files = http.get(f"{c.url}/api/recordings").json()
    assert all(f["state"] == "complete" for f in files) and len({f["name"] for f in files}) == len(files)
    for f in files[1:-1]:  # the middle ones: a whole second each, with every channel and its schema
        channels, messages = read(tmp_path / "rec" / f["name"])
        assert set(channels) == BOTH_VERSIONS | JSON_TOPICS
        assert messages["UMAA::SEM::GPSFixStatus::GPSFixReport"] and 0.5 <= f["end"] - f["start"] <= 2.5


def test_umaa_6_0_samples_are_recorded_under_the_6_0_schemas(tmp_path: Path) -> None:
    """Every UMAA 6.0 topic has its channel, named by the topic (the type's full name), with the 6.0 IDL as its schema
    and `umaaVersion` 6.0, beside the 3.0.1 channels: read back with the mcap library (CRCs checked) and decoded with
    types idlc builds from the schema text alone, each sample comes back member for member, GlobalPose's optional
    members all present, all absent and at random. A disposed 6.0 instance names its vehicle (the `id` of its
    IdentifierType source). On the recorder alone, its tap fed as the ingest feeds it."""
    from sem_console.recording.recorder import Recorder
    from support.samplegen import random_sample

    samples: dict[Sem60, list[Any]] = {
        sem: [
            random_sample(sem.spec.type, random.Random(seed), absent=absent)
            for seed, absent in ((1, 0.0), (2, 1.0), (3, 0.5), (4, 0.5))
        ]
        for sem in Sem60
    }
    pose = samples[Sem60.GLOBAL_POSE_REPORT]
    assert pose[0].depth is not None and pose[0].positionCovariance is not None  # every optional member present
    assert pose[1].altitude is None and pose[1].attitudeCovariance is None  # every one absent
    r = Recorder(tmp_path, max_bytes=1 << 30, max_seconds=3600)
    r.start()
    now = time.time_ns()
    for sem, values in samples.items():
        r.on_samples(
            sem, [(v.serialize(use_version_2=sem.spec.xcdr2_only), True, int(InstanceState.Alive), now) for v in values], now
        )
    gone = pose[2]
    r.on_samples(Sem60.GLOBAL_POSE_REPORT, [(gone.serialize_key(), False, int(InstanceState.NotAliveDisposed), now)], now)
    r.stop()
    assert r.status()["state"] == "off" and r.messages == 4 * len(Sem60) + 1

    [path] = tmp_path.glob("*.mcap")
    with open(path, "rb") as f:
        summary = make_reader(f, validate_crcs=True).get_summary()
    assert summary is not None
    channels = {c.topic: c for c in summary.channels.values()}
    assert set(channels) == BOTH_VERSIONS | JSON_TOPICS
    assert {channels[t].metadata["umaaVersion"] for t in SEM_TOPICS} == {"3.0.1"}
    for sem, values in samples.items():
        channel = channels[sem.spec.name]
        schema = summary.schemas[channel.schema_id]
        assert sem.spec.name == schema.name == str(sem.spec.type.__idl_typename__).replace(".", "::")
        assert channel.metadata == {"umaaVersion": "6.0"} and channel.message_encoding == "cdr"
        assert schema.encoding == "omgidl" and "#include" not in schema.data.decode()
        got = decode_with_schema(schema.name, schema.data.decode(), sem.spec.name, path, tmp_path)
        assert got == json.loads(json.dumps([_plain(v) for v in values])), sem.name
    # 3.0.1's GPSReportType has the same name: its own schema, the 3.0.1 IDL
    old = summary.schemas[channels[Sem.GPS_REPORT.spec.name].schema_id]
    new = summary.schemas[channels[Sem60.GPS_REPORT.spec.name].schema_id]
    assert (
        old.name == new.name
        and old.id != new.id
        and "timeFigureOfMerit" in new.data.decode()
        and "timeFigureOfMerit" not in old.data.decode()
    )
    _, messages = read(path)
    [disposed] = [json.loads(m.data) for m in messages["sem-console/instances"]]
    assert disposed["topic"] == Sem60.GLOBAL_POSE_REPORT.spec.name and disposed["state"] == "disposed"
    assert disposed["source"] == str(uuid.UUID(bytes=bytes(gone.source.id))) and disposed["sessionId"] is None


def test_the_umaa_6_0_command_flow_topics_on_the_bus_are_recorded(console, domain: int, tmp_path: Path) -> None:
    """The 6.0 InertialSensorControl command, status and ack a consumer and a vehicle write on the bus are in the
    console's recording (read for it, whatever the console follows), decoded from the file with the schema's types;
    the status's dispose is an instance event naming the vehicle and the session."""
    from sem_console.dds.bus import Bus, wait_for_acks
    from support.samplegen import random_sample

    c = console("--record", str(tmp_path / "rec"))
    flow = (Sem60.INS_COMMAND, Sem60.INS_COMMAND_STATUS, Sem60.INS_COMMAND_ACK)
    written = {sem: random_sample(sem.spec.type, random.Random(i)) for i, sem in enumerate(flow)}
    bus = Bus(domain)
    try:
        writers = {sem: bus.writer(sem) for sem in flow}
        wait_until(lambda: all(w.get_matched_subscriptions() for w in writers.values()), 10, "the console's readers")
        for sem, w in writers.items():
            w.write(written[sem])
        status = written[Sem60.INS_COMMAND_STATUS]
        writers[Sem60.INS_COMMAND_STATUS].dispose(status)
        wait_for_acks(list(writers.values()), 5.0)
        wait_until(lambda: http.get(f"{c.url}/api/recordings/status").json()["messages"] >= 4, 5, "the samples recorded")
    finally:
        bus.close()
    path = recorded(c.url, tmp_path)
    channels, messages = read(path)
    for sem in flow:
        schema, channel = channels[sem.spec.name]
        assert channel.metadata == {"umaaVersion": "6.0"} and len(messages[sem.spec.name]) == 1, sem.name
        got = decode_with_schema(schema.name, schema.data.decode(), sem.spec.name, path, tmp_path)
        assert got == json.loads(json.dumps([_plain(written[sem])])), sem.name
    events = [json.loads(m.data) for m in messages["sem-console/instances"]]  # the dispose; the writers' end (noWriters)
    [disposed] = [e for e in events if e["state"] == "disposed"]
    assert disposed["topic"] == Sem60.INS_COMMAND_STATUS.spec.name
    assert disposed["source"] == str(uuid.UUID(bytes=bytes(status.source.id)))
    assert disposed["sessionId"] == str(uuid.UUID(bytes=bytes(status.sessionID)))


@pytest.mark.parametrize("sem", [s for s in Sem if s.spec.appendable is not None], ids=lambda s: s.name)
def test_an_appendable_writers_samples_are_recorded_under_their_own_schema(sem: Sem, tmp_path: Path) -> None:
    """An RTI vehicle's GPSReport and GPSFixReport are appendable (delimited XCDR2: a DHEADER before each struct). The
    recorder puts them on a channel of their own on the same topic, whose schema says @appendable, so a reader of the
    file that goes by the schema (here idlc's types built from the schema text alone) reads them right; the final
    writer's samples stay on the topic's channel with the @final IDL. On the recorder alone: its tap is fed as the
    ingest feeds it (a take of both writers at once)."""
    from sem_console.recording.recorder import Recorder
    from support.samplegen import random_sample

    assert sem.spec.appendable is not None
    finals = [random_sample(sem.spec.type, random.Random(seed)) for seed in range(5)]
    appendables = [random_sample(sem.spec.appendable, random.Random(seed)) for seed in range(5, 10)]
    r = Recorder(tmp_path, max_bytes=1 << 30, max_seconds=3600)
    r.start()
    now = time.time_ns()
    take = [(s.serialize(use_version_2=True), True, 16, now) for pair in zip(finals, appendables, strict=True) for s in pair]
    r.on_samples(sem, take, now)
    r.stop()
    assert r.status()["state"] == "off" and r.messages == 10
    [path] = tmp_path.glob("*.mcap")
    with open(path, "rb") as f:
        summary = make_reader(f, validate_crcs=True).get_summary()
    assert summary is not None
    channels = [c for c in summary.channels.values() if c.topic == sem.spec.name]
    by_extensibility = {c.metadata.get("extensibility", "final"): c for c in channels}
    assert len(channels) == 2 and set(by_extensibility) == {"final", "appendable"}, channels
    type_name = str(sem.spec.type.__idl_typename__).replace(".", "::")
    for kind, samples in (("final", finals), ("appendable", appendables)):
        channel = by_extensibility[kind]
        schema = summary.schemas[channel.schema_id]
        assert schema.name == type_name and schema.encoding == "omgidl"
        assert (
            f"@{kind}\nstruct" in schema.data.decode()
            and f"@{'final' if kind == 'appendable' else 'appendable'}" not in schema.data.decode()
        )
        got = decode_with_schema(schema.name, schema.data.decode(), sem.spec.name, path, tmp_path, channel.id)
        assert got == json.loads(json.dumps([_plain(s) for s in samples])), kind


def test_sem_replay_republishes_an_appendable_writers_sample_as_it_was_sent(domain: int, tmp_path: Path) -> None:
    """sem-replay of an RTI vehicle's GPSFixReport (delimited XCDR2): written by a writer of the appendable copy, so
    the console's reader of that copy gets the same values, and its final reader (force_type_validation) nothing;
    re-encoding it with the final type would misread it. Its dispose the same way (the recorder's instance event)."""
    from sem_console.dds.bus import Bus
    from sem_console.dds.qos import reader_qos
    from sem_console.dds.topics import final_type_qos
    from sem_console.recording.recorder import _instance_event
    from sem_console.recording.sem_replay import Replay
    from support.samplegen import random_sample

    sem = Sem.GPS_FIX_REPORT
    assert sem.spec.appendable is not None
    sent = random_sample(sem.spec.appendable, random.Random(7))
    bus = Bus(domain)
    try:
        appendable = bus.reader(sem, appendable=True)
        final = bus.reader(sem, reader_qos(sem.spec.cls) + final_type_qos(sem))
        replay = Replay(bus, tmp_path / "unused.mcap", 1.0, retime=False)
        replay.sample(sem, sent.serialize(use_version_2=True), time.time_ns())
        got = wait_until(lambda: appendable.take(), 10, "the replayed sample")
        assert got == [sent] and replay.reencoded == 0
        assert final.take() == [] and final.get_matched_publications() == []
        # its dispose, as the recorder writes it (a valid sample taken disposed) and sem-replay republishes it
        event = _instance_event(sem, sent.serialize(use_version_2=True), True, InstanceState.NotAliveDisposed)
        assert event["source"] == str(uuid.UUID(bytes=bytes(sent.source)))
        replay.instance(event, time.time_ns())
        ended = wait_until(lambda: appendable.take(), 10, "the replayed dispose")
        assert [s.sample_info.instance_state for s in ended] == [InstanceState.NotAliveDisposed]
    finally:
        bus.close()


def test_files_roll_over_at_their_size(tmp_path: Path) -> None:
    """The size limit, on the recorder alone (no DDS here: its tap is fed as the ingest threads feed it). Every file
    names the recording console's station (a replay of any one of them tells its commands from other stations'),
    also read from a file cut short, and a file cut before its first chunk is no station, not an exception."""
    from sem_console.recording.reader import recorded_station
    from sem_console.recording.recorder import Recorder

    limit = 65_536  # the least --record-max-bytes; a file's schemas alone are about 50 kB (both UMAA versions)
    r = Recorder(tmp_path, max_bytes=limit, max_seconds=3600, station="watch")
    r.start()
    sent = 0
    for _batch in range(20):
        for _ in range(50):  # incompressible samples: the file grows as fast as they come
            now = time.time_ns()
            r.on_samples(Sem.GPS_FIX_REPORT, [(b"\x00\x07\x00\x00" + os.urandom(200), True, 16, now - 1_000)], now)
            sent += 1
        wait_until(lambda: not r._buffer, 10, "the writer took the batch")  # one batch per write
    r.stop()
    assert r.status()["state"] == "off" and r.dropped == 0
    files = sorted(tmp_path.glob("*.mcap"))
    assert len(files) >= 3
    got = 0
    for path in files:
        raw = path.read_bytes()
        summary_start = int.from_bytes(raw[-8 - 29 + 9 : -8 - 29 + 17], "little")  # the footer's first field
        # the data section: at the limit (but the last file's; counted before compression), at most a batch (50
        # samples here) beyond it;
        # the summary after it repeats the schemas
        assert summary_start <= limit + 50 * 250, (path.name, summary_start, len(raw))
        assert path == files[-1] or summary_start >= 0.85 * limit, (path.name, summary_start)  # the held chunk compresses
        with open(path, "rb") as f:
            reader = make_reader(f, validate_crcs=True)
            summary = reader.get_summary()
            assert summary is not None and {c.topic for c in summary.channels.values()} == BOTH_VERSIONS | JSON_TOPICS
            got += sum(1 for _ in reader.iter_messages(topics=["UMAA::SEM::GPSFixStatus::GPSFixReport"]))
        assert recorded_station(path) == "watch", path.name
        cut = tmp_path / "cut" / path.name
        cut.parent.mkdir(exist_ok=True)
        cut.write_bytes(raw[:summary_start])  # the data section only: the recording was not closed
        assert recorded_station(cut) == "watch", path.name
        cut.write_bytes(raw[:100])  # the header only
        assert recorded_station(cut) is None
    assert got == sent
