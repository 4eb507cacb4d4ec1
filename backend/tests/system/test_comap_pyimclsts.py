"""An IMC implementation we did not write, pyimclsts (LSTS, PyPI), fed tests/data/comap-imc.xml (the
CoMap tables written by hand in IMC's schema format), reads what our codec writes, and our codec
and a running console read what it writes, in both byte orders."""

from __future__ import annotations

import json
import math
import shutil
import socket
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from conftest import free_udp_port
from sem_console.comap.codec import decode_packet, encode_packet, msg
from support import http
from test_console import wait_until

pytestmark = [pytest.mark.interop, pytest.mark.process]

TESTS = Path(__file__).parents[1]


@pytest.fixture(scope="module")
def peer(tmp_path_factory: pytest.TempPathFactory) -> Path:
    work = tmp_path_factory.mktemp("pyimclsts")
    shutil.copy(TESTS / "data" / "comap-imc.xml", work / "IMC.xml")
    shutil.copy(TESTS / "support" / "pyimclsts_peer.py", work / "peer.py")
    subprocess.run([sys.executable, "-m", "pyimclsts.extract"], cwd=work, check=True, capture_output=True, timeout=60)
    return work


def run_peer(work: Path, packets: list[bytes]) -> dict[str, Any]:
    out = subprocess.run(
        [sys.executable, "peer.py"],
        cwd=work,
        input=json.dumps({"decode": [p.hex() for p in packets]}),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)  # type: ignore[no-any-return]


OURS = [
    msg(
        "WorldModel",
        geo_features=[
            msg(
                "GeoFeature",
                feature_id=7,
                points=[
                    msg("MapPoint", lat=0.5, lon=-0.25, alt=1.5),
                    msg("MapPoint", lat=0.5, lon=-0.125, alt=0.0),
                    msg("MapPoint", lat=0.375, lon=-0.25, alt=0.0),
                ],
            )
        ],
        cov_states=[msg("CoverageState", feature_id=7, state=2)],
    ),
    msg("TaskAdmin", tid=9, op=3, arg=msg("SurveyTask", task_id=9, feature_id=7, sensor=1, resolution=2.5, deadline=1.9e9)),
    msg(
        "TaskAdmin",
        tid=9,
        op=3,
        arg=msg("MoveTask", task_id=9, deadline=1.9e9, destination=msg("MapPoint", lat=0.1, lon=0.2, alt=0.0)),
    ),
    msg("TaskAdmin", tid=9, op=1, arg=None),
    msg("SynchAdmin", op=3),
    msg(
        "VehicleCapabilities",
        capabilities=[msg("CapabilityPointSurvey", sensor=2, resolution=4.0, duration=10.0), msg("CapabilityMove", speed=1.5)],
    ),
    msg("SynchTask", task_id=1, feature_id=2, time_window=30, deadline=1.9e9),
]


def as_plain(m: Any) -> Any:
    if isinstance(m, list):
        return [as_plain(x) for x in m]
    if hasattr(m, "fields"):
        return {"_name": m.name, **{k: as_plain(v) for k, v in m.fields.items()}}
    return m


def test_pyimclsts_reads_what_we_send(peer: Path) -> None:
    packets = [encode_packet(m, src=0x4001, dst=0x2001, dst_ent=0) for m in OURS]
    got = run_peer(peer, packets)
    decoded = got["decoded"]
    assert len(decoded) == len(OURS)
    assert got["crc"] == [int.from_bytes(p[-2:], "little") for p in packets]  # its CRC-16-IBM agrees with ours
    for m, packet, theirs in zip(OURS, packets, decoded, strict=True):
        header = theirs.pop("_header")
        assert header[:3] == [0xFE55, m.id, len(packet) - 22] and header[4:] == [0x4001, 0xFF, 0x2001, 0]
        assert _close(theirs, as_plain(m)), (theirs, as_plain(m))


def _close(a: Any, b: Any) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_close(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_close(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) or isinstance(b, float):
        return math.isclose(a, b, rel_tol=1e-6)  # fp32 fields
    return bool(a == b)


def test_we_read_what_pyimclsts_sends_and_the_console_takes_its_world_model(peer: Path, console) -> None:
    enc = {k: bytes.fromhex(v) for k, v in run_peer(peer, [])["encoded"].items()}
    for order in ("WorldModel-le", "WorldModel-be"):
        header, m = decode_packet(enc[order])
        assert header.big_endian == (order == "WorldModel-be") and header.src == 0x2001
        (f,) = m["geo_features"]
        assert f["feature_id"] == 42 and [p["lat"] for p in f["points"]] == [0.6422, 0.6422, 0.6424]
        assert m["cov_states"][0].fields == {"feature_id": 42, "state": 2}
    assert decode_packet(enc["TaskStatus"])[1].fields == {"task_id": 3, "status": 2, "progress": 40, "quality": 80}
    assert decode_packet(enc["TaskAdmin"])[1].fields == {"tid": 3, "op": 1, "arg": None}
    caps = decode_packet(enc["VehicleCapabilities"])[1]["capabilities"]
    assert [c.name for c in caps] == ["CapabilityAreaSurvey", "CapabilityMove"] and caps[1]["speed"] == 2.0

    port = free_udp_port()
    c = console("--imc-port", str(port), "--imc-host", "127.0.0.1")
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.sendto(enc["WorldModel-be"], ("127.0.0.1", port))
    model = wait_until(
        lambda: (lambda w: w if w["features"] else None)(http.get(f"{c.url}/api/worldmodel").json()), 10, "the world model"
    )
    (f,) = model["features"]
    assert model["source"] == f"imc:{0x2001}" and f["properties"] == {"featureId": 42, "coverage": "PARTIAL"}
    ring = f["geometry"]["coordinates"][0]
    assert f["geometry"]["type"] == "Polygon" and len(ring) == 4 and ring[0] == ring[-1]
    assert ring[0] == pytest.approx([math.degrees(-1.3212), math.degrees(0.6422)])
