"""The UMAA Service Consumer logic, without a network: a real SQLite store, DDS writes recorded."""

from __future__ import annotations

import asyncio
import threading
import time
import uuid
from pathlib import Path
from typing import Any

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as R

from sem_console.console import commands as commands_module
from sem_console.console.commands import Commands
from sem_console.dds.topics import Service
from sem_console.storage.database import Database
from sem_console.versions.commands import COMMANDING

OK = R.SUCCEEDED
VEHICLE = uuid.uuid4()

GPS_FIX_3_0_1, INS_3_0_1 = COMMANDING["3.0.1", Service.GPS_FIX], COMMANDING["3.0.1", Service.INERTIAL_SENSOR]


class Bus:
    def __init__(self) -> None:
        self.written: list[Any] = []
        self.disposed: list[Any] = []
        self.emitted: list[dict[str, Any]] = []


_stores: dict[Path, Database] = {}


def consumer(db: Path, bus: Bus, timeout: float = 5.0) -> Commands:
    """A console's commands on the SQLite file `db`; one opened again on a file is a console restarted: the earlier
    one's writes are done first, as at its stop."""
    if db in _stores:
        _stores[db].flush()
    store = _stores[db] = Database(db)
    return Commands(
        store.claim("test", hold=False),
        store,
        lambda _s, x: bus.written.append(x),
        lambda _s, x: bus.disposed.append(x),
        bus.emitted.append,
        timeout,
    )


def test_every_transition_recorded_even_with_equal_provider_times(tmp_path: Path) -> None:
    bus = Bus()
    c = consumer(tmp_path / "db", bus)
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    for st in (S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED):
        c.on_status(Service.GPS_FIX, cmd.session_id, VEHICLE, st, OK, "", 1000.0)  # a provider with a coarse clock
    assert [t.status for t in cmd.flow.transitions] == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED]
    assert cmd.cleaned_up and bus.disposed == [cmd.sample]  # cleanup disposes the finished command
    assert [m["type"] for m in bus.emitted] == ["command"] + ["transition"] * 4


def test_restart_ignores_replayed_history_and_keeps_following(tmp_path: Path) -> None:
    bus = Bus()
    first = consumer(tmp_path / "db", bus)
    cmd = first.issue(INS_3_0_1, VEHICLE, "RESTARTING", None)
    for i, st in enumerate((S.ISSUED, S.COMMANDED, S.EXECUTING)):
        first.on_status(Service.INERTIAL_SENSOR, cmd.session_id, VEHICLE, st, OK, "", 10.0 + i)
    second = consumer(tmp_path / "db", Bus())
    resumed = second.startup()
    assert [c.session_id for c in resumed] == [cmd.session_id]
    again = second.by_session[cmd.session_id]
    for i, st in enumerate((S.ISSUED, S.COMMANDED, S.EXECUTING)):  # the provider's transient-local history
        second.on_status(Service.INERTIAL_SENSOR, cmd.session_id, VEHICLE, st, OK, "", 10.0 + i)
    second.on_status(Service.INERTIAL_SENSOR, cmd.session_id, VEHICLE, S.COMPLETED, OK, "", 13.0)
    assert [t.status for t in again.flow.transitions] == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED]
    assert again.flow.violations == [] and again.state == "RESTARTING"


def test_unknown_ordinal_is_recorded_as_a_violation_and_survives_restart(tmp_path: Path) -> None:
    c = consumer(tmp_path / "db", Bus())
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    c.on_status(Service.GPS_FIX, cmd.session_id, VEHICLE, S.ISSUED, OK, "", 1.0)
    c.on_status(Service.GPS_FIX, cmd.session_id, VEHICLE, 99, OK, "", 2.0)
    assert cmd.to_json()["transitions"][1]["status"] == "UNKNOWN(99)"
    assert cmd.flow.violations == ["unknown commandStatus ordinal 99"] and cmd.flow.status is S.ISSUED
    again = consumer(tmp_path / "db", Bus()).by_session[cmd.session_id]
    assert again.to_json()["violations"] == ["unknown commandStatus ordinal 99"]


