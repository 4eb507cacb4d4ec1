"""Link configurations: each vehicle's link thresholds and comms-lost settings as an operator set them (JSON of
core.contract.LinkConfig), shared by the consoles of one database (notification kind "link")."""

from __future__ import annotations

import json
from typing import Any

from sqlalchemy import Connection, select

from sem_console.storage.context import Context
from sem_console.storage.models import LinkConfigRecord, table

LINK_CONFIG = table(LinkConfigRecord)


class Links:
    def __init__(self, ctx: Context) -> None:
        self.ctx = ctx

    def link_configs(self) -> dict[str, Any]:
        """provider GUID string -> the link configuration an operator set for it (as stored: the caller validates)."""
        out: dict[str, Any] = {}
        with self.ctx.writes.reads() as c:
            for provider, config in c.execute(select(LINK_CONFIG.c.provider_id, LINK_CONFIG.c.config)):
                try:
                    out[provider] = json.loads(config)
                except ValueError:  # not JSON: the caller's validation refuses it
                    out[provider] = config
        return out

    def set_link_config(self, provider_id: str, config: dict[str, Any]) -> None:
        stmt = self.ctx.insert(LINK_CONFIG).values(provider_id=provider_id, config=json.dumps(config))
        upsert = stmt.on_conflict_do_update(index_elements=["provider_id"], set_={"config": stmt.excluded.config})

        def write(c: Connection) -> None:
            c.execute(upsert)
            self.ctx.notify(c, "link", provider=provider_id)

        self.ctx.writes.write(write)
