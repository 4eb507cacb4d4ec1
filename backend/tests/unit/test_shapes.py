"""Each shape that leaves the process is declared once, and what mirrors it cannot drift from it: the WebSocket builders'
TypedDicts (core/messages.py) name the fields of the contract's models (api/schemas.py, the JSON Schema the
dashboard's types are generated from), and the rows, API models and domain classes derived from one base
(storage/models/) keep its fields."""

from __future__ import annotations

import typing
from typing import Any, NotRequired, get_args, get_origin, get_type_hints, is_typeddict

import pytest
from pydantic import BaseModel
from pydantic.alias_generators import to_camel
from sqlmodel import SQLModel

from sem_console.api import schemas
from sem_console.console.alarms import Alarm, Shelf, Silence
from sem_console.console.hub import dumps
from sem_console.core import messages
from sem_console.storage.models import (
    AlarmBase,
    AlarmHandled,
    AlarmRaised,
    AlarmRecord,
    AlarmShelfRecord,
    ComapTaskRecord,
    CommandHandled,
    CommandIssued,
    CommandRecord,
    PlannedSilenceRecord,
    ShelfBase,
    SilenceBase,
    TaskOwned,
    TaskPlanned,
    TaskProgress,
    TransitionBase,
    TransitionRecord,
    table,
)

# shapes a builder carries as a plain dict: GeoJSON (comap/geo.py) and a task's point, {lat, lon}
OPAQUE = {("WorldModelMessage", "worldModel"), ("Task", "point")}
TYPED_DICTS = {name: t for name, t in vars(messages).items() if is_typeddict(t) and t.__module__ == messages.__name__}


def wire_fields(model: type[BaseModel]) -> dict[str, bool]:
    """The JSON names of a model's fields, each with whether the JSON must have it."""
    return {f.alias or name: f.is_required() for name, f in model.model_fields.items()}


def typed_fields(td: Any) -> dict[str, bool]:
    """A TypedDict's keys, each with whether it is required (NotRequired: not; read from the hint, since the string
    annotations of `from __future__ import annotations` hide it from __required_keys__)."""
    return {k: get_origin(hint) is not NotRequired for k, hint in get_type_hints(td, include_extras=True).items()}


def _nested(tp: Any) -> list[Any]:
    """The TypedDicts inside a field's type (list[Alarm], Alarm | None, dict[str, TopicHealth])."""
    if is_typeddict(tp):
        return [tp]
    return [t for arg in get_args(tp) for t in _nested(arg)] if get_origin(tp) is not None or get_args(tp) else []


def test_every_typed_dict_has_its_model() -> None:
    assert "AlarmsMessage" in TYPED_DICTS and "Alarm" in TYPED_DICTS
    missing = [name for name in TYPED_DICTS if not isinstance(getattr(schemas, name, None), type)]
    assert not missing, f"core/messages.py declares shapes the API's contract has no model of: {missing}"


@pytest.mark.parametrize("name", sorted(TYPED_DICTS))
def test_a_builders_shape_names_its_models_fields(name: str) -> None:
    model = getattr(schemas, name)
    td = TYPED_DICTS[name]
    want = set(wire_fields(model))
    have = set(typed_fields(td))
    assert have == want, f"{name}: only in core/messages.py {sorted(have - want)}, only in the model {sorted(want - have)}"
    # a field the builder may leave out (NotRequired) must be one the model lets the JSON leave out
    optional = {k for k, required in typed_fields(td).items() if not required}
    assert not optional & {k for k, required in wire_fields(model).items() if required}


@pytest.mark.parametrize("name", sorted(TYPED_DICTS))
def test_a_nested_shape_is_the_models_nested_shape(name: str) -> None:
    """Alarm.shelf is an AlarmShelf on both sides, not some other shape with the same field names."""
    model = getattr(schemas, name)
    hints = get_type_hints(TYPED_DICTS[name])
    for field, info in model.model_fields.items():
        if (name, field) in OPAQUE:
            continue
        nested = _nested(hints[info.alias or field])
        models = [t.__name__ for t in _models(info.annotation)]
        assert sorted(t.__name__ for t in nested) == sorted(models), f"{name}.{field}"


def _models(tp: Any) -> list[type[BaseModel]]:
    if isinstance(tp, type) and issubclass(tp, BaseModel):
        return [tp]
    return [t for arg in get_args(tp) for t in _models(arg)]


def test_the_server_message_union_is_the_contracts() -> None:
    ours = {t.__name__ for t in get_args(messages.ServerMessage)}
    theirs = {t.__name__ for t in get_args(get_args(schemas.ServerMessage)[0])}
    assert ours == theirs


def test_the_comparison_sees_a_drift() -> None:
    """A TypedDict with a field renamed, or one left out, is told apart from its model."""

    class AlarmShelf(typing.TypedDict):
        id: str
        reason: str
        byOperator: str | None
        station: str | None
        at: float
        until: NotRequired[float]

    assert set(typed_fields(AlarmShelf)) != set(wire_fields(schemas.AlarmShelf))
    assert typed_fields(AlarmShelf)["until"] is False


