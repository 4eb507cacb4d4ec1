"""What every aggregate's queries share: the engine, the outage write-behind, the station's name (sent with each
notification, so a console skips its own) and the dialect's INSERT (for ON CONFLICT)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sqlalchemy import Connection, Engine
from sqlalchemy.dialects import postgresql, sqlite

from sem_console.storage.notify import notify
from sem_console.storage.outage import WriteBehind
from sem_console.storage.url import DatabaseUrl


@dataclass
class Context:
    db: DatabaseUrl
    engine: Engine
    writes: WriteBehind
    station: str | None = None  # the console name claimed (storage/names.py)

    def insert(self, table: Any) -> Any:
        """The dialect's INSERT of `table` (its on_conflict_do_update and on_conflict_do_nothing)."""
        return (postgresql if self.engine.dialect.name == "postgresql" else sqlite).insert(table)

    def notify(self, c: Connection, kind: str, **fields: Any) -> None:
        """Tell the other consoles on this database what changed (delivered when the transaction commits)."""
        if self.db.path is None:
            notify(c, {"kind": kind, "console": self.station, **fields})
