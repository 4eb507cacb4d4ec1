"""The operator's words (`core/words.py`): every state the console shows has them, and the alarms say them."""

from __future__ import annotations

import csv
import importlib
import io
import pkgutil
from typing import get_args

import pytest
from cyclonedds.idl import IdlEnum

import UMAA.Common.MaritimeEnumeration as maritime
import UMAA_6_0.Common.MaritimeEnumeration as maritime_6_0

from sem_console.api.routes.history import commands_csv
from sem_console.api.schemas import AlarmKind, AlarmState
from sem_console.console.alarms import RETURNS, SEVERITY, overdue_text
from sem_console.core.words import WORDS, inline, word
from sem_console.schema_export import schemas
from sem_console.umaa.flow import Updated


def _umaa_enums() -> list[type[IdlEnum]]:
    """Every enumeration of UMAA::Common::MaritimeEnumeration the console's generated types hold, of either UMAA
    version (6.0's in a module `<name>Module`)."""
    found = []
    for package in (maritime, maritime_6_0):
        for m in pkgutil.iter_modules(package.__path__):
            name = m.name.removesuffix("Module")
            enum = getattr(
                importlib.import_module(f"{package.__name__}.{m.name}"),
                name.removesuffix("Enum") + "EnumType" if m.name.endswith("EnumModule") else m.name,
            )
            assert issubclass(enum, IdlEnum)
            found.append(enum)
    return found


def _literals(name: str) -> set[str]:
    """The literals of enumeration `name` in either UMAA version."""
    return {m.name for e in _umaa_enums() if e.__name__ == name for m in e}


@pytest.mark.parametrize("enum", _umaa_enums(), ids=lambda e: f"{e.__module__.split('.')[0]}.{e.__name__}")
def test_every_umaa_literal_has_words(enum: type[IdlEnum]) -> None:
    table = WORDS.get(enum.__name__)
    assert table is not None, f"core/words.py has no table {enum.__name__}"
    missing = [m.name for m in enum if not table.get(m.name, "").strip()]
    assert not missing, f"core/words.py has no words for {enum.__name__} {missing}"
    beyond = {m.name for m in Updated} if enum.__name__ == "CommandStatusReasonEnumType" else set()  # the model's own
    assert set(table) <= _literals(enum.__name__) | beyond, f"{enum.__name__}: words for literals UMAA does not have"


def test_every_alarm_kind_has_words_and_a_severity() -> None:
    kinds = set(get_args(AlarmKind))
    assert kinds == set(WORDS["alarmKind"]), "an alarm kind without words (or words for no kind) in core/words.py"
    assert kinds == set(SEVERITY), "an alarm kind without a severity in console/alarms.py"
    assert all(w.strip() for w in WORDS["alarmKind"].values())
    assert set(get_args(AlarmState)) == set(WORDS["alarmState"]), "an alarm state without words in core/words.py"
    assert set(SEVERITY.values()) == set(WORDS["alarmSeverity"]), "an alarm severity without words in core/words.py"


# Every enumeration the console publishes (its REST and WebSocket schemas), by schema and property: the words table that
# names its literals wherever the console shows them ...
SAID_BY = {
    ("Alarm", "kind"): "alarmKind",
    ("Alarm", "severity"): "alarmSeverity",
    ("Alarm", "state"): "alarmState",
    ("ProviderSummary", "link"): "link",
    ("ProviderDetail", "link"): "link",
    ("VehicleBrief", "link"): "link",
    ("FeatureProperties", "coverage"): "coverage",
    ("Task", "state"): "taskState",
    ("Task", "kind"): "taskKind",
    ("Task", "sensor"): "sensor",
    ("MoveTaskRequest", "sensor"): "sensor",
    ("SurveyTaskRequest", "sensor"): "sensor",
    ("Command", "cancelCause"): "cancelCause",
}
# ... or none, for one that is no state the console names: what a request asks (an action, a command's target state
# "INS OFF", as its button says it), a name (a service, a topic, a gateway, a capability), or a state said by a
# control or a phrase of its own (recording, replay, audit, diagnostics)
NO_STATE = {
    ("AuditEntry", "outcome"),
    ("Capability", "kind"),
    ("Command", "closedUnheard"),
    ("Command", "service"),
    ("Command", "state"),
    ("GatewayState", "name"),
    ("InertialSensorRequest", "state"),
    ("LinkConfig", "policy"),
    ("PeerFinding", "kind"),
    ("ProviderMessage", "event"),
    ("RecordingFile", "state"),
    ("RecordingRequest", "action"),
    ("RecordingStatus", "state"),
    ("ReplayStatus", "state"),
    ("ReportMessage", "topic"),
    ("SynchRequest", "action"),
    ("Task", "synch"),
    ("ProviderSummary", "umaaVersion"),
    ("ProviderDetail", "umaaVersion"),
    ("VehicleBrief", "umaaVersion"),
}


