"""CoMap: the world model (one row) and the tasks the console stations assigned, shared by the consoles of one
database (notification kinds "worldmodel" and "task"), and the task ids they take in turn."""

from __future__ import annotations

import json
import threading
from typing import Any, TypedDict, cast

from sqlalchemy import Connection, and_, case, delete, insert, or_, select, update

from sem_console.storage.context import Context
from sem_console.storage.models import ComapTaskIds, ComapTaskRecord, ComapWorldRecord, table
from sem_console.storage.outage import Unavailable

COMAP_WORLD, COMAP_TASKS, COMAP_TASK_IDS = table(ComapWorldRecord), table(ComapTaskRecord), table(ComapTaskIds)
TASK_IDS = 0xFFFE  # CoMap task ids 1..65534 (a u16 on IMC), wrapping


class WorldRow(TypedDict):
    """The row of ComapWorldRecord, its `features` JSON parsed."""

    id: int
    features: list[dict[str, Any]]
    updated_at: float
    source: str | None
    highest_feature: int
    station: str | None


class TaskRow(TypedDict):
    """A row of ComapTaskRecord, its `point` JSON parsed."""

    task_id: int
    kind: str
    vehicle: str
    imc_id: int
    operator: str | None
    feature_id: int | None
    sensor: str | None
    resolution: float | None
    deadline: float | None
    point: dict[str, float] | None
    state: str
    progress: int
    quality: int | None
    created_at: float
    updated_at: float
    last_synch: str | None
    station: str | None
    state_at: float


class Comap:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx
        self._taking_task_id = threading.Lock()  # new_task, from the assigns' worker threads

    def world(self) -> WorldRow | None:
        """The stored world model, None before any."""
        with self.ctx.writes.reads() as c:
            row = c.execute(select(*COMAP_WORLD.c)).mappings().first()
        return None if row is None else cast(WorldRow, {**row, "features": json.loads(row["features"])})

    def tasks(self, task_id: int | None = None) -> list[TaskRow]:
        """Every stored task (or the one `task_id`), oldest first."""
        q = select(*COMAP_TASKS.c).order_by(COMAP_TASKS.c.created_at)
        if task_id is not None:
            q = q.where(COMAP_TASKS.c.task_id == task_id)
        with self.ctx.writes.reads() as c:
            rows = [dict(r) for r in c.execute(q).mappings()]
        return [cast(TaskRow, {**r, "point": json.loads(r["point"]) if r["point"] else None}) for r in rows]

    def set_world(self, world: dict[str, Any]) -> None:
        """Store the world model (keys: features, updated_at, source, highest_feature), unless the row holds a newer
        one (written by another console meanwhile, or before this console's held write after an outage)."""
        t = COMAP_WORLD
        values = {**world, "id": 1, "features": json.dumps(world["features"]), "station": self.ctx.station}
        ins = self.ctx.insert(t).values(values)
        stmt = ins.on_conflict_do_update(
            index_elements=[t.c.id],
            set_={k: ins.excluded[k] for k in values if k != "id"},
            where=t.c.updated_at <= ins.excluded.updated_at,
        )

        def write(c: Connection) -> None:
            c.execute(stmt)
            self.ctx.notify(c, "worldmodel")

        self.ctx.writes.write(write)

    def set_task(self, task: dict[str, Any], final: frozenset[str]) -> None:
        """Store a task's change (keys: ComapTaskRecord's). Its state and synch are written where decided after the
        row's (`state_at`), its progress and quality where newer than the row's (`updated_at`), each by its own stamp:
        a station's progress write carries the stamp of the state it read, so it never stores that state over another
        station's newer one (a HOLD), and a HOLD held through an outage is stored after it even though the vehicle's
        progress, stored by another station meanwhile, is newer. A `final` state stored is never replaced by one that
        is not, nor by a final one decided after it (comap.c2.decided_over: the same rule on each console). Never over
        another task of that id."""
        t = COMAP_TASKS
        ins = self.ctx.insert(t).values(_task_row(task))
        new = ins.excluded
        stored_final, new_final = t.c.state.in_(final), new.state.in_(final)
        state_wins = or_(
            and_(new_final, or_(~stored_final, new.state_at < t.c.state_at)),
            and_(~new_final, ~stored_final, t.c.state_at <= new.state_at),
        )
        progress_wins = t.c.updated_at <= new.updated_at

        def newest(column: Any, wins: Any) -> Any:
            return case((wins, new[column.name]), else_=column)

        stmt = ins.on_conflict_do_update(
            index_elements=[t.c.task_id],
            set_={
                **{c.name: newest(c, state_wins) for c in (t.c.state, t.c.last_synch, t.c.state_at)},
                **{c.name: newest(c, progress_wins) for c in (t.c.progress, t.c.quality, t.c.updated_at)},
            },
            where=(t.c.created_at == new.created_at) & (state_wins | progress_wins),
        )

        def write(c: Connection) -> None:
            c.execute(stmt)
            self.ctx.notify(c, "task", id=task["task_id"])

        self.ctx.writes.write(write)

    def new_task(self, task: dict[str, Any], final: frozenset[str]) -> int | None:
        """Take a task id for `task` and store it, in one transaction on the locked counter row: ids go up from the
        last one any console took and wrap at 65534; an id whose task is not in a `final` state is skipped. None:
        every id is taken by an unfinished task. For a worker thread; Unavailable during an outage (the id could
        collide with one another console takes meanwhile)."""
        if self.ctx.writes.unavailable_since is not None:
            raise self._unavailable()
        # one at a time in this console: SQLite has no FOR UPDATE (two assigns at once read one counter, and the
        # second deleted the first's task of that id and took it again)
        with self.ctx.writes.outage(self._unavailable), self._taking_task_id, self.ctx.engine.begin() as c:
            start = c.execute(select(COMAP_TASK_IDS.c.next_task).where(COMAP_TASK_IDS.c.id == 1).with_for_update()).scalar_one()
            busy = set(c.execute(select(COMAP_TASKS.c.task_id).where(COMAP_TASKS.c.state.not_in(final))).scalars())
            order = (((start - 1 + k) % TASK_IDS) + 1 for k in range(TASK_IDS))  # from start, wrapping
            tid: int | None = next((i for i in order if i not in busy), None)
            if tid is None:
                return None
            c.execute(delete(COMAP_TASKS).where(COMAP_TASKS.c.task_id == tid))  # a finished task of that id
            c.execute(insert(COMAP_TASKS).values(_task_row({**task, "task_id": tid})))
            c.execute(update(COMAP_TASK_IDS).where(COMAP_TASK_IDS.c.id == 1).values(next_task=tid % TASK_IDS + 1))
            self.ctx.notify(c, "task", id=tid)
            return tid

    def _unavailable(self) -> Unavailable:
        return Unavailable(
            f"no new CoMap task while the database {self.ctx.db.shown} cannot be reached (since "
            f"{self.ctx.writes.since()}): task ids are taken there so that no two stations send the same "
            "one; assign it when the database is back (the tasks already assigned go on)"
        )


def _task_row(task: dict[str, Any]) -> dict[str, Any]:
    return {
        **{k: task[k] for k in (col.name for col in COMAP_TASKS.c)},
        "vehicle": str(task["vehicle"]),
        "point": json.dumps(task["point"]) if task["point"] is not None else None,
    }