def test_unanswered_then_late_answer_is_persisted(tmp_path: Path) -> None:
    c = consumer(tmp_path / "db", Bus(), timeout=1.0)
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    c.tick(cmd.issued_by_deadline + 0.1, lambda _p: None)
    assert cmd.unanswered
    c.on_status(Service.GPS_FIX, cmd.session_id, VEHICLE, S.ISSUED, OK, "", 1.0)
    assert not cmd.unanswered
    assert not consumer(tmp_path / "db", Bus()).by_session[cmd.session_id].unanswered


def _stored_at_dispose(tmp_path: Path) -> tuple[Commands, Database, list[tuple[float, list[str | None]]]]:
    """A console whose dispose notes when it went and the canceller the database held then (what another station could
    read), or [] when the writer was still busy (the row cannot be read before it is written)."""
    store = Database(tmp_path / "db")
    seen: list[tuple[float, list[str | None]]] = []

    def dispose(_s: Any, sample: Any) -> None:
        session = str(uuid.UUID(bytes=bytes(sample.sessionID)))
        stored = store.writes.flush(0.05)
        seen.append((time.monotonic(), [r["canceled_by"] for r in store.commands(session_id=session)] if stored else []))

    c = Commands(store.claim("test", hold=False), store, lambda _s, _x: None, dispose, lambda _m: None, 5.0)
    return c, store, seen


def test_a_cancel_goes_to_the_vehicle_once_stored_so_other_stations_know_the_canceller_first(tmp_path: Path) -> None:
    """The dispose (the cancel on the wire) waits for the database to store who cancelled: the other stations are
    notified at that commit, so the vehicle's CANCELED never reaches them before its canceller (it did under load)."""
    c, store, seen = _stored_at_dispose(tmp_path)
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    store.flush()
    busy = threading.Event()

    async def main() -> None:
        store.writes.write(lambda _c: busy.wait(5))  # the writer busy with an earlier write
        c.cancel(cmd.session_id, "bob")
        await asyncio.sleep(0.2)
        assert seen == []  # not on the wire before the database has it
        busy.set()
        for _ in range(100):
            if seen:
                break
            await asyncio.sleep(0.02)

    try:
        asyncio.run(main())
    finally:
        busy.set()
    assert [names for _t, names in seen] == [["bob"]]


def test_a_cancel_goes_to_the_vehicle_within_its_bound_whatever_the_database_does(tmp_path: Path) -> None:
    """A database that does not store the cancel at once (an outage, a long queue) holds it CANCEL_STORED_WAIT at most;
    and a console that stops sends every cancel still waiting, at once."""
    c, store, seen = _stored_at_dispose(tmp_path)
    first = c.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    second = c.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    store.flush()
    busy = threading.Event()

    async def main() -> None:
        store.writes.write(lambda _c: busy.wait(10))
        asked = time.monotonic()
        c.cancel(first.session_id, "bob")
        while not seen and time.monotonic() - asked < 5:
            await asyncio.sleep(0.02)
        wait = commands_module.CANCEL_STORED_WAIT
        assert seen and seen[0][1] == [] and wait <= seen[0][0] - asked < wait + 2, (seen, asked)
        c.cancel(second.session_id, "bob")
        c.shutdown()  # the console stops: the cancel still waiting goes now
        assert len(seen) == 2

    try:
        asyncio.run(main())
    finally:
        busy.set()


