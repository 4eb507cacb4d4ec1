"""A streaming MCAP writer whose per-message cost fits the recorder's budget (MCAP version 0).

Why not `mcap.writer.Writer`: its `add_message` builds a `Message` dataclass and packs seven
fields one by one into a seeking BytesIO: 4-5 µs per message alone (`bench/mcap_write.py`), 11 µs
in the running console (the writer thread's CPU, `bench/recording.py`), which at the 50-vehicle
ingest rate is more than the 10% of the console's CPU recording may cost. Here a message is one struct pack
and a few list appends; the chunk's time range is worked out once per chunk, and its message
index records are packed in one call per channel. The other records (header, schema, channel,
chunk, chunk index, data end, statistics, summary offsets, footer) are serialised by the mcap
library's own record classes.

The layout: schemas and channels in the data section, outside chunks, as they are registered
(the mcap library puts them in the chunk in progress; the specification allows both), chunks
(zstd) each followed by one message index per channel, then a summary with the schemas,
channels, statistics and chunk indexes, summary offsets, and a footer with the summary CRC.
`tests/unit/test_mcap_writer.py` reads it back with the mcap library's readers (CRCs validated) and
checks a message record against bytes worked out from the specification.
"""

from __future__ import annotations

import struct
import zlib
from collections import defaultdict
from collections.abc import Sequence
from typing import BinaryIO

import zstandard
from mcap.opcode import Opcode
from mcap.records import Channel, Chunk, ChunkIndex, DataEnd, Footer, Header, McapRecord, Schema, Statistics, SummaryOffset

from sem_console.recording.mcap_private import record_bytes

MAGIC = b"\x89MCAP0\r\n"
# Message record: opcode, record length, channel id, sequence, log time, publish time; then the data
_MESSAGE = struct.Struct("<BQHIQQ")
_MESSAGE_OP = int(Opcode.MESSAGE)
_MESSAGE_FIXED = 2 + 4 + 8 + 8  # the record's length without its data
_MESSAGE_HEADER = 1 + 8 + _MESSAGE_FIXED
# Message index record: opcode, record length, channel id, byte length of the (log time, offset) array
_MESSAGE_INDEX = struct.Struct("<BQHI")
_FOOTER_HEAD = struct.Struct("<BQQQ")  # what the summary CRC covers of the footer: opcode, length, two offsets


class _Finished(dict[int, list[int]]):
    """The channel index of a finished file: every channel is missing, with a clear error."""

    def __missing__(self, key: int) -> list[int]:
        raise ValueError("the MCAP file is finished")


