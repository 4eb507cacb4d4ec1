"""CoMap's world model and tasks."""

from __future__ import annotations

from sqlmodel import Field, SQLModel


class ComapWorldRecord(SQLModel, table=True):
    """The CoMap world model the consoles of one database share: one row (id 1), the newest change of any of them."""

    __tablename__ = "comap_world"
    id: int = Field(1, primary_key=True, sa_column_kwargs={"autoincrement": False})
    features: str = Field(description="JSON list of the features: featureId, points ([lat, lon] degrees), coverage, properties")
    updated_at: float = Field(description="UTC seconds of the change (a write older than the row's is not applied)")
    source: str | None = Field(None, description="operator, coverage or imc:<system id>")
    highest_feature: int = Field(0, description="the highest featureId seen: a new feature is numbered above it")
    station: str | None = Field(None, description="the console station that wrote it")


class TaskPlanned(SQLModel):
    """A CoMap task as planned; with TaskProgress and TaskOwned, what the row (ComapTaskRecord) and the API's task
    (api/schemas.py, in camelCase) have in common."""

    task_id: int = Field(description="the CoMap task id (u16), unique among the unfinished tasks of the consoles on one database")
    kind: str
    vehicle: str = Field(description="the provider GUID")
    imc_id: int
    feature_id: int | None
    sensor: str | None
    resolution: float | None
    deadline: float | None = Field(description="UTC seconds since the epoch")


class TaskProgress(SQLModel):
    """A task's state and progress, as the vehicle's TaskStatus reports them."""

    state: str
    progress: int = Field(ge=0, le=100, description="% from the vehicle's TaskStatus")
    quality: int | None = Field(description="% from the vehicle's TaskStatus, null before any")


class TaskOwned(SQLModel):
    """Who assigned a task, where, and when it changed."""

    operator: str | None
    station: str | None = Field(description="the console station that assigned it (--console-name)")
    created_at: float
    updated_at: float = Field(
        description="UTC seconds of the newest progress (the vehicle's TaskStatus); the task's creation before any"
    )
    state_at: float = Field(
        description="UTC seconds the state and synch were decided (a synch, a state the vehicle "
        "reported): a client merging copies of a task takes state and synch from the "
        "one with the later stateAt, progress and quality from the later updatedAt"
    )


class ComapTaskRecord(TaskOwned, TaskProgress, TaskPlanned, table=True):
    """A CoMap task a console station assigned (comap/c2.py's Task), its state as the newest change says."""

    __tablename__ = "comap_tasks"
    task_id: int = Field(primary_key=True, sa_column_kwargs={"autoincrement": False})
    point: str | None = Field(default=None, description="a move's destination as JSON {lat, lon}")
    last_synch: str | None = None
    state_at: float = Field(
        0.0, sa_column_kwargs={"server_default": "0"}, description="a final state is never replaced (comap.c2.decided_over)"
    )


class ComapTaskIds(SQLModel, table=True):
    """The next CoMap task id to try (one row, id 1, locked while a console takes an id: no two take the same)."""

    __tablename__ = "comap_task_ids"
    id: int = Field(1, primary_key=True, sa_column_kwargs={"autoincrement": False})
    next_task: int = Field(1, description="1..65534, wrapping")
