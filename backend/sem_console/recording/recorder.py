"""Recording to MCAP: every SEM sample the console takes, raw, plus the console's own view.

- **SEM topics**: one channel per DDS topic of either UMAA version (named by the topic, e.g.
  `UMAA::SEM::GPSStatus::GPSReport` in 3.0.1, `UMAA::SEM::GPSStatus::GPSReportType` in 6.0; channel metadata
  `umaaVersion`), message encoding `cdr`: each message is the sample's CDR as
  it came off the wire, with its 4-byte encapsulation header; `log_time` is when the console took
  it, `publish_time` the writer's source timestamp (ns since the epoch). Schemas: `omgidl`, named
  by the UMAA type, the IDL of the topic's version (`schema.py`). Disposes and instances that lost their writers have no sample
  to record: they go to the JSON channel `sem-console/instances` (topic, key CDR, source, sessionId).
- **The console's view**: JSON channels (`jsonschema` schemas) `sem-console/commands`,
  `sem-console/transitions` (each with its Figure 4 verdict) and `sem-console/links` (provider
  events), holding the WebSocket messages of the same names (`core/contract.py`); a command's says too whether the
  console followed it as its own (`RecordedCommandMessage.followed`: its alarms, for a replay); and
  `sem-console/alarm-acks`, each alarm acknowledgement the console applied (`AlarmAckEvent`: a replay derives the alarms
  again and acknowledges them from these); and `sem-console/names`, the vehicles' names as the console showed them
  (`VehicleNameEvent`): every one in force when a file starts, at its start, then each rename (a replay names the
  vehicles as the recording station did, not by its own --vehicle-names).

Files `DIR/<UTC start>.mcap` roll over at `max_bytes` or `max_seconds`. Recording never blocks
ingest: the ingest threads (one item per take of a topic) and the event loop only put items on
a bounded buffer (a deque: no lock; full, the item is dropped and its samples counted, a rename never); one
writer thread per recording writes what was queued every BATCH_SECONDS (a thread wake costs
about 0.1 ms of CPU in the running console, more than writing a take). Any OSError (a full
disk: ENOSPC) stops the recording with the error in its status and in the log; the console
goes on. Chunks are flushed at least every FLUSH_SECONDS, so a crash loses at most that much.
"""

from __future__ import annotations

import base64
import contextlib
import datetime as dt
import errno
import json
import logging
import re
import threading
import time
import uuid
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, BinaryIO, Literal

from cyclonedds.core import InstanceState
from mcap.exceptions import McapError
from mcap.reader import make_reader
from pydantic import BaseModel, ConfigDict, Field

from sem_console import __version__
from sem_console.core.contract import CommandMessage, ProviderMessage, TransitionMessage
from sem_console.core.messages import RecordingStatus
from sem_console.dds.topics import AnySem, Sem, Sem60, delimited
from sem_console.recording.mcap_writer import McapWriter
from sem_console.recording.reader import ALARM_ACKS, COMMANDS, INSTANCES, NAMES
from sem_console.recording.schema import MESSAGE_ENCODING, SCHEMA_ENCODING, topic_idl, type_name, version_of

log = logging.getLogger("sem-console.recording")

FLUSH_SECONDS = 2.0
BATCH_SECONDS = 0.2  # the writer thread writes what was queued at most this often: a wake costs ~0.1 ms of CPU
# the extensibility of a channel of samples an appendable writer sent (_File.appendable)
APPENDABLE: Literal["appendable"] = "appendable"
SEM_TOPICS: tuple[AnySem, ...] = (*Sem, *Sem60)  # every SEM topic of both UMAA versions: a channel each in every file
PROFILE = ""  # MCAP profile: none of the well-known ones (ros1, ros2...) applies
_ALIVE = InstanceState.Alive
NAME = re.compile(r"^\d{8}T\d{6}\.\d{3}Z(-\d+)?\.mcap$")


class InstanceEvent(BaseModel):
    """An instance of a SEM topic that was disposed or lost its last writer (channel `sem-console/instances`)."""

    model_config = ConfigDict(extra="forbid")
    topic: str = Field(description="the DDS topic name")
    state: str = Field(description="'disposed' or 'noWriters'")
    key: str = Field(description="the instance's key as received: CDR with its encapsulation header, base64")
    source: str | None = Field(description="the key's source GUID as a UUID string")
    sessionId: str | None = Field(description="the key's sessionID (command, status and ack topics)")


