"""The recorder's MCAP writer (`recording/mcap_writer.py`) against the mcap library's readers and
against bytes worked out by hand from the MCAP specification (mcap.dev/spec, format version 0).
No DDS here: the writer is plain file I/O; `test_recording.py` records real DDS through it."""

from __future__ import annotations

import io
import random
import struct
import zlib

import pytest
import zstandard
from mcap.reader import NonSeekingReader, make_reader
from mcap.records import Channel, Chunk, ChunkIndex, DataEnd, Footer, MessageIndex, Schema, Statistics, SummaryOffset
from mcap.stream_reader import StreamReader

from sem_console.recording.mcap_writer import McapWriter

T0 = 1_795_000_000_000_000_000  # 2026-11 in ns since the epoch


def records_in(buf: bytes) -> list[object]:
    """The records back to back in `buf` (opcode u8, length u64, content), each parsed by the mcap library."""
    out, at = [], 0
    while at < len(buf):
        (length,) = struct.unpack_from("<Q", buf, at + 1)
        out.append(next(iter(StreamReader(io.BytesIO(buf[at : at + 9 + length]), skip_magic=True).records)))
        at += 9 + length
    assert at == len(buf)
    return out


def test_message_record_and_index_are_the_spec_bytes() -> None:
    out = io.BytesIO()
    w = McapWriter(out, profile="", library="test")
    sid = w.register_schema("UMAA::SEM::GPSStatus::GPSReportType", "omgidl", b"module M { struct S { long x; }; };")
    cid = w.register_channel("UMAA::SEM::GPSStatus::GPSReport", "cdr", sid)
    assert (sid, cid) == (1, 1)
    w.add_message(cid, 0x0102030405060708, b"\x00\x01\x00\x00\x2a\x00\x00\x00", 0x1112131415161718, 7)
    w.finish()
    # Message, by hand: opcode 0x05; record length 2+4+8+8+8 = 30 (u64 LE); channel id 1 (u16);
    # sequence 7 (u32); log time; publish time (u64 LE each); the data (XCDR1 LE header, long 42)
    golden = bytes.fromhex("051e0000000000000001000700000008070605040302011817161514131211000100002a000000")
    records = list(StreamReader(io.BytesIO(out.getvalue()), emit_chunks=True, validate_crcs=True).records)
    chunks = [r for r in records if isinstance(r, Chunk)]
    assert len(chunks) == 1 and chunks[0].compression == "zstd"
    assert zstandard.ZstdDecompressor().decompress(chunks[0].data, max_output_size=1 << 20) == golden
    assert (chunks[0].message_start_time, chunks[0].message_end_time) == (0x0102030405060708, 0x0102030405060708)
    assert chunks[0].uncompressed_size == len(golden) and chunks[0].uncompressed_crc == zlib.crc32(golden)
    # Message index, by hand: opcode 0x07; length 2+4+16 = 22; channel 1; array of 16 bytes: (log time, offset 0)
    raw = out.getvalue()
    at = raw.index(bytes.fromhex("071600000000000000010010000000"))
    assert raw[at + 15 : at + 31] == bytes.fromhex("08070605040302010000000000000000")
    assert [r for r in records if isinstance(r, MessageIndex)] == [MessageIndex(channel_id=1, records=[(0x0102030405060708, 0)])]
    # data end: the CRC of every byte before it (magic included)
    end = next(r for r in records if isinstance(r, DataEnd))
    assert end.data_section_crc == zlib.crc32(
        raw[: raw.index(b"\x0f\x04\x00\x00\x00\x00\x00\x00\x00" + struct.pack("<I", end.data_section_crc))]
    )
    assert raw[:8] == b"\x89MCAP0\r\n" and raw[-8:] == b"\x89MCAP0\r\n"