def _published_enums() -> dict[tuple[str, str | None], list[str]]:
    """Every enumeration of the published schemas: (schema, property) for a property's, (name, None) for a named one."""
    docs = schemas()
    defs = {**docs["openapi.json"]["components"]["schemas"], **docs["ws-schema.json"]["$defs"]}
    found: dict[tuple[str, str | None], list[str]] = {}
    for name, d in defs.items():
        if "enum" in d:
            found[(name, None)] = d["enum"]
        for prop, p in d.get("properties", {}).items():
            for alt in [p, p.get("items", {}), *p.get("anyOf", [])]:
                if "enum" in alt:
                    found[(name, prop)] = alt["enum"]
    return found


def test_every_published_literal_the_console_names_has_words() -> None:
    enums = _published_enums()
    undecided = sorted(f"{n}.{p}" for n, p in enums if p is not None and (n, p) not in SAID_BY | dict.fromkeys(NO_STATE))
    assert not undecided, f"published enumerations with no words table named for them in test_words.py: {undecided}"
    for (name, prop), literals in enums.items():
        table = WORDS.get(name) if prop is None else WORDS.get(SAID_BY.get((name, prop), ""))
        if prop is not None and (name, prop) in NO_STATE:
            continue
        assert table is not None, f"core/words.py has no table for {name}"
        missing = [lit for lit in literals if not table.get(lit, "").strip()]
        assert not missing, f"core/words.py has no words for {name}{'.' + prop if prop else ''} {missing}"


def test_every_watch_state_has_words() -> None:
    """Alarm management on a watch: an alarm's marks (shelved, chattering), each way a shelf ends that brings its alarm
    back (`Alarm.returned`), and a vehicle lost in its planned silence."""
    assert set(RETURNS) == set(WORDS["alarmReturned"]), "a shelf ending that brings an alarm back, without words"
    assert set(WORDS["alarmMark"]) == {"shelved", "chattering"}
    said = [*WORDS["alarmReturned"].values(), *WORDS["alarmMark"].values(), WORDS["link"].get("planned", "")]
    assert all(w.strip() for w in said), "a watch state without words in core/words.py"


def test_the_silence_overdue_sentence_is_the_words_tables(monkeypatch: pytest.MonkeyPatch) -> None:
    """The overdue alarm's sentence is written in core/words.py, not in console/alarms.py: a change of the table's words
    changes what the alarm says."""
    t = 1_800_000_000.0  # 2027-01-15 08:00 UTC
    assert overdue_text(t + 20 * 60, 30, t) == "not heard by 08:20 UTC, the end of its planned silence (30 s grace)"
    assert overdue_text(t + 86_400, 2.5, t) == "not heard by 2027-01-16 08:00 UTC, the end of its planned silence (2.5 s grace)"
    monkeypatch.setitem(WORDS["alarmText"], "silence-overdue", "Still silent at {until} ({grace} s grace)")
    assert overdue_text(t + 20 * 60, 30, t) == "still silent at 08:20 UTC (30 s grace)"


def test_words_inside_a_phrase() -> None:
    assert inline("Operational") == "operational"
    assert inline("GPS 3D") == "GPS 3D"
    assert inline("INS failed") == "INS failed"
    assert word("InertialSensorStateEnumType", "SOMETHING_NEWER") == "SOMETHING_NEWER"


def test_the_commands_export_says_each_transition_in_the_operators_words() -> None:
    command = {
        "sessionId": "s1",
        "service": "InertialSensor",
        "providerId": "p1",
        "state": "OFF",
        "operator": "alice",
        "console": "watch",
        "createdAt": 1.0,
        "ackedAt": 1.1,
        "status": "FAILED",
        "terminal": True,
        "unanswered": False,
        "cancelRequested": False,
        "canceledBy": None,
        "canceledOn": None,
        "canceledAt": None,
        "cancelCause": None,
        "closedUnheard": None,
        "closedAt": None,
        "cleanedUp": True,
        "transitions": [
            {
                "seq": 0,
                "status": "ISSUED",
                "reason": "SUCCEEDED",
                "logMessage": "",
                "violation": None,
                "providerTime": 1.2,
                "receivedAt": 1.2,
            },
            {
                "seq": 1,
                "status": "FAILED",
                "reason": "RESOURCE_FAILED",
                "logMessage": "",
                "violation": None,
                "providerTime": 1.3,
                "receivedAt": 1.3,
            },
        ],
    }
    reader = csv.DictReader(io.StringIO(commands_csv([command])))
    assert reader.fieldnames is not None
    names = list(reader.fieldnames)  # each literal with its words beside it
    assert names[names.index("status") + 1] == "status_words" and names[names.index("reason") + 1] == "reason_words"
    rows = list(reader)
    assert [(r["status"], r["status_words"], r["reason"], r["reason_words"]) for r in rows] == [
        ("ISSUED", "Received", "SUCCEEDED", "Succeeded"),
        ("FAILED", "Failed", "RESOURCE_FAILED", "The equipment failed"),
    ]
