"""Names: each console station's name and its UMAA source GUID, and the names operators gave vehicles from the
dashboard (shared by the consoles of one database: notification kind "name")."""

from __future__ import annotations

import time
import uuid
from typing import Any

from sqlalchemy import Connection, delete, insert, select, update
from sqlalchemy.exc import IntegrityError

from sem_console.storage.context import Context
from sem_console.storage.engine import StorageError
from sem_console.storage.models import AlarmRecord, CommandRecord, ConsoleIdentity, Meta, VehicleNameRecord, table

CONSOLES, META, VEHICLE_NAMES = table(ConsoleIdentity), table(Meta), table(VehicleNameRecord)
COMMANDS, ALARMS = table(CommandRecord), table(AlarmRecord)


class Names:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx

    def identity(self, name: str) -> uuid.UUID:
        """The source GUID of console `name`: the one it had, else the first release's (meta 'source') when no name
        took it yet, else a new one."""
        for _attempt in range(3):  # another console may take the first release's GUID at the same moment
            try:
                with self.ctx.engine.begin() as c:
                    guid = c.execute(select(CONSOLES.c.guid).where(CONSOLES.c.name == name)).scalar()
                    if guid is not None:
                        return uuid.UUID(guid)
                    legacy = c.execute(select(META.c.value).where(META.c.key == "source")).scalar()
                    if legacy is None or c.execute(select(CONSOLES.c.name).where(CONSOLES.c.guid == legacy)).first():
                        legacy = None
                    guid = legacy or str(uuid.uuid4())
                    c.execute(insert(CONSOLES).values(name=name, guid=guid, created_at=time.time()))
                    if legacy is not None:  # the first release's commands and alarms were this station's
                        c.execute(update(COMMANDS).where(COMMANDS.c.console.is_(None)).values(console=name))
                        c.execute(update(ALARMS).where(ALARMS.c.console.is_(None)).values(console=name))
                    return uuid.UUID(guid)
            except IntegrityError:
                continue
        raise StorageError(f"{self.ctx.db.shown}: could not record the console name {name!r}: try again")

    def consoles(self) -> dict[str, uuid.UUID]:
        """Every console name that used this database -> its source GUID."""
        with self.ctx.writes.reads() as c:
            return {n: uuid.UUID(g) for n, g in c.execute(select(CONSOLES.c.name, CONSOLES.c.guid))}

    def vehicle_names(self) -> dict[str, str]:
        """provider GUID string -> the name an operator set for it from the dashboard."""
        with self.ctx.writes.reads() as c:
            return {p: n for p, n in c.execute(select(VEHICLE_NAMES.c.provider_id, VEHICLE_NAMES.c.name))}

    def set_vehicle_name(self, provider_id: str, name: str | None, by: str | None) -> None:
        """Store a vehicle's name; None removes it (the configured name applies again)."""
        if name is None:
            stmt: Any = delete(VEHICLE_NAMES).where(VEHICLE_NAMES.c.provider_id == provider_id)
        else:
            ins = self.ctx.insert(VEHICLE_NAMES).values(provider_id=provider_id, name=name, set_by=by, set_at=time.time())
            stmt = ins.on_conflict_do_update(
                index_elements=["provider_id"],
                set_={"name": ins.excluded.name, "set_by": ins.excluded.set_by, "set_at": ins.excluded.set_at},
            )

        def write(c: Connection) -> None:
            c.execute(stmt)
            self.ctx.notify(c, "name", provider=provider_id)

        self.ctx.writes.write(write)
