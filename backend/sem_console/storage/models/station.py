"""The station's own tables: its identity, the audit trail, the vehicles' link configurations and names."""

from __future__ import annotations

from sqlmodel import Field, SQLModel


class Meta(SQLModel, table=True):
    """Key/value of the first schema; its 'source' row held the console's source GUID before the consoles table."""

    __tablename__ = "meta"
    key: str = Field(primary_key=True)
    value: str


class ConsoleIdentity(SQLModel, table=True):
    """A console station's name and its UMAA source GUID (NumericGUID): one per name, never shared."""

    __tablename__ = "consoles"
    name: str = Field(primary_key=True, description="--console-name (default: host name and HTTP port)")
    guid: str = Field(unique=True, description="the console's source GUID as a UUID string")
    created_at: float = Field(description="UTC seconds since the epoch when the name was first used")


class AuditRecord(SQLModel, table=True):
    """One request to a command route (accepted or refused); the newest Settings.audit_max_rows are kept."""

    __tablename__ = "audit"
    __table_args__ = {"sqlite_autoincrement": True}  # ids never reused: the prune is one range delete on the key
    id: int | None = Field(None, primary_key=True)
    at: float
    outcome: str
    status: int
    method: str
    path: str
    client: str | None = None
    origin: str | None = None
    operator: str | None = None
    session_id: str | None = None
    reason: str


class LinkConfigRecord(SQLModel, table=True):
    """A vehicle's link configuration as an operator set it (JSON of core.contract.LinkConfig)."""

    __tablename__ = "link_config"
    provider_id: str = Field(primary_key=True)
    config: str


class VehicleNameRecord(SQLModel, table=True):
    """A vehicle's name as an operator set it from the dashboard (over --vehicle-names), who set it and when."""

    __tablename__ = "vehicle_names"
    provider_id: str = Field(primary_key=True)
    name: str
    set_by: str | None = None
    set_at: float
