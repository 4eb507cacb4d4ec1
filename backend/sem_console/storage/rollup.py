"""Old track and chart history rolled up: of each vehicle's rows in a span of time, only the first of each interval
is kept (intervals counted from the epoch), on SQLite and PostgreSQL alike."""

from __future__ import annotations

from typing import Any

from sqlalchemy import ColumnElement, Integer, cast, func, literal
from sqlalchemy.orm import aliased
from sqlmodel import Session, col, delete, select

from sem_console.storage.models import SeriesPoint, TrackPoint


def interval_start(t: float, every: float) -> float:
    """The start of the interval of `every` seconds that `t` falls in."""
    return (t // every) * every


def roll_up(s: Session, model: type[TrackPoint] | type[SeriesPoint], since: float | None, before: float, every: float) -> int:
    """Delete the rows of `model` whose time is in [since, before) (since None: from the oldest) and that are not the
    first of their vehicle's interval of `every` seconds; how many were deleted. `since` and `before` are interval
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
    if since is not None:
        stmt = stmt.where(col(model.time) >= since)
    return int(s.execute(stmt).rowcount)  # type: ignore[attr-defined]  # a DELETE's result is a CursorResult