class RecordedCommandMessage(CommandMessage):
    """A `command` WebSocket message as recorded (channel `sem-console/commands`), with whether the recording console
    followed the command as its own."""

    followed: bool | None = Field(
        None,
        description=(
            "the recording console followed this command as its own when it sent this message: it issued it, or took it "
            "over from another station (to cancel it), so it raised the command's alarms; false: another station's command, "
            "only shown; absent in files of recorders that did not write it (a replay then goes by the issuing station)"
        ),
    )


class AlarmAckEvent(BaseModel):
    """An alarm of the console's active set acknowledged, here or on another station (channel `sem-console/alarm-acks`):
    the alarms are derived again in a replay, and these acknowledge them there as they were."""

    model_config = ConfigDict(extra="forbid")
    type: str = Field(description="'alarm-ack'")
    key: str = Field(description="the alarm's key (kind|provider|session|detail), the same in a replay that derives it again")
    kind: str
    providerId: str | None
    sessionId: str | None
    ackedAt: float = Field(description="when it was acknowledged, UTC seconds")
    ackedBy: str | None = Field(description="the operator who acknowledged it (null: no sign-in)")
    station: str | None = Field(
        description="the console station it was acknowledged on (--console-name): the recording "
        "console's, or another's of its database; null: not known (another station's, "
        "read again after a lost database connection)"
    )


class VehicleNameEvent(BaseModel):
    """A vehicle's name as the recording console showed it (channel `sem-console/names`): a replay names the vehicle so
    from this instant on, over its own --vehicle-names."""

    model_config = ConfigDict(extra="forbid")
    type: str = Field(description="'vehicle-name'")
    providerId: str = Field(description="the vehicle's source GUID as a UUID string")
    name: str | None = Field(
        description="its name: the one set from the dashboard, else the recording console's "
        "--vehicle-names name; null: it has none from here on (renamed back to none)"
    )
    initial: bool = Field(
        description="true: in force when the file started (one message per named vehicle, at the "
        "file's first instant); false: renamed while recording"
    )


# JSON channel -> (WebSocket message type it holds, the model of its messages)
JSON_CHANNELS: dict[str, tuple[str, type[BaseModel]]] = {
    COMMANDS: ("command", RecordedCommandMessage),
    "sem-console/transitions": ("transition", TransitionMessage),
    "sem-console/links": ("provider", ProviderMessage),
    INSTANCES: ("instance", InstanceEvent),
    ALARM_ACKS: ("alarm-ack", AlarmAckEvent),
    NAMES: ("vehicle-name", VehicleNameEvent),
}
_CHANNEL_OF_TYPE = {kind: channel for channel, (kind, _model) in JSON_CHANNELS.items()}


def file_name(at: float) -> str:
    """`DIR/<UTC start time>.mcap`, ISO 8601 basic format with milliseconds: 20261122T101530.123Z.mcap."""
    t = dt.datetime.fromtimestamp(at, dt.UTC)
    return t.strftime("%Y%m%dT%H%M%S.") + f"{t.microsecond // 1000:03d}Z.mcap"


def start_of(name: str) -> float:
    return dt.datetime.strptime(name[:19], "%Y%m%dT%H%M%S.%f").replace(tzinfo=dt.UTC).timestamp()


class RecordingError(Exception):
    """A recording that cannot start (the directory cannot be made or written)."""