def test_a_cancel_never_answered_ends_once_the_vehicle_is_heard_for_the_unanswered_timeout(tmp_path: Path) -> None:
    bus = Bus()
    c = consumer(tmp_path / "db", bus, timeout=2.0)
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    c.tick(cmd.issued_by_deadline + 0.1, lambda _p: None)  # lost: unanswered
    c.cancel(cmd.session_id, "bob")
    heard: list[float | None] = [cmd.cancel_mono - 5]  # last heard before the cancel: not heard since
    c.tick(0, lambda _p: heard[0])
    heard[0] = cmd.cancel_mono + 1  # back
    c.tick(0, lambda _p: heard[0])
    heard[0] = cmd.cancel_mono + 2.9  # heard for less than the unanswered timeout: it may still answer
    c.tick(0, lambda _p: heard[0])
    assert not cmd.terminal
    heard[0] = cmd.cancel_mono + 3.1
    c.tick(0, lambda _p: heard[0])
    assert cmd.terminal and cmd.closed_unheard == "heard" and cmd.cleaned_up
    assert bus.emitted[-1]["command"]["closedUnheard"] == "heard" and bus.emitted[-1]["command"]["terminal"]
    reloaded = consumer(tmp_path / "db", Bus()).by_session[cmd.session_id]  # after a restart: ended, not running
    assert reloaded.terminal and reloaded.cleaned_up and reloaded.to_json()["canceledBy"] == "bob"
    # it answers after all: what it says stands, the console's ending is withdrawn
    c.on_status(Service.GPS_FIX, cmd.session_id, VEHICLE, S.CANCELED, R.CANCELED, "", 1.0)
    assert cmd.closed_unheard is None and cmd.flow.status is S.CANCELED and cmd.terminal
    stored = asyncio.run(c.get(cmd.session_id))
    assert stored is not None and stored.to_json()["closedUnheard"] is None


def test_a_cancel_asked_on_another_station_ends_unanswered_only_once_the_vehicle_is_heard_after_it(tmp_path: Path) -> None:
    """The station that issued it learns the cancel from the shared database: a vehicle last heard long before (lost)
    is not "heard again without it" at its first sample back, which may well be followed by its answer."""
    bus = Bus()
    store = Database(tmp_path / "db")
    a = Commands(
        store.claim("alpha", hold=False),
        store,
        lambda _s, x: bus.written.append(x),
        lambda _s, x: bus.disposed.append(x),
        bus.emitted.append,
        2.0,
        station="alpha",
    )
    cmd = a.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    last_heard = a.clock.monotonic() - 60  # lost a minute ago
    a.tick(cmd.issued_by_deadline + 0.1, lambda _p: last_heard)
    assert cmd.unanswered
    store.set_canceled(str(cmd.session_id), "bob", "bravo", a.clock.wall())  # bob cancels it on station bravo
    assert a.merge_shared(store.commands(session_id=str(cmd.session_id))[0]) is cmd
    assert (cmd.canceled_by, cmd.canceled_on) == ("bob", "bravo")
    a.tick(0, lambda _p: last_heard)  # still lost
    back = a.clock.monotonic() + 0.1
    a.tick(0, lambda _p: back)  # its first sample back
    assert not cmd.terminal and cmd.closed_unheard is None
    a.tick(0, lambda _p: back + 2.1)  # heard for the unanswered timeout without a word of it
    assert cmd.closed_unheard == "heard"


