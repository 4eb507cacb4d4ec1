"""The IMC codec against byte strings worked out by hand from the CoMap definitions (never produced
by our encoder), and against malformed input."""

from __future__ import annotations

import contextlib
import random
import struct

import pytest

from sem_console.comap.codec import ImcError, crc16, decode_packet, encode_packet, msg
from sem_console.comap.messages import BY_ID, LAYOUTS


def h(s: str) -> bytes:
    return bytes.fromhex("".join(s.split()))


# WorldModel with one polygon feature (id 7, three vertices) and one CoverageState (7, PARTIAL).
# lat/lon in radians, chosen exactly representable: 0.5 = 0x3FE0..., -0.25 = 0xBFD0..., -0.125 = 0xBFC0..., 0.375 = 0x3FD8...
WORLD_MODEL = h(
    "55FE"  # sync 0xFE55, little-endian
    "B90B"  # mgid 3001 WorldModel
    "5100"  # size 81 payload bytes
    "000000000000D041"  # timestamp fp64 2^30 = 1073741824.0 s
    "0140"  # src 0x4001
    "FF"  # src_ent 255
    "FFFF"  # dst 0xFFFF broadcast
    "FF"  # dst_ent 255
    # payload
    "0100"  # geo_features: count 1
    "BA0B"  #   element id 3002 GeoFeature
    "0700"  #     feature_id 7
    "0300"  #     points: count 3
    "5C02"  #       id 604 MapPoint
    "000000000000E03F"  #         lat 0.5 rad
    "000000000000D0BF"  #         lon -0.25 rad
    "00000000"  #         alt 0.0 m
    "5C02"  #       id 604 MapPoint
    "000000000000E03F"  #         lat 0.5
    "000000000000C0BF"  #         lon -0.125
    "00000000"  #         alt 0.0
    "5C02"  #       id 604 MapPoint
    "000000000000D83F"  #         lat 0.375
    "000000000000D0BF"  #         lon -0.25
    "00000000"  #         alt 0.0
    "0100"  # cov_states: count 1
    "BB0B"  #   element id 3003 CoverageState
    "0700"  #     feature_id 7
    "02"  #     state 2 PARTIAL
    "C019"  # CRC-16-IBM 0x19C0 (reflected 0xA001, init 0) over the 101 bytes above
)

TASK_STATUS = h(
    "55FE"  # sync
    "1F0C"  # mgid 3103 TaskStatus
    "0500"  # size 5
    "000000000000D041"  # timestamp 2^30 s
    "0140"
    "FF"
    "FFFF"
    "FF"  # src 0x4001, src_ent 255, dst broadcast, dst_ent 255
    "0302"  # task_id 0x0203 = 515
    "02"  # status 2 IN_PROGRESS
    "32"  # progress 50 %
    "5A"  # quality 90 %
    "DE24"  # CRC 0x24DE
)

# The same TaskStatus from a big-endian sender: every field and the CRC byte-swapped.
TASK_STATUS_BE = h("FE550C1F000541D00000000000004001FFFFFFFF020302325A73FD")


def test_crc_is_crc16_ibm_reflected() -> None:
    assert crc16(b"123456789") == 0xBB3D  # the catalogue check value of CRC-16/ARC (poly 0x8005 reflected, init 0)


def test_world_model_golden_decodes_and_reencodes() -> None:
    header, m = decode_packet(WORLD_MODEL)
    assert (header.mgid, header.size, header.timestamp, header.src, header.dst, header.dst_ent) == (
        3001,
        81,
        1073741824.0,
        0x4001,
        0xFFFF,
        0xFF,
    )
    assert m.name == "WorldModel"
    (feature,) = m["geo_features"]
    assert feature["feature_id"] == 7
    assert [(p["lat"], p["lon"], p["alt"]) for p in feature["points"]] == [
        (0.5, -0.25, 0.0),
        (0.5, -0.125, 0.0),
        (0.375, -0.25, 0.0),
    ]
    (cov,) = m["cov_states"]
    assert (cov["feature_id"], cov["state"]) == (7, 2)
    assert encode_packet(m, src=0x4001, src_ent=0xFF, timestamp=header.timestamp) == WORLD_MODEL


