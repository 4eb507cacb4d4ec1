"""Per-vehicle track and chart series in the console's database, for reloads, charts and exports.

One model per concept: `TrackPoint` and `SeriesPoint` (storage/models/) are SQLModel classes, each both the
table mapping and the REST response model. Points are taken from reports on the event loop (a few
dictionary lookups, at most one point per vehicle and UTC second for each; a track point only when the vehicle
moved, time passed or its state changed: `Thinning`), batched, and written, rolled up (older than the rollup age:
the first point of each interval), pruned (older than the retention) and read in a worker thread, so the database
never runs on the loop.
"""

from __future__ import annotations

import asyncio
import logging
import math
import time
import uuid
from collections.abc import Sequence
from typing import Any, NamedTuple

from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.engine import Engine
from sqlmodel import Session, col, delete, func, select

from sem_console.comap.geo import distance_m
from sem_console.core.config import Settings
from sem_console.storage.locks import VehicleWriters
from sem_console.storage.models import SeriesPoint, TrackPoint
from sem_console.storage.rollup import interval_start, roll_up_step

log = logging.getLogger("sem-console.history")
FLUSH_INTERVAL = 1.0  # seconds between batched writes
HELD_POINTS = 100_000  # track (and series) points held while they cannot be written (a database outage)
PRUNE_INTERVAL_MAX = 60.0  # seconds between prunes and rollups (sooner for a short retention or rollup age)
__all__ = ["History", "SeriesPoint", "Thinning", "TrackPoint", "series_point", "track_point"]


class Thinning(NamedTuple):
    """Which track points are stored, and how old history is rolled up."""

    metres: float  # a track point is stored when the vehicle moved this far from the last one stored,
    seconds: float  # or this long passed since it, or its GPSLatLongValid or fixValid changed
    rollup_after: float  # seconds: older track and series points are rolled up
    rollup_every: float  # to the first of each vehicle's interval of this many seconds

    @classmethod
    def of(cls, settings: Settings) -> Thinning:
        return cls(
            settings.track_thin_metres,
            settings.track_thin_seconds,
            settings.track_rollup_after_hours * 3600.0,
            settings.track_rollup_seconds,
        )


KEEP_ALL = Thinning(0.0, 0.0, math.inf, 60.0)  # every second's point, none rolled up


def _get(d: Any, *path: str) -> Any:
    for key in path:
        if not isinstance(d, dict):
            return None
        d = d.get(key)
    return d


def _number(v: Any) -> float | None:
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) else None


def _flagged(invalid: Sequence[str], path: str) -> bool:
    return any(x.startswith(path) for x in invalid)


def track_point(
    provider: str, received_at: float, fix: dict[str, Any], invalid: Sequence[str], fix_valid: bool | None
) -> dict[str, Any] | None:
    """The track point of a GPSFixReport's JSON, or None when it has no valid position.
    A value the ingest flagged as invalid (out of range) is left out (null)."""
    pos = _get(fix, "position2DWithTime", "geodeticPosition")
    lat, lon = _number(_get(pos, "geodeticLatitude", "latitude")), _number(_get(pos, "geodeticLongitude", "longitude"))
    if lat is None or lon is None or _flagged(invalid, "position2DWithTime.geodeticPosition"):
        return None

    def value(path: str, v: Any) -> float | None:
        return None if _flagged(invalid, path) else _number(v)

    course = value("trueCourse", fix.get("trueCourse"))
    return {
        "providerId": provider,
        "time": received_at,
        "positionTime": value("position2DWithTime.timeAtPosition", _get(fix, "position2DWithTime", "timeAtPosition")),
        "latitude": lat,
        "longitude": lon,
        "altitudeMsl": value("altitudeMSL", _get(fix, "altitudeMSL", "altitude")),
        "course": None if course is None else math.degrees(course) % 360.0,
        "sog": value("SOG", fix.get("SOG")),
        "latLongValid": fix.get("GPSLatLongValid") is True,
        "fixValid": fix_valid,
    }