class _File:
    """One MCAP file being written, with a channel for every SEM topic and JSON channel."""

    def __init__(self, path: Path, station: str | None = None) -> None:
        self.path = path
        self.stream: BinaryIO = open(path, "xb")  # noqa: SIM115 (closed in close())
        self.writer = McapWriter(self.stream, profile=PROFILE, library=f"sem-console {__version__}")
        self.channels: dict[Any, int] = {}
        self.sequence: dict[int, int] = {}
        for sem in SEM_TOPICS:
            schema = self.writer.register_schema(type_name(sem.spec.type), SCHEMA_ENCODING, topic_idl(sem).encode())
            self.channels[sem] = self.writer.register_channel(
                sem.spec.name, MESSAGE_ENCODING, schema, {"umaaVersion": version_of(sem)}
            )
        for channel, (_kind, model) in JSON_CHANNELS.items():
            schema = self.writer.register_schema(model.__name__, "jsonschema", json.dumps(model.model_json_schema()).encode())
            # the commands' channel names the recording console's station: a replay tells its own commands (its
            # alarms) from other stations' on the same database, which reached it only to be shown (reader.recorded_station)
            metadata = {"station": station} if channel == COMMANDS and station else None
            self.channels[channel] = self.writer.register_channel(channel, "json", schema, metadata)
        self.opened = time.monotonic()
        self.opened_ns = time.time_ns()
        self.named = False  # the names in force at its start written (Recorder._write_names)

    def appendable(self, sem: AnySem) -> tuple[AnySem, str]:
        """The channel key of the samples of `sem` that an appendable writer sent (an RTI vehicle's GPSReport and
        GPSFixReport: delimited XCDR2, TopicSpec.appendable). Their own channel, on the same topic, whose schema is the
        IDL with every struct appendable, so a reader of the file decodes them as they are laid out; registered at the
        first such sample, so a recording without one has none."""
        key = (sem, APPENDABLE)
        if key not in self.channels:
            schema = self.writer.register_schema(
                type_name(sem.spec.type), SCHEMA_ENCODING, topic_idl(sem, extensibility=APPENDABLE).encode()
            )
            self.channels[key] = self.writer.register_channel(
                sem.spec.name, MESSAGE_ENCODING, schema, {"umaaVersion": version_of(sem), "extensibility": APPENDABLE}
            )
        return key

    def add(self, key: Any, data: bytes, log_ns: int, publish_ns: int) -> None:
        cid = self.channels[key]
        seq = self.sequence[cid] = self.sequence.get(cid, 0) + 1
        self.writer.add_message(cid, log_ns, data, publish_ns, seq)

    def add_samples(self, key: AnySem | tuple[AnySem, str], samples: list[tuple[bytes, bool, int, int]], log_ns: int) -> int:
        """The valid samples of one take, in order; returns how many. The hot path: one call per sample."""
        add, cid = self.writer.add_message, self.channels[key]
        seq = self.sequence.get(cid, 0)
        for raw, valid, _state, source_ns in samples:
            if valid:
                seq += 1
                add(cid, log_ns, raw, source_ns if source_ns > 0 else 0, seq)
        n = seq - self.sequence.get(cid, 0)
        self.sequence[cid] = seq
        return n

    def size(self) -> int:
        """The size the rollover goes by: what is written, and the chunk in progress before compression."""
        return self.writer.tell() + self.writer.pending()

    def close(self) -> None:
        try:
            self.writer.finish()
        finally:
            self.stream.close()

    def abandon(self) -> None:
        with contextlib.suppress(OSError):
            self.stream.close()


