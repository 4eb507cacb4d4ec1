"""The private part of the mcap library the project uses (sem_console/recording/mcap_private.py), pinned against the
installed mcap: records serialise as the MCAP specification lays them out. (tests/test_mcap_writer.py reads whole
files written this way back with mcap's own readers.)"""

from __future__ import annotations

import struct
import tomllib
from importlib.metadata import version
from pathlib import Path

from mcap.opcode import Opcode
from mcap.records import Channel, Footer, Header, SummaryOffset

from sem_console.recording import mcap_private
from sem_console.recording.mcap_private import record_bytes

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def _string(s: str) -> bytes:
    return struct.pack("<I", len(s.encode())) + s.encode()


def test_the_pinned_version_is_installed() -> None:
    assert "mcap>=1.6,<2" in tomllib.loads(PYPROJECT.read_text())["project"]["dependencies"]
    major, minor = (int(x) for x in version("mcap").split(".")[:2])
    assert major == 1 and minor >= 6


def test_only_mcap_private_imports_the_private_module() -> None:
    package = Path(mcap_private.__file__).parents[1]
    users = sorted(
        str(p.relative_to(package))
        for p in package.rglob("*.py")
        if p.name != "mcap_private.py" and "mcap.data_stream" in p.read_text()
    )
    assert users == []


def test_records_as_the_specification_lays_them_out() -> None:
    """opcode (u8), record length (u64), then the fields: strings u32-length-prefixed, integers little endian."""
    body = _string("p") + _string("sem-console 1")
    assert (
        record_bytes(Header(profile="p", library="sem-console 1")) == bytes([Opcode.HEADER]) + struct.pack("<Q", len(body)) + body
    )

    body = struct.pack("<BQQ", Opcode.CHANNEL, 123, 45)
    assert record_bytes(SummaryOffset(group_opcode=Opcode.CHANNEL, group_start=123, group_length=45)) == (
        bytes([Opcode.SUMMARY_OFFSET]) + struct.pack("<Q", len(body)) + body
    )

    body = struct.pack("<QQI", 10, 20, 0xDEADBEEF)
    assert record_bytes(Footer(summary_start=10, summary_offset_start=20, summary_crc=0xDEADBEEF)) == (
        bytes([Opcode.FOOTER]) + struct.pack("<Q", len(body)) + body
    )

    metadata = struct.pack("<I", len(_string("k") + _string("v"))) + _string("k") + _string("v")
    body = struct.pack("<HH", 3, 2) + _string("t") + _string("cdr") + metadata
    assert record_bytes(Channel(id=3, schema_id=2, topic="t", message_encoding="cdr", metadata={"k": "v"})) == (
        bytes([Opcode.CHANNEL]) + struct.pack("<Q", len(body)) + body
    )
