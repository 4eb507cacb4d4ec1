"""The console's alarms, after ISA-18.2, derived from its own state: never from what a browser saw.

Inputs: the providers (link, latest INS status and fixValid), this console's commands (statuses,
transitions, unanswered) and the recorder's error. Outputs: the active set (every alarm not back
to normal), kept in the console's database (`Database`, table `alarms`) so a restart keeps it.

Two kinds of alarm (see `api.schemas.Alarm`):
- condition alarms are active while their condition holds: link-lost, ins-failure, fix-lost,
  no-fix-after-command, command-unanswered. Cleared but not acknowledged they stay in the set
  (cleared-unacknowledged); acknowledged and cleared, they return to normal and leave it.
- event alarms (command-failed, command-interrupted, flow-violation, executed-late, recording-failed)
  record something that happened and cannot "clear" by itself: the order was not carried out, the
  vehicle ran a command late. They are shown active-unacknowledged until the operator acknowledges
  them, which returns them to normal (an event never shows as "cleared": that would read as "solved").

One alarm per key (kind, vehicle, command) while it is not back to normal. An event is raised once:
the events already in the history loaded at start (`baseline`) were raised by an earlier run, or
predate alarms, and are not raised again.

The operator's own supersession (a command FAILED/INTERRUPTED because this console sent a newer
command of the same service to the same vehicle; sem-sim logs "superseded by command <id>") is
information, not an alarm. An INTERRUPTED that nothing of ours explains (another operator's command)
is command-interrupted.

Managing them on a watch (after ISA-18.2; docs/console.md#alarms):
- shelving: an operator takes an alarm out of view for a bounded time, with a reason (`Shelf`, kept in the database and
  shared by every station by the alarm's key). It comes back when the time ends, when unshelved, or at once when it gets
  worse (`worse_than`): a new alarm of its vehicle (the console, for the console's own) at least as severe as it was.
- planned silence: an operator declares a vehicle out of comms until a time (`Silence`); its link loss raises no alarm
  until then and `silence_grace` seconds after. Still lost then, that is a silence-overdue alarm (instead of link-lost)
  until it is heard again.
- chattering: an alarm activated again `chatter[0]` times within `chatter[1]` seconds (it cleared and came back) is
  marked `chattering` (the dashboard stops sounding it again) until acknowledged.
- a relay gone silent (console/hops.py): one relay-silent alarm, "relay ship-1 silent: 12 vehicles", of the console
  (no vehicle), while no data comes over its link for the comms-lost timeout, unless every vehicle it carries is in a
  planned silence; a vehicle lost with its relay (no data came over the relay's link since the vehicle went silent)
  raises no link-lost of its own. A vehicle lost while its relay still carries the others' data is link-lost, as any.
- the console behind (console/load.py): one console-overloaded alarm, of the console, while it is behind and that
  withheld the check of a vehicle's silence (such a vehicle is `unchecked`, not lost: no link-lost of its own); it
  clears when the console keeps up again, and a vehicle still silent then is lost as any.
- floods: every alarm carries its `cause` (its kind in words), by which the dashboard groups many at once.

Cost: `report_changed` is on the report path (thousands of samples a second): one dict lookup and
a comparison. `update` runs on the console's tick (5 Hz) and after the events that change a
condition; it looks at a command only when that command changed (`changed`).
"""

from __future__ import annotations

import time
import uuid
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as Reason

from sem_console.console.commands import Command
from sem_console.console.hops import RELAY_GRACE, Hop, silent_relays
from sem_console.console.providers import Provider
from sem_console.core import messages
from sem_console.core.words import WORDS, inline, word
from sem_console.dds.topics import Service
from sem_console.storage.database import Database
from sem_console.storage.models import AlarmBase, AlarmShelfRecord, PlannedSilenceRecord, ShelfBase, SilenceBase

