"""Old track and chart history rolled up: of each vehicle's rows in a span of time, only the first of each interval
is kept (intervals counted from the epoch), on SQLite and PostgreSQL alike."""

from __future__ import annotations

from typing import Any

from sqlalchemy import ColumnElement, Integer, cast, func, literal
from sqlalchemy.orm import aliased
from sqlmodel import Session, col, delete, select

from sem_console.storage.locks import _key
from sem_console.storage.models import SeriesPoint, TrackPoint

STEP_SECONDS = 60.0  # of history rolled up in one transaction (a whole number of intervals, at least one)


def interval_start(t: float, every: float) -> float:
    """The start of the interval of `every` seconds that `t` falls in."""
    return (t // every) * every


def roll_up(s: Session, model: type[TrackPoint] | type[SeriesPoint], since: float | None, before: float, every: float) -> int:
    """Delete the rows of `model` whose time is in [since, before) (since None: from the oldest) and that are not the
    first of their vehicle's interval of `every` seconds (nor, on the track, one whose GPSLatLongValid or fixValid
    differs from the vehicle's row before it); how many were deleted. `since` and `before` are interval
    starts, so an interval is rolled up once and whole."""
    earlier = aliased(model)
    postgresql = s.get_bind().dialect.name == "postgresql"

    def start(t: Any) -> ColumnElement[Any]:  # SQLite's CAST truncates (a time is positive); PostgreSQL's rounds
        return (func.floor(t / every) if postgresql else cast(t / every, Integer)) * every

    first = (
        select(literal(1))
        .where(
            col(earlier.providerId) == col(model.providerId),
            col(earlier.time) < col(model.time),
            col(earlier.time) >= start(col(model.time)),
        )
        .exists()
    )
    stmt = delete(model).where(col(model.time) < before, first)
    if model is TrackPoint:  # a change of GPSLatLongValid or fixValid is kept, at its time: the track says when it was
        prev = aliased(TrackPoint)

        def previous(c: Any) -> Any:  # the vehicle's row before this one: its value of `c`
            q = select(c).where(col(prev.providerId) == col(TrackPoint.providerId), col(prev.time) < col(TrackPoint.time))
            return q.order_by(col(prev.time).desc()).limit(1).scalar_subquery()

        stmt = stmt.where(
            col(TrackPoint.latLongValid) == previous(col(prev.latLongValid)),
            col(TrackPoint.fixValid).is_not_distinct_from(previous(col(prev.fixValid))),
        )
    if since is not None:
        stmt = stmt.where(col(model.time) >= since)
    return int(s.execute(stmt).rowcount)  # type: ignore[attr-defined]  # a DELETE's result is a CursorResult


def roll_up_step(
    s: Session, model: type[TrackPoint] | type[SeriesPoint], since: float | None, before: float, every: float
) -> tuple[float, int] | None:
    """Roll up the next STEP_SECONDS of `model`'s rows from `since` (None: the oldest) towards `before`, in the session's
    transaction (its commit ends the step): where the next step starts and how many rows were deleted. A step is
    bounded, so the database's writer (SQLite has one) is never held long for a backlog (a day of history after a
    start), and time with no rows is skipped at once. None: another console on the database (PostgreSQL) is rolling
    this table up now; it is not waited for (two consoles deleting the same rows would wait on, or deadlock with,
    each other)."""
    if s.get_bind().dialect.name == "postgresql":
        taken = s.execute(select(func.pg_try_advisory_xact_lock(_key(f"rollup:{model.__tablename__}")))).scalar()
        if not taken:
            return None
    oldest = select(func.min(col(model.time))).where(col(model.time) < before)
    if since is not None:
        oldest = oldest.where(col(model.time) >= since)
    first = s.execute(oldest).scalar()
    if first is None:
        return before, 0
    start = interval_start(first, every)
    end = min(before, start + every * max(1.0, STEP_SECONDS // every))
    return end, roll_up(s, model, start, end, every)