def test_another_station_s_cancel_never_answered_is_ended_here_and_only_once(tmp_path: Path) -> None:
    """Station alpha cancels a command its lost vehicle never answered, then stops for good: it counted up for ever on
    the stations sharing the database. Bravo (started after, from the database) and charlie (running, from the
    notification) end it by the same rule; the first ending stored stands, and the other station shows it."""
    store = Database(tmp_path / "db")
    emitted: dict[str, list[dict[str, Any]]] = {"alpha": [], "bravo": [], "charlie": [], "delta": []}

    def station(name: str) -> Commands:
        return Commands(
            store.claim(name, hold=False),
            store,
            lambda _s, _x: None,
            lambda _s, _x: None,
            emitted[name].append,
            2.0,
            station=name,
        )

    alpha, charlie = station("alpha"), station("charlie")
    cmd = alpha.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    alpha.tick(cmd.issued_by_deadline + 0.1, lambda _p: None)  # lost: unanswered
    alpha.cancel(cmd.session_id, "alice")
    shown = charlie.merge_shared(store.commands(session_id=str(cmd.session_id))[0])  # charlie hears of the cancel
    assert shown is not None and shown.cancel_requested and not shown.terminal
    bravo = station("bravo")  # started after the cancel
    assert set(bravo.others) == set(charlie.others) == {cmd.session_id}
    back = bravo.clock.monotonic() + 0.1  # alpha stopped for good; the vehicle back
    for s in (bravo, charlie):
        s.tick(0, lambda _p: back)
    bravo.tick(0, lambda _p: back + 1.9)  # heard for less than the unanswered timeout: it may still answer
    assert store.commands(session_id=str(cmd.session_id))[0]["closed_unheard"] is None
    bravo.tick(0, lambda _p: back + 2.1)
    ended = emitted["bravo"][-1]["command"]
    assert (ended["closedUnheard"], ended["terminal"], ended["canceledBy"]) == ("heard", True, "alice")
    assert bravo.others == {}
    stored = store.commands(session_id=str(cmd.session_id))[0]
    assert (stored["closed_unheard"], stored["closed_at"], stored["cleaned_up"]) == ("heard", ended["closedAt"], True)
    charlie.tick(0, lambda _p: back + 3.0)  # charlie would end it too, later: refused, it shows the stored ending
    assert store.flush(30)
    charlie.tick(0, lambda _p: back + 3.1)  # from the tick after its refused write
    assert emitted["charlie"][-1]["command"]["closedAt"] == ended["closedAt"]
    assert store.commands(session_id=str(cmd.session_id))[0]["closed_at"] == ended["closedAt"]
    assert charlie.others == {} and station("delta").others == {}


def test_a_cancel_never_answered_is_not_ended_by_a_vehicle_heard_a_moment_then_lost(tmp_path: Path) -> None:
    """A flaky link: heard once after the cancel, lost a minute, back: its answer comes with the link, so the first
    sample back does not end the command as never heard."""
    c = consumer(tmp_path / "db", Bus(), timeout=2.0)
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    c.cancel(cmd.session_id, "bob")
    c.tick(0, lambda _p: cmd.cancel_mono + 0.5)  # heard a moment
    c.tick(0, lambda _p: None)  # lost
    c.tick(0, lambda _p: cmd.cancel_mono + 60)  # back
    assert not cmd.terminal
    c.tick(0, lambda _p: cmd.cancel_mono + 62.1)  # heard for the unanswered timeout since
    assert cmd.closed_unheard == "heard"


def test_a_recorded_command_first_heard_canceled_and_ended_replays_so(tmp_path: Path) -> None:
    """A recording that starts (or rolls over) after the cancel: the first message of the command carries its cancel
    and the console's ending; the replay showed it running ("Sent", then "No answer") for ever."""
    recorded = consumer(tmp_path / "recorded", Bus(), timeout=1.0)
    cmd = recorded.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    recorded.tick(cmd.issued_by_deadline + 0.1, lambda _p: None)
    recorded.cancel(cmd.session_id, "bob")
    recorded.tick(0, lambda _p: cmd.cancel_mono + 0.1)
    recorded.tick(0, lambda _p: cmd.cancel_mono + 1.2)
    message = cmd.to_json()
    assert message["closedUnheard"] == "heard" and message["cancelRequested"]
    bus = Bus()
    replay = consumer(tmp_path / "replay", bus)
    again = replay.adopt(message)
    assert again.terminal and again.cleaned_up and (again.canceled_by, again.closed_unheard) == ("bob", "heard")
    assert (again.canceled_at, again.closed_at) == (cmd.canceled_at, cmd.closed_at)
    assert [m["command"]["terminal"] for m in bus.emitted] == [True]  # one message, the command as recorded
    assert asyncio.run(replay.get(cmd.session_id)) is again
    assert replay.store.commands(session_id=str(cmd.session_id))[0]["closed_unheard"] == "heard"


