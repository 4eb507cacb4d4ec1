"""Alarms, and the shelves and planned silences the stations share (notification kinds "alarm-ack", "shelf" and
"silence"). Each console station writes its own alarms; an acknowledgement reaches the other stations' alarm of the
same key."""

from __future__ import annotations

import itertools
from collections import deque
from concurrent.futures import Future
from typing import Any

from sqlalchemy import Connection, Table, delete, func, insert, or_, select, text, update

from sem_console.storage.context import Context
from sem_console.storage.models import AlarmRecord, AlarmShelfRecord, PlannedSilenceRecord, table

ALARMS, SHELVES, SILENCES = table(AlarmRecord), table(AlarmShelfRecord), table(PlannedSilenceRecord)
ALARMS_KEPT = 100_000  # alarms back to normal kept in the database
IDS_AHEAD = 64  # alarm ids taken from the database ahead of the alarms, so an alarm has its row's id at once
ALARM_COLUMNS = (
    "key",
    "kind",
    "severity",
    "provider_id",
    "vehicle",
    "session_id",
    "text",
    "since",
    "cleared_at",
    "acked_at",
    "acked_by",
    "normal_at",
)


class Alarms:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self._ahead: deque[int] = deque()  # row ids taken for the next alarms (the caller's, on the loop)
        self._taking: Future[list[int]] | None = None
        self._taken = 0  # SQLite: the highest id taken (the writer thread's)
        self._temporary_ids = itertools.count(-1, -1)  # alarms raised with no id taken ahead (a database outage)
        self._ids: dict[int, int] = {}  # such a temporary id -> its row's id once written (the writer thread's)
        self._take_ids()

    def _take_ids(self) -> None:
        """Take the next row ids ahead, on the writer thread (the caller does not wait), when few are left."""
        if self._taking is not None and self._taking.done():
            if not self._taking.cancelled() and self._taking.exception() is None:
                self._ahead.extend(self._taking.result())
            self._taking = None
        if self._taking is None and len(self._ahead) < IDS_AHEAD // 2:
            self._taking = self.ctx.writes.write(lambda c: self._next_ids(c, IDS_AHEAD))

    def _next_ids(self, c: Connection, n: int) -> list[int]:
        """`n` row ids no alarm has, nor is given (on the writer thread)."""
        if self.ctx.db.path is None:  # the table's sequence, shared by the consoles of the database
            q = text("SELECT nextval(pg_get_serial_sequence('alarms', 'id')) FROM generate_series(1, :n)")
            return list(c.execute(q, {"n": n}).scalars())
        top = max(c.execute(select(func.max(ALARMS.c.id))).scalar() or 0, self._taken)  # one console per file
        self._taken = top + n
        return list(range(top + 1, self._taken + 1))

    def add(self, alarm: dict[str, Any]) -> int:
        """A new alarm (keys: ALARM_COLUMNS); returns its id at once: its row's, taken ahead. With none taken (the
        database away since the console started, or long) a temporary negative one, which the writer thread maps to
        the row it writes, where the alarm's updates go (its last, back to normal, lets it go); the row's id is the
        alarm's after a restart. The oldest alarms back to normal beyond ALARMS_KEPT go."""
        self._take_ids()
        given = self._ahead.popleft() if self._ahead else next(self._temporary_ids)
        row = {**{k: alarm.get(k) for k in ALARM_COLUMNS}, "console": self.ctx.station}

        def write(c: Connection) -> None:
            new_id = given if given > 0 else self._next_ids(c, 1)[0]  # not one of those taken ahead meanwhile
            c.execute(insert(ALARMS).values({**row, "id": new_id}))
            c.execute(delete(ALARMS).where(ALARMS.c.id <= new_id - ALARMS_KEPT, ALARMS.c.normal_at.is_not(None)))
            if given < 0:
                self._ids[given] = new_id

        self.ctx.writes.write(write)
        return given

    def update(self, alarm: dict[str, Any]) -> None:
        values = {k: alarm[k] for k in ("since", "cleared_at", "acked_at", "acked_by", "normal_at")}

        def write(c: Connection) -> None:
            row_id = self._ids.get(alarm["id"], alarm["id"])
            if alarm["normal_at"] is not None:  # its last write: the alarm leaves the console's memory
                self._ids.pop(alarm["id"], None)
            acked_before = c.execute(select(ALARMS.c.acked_at).where(ALARMS.c.id == row_id)).scalar()
            c.execute(update(ALARMS).where(ALARMS.c.id == row_id).values(values))
            # the other stations' alarm of the same key is acknowledged too: told once, as it is acknowledged, not again
            # at each later save of it (its words changed, back to normal), which would acknowledge an alarm of that key
            # another station raised since (the vehicle lost again) that nobody has seen
            if alarm["acked_at"] is not None and acked_before is None:
                self.ctx.notify(c, "alarm-ack", key=alarm["key"], at=alarm["acked_at"], by=alarm["acked_by"])

        self.ctx.writes.write(write)

    def open(self) -> list[AlarmRecord]:
        """This console's alarms not back to normal, oldest first."""
        q = select(*ALARMS.c).where(ALARMS.c.normal_at.is_(None)).order_by(ALARMS.c.id)
        if self.ctx.station is not None:
            q = q.where(ALARMS.c.console == self.ctx.station)
        with self.ctx.writes.reads() as c:
            return [AlarmRecord(**r) for r in c.execute(q).mappings()]

    def acked_elsewhere(self, since: dict[str, float]) -> dict[str, tuple[float, str | None]]:
        """Alarm key -> (when, by whom) another console station acknowledged its alarm of that key, at or after
        `since[key]` (this console's alarm of the key was raised then): what a reopened listener may have missed."""
        out: dict[str, tuple[float, str | None]] = {}
        if not since:
            return out
        q = (
            select(ALARMS.c.key, ALARMS.c.acked_at, ALARMS.c.acked_by)
            .where(
                ALARMS.c.key.in_(list(since)),
                ALARMS.c.acked_at.is_not(None),
                or_(ALARMS.c.console.is_(None), ALARMS.c.console != self.ctx.station),
            )
            .order_by(ALARMS.c.acked_at)
        )
        with self.ctx.writes.reads() as c:
            for key, at, by in c.execute(q):
                if at >= since[key]:
                    out[key] = (at, by)
        return out

    def add_shelf(self, shelf: dict[str, Any]) -> None:
        """A new shelf (keys: AlarmShelfRecord's); the other stations hear it with the row."""
        self._add_shared(SHELVES, "shelf", shelf)

    def end_shelf(self, shelf_id: str, at: float, by: str | None, why: str) -> None:
        """End a shelf, unless it has ended already (another station, or its time, ended it first)."""
        self._end_shared(SHELVES, "shelf", shelf_id, at, by, why)

    def add_silence(self, silence: dict[str, Any]) -> None:
        """A new planned silence (keys: PlannedSilenceRecord's)."""
        self._add_shared(SILENCES, "silence", silence)

    def end_silence(self, silence_id: str, at: float, by: str | None, why: str) -> None:
        self._end_shared(SILENCES, "silence", silence_id, at, by, why)

    def shelves(self) -> list[AlarmShelfRecord]:
        """The shelves not ended, oldest first."""
        with self.ctx.writes.reads() as c:
            q = select(*SHELVES.c).where(SHELVES.c.ended_at.is_(None)).order_by(SHELVES.c.shelved_at)
            return [AlarmShelfRecord(**r) for r in c.execute(q).mappings()]

    def silences(self) -> list[PlannedSilenceRecord]:
        """The planned silences not ended, oldest first."""
        with self.ctx.writes.reads() as c:
            q = select(*SILENCES.c).where(SILENCES.c.ended_at.is_(None)).order_by(SILENCES.c.set_at)
            return [PlannedSilenceRecord(**r) for r in c.execute(q).mappings()]

    def _add_shared(self, t: Table, kind: str, values: dict[str, Any]) -> None:
        row = {c.name: values.get(c.name) for c in t.c}

        def write(c: Connection) -> None:
            c.execute(insert(t).values(row))
            self.ctx.notify(c, kind, row=row)

        self.ctx.writes.write(write)

    def _end_shared(self, t: Table, kind: str, row_id: str, at: float, by: str | None, why: str) -> None:
        def write(c: Connection) -> None:
            ended = c.execute(
                update(t).where(t.c.id == row_id, t.c.ended_at.is_(None)).values(ended_at=at, ended_by=by, end_reason=why)
            ).rowcount
            if ended:
                self.ctx.notify(c, kind, row={"id": row_id, "ended_at": at, "ended_by": by, "end_reason": why})

        self.ctx.writes.write(write)

    def clear(self) -> None:
        """Forget every alarm, shelf and silence (a replay rebuilding its state)."""

        def write(c: Connection) -> None:
            for t in (ALARMS, SHELVES, SILENCES):
                c.execute(delete(t))

        self.ctx.writes.write(write)
