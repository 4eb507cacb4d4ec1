"""The audit trail: one row per request to a command route, accepted or refused; the newest `max_rows` are kept."""

from __future__ import annotations

from typing import Any

from sqlalchemy import Connection, delete, insert, select

from sem_console.storage.context import Context
from sem_console.storage.models import AuditRecord, table

AUDIT = table(AuditRecord)
AUDIT_COLUMNS = ("at", "outcome", "status", "method", "path", "client", "origin", "operator", "session_id", "reason")


class Audit:
    def __init__(self, ctx: Context, max_rows: int) -> None:
        self.ctx, self.max_rows = ctx, max_rows

    def add(self, entry: dict[str, Any]) -> None:
        """One entry (keys: AUDIT_COLUMNS). Ids count up (never reused), so the prune is one range delete on the key."""
        row = {k: entry.get(k) for k in AUDIT_COLUMNS}

        def write(c: Connection) -> None:
            new_id = c.execute(insert(AUDIT).values(row).returning(AUDIT.c.id)).scalar_one()
            c.execute(delete(AUDIT).where(AUDIT.c.id <= new_id - self.max_rows))
            self.ctx.notify(c, "audit", id=new_id)

        self.ctx.writes.write(write)

    def newest(self, limit: int, offset: int) -> list[AuditRecord]:
        """Newest first."""
        with self.ctx.writes.reads() as c:
            q = select(*AUDIT.c).order_by(AUDIT.c.id.desc()).limit(limit).offset(offset)
            return [AuditRecord(**r) for r in c.execute(q).mappings()]