def test_statuses_from_another_provider_or_for_other_sessions_are_ignored(tmp_path: Path) -> None:
    c = consumer(tmp_path / "db", Bus())
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    c.on_status(Service.GPS_FIX, cmd.session_id, uuid.uuid4(), S.ISSUED, OK, "", 1.0)
    c.on_status(Service.INERTIAL_SENSOR, cmd.session_id, VEHICLE, S.ISSUED, OK, "", 1.0)
    c.on_status(Service.GPS_FIX, uuid.uuid4(), VEHICLE, S.ISSUED, OK, "", 1.0)
    assert cmd.flow.transitions == []


def test_memory_keeps_active_and_recent_commands_history_pages_from_the_database(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setattr(commands_module, "KEEP_FINISHED", 3)
    c = consumer(tmp_path / "db", Bus())
    sessions = []
    for i in range(6):
        cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
        sessions.append(cmd.session_id)
        if i < 5:
            for st in (S.ISSUED, S.FAILED):
                c.on_status(Service.GPS_FIX, cmd.session_id, VEHICLE, st, OK if st is S.ISSUED else R.RESOURCE_FAILED, "", 1.0)
    assert set(c.by_session) == set(sessions[2:])  # the running one and the three newest finished
    page = c.history(limit=2, offset=0)
    assert [p["sessionId"] for p in page] == [str(s) for s in sessions[::-1][:2]]
    old = asyncio.run(c.get(sessions[0]))
    assert old is not None and [t.status for t in old.flow.transitions] == [S.ISSUED, S.FAILED]
    assert len(c.history(limit=100, offset=0)) == 6


def test_ack_recorded(tmp_path: Path) -> None:
    bus = Bus()
    c = consumer(tmp_path / "db", bus)
    cmd = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    c.on_ack(Service.GPS_FIX, cmd.session_id, VEHICLE)
    assert cmd.acked_at is not None and bus.emitted[-1]["command"]["ackedAt"] == cmd.acked_at
    assert consumer(tmp_path / "db", Bus()).by_session[cmd.session_id].acked_at == cmd.acked_at


def _statuses(c: Commands, cmd: Any, *steps: tuple[S, R, float]) -> None:
    for st, reason, at in steps:
        c.on_status(cmd.service, cmd.session_id, VEHICLE, st, reason, "", at)


def test_statuses_with_tied_or_backward_provider_times_are_all_applied_in_arrival_order(tmp_path: Path) -> None:
    c = consumer(tmp_path / "db", Bus())
    tied = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    _statuses(c, tied, (S.ISSUED, OK, 50.0), (S.FAILED, R.RESOURCE_REJECTED, 50.0))  # one millisecond, one stamp
    assert [(t.status, t.reason) for t in tied.flow.transitions] == [(S.ISSUED, OK), (S.FAILED, R.RESOURCE_REJECTED)]
    backward = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    _statuses(c, backward, (S.ISSUED, OK, 40.0), (S.COMMANDED, OK, 39.0), (S.EXECUTING, OK, 20.0), (S.COMPLETED, OK, 1.0))
    assert [t.status for t in backward.flow.transitions] == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED]
    assert backward.flow.violations == [] and backward.cleaned_up
    # a broken provider repeating an earlier status with the same stamp: recorded as the violation it is
    repeat = c.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    _statuses(c, repeat, (S.ISSUED, OK, 5.0), (S.COMMANDED, OK, 5.0), (S.ISSUED, OK, 5.0))
    assert [t.status for t in repeat.flow.transitions] == [S.ISSUED, S.COMMANDED, S.ISSUED]
    assert repeat.flow.violations == ["COMMANDED -> ISSUED is not a Figure 4 transition"]


def test_restart_skips_a_replay_of_only_the_last_statuses(tmp_path: Path) -> None:
    """A provider whose status history keeps one sample replays only its last status after our restart."""
    first = consumer(tmp_path / "db", Bus())
    cmd = first.issue(GPS_FIX_3_0_1, VEHICLE, None, None)
    _statuses(first, cmd, (S.ISSUED, OK, 7.0), (S.COMMANDED, OK, 7.0), (S.EXECUTING, OK, 7.0))
    second = consumer(tmp_path / "db", Bus())
    second.startup()
    again = second.by_session[cmd.session_id]
    _statuses(second, again, (S.EXECUTING, OK, 7.0), (S.COMPLETED, OK, 7.0))  # the replay, then a new status, same stamp
    assert [t.status for t in again.flow.transitions] == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED]
    assert again.flow.violations == [] and again.cleaned_up