def series_point(provider: str, received_at: float, gps: dict[str, Any]) -> dict[str, Any]:
    """The chart values of a GPSReport's JSON."""
    sats = [s for s in gps.get("satellites") or [] if isinstance(s, dict)]
    cn0 = [v for v in (_number(s.get("antennaCarrierNoiseDensity")) for s in sats) if v is not None]
    in_view = gps.get("numberSatellitesInView")
    return {
        "providerId": provider,
        "time": received_at,
        "cn0Mean": sum(cn0) / len(cn0) if cn0 else None,
        "satellitesUsed": sum(1 for s in sats if s.get("usedInFix") is True),
        "satellitesInView": in_view if isinstance(in_view, int) and not isinstance(in_view, bool) and in_view >= 0 else len(sats),
    }


class History:
    """Takes points on the loop (`on_fix`, `on_gps`), writes them in batches off it (`run`)."""

    def __init__(self, engine: Engine, retention_hours: float, replay: bool = False, thinning: Thinning = KEEP_ALL) -> None:
        self.engine = engine  # the console's database (storage.Database), which made the tables and closes it
        # shared by consoles (PostgreSQL): each vehicle's points written by one of them
        self.writers = VehicleWriters(engine) if engine.dialect.name == "postgresql" else None
        self._insert = (postgresql if engine.dialect.name == "postgresql" else sqlite).insert
        self.retention = retention_hours * 3600.0
        self.thinning = thinning
        # a replay's points are at the recording's times: their age is not the wall clock's, nothing is rolled up
        self.rollup_after = math.inf if replay else thinning.rollup_after
        self.prune_interval = max(FLUSH_INTERVAL, min(PRUNE_INTERVAL_MAX, self.retention / 4, self.rollup_after / 4))
        # per table: the start of the first interval not rolled up yet (none: from the oldest row), and whether the
        # rollup is behind (a step of it at each flush until it is not)
        self._rolled_to: dict[str, float] = {}
        self._rollup_behind = False
        self._stored: dict[uuid.UUID, dict[str, Any]] = {}  # each vehicle's last track point stored
        self._unstored: dict[uuid.UUID, dict[str, Any]] = {}  # its latest point not stored (thinned) since
        self._track: list[dict[str, Any]] = []
        self._series: list[dict[str, Any]] = []
        self._slot: dict[tuple[str, uuid.UUID], int] = {}  # (table, provider) -> UTC second of its last point
        # a replay's clock only goes forward (a seek back resets the slots): no point in a second not later than
        # the last one's. Live, only the same second is refused: a wall clock stepped back must not stop the track.
        self.replay = replay
        self._lock = asyncio.Lock()
        self._last_prune = 0.0
        # figures for /api/metrics
        self.rows_written = 0
        self.rows_pruned = 0
        self.rows_rolled_up = 0
        self.last_write_seconds = 0.0
        self.max_write_seconds = 0.0

    # ---- on the loop ----------------------------------------------------------------------
    def _due(self, table: str, provider: uuid.UUID, received_at: float) -> bool:
        """At most one point a second: the first report of a new second (in a replay, of a later second)."""
        slot = math.floor(received_at)
        last = self._slot.get((table, provider))
        if last is not None and (slot == last or (self.replay and slot < last)):
            return False
        self._slot[(table, provider)] = slot
        return True

    def on_fix(
        self, provider: uuid.UUID, received_at: float, fix: dict[str, Any], invalid: Sequence[str], fix_valid: bool | None
    ) -> None:
        if not self._due("track", provider, received_at):  # most reports: the vehicle has this second's point
            return
        point = track_point(str(provider), received_at, fix, invalid, fix_valid)
        if point is not None and self._keeps(provider, point):
            self._track.append(point)

    def _keeps(self, provider: uuid.UUID, point: dict[str, Any]) -> bool:
        """Whether the point is stored: the vehicle's first, one that moved at least the thinning's metres from the
        last stored, one at least its seconds after it (or before it: a wall clock stepped back), a changed
        GPSLatLongValid or fixValid. A vehicle that stays put keeps one point per that many seconds."""
        last = self._stored.get(provider)
        if not (
            last is None
            or point["latLongValid"] != last["latLongValid"]
            or point["fixValid"] != last["fixValid"]
            or not 0 <= point["time"] - last["time"] < self.thinning.seconds
            or distance_m((last["latitude"], last["longitude"]), (point["latitude"], point["longitude"])) >= self.thinning.metres
        ):
            self._unstored[provider] = point
            return False
        self._stored[provider] = point
        self._unstored.pop(provider, None)
        return True

    def _quiet(self, now: float | None) -> list[dict[str, Any]]:
        """The latest point of each vehicle whose fixes stopped (none for the thinning's seconds; `now` None: the
        console stops) when it was thinned away: stored, so the track ends where the vehicle was last heard, not up to
        the thinning's metres and seconds short of it (its last known position after a restart). A vehicle silent that
        long is forgotten (its next fix is stored as a first): one that left holds nothing here."""
        if now is None:
            quiet = list(self._unstored)
        elif self.replay:  # a recording's times, not the wall clock's: its points are stored as they are played
            return []
        else:
            quiet = [v for v, p in self._stored.items() if now - self._unstored.get(v, p)["time"] >= self.thinning.seconds]
            for v in quiet:
                del self._stored[v]
        return [self._unstored.pop(v) for v in quiet if v in self._unstored]

    def on_gps(self, provider: uuid.UUID, received_at: float, gps: dict[str, Any]) -> None:
        if self._due("series", provider, received_at):
            self._series.append(series_point(str(provider), received_at, gps))

    async def run(self) -> None:
        """Flush every FLUSH_INTERVAL until canceled (then once more)."""
        failing = False
        try:
            while True:
                await asyncio.sleep(FLUSH_INTERVAL)
                try:
                    await self.flush()
                    if failing:
                        log.warning("the track and series are written again")
                    failing = False
                except Exception as e:  # a full disk or a database outage must not stop the console: held, logged once
                    if not failing:
                        log.warning(
                            "could not write the track and series (%s): held (up to %d points) and tried again each second",
                            str(e).splitlines()[0] if str(e) else type(e).__name__,
                            HELD_POINTS,
                        )
                    failing = True
        finally:
            self._track += self._quiet(None)
            if self._track or self._series:
                await asyncio.shield(self.flush())

    async def flush(self, upkeep: bool = True) -> None:
        """Write the points taken; with `upkeep`, prune and roll up when due (a read asks for the points only: it
        must not wait for a step of the rollup of a backlog, each of a dashboard's reads of every vehicle's track)."""
        async with self._lock:
            now = time.time()
            track, series, self._track, self._series = self._track + self._quiet(now), self._series, [], []
            due = upkeep and now - self._last_prune >= self.prune_interval
            prune_before = now - self.retention if due else None
            rollup_before = None
            if math.isfinite(self.rollup_after) and (due or (upkeep and self._rollup_behind)):
                rollup_before = interval_start(now - self.rollup_after, self.thinning.rollup_every)
            if not (track or series or due or rollup_before is not None):
                return
            if due:
                self._last_prune = now
            started = time.perf_counter()
            try:
                await asyncio.to_thread(self._write, track, series, prune_before, rollup_before)
            except Exception:  # kept for the next flush (a database outage), up to HELD_POINTS: then the oldest go
                self._track, self._series = (track + self._track)[-HELD_POINTS:], (series + self._series)[-HELD_POINTS:]
                raise
            for model, rows in ((TrackPoint, track), (SeriesPoint, series)):  # points held through an outage: rolled up
                rolled_to = self._rolled_to.get(model.__tablename__)
                if rolled_to is not None and rows:
                    oldest = interval_start(min(p["time"] for p in rows), self.thinning.rollup_every)
                    self._rolled_to[model.__tablename__] = min(rolled_to, oldest)
            self.last_write_seconds = time.perf_counter() - started
            self.max_write_seconds = max(self.max_write_seconds, self.last_write_seconds)

    def _write(
        self,
        track: list[dict[str, Any]],
        series: list[dict[str, Any]],
        prune_before: float | None,
        rollup_before: float | None,
    ) -> None:
        if self.writers is not None:  # another console writes the vehicles it holds: their points here are dropped
            w = self.writers
            mine = w.mine({p["providerId"] for p in (*track, *series)})
            track = [p for p in track if p["providerId"] in mine and w.after_last(TrackPoint.__tablename__, p)]
            series = [p for p in series if p["providerId"] in mine and w.after_last(SeriesPoint.__tablename__, p)]
        with Session(self.engine) as s:
            for model, rows in ((TrackPoint, track), (SeriesPoint, series)):
                if rows:
                    s.execute(self._insert(model).on_conflict_do_nothing(), rows)
            if prune_before is not None:
                for model in (TrackPoint, SeriesPoint):
                    self.rows_pruned += s.execute(delete(model).where(col(model.time) < prune_before)).rowcount  # type: ignore[attr-defined]  # a DELETE's result is a CursorResult
            s.commit()
            if rollup_before is not None:  # a step per table and transaction: a command's write waits for one at most
                behind = False
                for model in (TrackPoint, SeriesPoint):
                    name = model.__tablename__
                    step = roll_up_step(s, model, self._rolled_to.get(name), rollup_before, self.thinning.rollup_every)
                    s.commit()
                    if step is None:  # another console's rollup: this one's at its next prune
                        continue
                    self._rolled_to[name] = step[0]
                    self.rows_rolled_up += step[1]
                    behind = behind or step[0] < rollup_before
                self._rollup_behind = behind
        self.rows_written += len(track) + len(series)

    async def forget_after(self, t: float) -> None:
        """A replay seeking back to `t`: every point after it goes, held or written, so the track and
        charts show what the recording had said by then (the points played next are taken again)."""
        async with self._lock:  # after a flush in progress, before the next
            self._track = [p for p in self._track if p["time"] <= t]
            self._series = [p for p in self._series if p["time"] <= t]
            self._stored, self._unstored = {}, {}  # the first point played next is stored
            kept = await asyncio.to_thread(self._delete_after, t)
            # each vehicle's last second with a point, kept or held: the rebuild up to `t` adds none before it
            for table, rows in (("track", self._track), ("series", self._series)):
                for p in rows:
                    kept[(table, p["providerId"])] = max(kept.get((table, p["providerId"]), p["time"]), p["time"])
            self._slot = {(table, uuid.UUID(provider)): math.floor(time_) for (table, provider), time_ in kept.items()}

    def _delete_after(self, t: float) -> dict[tuple[str, str], float]:
        """Delete the points after `t`; the latest time kept per (table, provider)."""
        kept: dict[tuple[str, str], float] = {}
        with Session(self.engine) as s:
            for table, model in (("track", TrackPoint), ("series", SeriesPoint)):
                s.execute(delete(model).where(col(model.time) > t))
                for provider, latest in s.exec(select(model.providerId, func.max(model.time)).group_by(model.providerId)).all():
                    kept[(table, provider)] = latest
            s.commit()
        return kept

    # ---- reads (REST) ------------------------------------------------------------------------
    async def track(self, provider: uuid.UUID, since: float | None, until: float | None) -> list[TrackPoint]:
        return await self._read(TrackPoint, provider, since, until)

    async def series(self, provider: uuid.UUID, since: float | None, until: float | None) -> list[SeriesPoint]:
        return await self._read(SeriesPoint, provider, since, until)

    async def has(self, provider: uuid.UUID) -> bool:
        """Whether the database has any point of this provider (it may not be on the bus now)."""

        def query() -> bool:
            with Session(self.engine) as s:
                for model in (TrackPoint, SeriesPoint):
                    if s.exec(select(model.time).where(model.providerId == str(provider)).limit(1)).first() is not None:
                        return True
            return False

        return await asyncio.to_thread(query)

    async def _read(self, model: type[Any], provider: uuid.UUID, since: float | None, until: float | None) -> list[Any]:
        await self.flush(upkeep=False)  # what arrived until now is included

        def query() -> list[Any]:
            q = select(model).where(model.providerId == str(provider))
            if since is not None:
                q = q.where(col(model.time) >= since)
            if until is not None:
                q = q.where(col(model.time) <= until)
            with Session(self.engine) as s:
                rows = list(s.exec(q.order_by(col(model.time))).all())
                s.expunge_all()
                return rows

        return await asyncio.to_thread(query)

    def close(self) -> None:
        """Let the vehicles this console wrote go (the engine is the database's, closed by it)."""
        if self.writers is not None:
            self.writers.close()