NO_FIX_GRACE = 5.0  # seconds after a COMPLETED GPS fix command before a still invalid fix is an alarm
CONDITIONS = frozenset(
    {
        "link-lost",
        "ins-failure",
        "fix-lost",
        "no-fix-after-command",
        "command-unanswered",
        "silence-overdue",
        "relay-silent",
        "console-overloaded",
    }
)
EVENTS = frozenset({"command-failed", "command-interrupted", "flow-violation", "executed-late", "recording-failed"})
SEVERITY = {
    "link-lost": "alarm",
    "ins-failure": "alarm",
    "fix-lost": "warning",
    "no-fix-after-command": "warning",
    "command-unanswered": "warning",
    "command-failed": "alarm",
    "command-interrupted": "alarm",
    "flow-violation": "alarm",
    "executed-late": "alarm",
    "recording-failed": "warning",
    "silence-overdue": "alarm",
    "relay-silent": "alarm",
    "console-overloaded": "alarm",
}
RANK = {"warning": 1, "alarm": 2}
# how a shelf ends that brings its alarm back in view, each with its words (`alarmReturned` of core/words.py); a shelf
# ended by a new alarm keeps it in its end_reason: "worse: <that alarm's text>"
WORSE = "worse"
RETURNS = ("expired", "unshelved", WORSE)
# the ending of the INS statuses that say it or its alignment failed: INERTIAL_SENSOR_FAILURE, GPS_ALIGNMENT_FAILURE...
INS_FAILURE = "_FAILURE"
INS_STATUS = "InertialSensorOpStatusEnumType"
WATCHED = {"InertialSensorReport": "status", "GPSFixStatusReport": "fixValid"}  # the report fields alarms depend on
TOOK_UP = frozenset({Status.ISSUED, Status.COMMANDED, Status.EXECUTING, Status.COMPLETED})
_MISSING = object()


def short_id(provider_id: uuid.UUID | str) -> str:
    return str(provider_id).replace("-", "")[:8]


def vehicle_label(provider_id: uuid.UUID | str, name: str | None) -> str:
    """The vehicle as the operator knows it: its configured name, else the first 8 hex digits of its GUID."""
    return name or short_id(provider_id)


def command_words(cmd: Command) -> str:
    """'GPS fix command', 'INS OFF', 'INS ON', 'INS RESTART'; a UMAA 6.0 alignment in its words, 'INS GPS-aided
    alignment'."""
    if cmd.service is Service.GPS_FIX:
        return "GPS fix command"
    state = cmd.state or "?"
    if state in WORDS["InertialSensorCmdEnumType"]:
        return f"INS {inline(word('InertialSensorCmdEnumType', state))}"
    return f"INS {'RESTART' if state == 'RESTARTING' else state}"


class Alarm(AlarmBase):
    """An alarm of the active set, as kept (AlarmBase: `vehicle` and `text` as raised; sent as named now, `to_json`)."""

    id: int = 0

    @property
    def state(self) -> str:
        if self.cleared_at is not None:
            return "cleared-unacknowledged"
        return "active-acknowledged" if self.acked_at is not None else "active-unacknowledged"

    def text_naming(self, vehicle: str | None) -> str:
        """The text with the vehicle as it is named now (`vehicle`): raised, it named the vehicle as `self.vehicle`,
        which the row keeps, as what was said then; a rename since must not leave "Alpha: link lost" beside Bravo."""
        said = f"{self.vehicle}: "
        if vehicle is None or self.vehicle is None or not self.text.startswith(said):
            return self.text
        return f"{vehicle}: {self.text.removeprefix(said)}"

    def to_json(
        self, vehicle: str | None, chattering: bool, shelf: messages.AlarmShelf | None, returned: str | None
    ) -> messages.Alarm:
        """What clients are sent; `vehicle`: the vehicle's name now (None: as raised)."""
        return {
            "id": self.id,
            "kind": self.kind,
            "severity": self.severity,
            "providerId": self.provider_id,
            "vehicle": vehicle or self.vehicle,
            "sessionId": self.session_id,
            "text": self.text_naming(vehicle),
            "since": self.since,
            "state": self.state,
            "clearedAt": self.cleared_at,
            "ackedAt": self.acked_at,
            "ackedBy": self.acked_by,
            "cause": word("alarmKind", self.kind),
            "chattering": chattering,
            "shelf": shelf,
            "returned": returned,
        }

    def row(self) -> dict[str, Any]:
        return self.model_dump()


@dataclass(frozen=True)
class Found:
    """A condition that holds or an event that happened, before it is an alarm."""

    kind: str
    provider_id: str | None
    session_id: str | None
    what: str  # the text without the vehicle, named when raised (`Alarms._raise`) and as it is named now when sent
    detail: str = ""  # part of the key only (recording-failed: which failure)

    @property
    def key(self) -> str:
        return "|".join((self.kind, self.provider_id or "", self.session_id or "", self.detail))


def returned_words(why: str, by: str | None = None, what: str = "") -> str:
    """Why a shelved alarm is back in view, by how its shelf ended (`RETURNS`): "back from shelving: its time ended",
    "... unshelved by alice", "... worse: Alpha: INS failed"."""
    said = inline(word("alarmReturned", why))
    if why == "unshelved":
        return f"{said} by {by or 'an operator'}"
    return f"{said}: {what}" if why == WORSE else said