class Recorder:
    """Owned by the console; an `ingest.Tap` of its feed (`on_samples`). start/stop/status run on the loop
    (start and stop do a little file I/O: call them off the loop); the writer thread does the rest."""

    def __init__(
        self,
        directory: Path,
        max_bytes: int,
        max_seconds: float,
        queue_size: int = 2_000,
        on_change: Callable[[RecordingStatus], None] | None = None,
        station: str | None = None,
        names: Callable[[], Mapping[str, str]] | None = None,
    ) -> None:
        self.directory, self.max_bytes, self.max_seconds = directory, max_bytes, max_seconds
        self.station = station  # the console's name, in each file (the commands' channel)
        self.names = names  # the vehicles' names in force (provider GUID string -> name), read when a recording starts
        self._names: dict[str, str] = {}  # the writer thread's: those at the start, with every rename written since
        self.queue_size = queue_size
        self.on_change = on_change
        self.active = False
        self.dropped = 0
        self.messages = 0
        self.writer_cpu = 0.0  # CPU seconds of this recording's writer thread (its files, all of them)
        self.started_at: float | None = None
        self.error: str | None = None
        self._file: _File | None = None
        self._files_written = 0
        self._buffer: deque[tuple[Any, Any, int, int]] = deque()  # appends and poplefts are atomic: no lock
        self._stopping = threading.Event()
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()  # start/stop against each other

    # ---- input (ingest threads, event loop): never blocks ---------------------------------
    def on_samples(self, sem: AnySem, samples: list[tuple[bytes, bool, int, int]], received_ns: int) -> None:
        """One take of a topic (ingest.Tap): one queue item, however many samples."""
        self._put((sem, samples, received_ns, len(samples)))

    def on_message(self, message: Mapping[str, Any], followed: bool | None = None) -> None:
        """A console WebSocket message; commands, transitions and provider events are recorded. `followed`, for a
        command: whether this console follows it as its own (RecordedCommandMessage.followed)."""
        channel = _CHANNEL_OF_TYPE.get(message.get("type", ""))
        if channel is not None and self.active:
            if followed is not None and channel == COMMANDS:
                message = {**message, "followed": followed}
            item = (channel, message, time.time_ns(), 1)
            if channel == NAMES:  # never dropped: a lost rename misnamed the vehicle in a replay for the rest of the
                self._buffer.append(item)  # recording, each later file's start too (rare: operators' renames)
            else:
                self._put(item)

    def _put(self, item: tuple[Any, Any, int, int]) -> None:
        buffer = self._buffer
        if len(buffer) >= self.queue_size:
            self.dropped += item[3]
        else:
            buffer.append(item)

    # ---- control -----------------------------------------------------------------------
    def start(self) -> RecordingStatus:
        with self._lock:
            if self.active:
                return self.status()
            if self._thread is not None:  # a writer that stopped on an error: it has finished
                self._thread.join()
            try:
                self.directory.mkdir(parents=True, exist_ok=True)
                first = self._open()
            except OSError as e:
                raise RecordingError(f"cannot record into {self.directory}: {e.strerror or e}") from None
            self._file, self.error, self.dropped, self.messages, self.writer_cpu = first, None, 0, 0, 0.0
            self.started_at = time.time()
            self._buffer, self._stopping = deque(), threading.Event()
            self.active = True
            # read after `active`: a rename from here on is queued as well (and written after these), none is missed;
            # a copy of the loop's dict, which dict() makes at once (holding the GIL)
            self._names = dict(self.names()) if self.names is not None else {}
            self._thread = threading.Thread(
                target=self._run, args=(self._buffer, self._stopping), name="sem-recorder", daemon=True
            )
            self._thread.start()
            log.info("recording to %s", first.path)
        self._changed()
        return self.status()

    def stop(self, timeout: float = 10.0) -> RecordingStatus:
        with self._lock:
            thread = self._thread
            if self.active:
                self.active = False
                self._stopping.set()  # the writer writes what is queued, then closes the file
            if thread is not None:
                thread.join(timeout)
                if not thread.is_alive():
                    self._thread = None
        self._changed()
        return self.status()

    def status(self) -> RecordingStatus:
        f = self._file
        state = "recording" if self.active else "failed" if self.error else "off"
        return {
            "state": state,
            "directory": str(self.directory),
            "file": f.path.name if f else None,
            "startedAt": self.started_at if self.active else None,
            "messages": self.messages,
            "dropped": self.dropped,
            "error": self.error,
            "writerCpuSeconds": round(self.writer_cpu, 4),
        }

    def _changed(self) -> None:
        if self.on_change is not None:
            self.on_change(self.status())

    # ---- files -------------------------------------------------------------------------
    def _open(self) -> _File:
        name = file_name(time.time())
        path, n = self.directory / name, 0
        while True:
            try:
                return _File(path, self.station)
            except FileExistsError:
                n += 1
                path = self.directory / name.replace(".mcap", f"-{n}.mcap")

    @staticmethod
    def valid_name(name: str) -> bool:
        """Only names the recorder makes: never a path (no '/', no '..')."""
        return NAME.fullmatch(name) is not None

    def path_of(self, name: str) -> Path | None:
        """The recording of that name in the directory, or None."""
        if not self.valid_name(name):
            return None
        path = self.directory / name
        return path if path.is_file() else None

    def current(self) -> str | None:
        f = self._file
        return f.path.name if f is not None and self.active else None

    def list(self) -> list[dict[str, Any]]:
        """Every recording in the directory, newest first (reads each file's summary)."""
        if not self.directory.is_dir():
            return []
        current = self.current()
        out = []
        for path in sorted((p for p in self.directory.iterdir() if NAME.fullmatch(p.name)), reverse=True):
            try:
                size = path.stat().st_size
            except OSError:
                continue
            start, end, state = start_of(path.name), None, "recording" if path.name == current else "incomplete"
            if state != "recording":
                stats = _statistics(path)
                if stats is not None:
                    state = "complete"
                    if stats.message_count:
                        start, end = stats.message_start_time / 1e9, stats.message_end_time / 1e9
            out.append({"name": path.name, "size": size, "start": start, "end": end, "state": state})
        return out

    # ---- the writer thread ---------------------------------------------------------------
    def _run(self, buffer: deque[tuple[Any, Any, int, int]], stopping: threading.Event) -> None:
        f = self._file
        assert f is not None
        flushed = time.monotonic()
        cpu0 = time.thread_time()
        try:
            while True:
                self.writer_cpu = time.thread_time() - cpu0
                # what was queued in the last BATCH_SECONDS, at once: a thread wake per take costs more than the write
                stop = stopping.wait(BATCH_SECONDS)
                items = [buffer.popleft() for _ in range(len(buffer))]
                if not f.named:
                    self._write_names(f, items)
                for item in items:
                    self._write(f, *item)
                if stop:
                    break
                now = time.monotonic()
                if f.size() >= self.max_bytes or now - f.opened >= self.max_seconds:
                    f.close()
                    f = self._file = self._open()
                    log.info("recording rolled over to %s", f.path)
                    flushed = now
                    self._changed_from_thread()
                elif now - flushed >= FLUSH_SECONDS:
                    f.writer.flush()
                    flushed = now
            f.close()
            log.info("recording stopped: %s (%d messages, %d dropped)", f.path, self.messages, self.dropped)
        except OSError as e:
            f.abandon()
            self.active = False
            reason = "the disk is full" if e.errno == errno.ENOSPC else (e.strerror or str(e))
            self.error = f"recording stopped: {reason} ({f.path})"
            log.error("%s; the console goes on without recording", self.error)
            self._changed_from_thread()
        except Exception as e:  # a bug here must never reach the console
            f.abandon()
            self.active = False
            self.error = f"recording stopped: {e}"
            log.exception("recording stopped")
            self._changed_from_thread()

    def _write(self, f: _File, key: Any, data: Any, log_ns: int, _count: int) -> None:
        if isinstance(key, Sem | Sem60):
            if key.spec.appendable is not None and any(delimited(s[0]) for s in data):  # from an appendable writer
                self.messages += f.add_samples(f.appendable(key), [s for s in data if delimited(s[0])], log_ns)
                self.messages += f.add_samples(key, [s for s in data if not delimited(s[0])], log_ns)
            else:
                self.messages += f.add_samples(key, data, log_ns)
            for raw, valid, instance_state, source_ns in data:
                if instance_state != _ALIVE:
                    event = _instance_event(key, raw, valid, instance_state)
                    f.add(INSTANCES, json.dumps(event).encode(), log_ns, max(source_ns, 0))
                    self.messages += 1
        else:
            f.add(key, json.dumps(data, separators=(",", ":")).encode(), log_ns, log_ns)
            self.messages += 1
            if key == NAMES:  # what the next file starts with
                if data["name"] is None:
                    self._names.pop(data["providerId"], None)
                else:
                    self._names[data["providerId"]] = data["name"]

    def _write_names(self, f: _File, items: Sequence[tuple[Any, Any, int, int]]) -> None:
        """The names in force at the start of file `f`, before its first batch `items`: at the earliest of its
        opening and their log times (a take is timed before it is queued, so one can be a little older than the file),
        so that a replay names each vehicle from its first message."""
        at = min([f.opened_ns, *(item[2] for item in items)])
        for provider_id, name in sorted(self._names.items()):
            event = {"type": "vehicle-name", "providerId": provider_id, "name": name, "initial": True}
            f.add(NAMES, json.dumps(event, separators=(",", ":")).encode(), at, at)
            self.messages += 1
        f.named = True

    def _changed_from_thread(self) -> None:
        if self.on_change is not None:
            self.on_change(self.status())