def _write(chunk_size: int) -> tuple[bytes, list[tuple[int, int, bytes, int, int]]]:
    """A file over three channels, many chunks, a flush in the middle; and what went in."""
    rng = random.Random(7)
    out = io.BytesIO()
    w = McapWriter(out, chunk_size=chunk_size, library="test")
    s_cdr = w.register_schema("A", "omgidl", b"struct A { long x; };")
    s_json = w.register_schema("B", "jsonschema", b"{}")
    channels = [
        w.register_channel("t/a", "cdr", s_cdr),
        w.register_channel("t/b", "cdr", s_cdr),
        w.register_channel("t/json", "json", s_json, {"k": "v"}),
    ]
    sent, seq = [], dict.fromkeys(channels, 0)
    t = T0
    for i in range(3000):
        t += rng.randrange(0, 2_000_000)
        cid = rng.choice(channels)
        seq[cid] += 1
        data = rng.randbytes(rng.randrange(0, 300))
        log_time = t - rng.randrange(0, 1_000_000) if i % 97 == 0 else t  # now and then a little out of order
        if i == 2950:
            log_time = T0 - 10**9  # the earliest of all, in a late chunk and not first in it
        w.add_message(cid, log_time, data, log_time - 5_000, seq[cid])
        sent.append((cid, log_time, data, log_time - 5_000, seq[cid]))
        if i == 1500:
            w.flush()
    w.finish()
    return out.getvalue(), sent


@pytest.mark.parametrize("chunk_size", [1 << 20, 4096])
def test_the_mcap_library_reads_it_back(chunk_size: int) -> None:
    raw, sent = _write(chunk_size)
    # streamed, every CRC checked: every message, in the order written
    streamed = [
        (c.id, m.log_time, m.data, m.publish_time, m.sequence)
        for _s, c, m in NonSeekingReader(io.BytesIO(raw), validate_crcs=True).iter_messages(log_time_order=False)
    ]
    assert streamed == sent
    reader = make_reader(io.BytesIO(raw), validate_crcs=True)
    summary = reader.get_summary()
    assert summary is not None
    st = summary.statistics
    assert st.message_count == len(sent) and st.schema_count == 2 and st.channel_count == 3
    assert st.chunk_count == len(summary.chunk_indexes) >= (2 if chunk_size > 3000 * 300 else 30)
    assert st.channel_message_counts == {cid: sum(1 for m in sent if m[0] == cid) for cid in (1, 2, 3)}
    assert (st.message_start_time, st.message_end_time) == (min(m[1] for m in sent), max(m[1] for m in sent))
    assert {c.topic: (c.schema_id, c.message_encoding) for c in summary.channels.values()} == {
        "t/a": (1, "cdr"),
        "t/b": (1, "cdr"),
        "t/json": (2, "json"),
    }
    assert summary.channels[3].metadata == {"k": "v"}
    assert {s.name: s.encoding for s in summary.schemas.values()} == {"A": "omgidl", "B": "jsonschema"}
    # through the summary's chunk indexes, in log time order, and a time window of one topic
    indexed = [(c.id, m.log_time, m.data) for _s, c, m in reader.iter_messages(log_time_order=True)]
    assert indexed == [(m[0], m[1], m[2]) for m in sorted(sent, key=lambda m: m[1])]
    lo, hi = sent[1000][1], sent[2000][1]
    window = [(m.log_time, m.data) for _s, _c, m in reader.iter_messages(topics=["t/b"], starting_at=lo, ending_before=hi)]
    assert window == sorted(((m[1], m[2]) for m in sent if m[0] == 2 and lo <= m[1] < hi), key=lambda x: x[0])
    # each chunk index points at its chunk, and at one message index per channel with the chunk's entries
    for ci, next_start in zip(
        summary.chunk_indexes, [c.chunk_start_offset for c in summary.chunk_indexes[1:]] + [None], strict=True
    ):
        chunk = next(
            iter(
                StreamReader(
                    io.BytesIO(raw[ci.chunk_start_offset : ci.chunk_start_offset + ci.chunk_length]),
                    skip_magic=True,
                    emit_chunks=True,
                ).records
            )
        )
        assert isinstance(chunk, Chunk)
        assert (chunk.message_start_time, chunk.message_end_time) == (ci.message_start_time, ci.message_end_time)
        assert ci.compressed_size == len(chunk.data) and ci.uncompressed_size == chunk.uncompressed_size
        records = zstandard.ZstdDecompressor().decompress(chunk.data, max_output_size=chunk.uncompressed_size)
        # the chunk record ends where its message indexes begin; they end where the next record begins
        assert ci.chunk_start_offset + ci.chunk_length == min(ci.message_index_offsets.values())
        after = ci.chunk_start_offset + ci.chunk_length + ci.message_index_length
        assert next_start is None or after == next_start
        assert raw[after] in (0x06, 0x0F)  # the next chunk or the data end
        # its time range is the least and greatest log time of the messages in it, wherever they are
        times, at = [], 0
        while at < len(records):
            _op, length, _cid, _seq, log_time = struct.unpack_from("<BQHIQ", records, at)
            times.append(log_time)
            at += 9 + length
        assert (ci.message_start_time, ci.message_end_time) == (min(times), max(times))
        for cid, offset in ci.message_index_offsets.items():
            index = next(
                iter(
                    StreamReader(
                        io.BytesIO(raw[offset : ci.chunk_start_offset + ci.chunk_length + ci.message_index_length]),
                        skip_magic=True,
                    ).records
                )
            )
            assert isinstance(index, MessageIndex) and index.channel_id == cid and index.records
            for log_time, at in index.records:  # the message record at that offset has that channel and log time
                opcode, _length, channel, _seq, at_log = struct.unpack_from("<BQHIQ", records, at)
                assert (opcode, channel, at_log) == (0x05, cid, log_time)
    # the footer's summary CRC, as the spec defines it: summary start to the footer's summary_offset_start field
    footer = next(r for r in StreamReader(io.BytesIO(raw[-8 - 29 :]), skip_magic=True).records)
    assert isinstance(footer, Footer) and footer.summary_start > 0
    assert footer.summary_crc == zlib.crc32(raw[footer.summary_start : len(raw) - 8 - 4])
    # the summary offsets: one per group, each group holding only records of its opcode, back to back
    offsets = records_in(raw[footer.summary_offset_start : len(raw) - 8 - 29])
    assert all(isinstance(o, SummaryOffset) for o in offsets)
    kinds = {0x03: Schema, 0x04: Channel, 0x0B: Statistics, 0x08: ChunkIndex}
    assert [o.group_opcode for o in offsets] == list(kinds)
    at = footer.summary_start
    for o in offsets:
        assert o.group_start == at
        group = records_in(raw[o.group_start : o.group_start + o.group_length])
        assert group and all(isinstance(r, kinds[o.group_opcode]) for r in group)
        at += o.group_length
    assert at == footer.summary_offset_start


