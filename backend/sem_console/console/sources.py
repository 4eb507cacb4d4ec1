"""Where the console's input comes from: DDS (live) or a recording (`sem-console --replay FILE.mcap`).

A recording is a data source like DDS: both decode samples with the same `Decoder` and hand them to the
same console methods (`Console.on_reports`, `on_statuses`, `apply`). What differs is kept here, chosen
once by `open_source(settings)`: the clock, the database the rebuilt state goes to, whether commands
can be published (a recording is read-only), the counters /api/metrics shows and the playback status
of the snapshot. `Console` composes one source and never asks which one it has.
"""

from __future__ import annotations

import asyncio
import logging
import math
import tempfile
import threading
from pathlib import Path
from typing import Any, Protocol

from cyclonedds.core import DDSException
from cyclonedds.sub import DataReader

from sem_console.console.clock import Clock, RecordingClock
from sem_console.console.hops import Links, listen
from sem_console.console.ingest import Ingest, ReportItem, StatusItem
from sem_console.console.replay_source import Replay, Replayed
from sem_console.core.config import Settings
from sem_console.core.messages import ReplayStatus
from sem_console.dds.bus import Bus, bus_security, wait_for_acks
from sem_console.dds.topics import AnySem
from sem_console.storage.database import Database
from sem_console.storage.url import sqlite_file
from sem_console.versions.commands import COMMAND_TOPICS

log = logging.getLogger("sem-console")


class ConsoleSink(Replayed, Protocol):
    """What a source drives: the console (`service.Console`), which hands itself in to `attach`. Declared here, so
    that the sources never import the console that composes them."""

    def on_reports(self, items: list[ReportItem]) -> None: ...

    def on_statuses(self, items: list[StatusItem]) -> None: ...

    def on_relay_links(self, links: Links, received: float) -> None: ...


class Source(Protocol):
    @property
    def clock(self) -> Clock: ...

    @property
    def read_only(self) -> bool:
        """Nothing is published: no commands, no recording, no IMC, no other station listened to."""
        ...

    @property
    def station(self) -> str:
        """The console's name in the database."""
        ...

    @property
    def retention_hours(self) -> float:
        """How long track and chart history is kept."""
        ...

    @property
    def seeks(self) -> bool:
        """Time may go backwards (a replay seeking): the history forgets what follows."""
        ...

    @property
    def replay(self) -> Replay | None:
        """The playback and its controls (api/routes/replay.py); None live."""
        ...

    def database(self, opened: Database | None) -> Database:
        """The database the console's state is kept in (`opened`: the one `sem-console` opened, if any)."""
        ...

    def attach(self, console: ConsoleSink) -> None:
        """Bind the input to the console (on the loop, before anything is resumed); nothing flows yet."""
        ...

    async def start(self) -> None: ...

    def write(self, topic: AnySem, sample: Any) -> None:
        """Publish a command on its topic (that of its vehicle's version: versions/commands.py)."""

    def dispose(self, topic: AnySem, sample: Any) -> None: ...

    def wait_for_acks(self, timeout: float) -> None:
        """Until the providers acknowledged every command sample written (blocking: off the loop)."""
        ...

    async def stop(self) -> None:
        """No more input reaches the console (the bus stays up)."""
        ...

    async def close(self) -> None:
        """Release what the input holds (the DDS participant; a replay's temporary database)."""
        ...

    def counters(self) -> dict[str, Any]:
        """The input's counters for /api/metrics."""
        ...

    def status(self) -> ReplayStatus | None:
        """The snapshot's `replay` field: the playback (None live)."""
        ...


def open_source(settings: Settings) -> Source:
    return DdsSource(settings) if settings.replay is None else RecordingSource(settings, settings.replay)