# ---- rows, API models and the console's classes derived from one base (storage/models/) --------------------------
# shape: (its bases, the row, the row's own columns, the API model (None: the API shows another view of it), its own
# fields, the console's class (None: none kept as the row is))
SHAPES: dict[
    str, tuple[tuple[type[SQLModel], ...], type[SQLModel], set[str], type[BaseModel] | None, set[str], type[SQLModel] | None]
] = {
    "alarm": (
        (AlarmRaised, AlarmHandled),
        AlarmRecord,
        {"key", "normal_at", "console"},
        schemas.Alarm,
        {"state", "cause", "chattering", "shelf", "returned"},
        Alarm,
    ),
    "command": (
        (CommandIssued, CommandHandled),
        CommandRecord,
        {"command"},
        schemas.Command,
        {"status", "terminal", "violations", "transitions"},
        None,
    ),
    "transition": ((TransitionBase,), TransitionRecord, {"session_id"}, schemas.Transition, set(), None),
    "task": (
        (TaskPlanned, TaskProgress, TaskOwned),
        ComapTaskRecord,
        {"point", "last_synch"},
        schemas.Task,
        {"point", "synch"},
        None,
    ),
    "shelf": ((ShelfBase,), AlarmShelfRecord, set(), None, set(), Shelf),
    "silence": ((SilenceBase,), PlannedSilenceRecord, set(), None, set(), Silence),
}


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_a_shapes_row_api_model_and_class_derive_from_its_base(shape: str) -> None:
    bases, row, row_only, api, api_only, kept = SHAPES[shape]
    fields = {f for base in bases for f in base.model_fields}
    assert all(issubclass(row, base) for base in bases)
    assert set(row.model_fields) == fields | row_only
    assert {c.name for c in table(row).columns} == fields | row_only  # the table's columns, by the same names
    if api is not None:
        assert all(issubclass(api, base) for base in bases)
        assert set(wire_fields(api)) == {to_camel(f) for f in fields} | api_only  # camelCase on the API
    if kept is not None:
        assert all(issubclass(kept, base) for base in bases)
        assert set(kept.model_fields) == fields | row_only - {"console"}  # the row's own but its station's name


def test_a_kept_alarm_goes_to_its_row_and_back() -> None:
    a = Alarm(
        key="link-lost|p||",
        kind="link-lost",
        severity="alarm",
        provider_id="p",
        vehicle="Alpha",
        session_id=None,
        text="Alpha: link lost",
        since=1.0,
        cleared_at=None,
        acked_at=None,
        acked_by=None,
        normal_at=None,
    )
    row = a.row()
    assert set(row) == set(AlarmBase.model_fields)
    assert Alarm.model_validate({**row, "console": "station-a"}) == a  # a row read back carries its station too


# ---- the REST JSON of a derived model is the API's as released, byte for byte ---------------------------------------
# each sample in the order the API's JSON has it (the release's): a model derived from bases puts its fields in their
# order, which must be this one
TRANSITION: messages.Transition = {
    "seq": 1,
    "status": "ISSUED",
    "reason": "SUCCEEDED",
    "logMessage": "",
    "violation": None,
    "providerTime": 1.5,
    "receivedAt": 2.5,
}
SAMPLES: dict[str, Any] = {
    "Alarm": {
        "id": 3,
        "kind": "link-lost",
        "severity": "alarm",
        "providerId": "p",
        "vehicle": "Alpha",
        "sessionId": None,
        "text": "Alpha: link lost",
        "since": 1.0,
        "state": "active-unacknowledged",
        "clearedAt": None,
        "ackedAt": None,
        "ackedBy": None,
        "cause": "Link lost",
        "chattering": False,
        "shelf": {"id": "s", "reason": "known", "by": "alice", "station": "a", "at": 2.0, "until": 3.0},
        "returned": None,
    },
    "Transition": TRANSITION,
    "Command": {
        "sessionId": "s",
        "service": "GPSFix",
        "providerId": "p",
        "state": None,
        "operator": "alice",
        "createdAt": 1.0,
        "status": "ISSUED",
        "terminal": False,
        "unanswered": False,
        "cancelRequested": False,
        "canceledBy": None,
        "canceledOn": None,
        "canceledAt": None,
        "cancelCause": None,
        "closedUnheard": None,
        "closedAt": None,
        "ackedAt": 1.2,
        "cleanedUp": False,
        "console": "a",
        "violations": [],
        "transitions": [TRANSITION],
    },
    "Task": {
        "taskId": 7,
        "kind": "move",
        "vehicle": "p",
        "imcId": 30,
        "featureId": None,
        "sensor": None,
        "resolution": None,
        "deadline": None,
        "point": {"lat": 1.0, "lon": 2.0},
        "state": "ASSIGNED",
        "progress": 0,
        "quality": None,
        "synch": None,
        "operator": "alice",
        "station": "a",
        "createdAt": 1.0,
        "updatedAt": 1.0,
        "stateAt": 1.0,
    },
}


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_a_derived_models_rest_json_is_the_releases(name: str) -> None:
    """FastAPI answers a route through its response model (validated, then dumped in the model's field order): the
    model derived from bases must give the JSON, key for key in order, that the API gave before it derived."""
    sample = SAMPLES[name]
    assert set(sample) == set(get_type_hints(TYPED_DICTS[name]))  # the builder's shape
    model = getattr(schemas, name)
    assert model.model_validate(sample).model_dump_json(by_alias=True) == dumps(sample)


@pytest.mark.parametrize("name", ["Alarm", "Task", "Transition"])
def test_the_websocket_sends_them_in_the_same_order(name: str) -> None:
    assert list(SAMPLES[name]) == list(get_type_hints(TYPED_DICTS[name]))