def _instance_event(sem: AnySem, data: bytes, valid: bool, instance_state: int) -> dict[str, Any]:
    # an appendable writer's (delimited XCDR2) with the appendable copy: the final type misreads it, and sem-replay
    # disposes such a key with a writer of that copy
    dtype = sem.spec.appendable if sem.spec.appendable is not None and delimited(data) else sem.spec.type
    try:
        key = dtype.deserialize(data) if valid else dtype.deserialize_key(data)
        key_cdr = key.serialize_key() if valid else data
    except Exception:  # an undecodable key: recorded as received
        key, key_cdr = None, data
    state = "disposed" if instance_state == InstanceState.NotAliveDisposed else "noWriters"
    return {
        "topic": sem.spec.name,
        "state": state,
        "key": base64.b64encode(key_cdr).decode(),
        "source": _uuid(getattr(key, "source", None)),
        "sessionId": _uuid(getattr(key, "sessionID", None)),
    }


def _uuid(raw: Any) -> str | None:
    """A NumericGUID as a UUID string; of an identifier (UMAA 6.0's IdentifierType, a `source`), its `id`."""
    raw = getattr(raw, "id", raw)
    try:
        return str(uuid.UUID(bytes=bytes(raw)))
    except (TypeError, ValueError):
        return None


def _statistics(path: Path) -> Any:
    """The statistics of a finished MCAP file; None for one without a summary (still written, or cut short)."""
    try:
        with open(path, "rb") as fh:
            summary = make_reader(fh).get_summary()
    except (OSError, McapError, ValueError, EOFError):
        return None
    return summary.statistics if summary is not None else None