class McapWriter:
    """Write an MCAP file to `stream` (opened for binary writing; never seeked, never closed here).

    `register_schema`/`register_channel`, then `add_message` as often as wanted (channel ids
    must be registered), `flush` to end the chunk in progress, `finish` to write the summary; after
    that, writing anything is a ValueError."""

    def __init__(
        self, stream: BinaryIO, *, chunk_size: int = 1 << 20, profile: str = "", library: str = "", zstd_level: int = 3
    ) -> None:
        self._out = stream
        self._offset = 0  # bytes written to the stream
        self._data_crc = 0  # CRC of the data section so far
        self._chunk_size = chunk_size
        self._compressor = zstandard.ZstdCompressor(level=zstd_level)
        self._schemas: list[Schema] = []
        self._channels: list[Channel] = []
        self._chunk_indexes: list[ChunkIndex] = []
        self._counts: defaultdict[int, int] = defaultdict(int)  # messages per channel, in finished chunks
        self._start_time: int | None = None
        self._end_time = 0
        # the chunk in progress: its records, their length, and per channel [log time, offset, ...]
        self._parts: list[bytes] = []
        self._size = 0
        self._index: dict[int, list[int]] = {}
        self._finished = False
        self._write(MAGIC)
        self._record(Header(profile=profile, library=library))

    # ---- the data section --------------------------------------------------------------
    def register_schema(self, name: str, encoding: str, data: bytes) -> int:
        schema = Schema(id=len(self._schemas) + 1, name=name, encoding=encoding, data=data)
        self._record(schema)  # first: a record that cannot be written is not kept either
        self._schemas.append(schema)
        return schema.id

    def register_channel(self, topic: str, message_encoding: str, schema_id: int, metadata: dict[str, str] | None = None) -> int:
        if schema_id != 0 and not 0 < schema_id <= len(self._schemas):
            raise ValueError(f"no schema {schema_id}")
        channel = Channel(
            id=len(self._channels) + 1,
            topic=topic,
            message_encoding=message_encoding,
            metadata=metadata or {},
            schema_id=schema_id,
        )
        self._record(channel)  # before the chunk that will hold its messages
        self._channels.append(channel)
        self._index[channel.id] = []
        return channel.id

    def add_message(self, channel_id: int, log_time: int, data: bytes, publish_time: int, sequence: int = 0) -> None:
        """The hot path: a KeyError for an unregistered channel, struct.error for a field out of range
        (sequence u32, times u64); either leaves the file as it was."""
        index = self._index[channel_id]
        head = _MESSAGE.pack(_MESSAGE_OP, _MESSAGE_FIXED + len(data), channel_id, sequence, log_time, publish_time)
        index.append(log_time)
        index.append(self._size)
        self._parts.append(head)
        self._parts.append(data)
        self._size += _MESSAGE_HEADER + len(data)
        if self._size >= self._chunk_size:
            self._end_chunk()

    def tell(self) -> int:
        """Bytes written to the stream so far (the chunk in progress not counted)."""
        return self._offset

    def pending(self) -> int:
        """Bytes of the chunk in progress, before compression."""
        return self._size

    def flush(self) -> None:
        """End the chunk in progress (so a reader of the file as it grows has it) and flush the stream."""
        self._end_chunk()
        self._out.flush()

    def finish(self) -> None:
        """The last chunk, the data end, the summary and the footer. The stream stays open."""
        if self._finished:
            return
        self._end_chunk()
        self._record(DataEnd(data_section_crc=self._data_crc))
        self._finished = True  # nothing more in the data section; what follows is not in its CRC
        self._index = _Finished()  # add_message: a ValueError, at no cost to the hot path
        summary_start = self._offset
        parts: list[bytes] = []
        length = 0  # of the summary so far
        offsets: list[SummaryOffset] = []
        groups: list[tuple[Opcode, Sequence[McapRecord]]] = [
            (Opcode.SCHEMA, self._schemas),
            (Opcode.CHANNEL, self._channels),
            (Opcode.STATISTICS, [self._statistics()]),
            (Opcode.CHUNK_INDEX, self._chunk_indexes),
        ]
        for opcode, records in groups:
            if not records:
                continue
            start = length
            for record in records:
                parts.append(record_bytes(record))
                length += len(parts[-1])
            offsets.append(SummaryOffset(group_opcode=opcode, group_start=summary_start + start, group_length=length - start))
        summary_offset_start = summary_start + length
        parts.extend(record_bytes(offset) for offset in offsets)
        summary = b"".join(parts)
        crc = zlib.crc32(summary)
        crc = zlib.crc32(_FOOTER_HEAD.pack(Opcode.FOOTER, 8 + 8 + 4, summary_start, summary_offset_start), crc)
        self._write(summary)
        self._record(Footer(summary_start=summary_start, summary_offset_start=summary_offset_start, summary_crc=crc))
        self._write(MAGIC)
        self._out.flush()

    # ---- internals ---------------------------------------------------------------------
    def _write(self, data: bytes) -> None:
        self._out.write(data)
        self._offset += len(data)
        if not self._finished:
            self._data_crc = zlib.crc32(data, self._data_crc)

    def _record(self, record: Header | Schema | Channel | DataEnd | Footer | Chunk) -> None:
        if self._finished and not isinstance(record, Footer):
            raise ValueError("the MCAP file is finished")
        self._write(record_bytes(record))

    def _end_chunk(self) -> None:
        if not self._parts:
            return
        if self._finished:
            raise ValueError("the MCAP file is finished")
        records = b"".join(self._parts)
        indexes = [(cid, entries) for cid, entries in self._index.items() if entries]
        start = min(min(entries[0::2]) for _cid, entries in indexes)
        end = max(max(entries[0::2]) for _cid, entries in indexes)
        chunk = Chunk(
            compression="zstd",
            data=self._compressor.compress(records),
            message_start_time=start,
            message_end_time=end,
            uncompressed_crc=zlib.crc32(records),
            uncompressed_size=len(records),
        )
        chunk_start = self._offset
        self._record(chunk)
        index_start, packed, index_offsets = self._offset, [], {}
        at = index_start
        for cid, entries in indexes:
            n = len(entries)
            record = _MESSAGE_INDEX.pack(Opcode.MESSAGE_INDEX, 2 + 4 + 8 * n, cid, 8 * n) + struct.pack(f"<{n}Q", *entries)
            index_offsets[cid] = at
            at += len(record)
            packed.append(record)
            self._counts[cid] += n // 2
            entries.clear()
        self._write(b"".join(packed))
        self._chunk_indexes.append(
            ChunkIndex(
                message_start_time=start,
                message_end_time=end,
                chunk_start_offset=chunk_start,
                chunk_length=index_start - chunk_start,
                message_index_offsets=index_offsets,
                message_index_length=self._offset - index_start,
                compression=chunk.compression,
                compressed_size=len(chunk.data),
                uncompressed_size=chunk.uncompressed_size,
            )
        )
        self._start_time = start if self._start_time is None else min(self._start_time, start)
        self._end_time = max(self._end_time, end)
        self._parts, self._size = [], 0

    def _statistics(self) -> Statistics:
        return Statistics(
            message_count=sum(self._counts.values()),
            schema_count=len(self._schemas),
            channel_count=len(self._channels),
            attachment_count=0,
            metadata_count=0,
            chunk_count=len(self._chunk_indexes),
            message_start_time=self._start_time or 0,
            message_end_time=self._end_time,
            channel_message_counts=dict(self._counts),
        )
