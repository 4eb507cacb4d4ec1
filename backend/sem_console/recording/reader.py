"""Reading a recording (MCAP): its messages in log time order, its time span, whether it can be read at all.
Shared by the console's replay (`console/replay_source.py`), `sem-replay` (`sem_replay.py`) and `sem-console --replay`'s
start-up check."""

from __future__ import annotations

import logging
import struct
from collections.abc import Collection, Generator, Iterator
from pathlib import Path
from typing import Any

from mcap.exceptions import EndOfFile, McapError
from mcap.reader import NonSeekingReader, make_reader
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader

log = logging.getLogger("sem-console.recording")

INSTANCES = "sem-console/instances"  # the JSON channel of disposes and lost writers (recorder.py)
COMMANDS = "sem-console/commands"  # the JSON channel of the console's commands; its metadata names the station
ALARM_ACKS = "sem-console/alarm-acks"  # the JSON channel of the alarm acknowledgements the console applied (recorder.py)
NAMES = "sem-console/names"  # the JSON channel of the vehicles' names: those in force at each file's start, each rename


def iter_messages(path: Path, topics: Collection[str]) -> Generator[tuple[str, Any], None, None]:
    """(channel topic, message) of the channels named in `topics`, in log time order; a file without a summary
    (the console stopped on an error or was killed) is read from the start in file order, up to where it is cut
    short or damaged (the iterator then raises McapError or OSError)."""
    with open(path, "rb") as f:
        try:
            complete = make_reader(f).get_summary() is not None
        except (McapError, ValueError, EOFError, struct.error):
            complete = False
        f.seek(0)
        reader = make_reader(f) if complete else NonSeekingReader(f)
        for _schema, channel, message in _records(reader.iter_messages(log_time_order=complete)):
            if channel.topic in topics:
                yield channel.topic, message


def recorded_station(path: Path, channel: str = COMMANDS) -> str | None:
    """The station (--console-name) of the console that recorded the file, from its commands' channel (recorder.py);
    None for a file of a release before it, or one that cannot be read that far."""
    try:
        with open(path, "rb") as f:
            for record in StreamReader(f).records:
                if isinstance(record, Channel) and record.topic == channel:
                    return record.metadata.get("station") or None
                if isinstance(record, Message):  # the recorder registers its channels before any message
                    return None
    except Exception:  # nothing but the file's bytes is parsed here: a file the replay then reports on its own
        return None
    return None


def _records(records: Iterator[tuple[Any, Any, Any]]) -> Generator[tuple[Any, Any, Any], None, None]:
    """`records` of an mcap reader, with what its parsing raises on a file cut short or damaged as one McapError
    that says which: mcap's EndOfFile and EOFError, without a message, and zstd's, lz4's, struct's or a KeyError
    from a damaged chunk (every reader of a recording stops there on McapError and OSError, the replay of what
    came before kept)."""
    while True:
        try:
            record = next(records)
        except StopIteration:
            return
        except (EndOfFile, EOFError):  # neither has a message
            raise McapError("the file is cut short (the recording was not closed)") from None
        except (McapError, OSError):
            raise
        except Exception as e:  # nothing but the file's bytes is parsed here
            raise McapError(f"a damaged chunk or record ({type(e).__name__}: {e})") from None
        yield record


def time_range(path: Path) -> tuple[int, int] | None:
    """(first, last) log time of a recording's messages in ns since the epoch, from its summary, or for a file
    cut short by reading it up to where it stops; None when it holds no message."""
    with open(path, "rb") as f:
        try:
            summary = make_reader(f).get_summary()
        except (McapError, ValueError, EOFError, struct.error):
            summary = None
        if summary is not None and summary.statistics is not None:
            stats = summary.statistics
            return (stats.message_start_time, stats.message_end_time) if stats.message_count else None
        f.seek(0)
        first = last = None
        try:
            # in file order: in log time order the reader sorts what it read only at the end, which a file cut
            # short never reaches (EndOfFile), so not one message was counted
            for _schema, _channel, message in _records(NonSeekingReader(f).iter_messages(log_time_order=False)):
                first = message.log_time if first is None else min(first, message.log_time)
                last = message.log_time if last is None else max(last, message.log_time)
        except (McapError, OSError) as e:
            log.warning("%s ends early: %s", path, e)
    return None if first is None or last is None else (first, last)


def check_file(path: Path) -> str | None:
    """Why `path` cannot be replayed (unreadable, not MCAP), or None."""
    try:
        with open(path, "rb") as f:
            make_reader(f).get_header()
    except OSError as e:
        return f"cannot read {path}: {e.strerror}"
    except (EndOfFile, EOFError, StopIteration):  # no message of their own
        return f"{path} is not an MCAP file: it ends before an MCAP header (empty or cut short)"
    except (McapError, ValueError, struct.error) as e:
        return f"{path} is not an MCAP file: {e}"
    return None