def test_task_status_golden_both_byte_orders() -> None:
    header, m = decode_packet(TASK_STATUS)
    assert m.name == "TaskStatus" and m.fields == {"task_id": 515, "status": 2, "progress": 50, "quality": 90}
    assert encode_packet(m, src=0x4001, timestamp=header.timestamp) == TASK_STATUS
    header_be, m_be = decode_packet(TASK_STATUS_BE)
    assert header_be.big_endian and m_be == m and header_be.src == 0x4001


def test_every_layout_round_trips_with_the_spec_payload_size() -> None:
    sizes = {3003: 3, 3005: 1, 3010: 17, 3011: 9, 3012: 4, 3101: 17, 3102: 32, 3103: 5, 3104: 14, 604: 20}
    for layout in LAYOUTS:
        if layout.id not in sizes:
            continue
        values = {name: (msg("MapPoint", lat=0.1, lon=0.2, alt=3.0) if isinstance(t, tuple) else 1) for name, t in layout.fields}
        packet = encode_packet(msg(layout.name, **values), src=1)
        assert len(packet) == 22 + sizes[layout.id], layout.name
        assert decode_packet(packet)[1] == msg(layout.name, **values)


def test_inline_none_and_task_admin_with_survey() -> None:
    for arg in (None, msg("SurveyTask", task_id=1, feature_id=7, sensor=1, resolution=0.5, deadline=2e9)):
        m = msg("TaskAdmin", tid=1, op=3, arg=arg)
        assert decode_packet(encode_packet(m, src=2, dst=3))[1] == m
    assert len(encode_packet(msg("TaskAdmin", tid=1, op=3, arg=None), src=1)) == 22 + 5


@pytest.mark.parametrize(
    "data,kind",
    [
        (WORLD_MODEL[:-3] + bytes([WORLD_MODEL[-3] ^ 1]) + WORLD_MODEL[-2:], "bad_crc"),
        (WORLD_MODEL[:30], "bad_size"),
        (b"\x55\xfe", "truncated"),
        (b"\x00" * 40, "bad_sync"),
        (WORLD_MODEL + b"\x00", "bad_size"),
    ],
)
def test_malformed_packets_raise_imc_error(data: bytes, kind: str) -> None:
    with pytest.raises(ImcError) as e:
        decode_packet(data)
    assert e.value.kind == kind


def _packet(mgid: int, payload: bytes) -> bytes:
    body = struct.pack("<HHHdHBHB", 0xFE55, mgid, len(payload), 0.0, 1, 0, 0xFFFF, 0xFF) + payload
    return body + struct.pack("<H", crc16(body))


def test_lying_counts_unknown_ids_and_extra_bytes() -> None:
    cases = {
        "bad_size": [
            _packet(3001, b"\xff\xff\x00\x00"),  # 65535 features in 2 bytes
            _packet(3103, h("0302 02 32 5A 00")),
        ],  # a byte beyond TaskStatus
        "truncated": [_packet(3001, h("0100 BA0B 0700 0100 5C02 00"))],  # a MapPoint cut short
        "unknown_id": [_packet(4242, b""), _packet(3001, h("0100 3930 0000"))],  # 4242; element id 12345
        "bad_message": [_packet(3001, h("0100 1F0C 0302 02 32 5A 0000"))],  # a TaskStatus as a GeoFeature
    }
    for kind, packets in cases.items():
        for p in packets:
            with pytest.raises(ImcError) as e:
                decode_packet(p)
            assert e.value.kind == kind, p.hex()


def test_random_bytes_only_ever_raise_imc_error() -> None:
    rng = random.Random(12)
    good = [WORLD_MODEL, TASK_STATUS]
    for _ in range(3000):
        base = bytearray(rng.choice(good))
        for _ in range(rng.randint(1, 6)):
            base[rng.randrange(len(base))] = rng.randrange(256)
        body = bytes(base[:-2])
        for data in (bytes(base), body + struct.pack("<H", crc16(body)), rng.randbytes(rng.randint(0, 80))):
            with contextlib.suppress(ImcError):
                decode_packet(data)
    assert 3001 in BY_ID