def clock_time(t: float, now: float | None = None) -> str:
    """ "14:20 UTC" of UTC seconds `t`, with its date when that is not the day of `now` (default: the time now): the
    house style of a time the operator reads, as the dashboard's `clockTime`."""
    day = time.strftime("%Y-%m-%d", time.gmtime(t))
    hhmm = time.strftime("%H:%M", time.gmtime(t))
    same = day == time.strftime("%Y-%m-%d", time.gmtime(time.time() if now is None else now))
    return f"{hhmm} UTC" if same else f"{day} {hhmm} UTC"


def overdue_text(until: float, grace: float, now: float | None = None) -> str:
    """The silence-overdue alarm's sentence, in the words table's words: "not heard by 14:20 UTC, the end of its
    planned silence (30 s grace)"."""
    return inline(word("alarmText", "silence-overdue")).format(until=clock_time(until, now), grace=f"{grace:g}")


class Shelf(ShelfBase):
    """An alarm shelved by an operator (ShelfBase): every station's alarm of `key` is out of view."""

    def to_json(self) -> messages.AlarmShelf:
        return {
            "id": self.id,
            "reason": self.reason,
            "by": self.shelved_by,
            "station": self.station,
            "at": self.shelved_at,
            "until": self.until,
        }


class Silence(SilenceBase):
    """A vehicle's planned link gap, "out of comms until" (SilenceBase)."""

    def to_json(self, vehicle: str) -> messages.PlannedSilence:
        return {
            "id": self.id,
            "providerId": self.provider_id,
            "vehicle": vehicle,
            "reason": self.reason,
            "by": self.set_by,
            "station": self.station,
            "at": self.set_at,
            "until": self.until,
        }


