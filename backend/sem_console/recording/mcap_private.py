"""The one private part of the mcap library the project uses, in this one module (mcap>=1.6,<2, pinned in
backend/pyproject.toml). `tests/unit/test_mcap_private.py` pins it against the installed version.

`mcap_writer.py` writes MCAP faster than `mcap.writer.Writer` can (see there), but serialises every record but
messages and message indexes with the library's own record classes: `McapRecord.write` into the library's
`mcap.data_stream.RecordBuilder`, neither of them part of the documented API (only `Writer` is).
"""

from __future__ import annotations

from mcap.data_stream import RecordBuilder
from mcap.records import McapRecord


def record_bytes(record: McapRecord) -> bytes:
    """A record as it goes in the file: opcode, length, fields (the MCAP specification's layout)."""
    builder = RecordBuilder()
    record.write(builder)
    data: bytes = builder.end()
    return data