def test_a_refused_message_leaves_the_file_as_it_was() -> None:
    out = io.BytesIO()
    w = McapWriter(out)
    cid = w.register_channel("t", "cdr", 0)
    w.add_message(cid, T0, b"a", T0, 1)
    for bad in [dict(sequence=2**32), dict(publish_time=-1), dict(log_time=2**64)]:
        with pytest.raises(struct.error):
            w.add_message(**{"channel_id": cid, "log_time": T0 + 1, "data": b"x", "publish_time": T0, "sequence": 2, **bad})
    with pytest.raises(AttributeError):
        w.register_channel("u", "cdr", 0, {"k": 1})  # type: ignore[dict-item]  # cannot be written: no channel 2
    w.add_message(cid, T0 + 2, b"b", T0, 2)
    w.finish()
    size = len(out.getvalue())
    with pytest.raises(ValueError):
        w.add_message(cid, T0 + 3, b"c", T0, 3)  # finished
    with pytest.raises(ValueError):
        w.register_schema("s", "omgidl", b"")
    w.flush()
    assert len(out.getvalue()) == size
    raw = out.getvalue()
    assert [m.data for _s, _c, m in NonSeekingReader(io.BytesIO(raw), validate_crcs=True).iter_messages()] == [b"a", b"b"]
    summary = make_reader(io.BytesIO(raw), validate_crcs=True).get_summary()
    assert summary is not None and summary.statistics.message_count == 2 and list(summary.channels) == [1]


def test_empty_file_and_bad_input() -> None:
    out = io.BytesIO()
    w = McapWriter(out)
    with pytest.raises(KeyError):
        w.add_message(1, T0, b"", T0)  # no such channel
    with pytest.raises(ValueError):
        w.register_channel("t", "cdr", 3)  # no such schema
    w.finish()
    w.finish()  # once only
    summary = make_reader(io.BytesIO(out.getvalue()), validate_crcs=True).get_summary()
    assert summary is not None and summary.statistics.message_count == 0 and not summary.chunk_indexes