class Alarms:
    def __init__(
        self,
        store: Database,
        names: Mapping[str, str] | None = None,
        on_ack: Callable[[Alarm, str | None], None] | None = None,
        silence_grace: float = 120.0,
        chatter: tuple[int, float] = (3, 600.0),
        relay_silent_after: float = 10.0,
        station: str = "",
    ) -> None:
        self.store = store
        # this console's station: its console-overloaded alarm's key names it, so that another station's
        # acknowledgement or shelf of its own overload (shared by key) is not one of this console's
        self.station = station
        self.names = dict(names or {})  # provider GUID string -> configured name (--vehicle-names)
        self.on_ack = on_ack  # an alarm just acknowledged, with the station it was acknowledged on (the recording)
        self.silence_grace = silence_grace
        self.chatter = chatter  # (returns, seconds): an alarm back this often is chattering
        self.relay_silent_after = relay_silent_after  # seconds without data over a relay's link: silent (the console's)
        self._load()

    def _load(self) -> None:
        self.open: dict[str, Alarm] = {}
        for r in self.store.open_alarms():
            a = Alarm.model_validate(r.model_dump())
            self.open[a.key] = a
        self._raised: set[str] = {k for k, a in self.open.items() if a.kind in EVENTS}  # events never raised twice
        # a vehicle with an open fix-lost alarm had a valid fix (kept across a restart)
        self._had_fix: set[str] = {a.provider_id for a in self.open.values() if a.kind == "fix-lost" and a.provider_id}
        self._watched: dict[tuple[uuid.UUID, str], Any] = {}
        # what the alarms need of the commands, kept up to date command by command (`_track`)
        self._unanswered: dict[str, Found] = {}
        self._latest_fix: dict[str, Command] = {}  # provider -> this console's newest GPS fix command to it
        # GPS fix commands that brought a valid fix after they completed: a later loss (the vehicle dives
        # again) is fix-lost, not "no fix after the command"
        self._fix_followed: set[str] = set()
        self._newest: dict[tuple[str, Service], float] = {}  # (provider, service) -> its newest command's creation
        self._sessions: set[str] = set()
        self._load_watch()
        # a vehicle not heard by the end of its planned silence -> the overdue alarm's words (kept across a restart)
        self._overdue: dict[str, str] = {
            a.provider_id: "" for a in self.open.values() if a.kind == "silence-overdue" and a.provider_id
        }
        self._activations: dict[str, deque[float]] = {}  # key -> when it became active, within the chatter window
        self._chattering: set[str] = set()
        self._returned: dict[str, str] = {}  # key -> why a shelved alarm is back in view, until acknowledged
        self.silences_changed = False  # a planned silence began or ended (the console sends them again)

    def _load_watch(
        self, shelves: list[AlarmShelfRecord] | None = None, silences: list[PlannedSilenceRecord] | None = None
    ) -> None:
        """The shelves and planned silences not ended, as read from the database (at start: read here; after a
        resync: read in a worker thread)."""
        self.shelves: dict[str, Shelf] = {}
        for r in self.store.shelves() if shelves is None else shelves:
            shelf = Shelf.model_validate(r.model_dump())
            self.shelves[shelf.key] = shelf
        self.silences: dict[str, Silence] = {}
        for s in self.store.silences() if silences is None else silences:
            silence = Silence.model_validate(s.model_dump())
            self.silences[silence.provider_id] = silence

    def reset(self) -> None:
        """A replay seeking backwards: forget every alarm (its state is rebuilt from the start)."""
        self.store.clear_alarms()
        self._load()

    def baseline(self, commands: Iterable[Command]) -> None:
        """At start, with the command history loaded: what it already holds of events is not raised again."""
        commands = list(commands)
        for c in commands:
            self._track(c)
        self._raised |= {f.key for c in commands for f in self._events(c)}
        # a fix command completed before the start: whether a fix followed it is not known, so it raises
        # nothing now (one already raised is in the database and clears as usual)
        raised_no_fix = {a.session_id for a in self.open.values() if a.kind == "no-fix-after-command"}
        self._fix_followed |= {
            str(c.session_id)
            for c in commands
            if c.service is Service.GPS_FIX and c.flow.status is Status.COMPLETED and str(c.session_id) not in raised_no_fix
        }

    # ---- inputs -------------------------------------------------------------------------
    def report_changed(self, source: uuid.UUID, topic: str, report: Mapping[str, Any]) -> bool:
        """A report arrived: True when a field an alarm depends on changed (then call `update`)."""
        field = WATCHED.get(topic)
        if field is None:
            return False
        value = report.get(field)
        key = (source, topic)
        if self._watched.get(key, _MISSING) == value:
            return False
        self._watched[key] = value
        return True

    def update(
        self,
        now: float,
        providers: Mapping[uuid.UUID, Provider],
        commands: Iterable[Command] = (),
        recording_error: str | None = None,
        relays: Mapping[str, Hop] | None = None,
        overloaded: str | None = None,
    ) -> bool:
        """Re-derive the active set at `now` (UTC seconds), looking again at `commands` (the ones that changed;
        new ones first), with the relays the vehicles come through (console/hops.py); `overloaded`: the words of the
        console's own overload while it holds (`overloaded_text`). Returns whether the active set changed."""
        relays = relays or {}
        commands = list(commands)
        for c in commands:
            self._track(c)
        events = [f for c in commands for f in self._events(c)]
        if recording_error:
            events.append(
                Found("recording-failed", None, None, f"Recording failed: {_recording_reason(recording_error)}", recording_error)
            )
        changed = self._end_in_time(now, providers)
        for f in events:
            if f.key not in self._raised:
                self._raised.add(f.key)
                self._raise(f, now)
                changed = True
        holding = self._conditions(now, providers, relays)
        if overloaded is not None:
            f = Found("console-overloaded", None, None, overloaded, self.station)
            holding[f.key] = f
        for key, a in list(self.open.items()):
            if a.kind not in CONDITIONS:
                continue
            if key in holding:
                said = f"{a.vehicle}: {holding[key].what}" if a.vehicle else holding[key].what
                if a.text != said:  # its words changed while it holds (how many vehicles, how far behind): true now
                    a.text = said
                    self._save(a)
                    changed = True
                if a.cleared_at is not None:  # back again before it was acknowledged: active once more
                    a.cleared_at, a.since = None, now
                    self._activated(key, now)
                    self._save(a)
                    changed = True
            elif self._can_judge(a, providers, relays):
                if a.acked_at is not None:
                    a.cleared_at = a.normal_at = now
                    del self.open[key]
                    self._save(a)
                    changed = True
                elif a.cleared_at is None:
                    a.cleared_at = now
                    self._save(a)
                    changed = True
        for key, f in holding.items():
            if key not in self.open:
                self._raise(f, now)
                changed = True
        return changed

    def acknowledge(self, alarm_id: int, operator: str | None, now: float, station: str | None = None) -> Alarm | None:
        """The operator has seen it (on `station`). None: no such alarm in the active set. An acknowledged event, or a
        condition that has cleared, returns to normal; acknowledging again changes nothing."""
        a = next((x for x in self.open.values() if x.id == alarm_id), None)
        if a is None or a.acked_at is not None:
            return a
        a.acked_at, a.acked_by = now, operator
        self._activations.pop(a.key, None)  # seen: a chattering alarm sounds again when it next returns
        self._chattering.discard(a.key)
        self._returned.pop(a.key, None)
        if a.kind in EVENTS or a.cleared_at is not None:
            a.cleared_at = a.cleared_at or now
            a.normal_at = now
            del self.open[a.key]
        self._save(a)
        if self.on_ack is not None:
            self.on_ack(a, station)
        return a

    def acknowledged_elsewhere(self, key: str, operator: str | None, at: float, station: str | None = None) -> bool:
        """Another console station (`station`, if known) acknowledged its alarm of this key, or a replay's recording
        says it was acknowledged: so is this one's (whether it changed)."""
        a = self.open.get(key)
        if a is None or a.acked_at is not None:
            return False
        self.acknowledge(a.id, operator, at, station)
        return True

    def active(self) -> list[messages.Alarm]:
        """The active set, newest first, each naming its vehicle as it is named now, with its cause, whether it is
        chattering, its shelf (null: in view) and why it is back in view after a shelf."""
        # of one instant, the last raised first (`open` keeps the order they were raised in; a sort keeps ties' order)
        newest_first = sorted(reversed(self.open.values()), key=lambda a: a.since, reverse=True)
        out = []
        for a in newest_first:
            shelf = self.shelves.get(a.key)
            out.append(
                a.to_json(
                    self._vehicle(a.provider_id) if a.provider_id else None,
                    a.key in self._chattering,
                    shelf.to_json() if shelf else None,
                    None if shelf else self._returned.get(a.key),
                )
            )
        return out

    def planned_silences(self) -> list[messages.PlannedSilence]:
        """The planned silences in force, the soonest to end first."""
        return [s.to_json(self._vehicle(s.provider_id)) for s in sorted(self.silences.values(), key=lambda s: s.until)]

    # ---- shelving and planned silence ---------------------------------------------------------
    def _find(self, alarm_id: int) -> Alarm | None:
        return next((x for x in self.open.values() if x.id == alarm_id), None)

    def shelve(
        self, alarm_id: int, reason: str, seconds: float, operator: str | None, now: float, station: str | None = None
    ) -> Alarm | None:
        """Take the alarm out of view for `seconds` (None: no such alarm in the active set); a shelved one is shelved
        again from now (its old shelf ended)."""
        a = self._find(alarm_id)
        if a is None:
            return None
        if a.key in self.shelves:
            self._end_shelf(a.key, now, operator, "reshelved", None)
        vehicle = self._vehicle(a.provider_id) if a.provider_id else None
        shelf = Shelf(
            id=str(uuid.uuid4()),
            key=a.key,
            kind=a.kind,
            provider_id=a.provider_id,
            session_id=a.session_id,
            severity=a.severity,
            text=a.text_naming(vehicle),
            reason=reason,
            shelved_by=operator,
            station=station,
            shelved_at=now,
            until=now + seconds,
        )
        self.store.add_shelf(shelf.model_dump())
        self.shelves[a.key] = shelf
        self._returned.pop(a.key, None)
        return a

    def unshelve(self, alarm_id: int, operator: str | None, now: float) -> Alarm | None:
        """Back in view at once (None: no such alarm; whether it was shelved: `shelves` before)."""
        a = self._find(alarm_id)
        if a is not None and a.key in self.shelves:
            self._end_shelf(a.key, now, operator, "unshelved", returned_words("unshelved", by=operator))
        return a

    def _end_shelf(self, key: str, now: float, by: str | None, why: str, back: str | None) -> None:
        shelf = self.shelves.pop(key)
        self.store.end_shelf(shelf.id, now, by, why)
        if back is not None:
            self._returned[key] = back

    def silence(
        self, provider_id: str, until: float, reason: str, operator: str | None, now: float, station: str | None = None
    ) -> Silence:
        """Declare the vehicle out of comms until `until` (one at a time: a new one replaces the one in force)."""
        if provider_id in self.silences:
            self._end_silence(provider_id, now, operator, "replaced")
        silence = Silence(
            id=str(uuid.uuid4()),
            provider_id=provider_id,
            reason=reason,
            set_by=operator,
            station=station,
            set_at=now,
            until=until,
        )
        self.store.add_silence(silence.model_dump())
        self.silences[provider_id] = silence
        self.silences_changed = True
        return silence

    def cancel_silence(self, provider_id: str, operator: str | None, now: float) -> Silence | None:
        """End the vehicle's planned silence now (None: it has none): its loss is an alarm again."""
        silence = self.silences.get(provider_id)
        if silence is not None:
            self._end_silence(provider_id, now, operator, "cancelled")
        return silence

    def _end_silence(self, provider_id: str, now: float, by: str | None, why: str) -> None:
        silence = self.silences.pop(provider_id)
        self.store.end_silence(silence.id, now, by, why)
        self.silences_changed = True

    def _end_in_time(self, now: float, providers: Mapping[uuid.UUID, Provider]) -> bool:
        """End the shelves whose time is up and the silences past their grace: a vehicle still lost (or not heard
        since a restart) is then overdue."""
        changed = False
        for key, shelf in list(self.shelves.items()):
            if now >= shelf.until:
                self._end_shelf(key, now, None, "expired", returned_words("expired"))
                changed = changed or key in self.open
        for pid, silence in list(self.silences.items()):
            if now >= silence.until + self.silence_grace:
                p = providers.get(uuid.UUID(pid))
                heard = p is not None and p.link in ("live", "regained")
                if not heard:
                    self._overdue[pid] = overdue_text(silence.until, self.silence_grace, now)
                self._end_silence(pid, now, None, "heard" if heard else "overdue")
        return changed

    def shared_shelf(self, row: Mapping[str, Any]) -> bool:
        """Another station shelved an alarm or ended a shelf (the notification's row): whether this one's set shows it."""
        if "key" in row:
            shelf = Shelf.model_validate(row)
            self.shelves[shelf.key] = shelf
            self._returned.pop(shelf.key, None)
            return shelf.key in self.open
        key = next((k for k, s in self.shelves.items() if s.id == row.get("id")), None)
        if key is None:
            return False
        del self.shelves[key]
        why = row.get("end_reason")
        if why == "unshelved":
            self._returned[key] = returned_words("unshelved", by=row.get("ended_by"))
        elif why == "expired":
            self._returned[key] = returned_words("expired")
        elif isinstance(why, str) and why.startswith(f"{WORSE}: "):
            self._returned[key] = returned_words(WORSE, what=why.removeprefix(f"{WORSE}: "))
        return key in self.open

    def shared_silence(self, row: Mapping[str, Any]) -> None:
        """Another station declared or ended a planned silence."""
        if "provider_id" in row:
            silence = Silence.model_validate(row)
            self.silences[silence.provider_id] = silence
        else:
            pid = next((p for p, s in self.silences.items() if s.id == row.get("id")), None)
            if pid is not None:
                del self.silences[pid]
        self.silences_changed = True

    def reload_shared(self, shelves: list[AlarmShelfRecord], silences: list[PlannedSilenceRecord]) -> None:
        """A resync: the shelves and silences as the database has them (what the other stations did meanwhile)."""
        before = set(self.shelves)
        self._load_watch(shelves, silences)
        for key in before - set(self.shelves):
            self._returned.setdefault(key, returned_words("expired"))
        self.silences_changed = True

    def _activated(self, key: str, now: float) -> None:
        """An alarm became active (raised, or back after it cleared): chattering when that is the chatter count's
        return within the window."""
        returns, window = self.chatter
        times = self._activations.setdefault(key, deque())
        times.append(now)
        while times and times[0] < now - window:
            times.popleft()
        if len(times) - 1 >= returns:
            self._chattering.add(key)

    def _worse(self, f: Found, now: float) -> None:
        """A new alarm of a vehicle (the console, for its own) ends the shelves of its other alarms that were no more
        severe: they come back at once."""
        rank = RANK[SEVERITY[f.kind]]
        for key, shelf in list(self.shelves.items()):
            if key != f.key and shelf.provider_id == f.provider_id and RANK[shelf.severity] <= rank:
                who = self._vehicle(f.provider_id) if f.provider_id else None
                what = f"{who}: {f.what}" if who else f.what
                self._end_shelf(key, now, None, f"{WORSE}: {what}", returned_words(WORSE, what=what))

    # ---- derivation ---------------------------------------------------------------------
    def _vehicle(self, provider_id: str) -> str:
        return vehicle_label(provider_id, self.names.get(provider_id))

    def _track(self, c: Command) -> None:
        """What the alarms need of a command: whether it is unanswered, the newest commands per vehicle."""
        pid, sid = str(c.provider_id), str(c.session_id)
        self._sessions.add(sid)
        key = (pid, c.service)
        self._newest[key] = max(self._newest.get(key, c.created_at), c.created_at)
        f = Found("command-unanswered", pid, sid, f"{command_words(c)}: {inline(word('command', 'unanswered'))}")
        if c.unanswered and not c.cancel_requested and not c.flow.terminal and not c.cleaned_up:
            self._unanswered[f.key] = f
        else:
            self._unanswered.pop(f.key, None)
        if c.service is Service.GPS_FIX:
            newest = self._latest_fix.get(pid)
            if newest is None or c.created_at >= newest.created_at:
                self._latest_fix[pid] = c

    def _events(self, c: Command) -> list[Found]:
        """What has happened to the command that is an alarm (raised once each: see `_raised`)."""
        pid, sid = str(c.provider_id), str(c.session_id)
        what = command_words(c)
        out: list[Found] = []
        if c.flow.violations:
            out.append(Found("flow-violation", pid, sid, f"{what}: the vehicle reported an invalid status sequence"))
        if c.flow.status is Status.FAILED:
            reason = next((t.reason for t in reversed(c.flow.transitions) if t.status is Status.FAILED), None)
            if reason is not Reason.INTERRUPTED:
                out.append(Found("command-failed", pid, sid, f"{what} {_status_words(Status.FAILED, reason)}"))
            elif not self._superseded(c):
                out.append(Found("command-interrupted", pid, sid, f"{what} interrupted by a command not from this console"))
        late = c.answered_late_after
        if late is not None and c.flow.transitions and c.flow.transitions[0].status in TOOK_UP:
            unanswered = inline(word("command", "unanswered"))
            out.append(Found("executed-late", pid, sid, f"{what} executed late ({unanswered} for {late:.0f} s)"))
        return out

    def _superseded(self, c: Command) -> bool:
        """FAILED/INTERRUPTED by this console's own newer command of the service to the vehicle (which sem-sim's
        log message names: "superseded by command <id>")."""
        if self._newest.get((str(c.provider_id), c.service), c.created_at) > c.created_at:
            return True
        message = next((t.log_message for t in reversed(c.flow.transitions) if t.status is Status.FAILED), "")
        own = str(c.session_id)
        return any(w != own and w in self._sessions for w in (word.strip(".,;:()") for word in message.split()))

    def _conditions(self, now: float, providers: Mapping[uuid.UUID, Provider], relays: Mapping[str, Hop]) -> dict[str, Found]:
        holding: dict[str, Found] = dict(self._unanswered)
        for hop in silent_relays(relays, now, self.relay_silent_after):
            if all(str(v) in self.silences for v in hop.vehicles):
                continue  # every vehicle it carries in a planned silence: its quiet is expected, as their loss is
            f = Found("relay-silent", None, None, relay_silent_text(hop.relay, len(hop.vehicles)), hop.relay)
            holding[f.key] = f
        fix_valid: dict[str, Any] = {}
        for p in providers.values():
            pid = str(p.id)
            found: list[Found] = []
            if p.link in ("live", "regained"):
                self._overdue.pop(pid, None)  # heard again: no longer overdue
            elif pid in self._overdue:
                found.append(Found("silence-overdue", pid, None, self._overdue[pid]))
            elif p.link == "unchecked":
                pass  # silent while the console is behind: the console's own alarm says it (console-overloaded)
            elif pid not in self.silences and not lost_with_relay(p, relays, now, self.relay_silent_after):
                # (a planned silence: the loss is expected; lost with its relay: the relay's alarm says it)
                found.append(Found("link-lost", pid, None, f"link {inline(word('link', 'lost'))}"))
            ins = p.reports.get("InertialSensorReport")
            ins_status = ins["report"].get("status") if ins is not None else None
            if isinstance(ins_status, str) and ins_status.endswith(INS_FAILURE):
                found.append(Found("ins-failure", pid, None, f"INS {inline(word(INS_STATUS, ins_status))}"))
            status = p.reports.get("GPSFixStatusReport")
            valid = status["report"].get("fixValid") if status is not None else None
            fix_valid[pid] = valid
            if valid is True:
                self._had_fix.add(pid)
            elif valid is False and pid in self._had_fix:
                found.append(Found("fix-lost", pid, None, inline(word("alarmKind", "fix-lost"))))
            holding.update((f.key, f) for f in found)
        for pid, what in self._overdue.items():  # not heard since a restart either
            if uuid.UUID(pid) not in providers and what:
                f = Found("silence-overdue", pid, None, what)
                holding[f.key] = f
        for pid, c in self._latest_fix.items():
            if c.flow.status is not Status.COMPLETED or not c.times:
                continue
            sid = str(c.session_id)
            if fix_valid.get(pid) is True:
                self._fix_followed.add(sid)
            elif fix_valid.get(pid) is False and sid not in self._fix_followed:
                completed_at = c.times[-1][1]
                if now - completed_at >= NO_FIX_GRACE:
                    text = f"no valid GPS fix {now - completed_at:.0f} s after the fix command completed"
                    f = Found("no-fix-after-command", pid, str(c.session_id), text)
                    holding[f.key] = f
        return holding

    def _can_judge(self, a: Alarm, providers: Mapping[uuid.UUID, Provider], relays: Mapping[str, Hop]) -> bool:
        """Whether the state holds what the alarm's condition is about; after a restart a vehicle not heard
        from yet (or not yet this report) is no evidence that its condition cleared."""
        if a.kind in ("command-unanswered", "console-overloaded"):
            return True  # the commands not finished are always in memory
        if a.kind == "relay-silent":
            return a.key.split("|", 3)[3] in relays  # its relay (the key's last part, whatever it holds) heard of
        p = providers.get(uuid.UUID(a.provider_id)) if a.provider_id else None
        if p is None:
            return False
        if a.kind == "ins-failure":
            return "InertialSensorReport" in p.reports
        if a.kind in ("fix-lost", "no-fix-after-command"):
            return "GPSFixStatusReport" in p.reports
        return True

    # ---- storage ------------------------------------------------------------------------
    def _raise(self, f: Found, now: float) -> Alarm:
        who = self._vehicle(f.provider_id) if f.provider_id else None
        a = Alarm(
            key=f.key,
            kind=f.kind,
            severity=SEVERITY[f.kind],
            provider_id=f.provider_id,
            vehicle=who,
            session_id=f.session_id,
            text=f"{who}: {f.what}" if who else f.what,
            since=now,
            cleared_at=None,
            acked_at=None,
            acked_by=None,
            normal_at=None,
        )
        a.id = self.store.add_alarm(a.row())
        self.open[a.key] = a
        self._activated(a.key, now)
        self._worse(f, now)
        return a

    def _save(self, a: Alarm) -> None:
        self.store.update_alarm(a.row())