def test_sem_check_addresses_a_6_0_command_to_the_providers_identifier_its_parent_too() -> None:
    """sem-check's command to a 6.0 provider carries the parentID the provider's reports give its source (ICD 6.0 4.1,
    5.2.9), and its update keeps it (the destination is a key of the command)."""
    import io
    import types

    from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as InsCmd

    from sem_console.check import umaa_6_0 as check60
    from sem_console.check.commands import CommandLimits, Consumer

    provider, parent = uuid.uuid4(), uuid.uuid4()
    written: list[object] = []
    writer = types.SimpleNamespace(write=written.append)
    observer = types.SimpleNamespace(parents={provider: parent})
    consumer = Consumer(observer, provider, CommandLimits(1, 1, 1), io.StringIO(), version=check60.V6_0)  # type: ignore[arg-type]
    sent = consumer.send(Service.INERTIAL_SENSOR, writer, InsCmd.GPS_ALIGN)  # type: ignore[arg-type]
    consumer.writers[Service.INERTIAL_SENSOR] = writer  # type: ignore[assignment]
    consumer.update_command(sent)
    assert len(written) == 2
    for sample in written:
        destination = sample.destination  # type: ignore[attr-defined]
        assert uuid.UUID(bytes=bytes(destination.id)) == provider
        assert uuid.UUID(bytes=bytes(destination.parentID)) == parent


def test_two_updates_in_a_row_are_two_transitions_kept_after_a_restart(tmp_path: Path) -> None:
    """A 6.0 command updated twice before it moved on: two ISSUED/UPDATED statuses, each a transition, stored, on the
    WebSocket and read back after a restart; the same status again is a repeat."""
    from sem_console.umaa.flow import UPDATED

    bus = Bus()
    c = consumer(tmp_path / "db", bus)
    ins60 = COMMANDING["6.0", Service.INERTIAL_SENSOR]
    cmd = c.issue(ins60, VEHICLE, "GPS_ALIGN", None)
    for i, (st, r) in enumerate(
        [(S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK), (S.ISSUED, UPDATED), (S.ISSUED, UPDATED), (S.ISSUED, UPDATED)]
    ):
        c.on_status(Service.INERTIAL_SENSOR, cmd.session_id, VEHICLE, st, r, "", 10.0 + min(i, 4))
    want = ["ISSUED", "COMMANDED", "EXECUTING", "ISSUED", "ISSUED"]
    assert [t["status"] for t in cmd.to_json()["transitions"]] == want and cmd.flow.violations == []
    assert [t["reason"] for t in cmd.to_json()["transitions"]][-2:] == ["UPDATED", "UPDATED"]
    assert [m["type"] for m in bus.emitted].count("transition") == 5
    again = consumer(tmp_path / "db", Bus()).by_session[cmd.session_id]
    assert [t["status"] for t in again.to_json()["transitions"]] == want


def test_a_6_0_breach_names_the_6_0_icds_figure(tmp_path: Path) -> None:
    """A 6.0 vehicle that skips COMMANDED (sem-sim's skip-commanded fault) breaks its ICD's Figure 14 (ICD 6.0 4.1), not
    3.0.1's Figure 4: the console's monitor and the simulator's own flow say so; a 3.0.1 command still names Figure 4."""
    from sem_console.sim.provider_flow import Execution

    c = consumer(tmp_path / "db", Bus())
    ins60 = COMMANDING["6.0", Service.INERTIAL_SENSOR]
    cmd = c.issue(ins60, VEHICLE, "GPS_ALIGN", None)
    old = c.issue(INS_3_0_1, VEHICLE, "ON", None)
    for command, service in ((cmd, Service.INERTIAL_SENSOR), (old, Service.INERTIAL_SENSOR)):
        c.on_status(service, command.session_id, VEHICLE, S.ISSUED, OK, "", 1.0)
        c.on_status(service, command.session_id, VEHICLE, S.EXECUTING, OK, "", 2.0)
    assert cmd.flow.violations == ["ISSUED -> EXECUTING is not a Figure 14 transition"]
    assert old.flow.violations == ["ISSUED -> EXECUTING is not a Figure 4 transition"]
    ex = Execution(ins60, cmd.sample, 0.0)
    ex.flow.observe(S.ISSUED, OK)
    breach = ex.flow.observe(S.EXECUTING, OK)
    assert breach is not None and breach.violation == "ISSUED -> EXECUTING is not a Figure 14 transition"