class DdsSource:
    """Live: the DDS participant, its ingest, the command writers and the embedded simulator (`--sim`)."""

    read_only = False
    seeks = False
    replay: Replay | None = None

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self.clock = Clock()
        self.station = settings.station()
        self.retention_hours = settings.track_retention_hours
        security = bus_security(settings.dds_security, settings.domain)
        self.bus = Bus(settings.domain, settings.dds_interface, settings.dds_peers, security)
        self.command_writers = {topic: self.bus.writer(topic) for topic in COMMAND_TOPICS}  # every version's
        self.ingest: Ingest | None = None
        self.relay_links: DataReader[Any] | None = None
        self._sim: tuple[threading.Thread, list[bool]] | None = None

    def database(self, opened: Database | None) -> Database:
        return opened or Database(self.settings.database(), self.settings.audit_max_rows)

    def attach(self, console: ConsoleSink) -> None:
        self.ingest = Ingest(
            self.bus,
            asyncio.get_running_loop(),
            console.on_reports,
            console.on_statuses,
            self.settings.report_interval,
            console.feed,  # the raw samples, to its taps (the recorder, the Foxglove gateway)
            self.settings.report_burst,
            dict(self.command_writers),
        )
        self.relay_links = listen(self.bus, asyncio.get_running_loop(), console.on_relay_links)  # console/hops.py

    async def start(self) -> None:
        assert self.ingest is not None, "attach() first"
        self.ingest.start()
        if self.settings.sim:
            self._start_sim()

    def write(self, topic: AnySem, sample: Any) -> None:
        writer = self.command_writers.get(topic)  # none once the bus is left
        if writer is not None:
            writer.write(sample)

    def dispose(self, topic: AnySem, sample: Any) -> None:
        writer = self.command_writers.get(topic)
        if writer is not None:
            writer.dispose(sample)

    def wait_for_acks(self, timeout: float) -> None:
        wait_for_acks(list(self.command_writers.values()), timeout)

    async def stop(self) -> None:
        if self.ingest is not None:
            await asyncio.to_thread(self.ingest.stop)

    async def close(self) -> None:
        if self._sim:
            thread, stop = self._sim
            stop[0] = True
            await asyncio.to_thread(thread.join, 10)  # start-up bus check (up to 3 s) plus its shutdown
            if thread.is_alive():
                log.warning(
                    "the embedded simulator did not finish its shutdown in 10 s: the console leaves the bus "
                    "under it (its vehicles' reports may stay on the bus until they time out)"
                )
        # Leave the bus: unregister as a publisher of commands (ICD 4.1.6.2), unsubscribe, delete the participant.
        self.command_writers.clear()
        self.ingest = None
        self.relay_links = None
        self.bus.close()

    def counters(self) -> dict[str, Any]:
        ingest = self.ingest
        return {
            "samplesTaken": ingest.taken if ingest else 0,
            "samplesDecoded": ingest.decoded if ingest else 0,
            "samplesByReader": dict(ingest.by_reader) if ingest else {},
            "undecodableSamples": sum(ingest.decoder.undecodable.values()) if ingest else 0,
            "incompatibleWriters": dict(ingest.incompatible) if ingest else {},
            "peerFindings": [f.to_json() for f in ingest.findings] if ingest else [],
            "reportWindowWaits": ingest.window_waits if ingest else 0,
            "samplesLost": ingest.samples_lost if ingest else 0,
        }

    def status(self) -> ReplayStatus | None:
        return None

    def _start_sim(self) -> None:
        from sem_console.sim.provider import InUse, SimOptions, Simulator

        stop = [False]
        opts = SimOptions(
            vehicles=self.settings.sim, first_vehicle=self.settings.sim_first_vehicle, time_scale=self.settings.sim_time_scale
        )

        def run() -> None:
            # A participant of its own, as a vehicle's: on the console's, a Service Consumer (sem-check) took the
            # console's readers of the command topics (a VOLATILE one among them) for the vehicle's.
            bus = Bus(self.settings.domain, self.settings.dds_interface, self.settings.dds_peers)
            try:
                simulate(bus)
            finally:
                bus.close()

        def simulate(bus: Bus) -> None:
            try:
                sim = Simulator(bus, opts)  # looks for its vehicles on the bus first: off the loop
            except InUse as e:
                hint = f"; start the console with --sim-first-vehicle {e.free} to run both" if e.free else ""
                log.error("the embedded simulator did not start: %s%s", e, hint)
                return
            twin = False
            try:
                sim.run(lambda: stop[0])
            except InUse as e:
                twin = True
                log.error("the embedded simulator stopped: %s", e)
            except DDSException as e:
                if not stop[0]:
                    raise
                log.warning("the embedded simulator was stopped by the bus closing under it: %s", e)
            finally:
                try:
                    sim.shutdown(twin=twin)
                except DDSException as e:  # its participant went under it (the process leaving): nothing to dispose on
                    log.warning("the embedded simulator's shutdown sequence did not finish: %s", e)

        thread = threading.Thread(target=run, name="sem-sim", daemon=True)
        thread.start()
        self._sim = (thread, stop)


class RecordingSource:
    """A recording played back (`console/replay_source.py`): no DDS participant, the recording's clock, and the
    rebuilt state in a temporary database removed when it stops, so the live console's is never touched (the
    exports read the database on connections of their own, so not ":memory:"). Its track and chart history is
    kept whatever the recording's age."""

    read_only = True
    seeks = True
    station = "replay"
    retention_hours = math.inf

    def __init__(self, settings: Settings, path: Path) -> None:
        self.settings, self.path = settings, path
        self.clock = RecordingClock()
        self._dir = tempfile.TemporaryDirectory(prefix="sem-replay-")
        self._store: Database | None = None
        self.replay: Replay | None = None

    def database(self, opened: Database | None) -> Database:
        self._store = Database(sqlite_file(Path(self._dir.name) / "replay.sqlite3"), self.settings.audit_max_rows)
        return self._store

    def attach(self, console: ConsoleSink) -> None:
        self.replay = Replay(console, self.path, self.settings.replay_speed, self.clock)

    async def start(self) -> None:
        assert self.replay is not None, "attach() first"
        await self.replay.open()

    def write(self, topic: AnySem, sample: Any) -> None:
        """Nothing is published from a recording."""

    def dispose(self, topic: AnySem, sample: Any) -> None:
        """Nothing is published from a recording."""

    def wait_for_acks(self, timeout: float) -> None:
        """Nothing was written."""

    async def stop(self) -> None:
        if self.replay is not None:
            await self.replay.close()

    async def close(self) -> None:
        if self._store is not None:
            await asyncio.to_thread(self._store.close)  # its writes flushed before its file goes (again: nothing)
        self._dir.cleanup()

    def counters(self) -> dict[str, Any]:
        decoder = self.replay.decoder if self.replay else None
        return {
            "samplesTaken": 0,
            "samplesDecoded": decoder.decoded if decoder else 0,
            "samplesByReader": {},
            "undecodableSamples": sum(decoder.undecodable.values()) if decoder else 0,
            "incompatibleWriters": {},
            "peerFindings": [],
            "reportWindowWaits": 0,
        }

    def status(self) -> ReplayStatus | None:
        return self.replay.status() if self.replay else None