def _status_words(status: Status, reason: object) -> str:
    """'failed: the equipment failed', as the command's card says it (`core/words.py`); a reason not of UMAA's literals
    (undecodable) leaves the status alone."""
    said = inline(word("CommandStatusEnumType", status.name))
    return f"{said}: {inline(word('CommandStatusReasonEnumType', reason.name))}" if isinstance(reason, Reason) else said


def _recording_reason(error: str) -> str:
    """'recording stopped: the disk is full (/var/x.mcap)' -> 'the disk is full (/var/x.mcap)'."""
    return error.removeprefix("recording stopped: ")


def relay_silent_text(relay: str, vehicles: int) -> str:
    """ "relay ship-1 silent: 12 vehicles", in the words table's words."""
    count = f"{vehicles} vehicle{'' if vehicles == 1 else 's'}"
    return inline(word("alarmText", "relay-silent")).format(relay=relay, vehicles=count)


def overloaded_text(delay: float, vehicles: int) -> str:
    """ "this console is overloaded: it ran up to 3.2 s behind and did not check 12 vehicles...", in the words table's
    words."""
    count = f"{vehicles} vehicle{'' if vehicles == 1 else 's'}"
    return inline(word("alarmText", "console-overloaded")).format(delay=f"{delay:.1f} s", vehicles=count)


def lost_with_relay(p: Provider, relays: Mapping[str, Hop], now: float, silent_after: float) -> bool:
    """Whether a lost vehicle was lost with the relay it comes through: no data came over the relay's link since the
    vehicle went silent (its newest time stamp and its timeout), or, without a time stamp of it, the relay is silent.
    Its loss is then the relay's, said by the relay's one alarm, which comes as the vehicle is lost or within
    RELAY_GRACE after (the console learns the link's age from the relay's samples, once a second); a vehicle lost while
    that alarm is not due until later (the relay's other vehicles' caps keep them quieter) says its own. A relay that
    has carried no data yet (its operations side's relay just restarted) is never silent: the loss is the vehicle's own."""
    hop = relays.get(p.relay) if p.relay is not None else None
    if hop is None or hop.data_at is None:
        return False
    made = p.data_at()
    if made is None:
        return hop.silent(now, silent_after)
    lost_at = made + p.lost_after()
    relay_silent_at = hop.data_at + silent_after + max(hop.quiet.values(), default=0.0)
    if not hop.silent(now, silent_after) and relay_silent_at > lost_at + RELAY_GRACE:
        return False  # the relay's alarm is not due until well after this vehicle's loss: it says its own
    return hop.data_at <= lost_at