def test_the_cancel_stored_first_stands_and_a_station_that_cancelled_after_shows_it(tmp_path: Path) -> None:
    """Bob cancels watch's command on relief; watch, not yet told, stops and cancels it too. The first cancel stored
    stands in the database (the history, the CSV, a restarted station) and watch shows it from its next tick, not its
    own: one canceller everywhere. A station told of the cancel first never writes its own (`cancel_requested`)."""
    store = Database(tmp_path / "db")
    emitted: list[dict[str, Any]] = []
    watch = Commands(
        store.claim("watch", hold=False), store, lambda _s, _x: None, lambda _s, _x: None, emitted.append, 2.0, station="watch"
    )
    cmd = watch.issue(GPS_FIX_3_0_1, VEHICLE, None, "alice")
    assert store.flush(30)
    assert store.set_canceled(str(cmd.session_id), "bob", "relief", 101.0).result(30) is None  # relief's, stored first
    watch.cancel(cmd.session_id, None, "shutdown")
    assert emitted[-1]["command"]["canceledOn"] == "watch"  # its own, until the database answers
    refused = store.set_canceled(str(cmd.session_id), "carol", "relief", 102.0).result(30)
    assert refused is not None and (refused["canceled_by"], refused["canceled_at"]) == ("bob", 101.0)
    assert store.flush(30)
    row = store.commands(session_id=str(cmd.session_id))[0]
    assert (row["canceled_by"], row["canceled_on"], row["canceled_at"], row["cancel_cause"]) == (
        "bob",
        "relief",
        101.0,
        "operator",
    )
    watch.tick(0, lambda _p: None)
    shown = emitted[-1]["command"]
    assert (shown["canceledBy"], shown["canceledOn"], shown["canceledAt"], shown["cancelCause"]) == (
        "bob",
        "relief",
        101.0,
        "operator",
    )


def test_a_replay_shows_the_canceller_its_console_showed_once_its_own_cancel_was_refused(tmp_path: Path) -> None:
    """A recording holds watch's command message with its own cancel (Alice), then the same command with the cancel the
    database had stored first (Bob, on relief), which watch showed from then on: the replay shows Bob too, in its card
    and its history."""
    recorded = consumer(tmp_path / "watch", Bus()).issue(GPS_FIX_3_0_1, VEHICLE, None, "alice").to_json()
    own = {**recorded, "cancelRequested": True, "canceledBy": "alice", "canceledOn": "watch", "canceledAt": 101.0}
    first = {**own, "canceledBy": "bob", "canceledOn": "relief", "canceledAt": 100.0}
    bus = Bus()
    replay = consumer(tmp_path / "replay", bus)
    replay.adopt(dict(own))
    shown = replay.adopt(dict(first))
    assert (shown.canceled_by, shown.canceled_on, shown.canceled_at) == ("bob", "relief", 100.0)
    assert (bus.emitted[-1]["command"]["canceledBy"], bus.emitted[-1]["command"]["canceledOn"]) == ("bob", "relief")
    store = _stores[tmp_path / "replay"]
    assert store.flush(30)
    [row] = store.commands(session_id=recorded["sessionId"])
    assert (row["canceled_by"], row["canceled_on"], row["canceled_at"]) == ("bob", "relief", 100.0)
