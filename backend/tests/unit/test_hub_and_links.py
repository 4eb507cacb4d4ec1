"""The WebSocket hub and link health, without a network."""

from __future__ import annotations

import asyncio
import itertools
import json
import time
import uuid
from collections.abc import Awaitable, Callable
from typing import Any

import pytest

from sem_console.console import hub as hub_module
from sem_console.console.feed import Feed
from sem_console.console.hub import SLOWEST_LINK, Client, Hub
from sem_console.console.providers import Providers
from sem_console.core.contract import LinkConfig


def test_hub_keeps_order_conflates_reports_and_drops_a_stalled_client() -> None:
    async def scenario() -> None:
        hub = Hub(max_queue=5, stall_seconds=0.0)
        fast: list[dict] = []
        gate = asyncio.Event()

        async def send_fast(text: str) -> None:
            fast.append(json.loads(text))

        async def send_stalled(_text: str) -> None:
            await gate.wait()  # never returns: a client that stopped reading

        hub.attach(send_fast, {"type": "snapshot"})
        stalled = hub.attach(send_stalled, {"type": "snapshot"})
        for i in range(3):
            hub.publish({"type": "report", "n": i}, key=("p", "GPSFixReport"))
        hub.publish({"type": "transition", "n": 1})
        await asyncio.sleep(0.01)
        for i in range(10):
            hub.publish({"type": "transition", "n": i + 2})
            await asyncio.sleep(0)  # the fast client gets to run between events; the stalled one never sends
        await asyncio.sleep(0.01)
        assert [m["type"] for m in fast][:2] == ["snapshot", "transition"]
        assert [m["n"] for m in fast if m["type"] == "transition"] == list(range(1, 12))
        assert [m["n"] for m in fast if m["type"] == "report"] == [2]  # conflated to the latest
        assert stalled.dropped and stalled not in hub.clients and len(stalled.ordered) == 0

    asyncio.run(scenario())


def test_link_lost_after_silence_and_regained_after_continuous_samples() -> None:
    links = Providers(comms_lost_timeout=1.0, regained_time=2.0)
    pid = uuid.uuid4()
    links.seen("GPSFixReport", pid, {"x": 1}, 0.0, 0.0, True)
    assert links.tick(0.5) == [] and links.by_id[pid].link == "live"
    assert [e for _, e in links.tick(1.6)] == ["lost"]
    t = 2.0
    while t < 3.9:  # samples every 0.2 s, but not yet for the regained time
        links.seen("GPSFixReport", pid, {"x": 1}, t, t, True)
        assert links.tick(t) == []
        t += 0.2
    links.seen("GPSFixReport", pid, {"x": 1}, 4.1, 4.1, True)
    assert [e for _, e in links.tick(4.1)] == ["regained"]
    for t in (4.8, 5.5):
        links.seen("GPSFixReport", pid, {"x": 1}, t, t, True)
        assert links.tick(t) == []
    links.seen("GPSFixReport", pid, {"x": 1}, 6.2, 6.2, True)
    assert [e for _, e in links.tick(6.2)] == ["live"] and links.by_id[pid].link == "live"


def test_link_lost_when_all_report_writers_go() -> None:
    links = Providers(comms_lost_timeout=10.0, regained_time=1.0)
    pid = uuid.uuid4()
    for topic in ("GPSFixReport", "InertialSensorReport"):
        links.seen(topic, pid, {"x": 1}, 0.0, 0.0, True)
    links.seen("GPSFixReport", pid, None, 0.1, 0.1, False)
    assert links.tick(0.2) == []
    links.seen("InertialSensorReport", pid, None, 0.2, 0.2, False)
    assert [e for _, e in links.tick(0.3)] == ["lost"]


def test_hub_batches_waiting_reports_for_a_client_that_asks_and_sends_a_lone_one_alone() -> None:
    async def scenario() -> None:
        hub = Hub()
        frames: dict[str, list[str]] = {"batch": [], "plain": []}

        def sender(name: str) -> Callable[[str], Awaitable[None]]:
            async def send(text: str) -> None:
                frames[name].append(text)

            return send

        hub.attach(sender("batch"), {"type": "snapshot"}, batch=True)
        hub.attach(sender("plain"), {"type": "snapshot"})
        for p in ("a", "b", "c"):  # three vehicles' reports before the senders run: waiting together
            hub.publish({"type": "report", "providerId": p}, key=(p, "GPSFixReport"))
        await asyncio.sleep(0.01)
        hub.publish({"type": "report", "providerId": "a"}, key=("a", "GPSFixReport"))  # sparse: alone, not wrapped
        await asyncio.sleep(0.01)
        batch = [json.loads(t) for t in frames["batch"]]
        assert batch[0] == {"type": "snapshot"}
        assert [m["providerId"] for m in batch[1]] == ["a", "b", "c"]  # one frame, in order
        assert batch[2] == {"type": "report", "providerId": "a"}
        assert [json.loads(t).get("providerId") for t in frames["plain"]] == [None, "a", "b", "c", "a"]

    asyncio.run(scenario())


def test_an_ordered_event_goes_out_next_while_reports_keep_coming() -> None:
    """Under load the reports never all go out (a new one arrives during each send): an alarm, a lost vehicle or a
    command published meanwhile must not wait for them, nor go after reports published later."""

    async def scenario(batch: bool) -> list[str]:
        hub = Hub()
        sent: list[str] = []
        n = 0

        async def send(text: str) -> None:
            nonlocal n
            sent.append(text)
            await asyncio.sleep(0)  # the socket's write: other publishers run meanwhile
            if text.startswith(("[", '{"type":"report"')) and n < 40:
                n += 1
                for v in range(2):  # more reports arrive during each send than one send takes
                    hub.publish({"type": "report", "n": n, "v": v}, key=(f"{n}-{v}", "GPSFixReport"))
                if n == 3:
                    hub.publish({"type": "alarms", "alarms": []})

        hub.attach(send, {"type": "snapshot"}, batch=batch)
        hub.publish({"type": "report", "n": 0}, key=("0", "GPSFixReport"))
        for _ in range(400):
            await asyncio.sleep(0)
        return sent

    for batch in (False, True):
        sent = asyncio.run(scenario(batch))
        alarm = next(i for i, t in enumerate(sent) if t.startswith('{"type":"alarms"'))
        # published during the third report's send: out right after it (the frame of reports 1-3 are before it)
        assert alarm == 4, (batch, alarm, len(sent))


def test_hub_burst_does_not_drop_a_healthy_client() -> None:
    async def scenario() -> None:
        hub = Hub(max_queue=5, stall_seconds=5.0)
        got: list[dict] = []

        async def send(text: str) -> None:
            got.append(json.loads(text))

        client = hub.attach(send, {"type": "snapshot"})
        for i in range(15):  # one synchronous burst, three times the bound
            hub.publish({"type": "transition", "n": i})
        await asyncio.sleep(0.01)
        assert not client.dropped and [m["n"] for m in got[1:]] == list(range(15))
        for i in range(25):  # past four times the bound: dropped whatever it does
            hub.publish({"type": "transition", "n": i})
        assert client.dropped

    asyncio.run(scenario())


def test_resync_storm_queues_one_snapshot() -> None:
    async def scenario() -> None:
        hub = Hub(max_queue=100)
        gate = asyncio.Event()

        async def slow(_text: str) -> None:
            await gate.wait()

        client = hub.attach(slow, {"type": "snapshot"})
        await asyncio.sleep(0)  # the first snapshot is being sent (and blocks)
        for _ in range(1000):
            client.push_snapshot(json.dumps({"type": "snapshot", "big": "x" * 1000}))
        assert len(client.ordered) == 1 and not client.dropped

    asyncio.run(scenario())


def test_the_window_reopens_on_the_acks_of_this_socket_across_a_resync() -> None:
    """/ws?ack=1: reports wait while the window is full; an ack beyond the frames sent (not this socket's count) is
    ignored, one of some frames frees theirs only, and a replay's resync keeps the count (the client counts on)."""

    async def scenario() -> None:
        hub = Hub(window=100)
        sent: list[str] = []

        async def send(text: str) -> None:
            sent.append(text)

        client = hub.attach(send, {"type": "snapshot", "pad": "x" * 200}, ack=True)  # the snapshot alone fills it
        hub.publish({"type": "report", "n": 1}, key=("a", "GPSFixReport"))
        hub.publish({"type": "alarms", "alarms": []})  # ordered: not held
        await asyncio.sleep(0.01)
        assert [json.loads(t)["type"] for t in sent] == ["snapshot", "alarms"]
        client.ack(3)  # more than were sent: ignored
        await asyncio.sleep(0.01)
        assert len(sent) == 2
        hub.publish({"type": "report", "n": 2}, key=("a", "GPSFixReport"))  # replaces the held one
        client.ack(1)  # the snapshot: the window opens
        await asyncio.sleep(0.01)
        assert json.loads(sent[2]) == {"type": "report", "n": 2} and len(sent) == 3
        hub.resync({"type": "snapshot", "pad": "y" * 200})  # a seek: counted on, frames 4
        hub.publish({"type": "report", "n": 3}, key=("a", "GPSFixReport"))
        await asyncio.sleep(0.01)
        assert [json.loads(t)["type"] for t in sent[3:]] == ["snapshot"]  # the window is full again
        client.ack(4)
        await asyncio.sleep(0.01)
        assert json.loads(sent[-1]) == {"type": "report", "n": 3} and client.inflight_bytes == len(sent[-1])

    asyncio.run(scenario())


def test_link_thresholds_are_per_vehicle() -> None:
    slow = uuid.uuid4()
    links = Providers(
        comms_lost_timeout=1.0,
        regained_time=1.0,
        configs={str(slow): LinkConfig(commsLostTimeout=5.0, regainedTime=1.0, policy="CONTINUE_MISSION", regainedBehavior=2)},
        jaus_subsystem=9,
    )
    fast = uuid.uuid4()
    links.seen("GPSFixReport", fast, {"x": 1}, 0.0, 0.0, True)
    links.seen("GPSFixReport", slow, {"x": 1}, 0.0, 0.0, True)
    assert [(p.id, e) for p, e in links.tick(2.0)] == [(fast, "lost")]  # slow has 5 s
    assert [(p.id, e) for p, e in links.tick(5.1)] == [(slow, "lost")]
    assert links.by_id[fast].summary(5.1)["linkConfig"] == {
        "commsLostTimeout": 1.0,
        "regainedTime": 1.0,
        "policy": "STOP_MISSION",
        "regainedBehavior": 0,
    }
    assert [links.by_id[x].summary(0)["jausId"] for x in (fast, slow)] == ["9.1.1", "9.1.2"]  # order of appearance
    links.by_id[fast].config = LinkConfig(commsLostTimeout=0.5, regainedTime=3.0, policy="STOP_MISSION", regainedBehavior=0)
    links.seen("GPSFixReport", fast, {"x": 1}, 6.0, 6.0, True)
    links.seen("GPSFixReport", fast, {"x": 1}, 6.4, 6.4, True)
    assert links.tick(6.4) == []  # 0.5 s lost timeout: 0.4 s gaps keep regaining going
    links.seen("GPSFixReport", fast, {"x": 1}, 9.1, 9.1, True)  # a 2.7 s gap restarts it
    assert links.tick(9.1) == []
    assert Providers(1.0, 1.0).seen("GPSFixReport", fast, None, 0, 0, True)[0].summary(0)["jausId"] is None  # JAUS off


def test_feed_delivers_in_order_and_survives_a_failing_subscriber() -> None:
    feed = Feed()
    got: list[int] = []

    def bad(_m: dict) -> None:
        raise RuntimeError("boom")

    feed.subscribe("bad", bad)
    stop = feed.subscribe("good", lambda m: got.append(m["n"]))
    for n in range(3):
        feed.publish({"type": "report", "n": n})
    stop()
    feed.publish({"type": "report", "n": 3})
    assert got == [0, 1, 2] and feed.errors == {"bad": 4}


def test_the_feed_taps_raw_samples_to_active_taps_and_survives_a_failing_one() -> None:
    """The feed is the ingest's tap: a take goes to every active tap (the recorder, the Foxglove gateway), none to an
    inactive one, and one that raises costs only itself."""
    from sem_console.dds.topics import Sem

    class Taken:
        def __init__(self, active: bool) -> None:
            self.active, self.takes = active, 0

        def on_samples(self, _sem: Any, samples: list[tuple[bytes, bool, int, int]], _received_ns: int) -> None:
            if not samples:
                raise RuntimeError("boom")
            self.takes += 1

    feed, on, off = Feed(), Taken(True), Taken(False)
    feed.tap("off", off)
    assert not feed.active  # the ingest then hands it nothing
    feed.tap("bad", Taken(True))
    stop = feed.tap("on", on)
    assert feed.active
    feed.on_samples(Sem.GPS_REPORT, [], 0)  # "bad" raises on an empty take (as "on" then does too)
    feed.on_samples(Sem.GPS_REPORT, [(b"\x00\x01\x00\x00", True, 0, 0)], 0)
    stop()
    feed.on_samples(Sem.GPS_REPORT, [(b"\x00\x01\x00\x00", True, 0, 0)], 0)
    assert (on.takes, off.takes) == (1, 0) and feed.errors == {"bad": 1, "on": 1}


async def held_client(hub: Hub, snapshot_bytes: int) -> tuple[Client, list[str]]:
    """A client taking batches and acknowledging, whose snapshot alone fills the hub's window (its reports wait until
    it acknowledges), and the frames sent to it."""
    sent: list[str] = []

    async def send(text: str) -> None:
        sent.append(text)

    client = hub.attach(send, {"type": "snapshot", "pad": "x" * snapshot_bytes}, batch=True, ack=True)
    await asyncio.sleep(0.01)
    return client, sent


def test_a_waiting_report_keeps_its_place_and_a_batch_keeps_within_the_window() -> None:
    """A report updated while it waits goes out in its place with the newest text (a 10 Hz fix is not sent to the back
    of the queue by each update); a batch stops at the window's room (at least one report)."""

    async def scenario() -> None:
        hub = Hub(window=2048)
        client, sent = await held_client(hub, 2100)
        for p in ("a", "b", "c", "a"):  # a, updated while it waits
            hub.publish({"type": "report", "providerId": p, "pad": "y" * 900}, key=(p, "GPSFixReport"))
        hub.publish({"type": "report", "providerId": "a", "newest": True, "pad": "y" * 900}, key=("a", "GPSFixReport"))
        await asyncio.sleep(0.01)
        assert len(sent) == 1  # held by the window
        client.ack(1)
        await asyncio.sleep(0.01)
        first = json.loads(sent[1])
        assert [m["providerId"] for m in first] == ["a", "b", "c"][: len(first)] and len(first) < 3  # within 2 kB
        assert first[0].get("newest") is True  # a in its place, with its newest report

    asyncio.run(scenario())


def test_a_selecting_client_gets_other_vehicles_gps_reports_thin_but_once_every_few_seconds(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A client that named the vehicle it draws gets that one's GPSReports whole and the others' thin, but one every
    FULL_EVERY seconds whole (the trails), the first within FULL_EVERY of its coming at a point spread by the vehicle's
    id (b's: 1.6 s); a client that named none gets every report whole."""
    now = [1000.0]  # the hub's clock of whole reports (the console's), not the loop's
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 0.0)  # each report goes (the rate of the others: below)

    async def scenario() -> None:
        hub = Hub(clock=lambda: now[0])
        got: dict[str, list[dict]] = {"dashboard": [], "other": []}

        def sender(name: str) -> Callable[[str], Awaitable[None]]:
            async def send(text: str) -> None:
                got[name].append(json.loads(text))

            return send

        dashboard = hub.attach(sender("dashboard"), {"type": "snapshot"})
        hub.attach(sender("other"), {"type": "snapshot"})
        dashboard.select("a")

        async def gps(p: str, n: int) -> None:
            whole = {"type": "report", "providerId": p, "topic": "GPSReport", "n": n, "report": {"satellites": [1, 2]}}
            hub.publish(whole, key=(p, "GPSReport"), thin={**whole, "partial": True, "report": {"satellites": []}})
            await asyncio.sleep(0.01)

        for n in range(3):
            await gps("a", n)
            await gps("b", n)
            now[0] += 2.0
        now[0] += 1.0
        await gps("b", 3)  # 5 s after b's first whole one: whole again
        dashboard.select("b")
        await gps("b", 4)
        await gps("a", 4)
        seen = [(m["providerId"], m["n"], m.get("partial", False)) for m in got["dashboard"] if m["type"] == "report"]
        assert seen == [
            ("a", 0, False),
            ("b", 0, True),
            ("a", 1, False),
            ("b", 1, False),
            ("a", 2, False),
            ("b", 2, True),
            ("b", 3, False),
            ("b", 4, False),
            ("a", 4, True),
        ]
        assert all(not m.get("partial") for m in got["other"])
        assert len([m for m in got["other"] if m["type"] == "report"]) == 9
        now[0] = 900.0  # a replay seeked back: its clock went back, and each vehicle's next is due afresh (a's: 0.47 s)
        hub.resync({"type": "snapshot"})
        await gps("a", 5)
        now[0] += 0.5
        await gps("a", 6)
        assert [(m["n"], m.get("partial", False)) for m in got["dashboard"][-2:]] == [(5, True), (6, False)]

    asyncio.run(scenario())


def test_a_report_that_waited_goes_thin_when_the_client_named_its_vehicle_meanwhile() -> None:
    """What goes out is decided when it is sent: a new page's reports wait (its window is full until its code takes
    the socket over) and its `select` comes meanwhile; they then go thin, not whole."""

    async def scenario() -> None:
        hub = Hub(window=1024, clock=lambda: 1000.0)  # the console's clock, stopped: none is due (a's at 0.47 s)
        client, sent = await held_client(hub, 1100)
        for p in ("a", "b"):
            whole = {"type": "report", "providerId": p, "topic": "GPSReport", "report": {"satellites": [1, 2]}}
            hub.publish(whole, key=(p, "GPSReport"), thin={**whole, "partial": True, "report": {"satellites": []}})
        client.select("a")
        client.ack(1)
        await asyncio.sleep(0.01)
        frames = [json.loads(t) for t in sent[1:]]
        got = {
            m["providerId"]: m.get("partial", False)
            for f in frames
            for m in (f if isinstance(f, list) else [f])
            if m["type"] == "report"
        }
        assert got == {"a": False, "b": True}

    asyncio.run(scenario())


def test_the_selected_vehicles_reports_go_ahead_of_the_fleets_and_past_the_window() -> None:
    """The fleet's reports wait for the window; the selected vehicle's go out at once, and first once it opens; a new
    selection takes its vehicle's waiting reports along, and gives the old one's back to the fleet."""

    async def scenario() -> None:
        hub = Hub(window=1024)
        client, sent = await held_client(hub, 1100)
        client.select("sel")
        await asyncio.sleep(hub_module.OTHERS_EVERY)  # each other vehicle's first report is due within a pace of its coming
        assert json.loads(sent.pop(1))["type"] == "pace"  # told with its first `select`, past the window

        def fix(p: str) -> None:
            hub.publish({"type": "report", "providerId": p, "topic": "GPSFixReport"}, key=(p, "GPSFixReport"))

        for p in ("a", "b", "sel", "c"):
            fix(p)
        await asyncio.sleep(0.01)
        assert [json.loads(t)["providerId"] for t in sent[1:]] == ["sel"]  # the window is full: only the selected's
        client.select("b")
        fix("a")
        client.ack(2)
        await asyncio.sleep(0.01)
        assert [json.loads(t)["providerId"] for t in sent[2:3]] == ["b"]
        assert [m["providerId"] for m in json.loads(sent[3])] == ["a", "c"]

    asyncio.run(scenario())


def test_a_client_that_never_acknowledges_is_dropped_once_its_unacknowledged_frames_pass_the_bound(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The selected vehicle's reports pass the window, each counted as in flight until acknowledged: a client that
    takes them and acknowledges none is dropped at MAX_UNACKED_FRAMES, one that acknowledges is not."""
    monkeypatch.setattr(hub_module, "MAX_UNACKED_FRAMES", 5)

    async def scenario() -> None:
        hub = Hub(window=1024)
        silent, sent = await held_client(hub, 10)
        acking, acked = await held_client(hub, 10)
        for c in (silent, acking):
            c.select("sel")
        for n in range(10):
            hub.publish({"type": "report", "providerId": "sel", "topic": "GPSFixReport", "n": n}, key=("sel", "GPSFixReport"))
            await asyncio.sleep(0.01)
            acking.ack(len(acked))
        assert silent.dropped and silent not in hub.clients and hub.dropped == 1
        assert len(sent) == 5  # the snapshot, its pace and three reports: the fourth report passed the bound
        assert not acking.dropped and len(acked) == 12

    asyncio.run(scenario())


def test_the_vehicles_a_client_does_not_draw_come_at_most_once_a_topic_every_quarter_second(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A selecting client gets each other vehicle's report of a topic at most once every OTHERS_EVERY, the newest (the
    ones between are replaced), and the selected vehicle's every one; a client that selects nothing gets every one."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 1.0)  # a second, so that a loaded machine sends all five within it

    async def scenario() -> None:
        hub = Hub()
        got: dict[str, list[tuple[str, int]]] = {"dashboard": [], "other": []}

        def sender(name: str) -> Callable[[str], Awaitable[None]]:
            async def send(text: str) -> None:
                if (m := json.loads(text))["type"] == "report":
                    got[name].append((m["providerId"], m["n"]))

            return send

        dashboard = hub.attach(sender("dashboard"), {"type": "snapshot"})
        hub.attach(sender("other"), {"type": "snapshot"})
        dashboard.select("sel")
        await asyncio.sleep(hub_module.OTHERS_EVERY)  # each other vehicle's first report is due within a pace of its coming
        for n in range(5):
            for p in ("fleet", "sel"):
                hub.publish({"type": "report", "providerId": p, "n": n}, key=(p, "GPSFixReport"))
            await asyncio.sleep(0.01)  # each goes before the next comes (5 in about 0.05 s)
        deadline = asyncio.get_running_loop().time() + 5
        while ("fleet", 4) not in got["dashboard"] and asyncio.get_running_loop().time() < deadline:
            await asyncio.sleep(0.01)
        assert [n for p, n in got["dashboard"] if p == "fleet"] == [0, 4]  # then the newest, when due
        assert [n for p, n in got["dashboard"] if p == "sel"] == [0, 1, 2, 3, 4]
        assert [n for p, n in got["other"] if p == "fleet"] == [0, 1, 2, 3, 4]
        assert not dashboard.later and dashboard.release is None

    asyncio.run(scenario())


def test_a_parked_report_goes_at_once_when_its_vehicle_is_selected_and_stops_with_its_socket(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Another vehicle's report parked until OTHERS_EVERY (never, here) goes at once when the client selects that
    vehicle; an ordered message is not held behind it; detaching the client cancels its release timer."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 3600.0)  # no parked report comes due during the test

    async def scenario() -> None:
        hub = Hub()
        got: list[tuple[str, object]] = []

        async def send(text: str) -> None:
            m = json.loads(text)
            got.append((m["type"], m.get("n")))

        client = hub.attach(send, {"type": "snapshot"})
        client.select("sel")
        await asyncio.sleep(0.01)
        hub.publish({"type": "report", "providerId": "fleet", "n": 0}, key=("fleet", "GPSFixReport"))
        await asyncio.sleep(0.01)
        hub.publish({"type": "report", "providerId": "fleet", "n": 1}, key=("fleet", "GPSFixReport"))
        hub.publish({"type": "alarms", "n": 9})
        await asyncio.sleep(0.01)
        # the first within a pace of the client's coming, then n 1 in its place: parked, the alarm not behind it
        assert got == [("snapshot", None), ("pace", None), ("alarms", 9)]
        assert ("fleet", "GPSFixReport") in client.later and client.release is not None
        client.select("fleet")
        await asyncio.sleep(0.01)
        assert got[-1] == ("report", 1) and not client.later
        client.select("sel")
        hub.publish({"type": "report", "providerId": "fleet", "n": 2}, key=("fleet", "GPSFixReport"))
        timer = client.release
        assert client.later and timer is not None
        hub.detach(client)
        assert timer.cancelled() and client.release is None and not client.later

    asyncio.run(scenario())


def test_a_client_whose_send_has_not_completed_for_the_bound_is_cut_whatever_waits() -> None:
    """A laptop asleep: its reports are conflated, so its queue never grows past the bound; time cuts it."""

    async def scenario() -> None:
        hub = Hub(max_queue=5, stall_seconds=0.0, cut_seconds=30.0)
        gate = asyncio.Event()

        async def send_stalled(_text: str) -> None:
            await gate.wait()

        async def send_fast(_text: str) -> None:
            return None

        fast = hub.attach(send_fast, {"type": "snapshot"})
        asleep = hub.attach(send_stalled, {"type": "snapshot"})
        hub.publish({"type": "report", "n": 1}, key=("p", "GPSFixReport"))
        await asyncio.sleep(0.01)
        assert asleep.sending_since is not None and fast.sending_since is None
        hub.sweep(asleep.sending_since + 29.0)
        assert not asleep.dropped and asleep in hub.clients
        hub.sweep(asleep.sending_since + 31.0)
        assert asleep.dropped and asleep not in hub.clients and fast in hub.clients
        assert asleep.dropped_for == "stopped reading: nothing taken for 31 s" and hub.dropped == 1
        # while the console waits for it to take its close frame, its socket may still send a select: counted once
        hub.select(asleep, "p")
        hub.sweep(asleep.sending_since + 40.0)
        assert hub.dropped == 1

    asyncio.run(scenario())


def test_a_big_snapshot_on_a_slow_link_is_given_the_time_its_size_takes_before_a_cut() -> None:
    """A send completes once the frame is nearly all out: a 200 kB snapshot on a 16 kbit/s satellite link that is still
    reading takes 100 s, and is not cut at the 30 s bound (it would be sent again on the reconnect, and cut again)."""

    async def scenario() -> None:
        hub = Hub(cut_seconds=30.0)
        gate = asyncio.Event()

        async def send_slow(_text: str) -> None:
            await gate.wait()

        snapshot = {"type": "snapshot", "pad": "x" * 200_000}
        slow = hub.attach(send_slow, snapshot)
        await asyncio.sleep(0.01)
        assert slow.sending_since is not None and slow.sending_bytes > 200_000
        hub.sweep(slow.sending_since + 31.0)
        assert not slow.dropped and slow in hub.clients
        hub.sweep(slow.sending_since + 30.0 + slow.sending_bytes / SLOWEST_LINK + 1.0)
        assert slow.dropped and slow not in hub.clients
        gate.set()

    asyncio.run(scenario())


def test_a_silence_while_the_console_is_behind_is_not_judged_until_it_keeps_up() -> None:
    links = Providers(comms_lost_timeout=1.0, regained_time=2.0)
    heard, silent = uuid.uuid4(), uuid.uuid4()
    for pid in (heard, silent):
        links.seen("GPSFixReport", pid, {"x": 1}, 0.0, 0.0, True)
    assert [e for _, e in links.tick(1.6, 1.6, behind_by=2.0)] == ["unchecked", "unchecked"]
    assert links.tick(1.8, 1.8, behind_by=2.0) == []
    links.seen("GPSFixReport", heard, {"x": 1}, 2.0, 2.0, True)
    assert [(p.id, e) for p, e in links.tick(2.1, 2.1, behind_by=2.0)] == [(heard, "live")]
    assert [(p.id, e) for p, e in links.tick(2.2, 2.2)] == [(silent, "lost")]  # kept up: its silence is its own


def test_a_silence_longer_than_the_consoles_own_delay_is_lost_however_long_the_console_stays_behind() -> None:
    """The console behind by 0.6 s at worst (a late tick now and then, each within the settle time, keeps it behind
    for good): that explains 0.6 s of a vehicle's silence, not more; a vehicle silent past it is lost, not hidden."""
    links = Providers(comms_lost_timeout=1.0, regained_time=2.0)
    pid = uuid.uuid4()
    links.seen("GPSFixReport", pid, {"x": 1}, 0.0, 0.0, True)
    assert [e for _, e in links.tick(1.5, 1.5, behind_by=0.6)] == ["unchecked"]
    assert [e for _, e in links.tick(1.7, 1.7, behind_by=0.6)] == ["lost"]
    assert links.by_id[pid].link == "lost" and links.tick(600.0, 600.0, behind_by=0.6) == []


def test_a_writer_gone_is_judged_however_far_behind_the_console_is() -> None:
    links = Providers(comms_lost_timeout=1.0, regained_time=2.0)
    pid = uuid.uuid4()
    links.seen("GPSFixReport", pid, {"x": 1}, 0.0, 0.0, True)
    links.seen("GPSFixReport", pid, None, 0.1, 0.1, False)
    assert [e for _, e in links.tick(0.2, 0.2, behind_by=60.0)] == ["lost"]


def test_the_vehicles_a_client_does_not_draw_share_a_budget_and_the_client_is_told_its_pace(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A client that named its vehicle on connect (/ws?vehicle=) gets the other vehicles' reports within a budget of
    reports a second shared by them all: each one's topic at most once a pace, the streams counted over STREAMS_EVERY
    divided by OTHERS_BUDGET, and is told that pace (with its `select`, and again when it moves); its own vehicle's
    every report; a client that names none gets every report, and no pace."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 0.05)
    monkeypatch.setattr(hub_module, "OTHERS_BUDGET", 20)  # 20 streams of the others: one report of each a second

    async def scenario() -> None:
        hub = Hub()
        got: dict[str, list[dict[str, Any]]] = {"dashboard": [], "script": []}

        def sender(name: str) -> Callable[[str], Awaitable[None]]:
            async def send(text: str) -> None:
                got[name].append(json.loads(text))

            return send

        keys = [(p, t) for p in [f"v{i}" for i in range(10)] + ["sel"] for t in ("GPSFixReport", "InertialSensorReport")]

        def publish_all(n: int) -> None:
            for p, t in keys:
                hub.publish({"type": "report", "providerId": p, "topic": t, "n": n}, key=(p, t))

        dashboard = hub.attach(sender("dashboard"), {"type": "snapshot"}, vehicle="sel")
        hub.attach(sender("script"), {"type": "snapshot"})
        publish_all(0)
        await asyncio.sleep(0.01)
        hub.sweep(100.0)
        hub.sweep(100.0 + hub_module.STREAMS_EVERY)  # 22 streams heard, 20 of them the others'
        assert dashboard.pace == 1.0
        start = asyncio.get_running_loop().time()
        n = 1
        while asyncio.get_running_loop().time() - start < 1.5:  # 20 Hz for 1.5 s
            publish_all(n)
            n += 1
            await asyncio.sleep(0.05)
        await asyncio.sleep(0.01)
        paces = [m["othersEvery"] for m in got["dashboard"] if m["type"] == "pace"]
        assert paces == [0.05, 1.0]  # told with the vehicle named on connect, and when the streams were counted
        reports = [m for m in got["dashboard"] if m["type"] == "report"]
        for key in keys:
            mine = [m["n"] for m in reports if (m["providerId"], m["topic"]) == key]
            if key[0] == "sel":
                assert mine == list(range(n))
            else:  # its first (n 0), within the first pace, then at most one a second: 1.5 s of them
                assert 1 <= len(mine) <= 3 and mine == sorted(mine), (key, mine)
        assert len(got["script"]) == 1 + len(keys) * n and all(m["type"] != "pace" for m in got["script"])

    asyncio.run(scenario())


def test_a_new_clients_first_reports_of_the_other_vehicles_are_spread_over_a_pace(monkeypatch: pytest.MonkeyPatch) -> None:
    """The snapshot has every vehicle's newest: the first report of each other vehicle's topic to a client that named
    its vehicle comes within a pace of its coming, spread by the stream, not all at once after the snapshot."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 0.5)

    async def scenario() -> None:
        hub = Hub()
        got: list[dict[str, Any]] = []

        async def send(text: str) -> None:
            got.append(json.loads(text))

        hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        for i in range(100):
            hub.publish({"type": "report", "providerId": f"v{i}", "topic": "GPSFixReport"}, key=(f"v{i}", "GPSFixReport"))
        await asyncio.sleep(0.01)
        at_once = len([m for m in got if m["type"] == "report"])
        await asyncio.sleep(0.6)
        assert at_once < 20 and len([m for m in got if m["type"] == "report"]) == 100

    asyncio.run(scenario())


def test_the_whole_gps_reports_of_the_vehicles_not_drawn_share_a_budget(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each other vehicle's whole GPSReport (its satellites: the trails) comes at most every FULL_EVERY, and every
    their count / WHOLE_BUDGET seconds of wall time: 10 vehicles at 20 a second, one every 0.5 s of each."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 0.0)
    monkeypatch.setattr(hub_module, "FULL_EVERY", 0.1)
    monkeypatch.setattr(hub_module, "WHOLE_BUDGET", 20)

    async def scenario() -> None:
        hub = Hub()
        got: list[dict[str, Any]] = []

        async def send(text: str) -> None:
            got.append({**json.loads(text), "sent": time.monotonic()})

        hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        vehicles = ["sel"] + [f"v{i}" for i in range(10)]
        rounds = 0

        async def gps() -> None:
            nonlocal rounds
            rounds += 1
            for p in vehicles:
                whole = {"type": "report", "providerId": p, "topic": "GPSReport", "n": rounds, "report": {"satellites": [1]}}
                hub.publish(whole, key=(p, "GPSReport"), thin={**whole, "partial": True, "report": {"satellites": []}})
            await asyncio.sleep(0.05)

        await gps()
        hub.sweep(0.0)
        hub.sweep(hub_module.STREAMS_EVERY)
        first, began = rounds, time.monotonic()
        while time.monotonic() - began < 2.0:
            await gps()
        whole = [m for m in got if m["type"] == "report" and not m.get("partial") and m["n"] > first]
        assert len([m for m in whole if m["providerId"] == "sel"]) == rounds - first
        for p in vehicles[1:]:
            times = [m["sent"] for m in whole if m["providerId"] == p]
            assert 3 <= len(times) <= 5 and all(b - a >= 0.5 for a, b in itertools.pairwise(times)), (p, times)

    asyncio.run(scenario())


def test_a_seek_while_a_pages_snapshot_is_in_flight_does_not_lose_its_pace() -> None:
    """A replay's seek (`resync`) clears what waits for each client; the `pace` message told with its `select` waited
    there behind the snapshot in flight: the page never learns the pace it is sent at, and judges every vehicle it does
    not draw by 3 s (at 1,000 vehicles, paced at 10 s, all 'stale' between their reports)."""

    async def scenario() -> None:
        hub = Hub()
        got: list[dict[str, Any]] = []
        gate = asyncio.Event()

        async def send(text: str) -> None:
            if not got:
                await gate.wait()  # its first snapshot (hundreds of kB) still going out
            got.append(json.loads(text))

        client = hub.attach(send, {"type": "snapshot", "n": 1}, vehicle="sel")  # /ws?vehicle=sel
        await asyncio.sleep(0.01)
        hub.resync({"type": "snapshot", "n": 2})  # another viewer of the replay seeks
        gate.set()
        await asyncio.sleep(0.05)
        assert client.selecting and [m["type"] for m in got][:2] == ["snapshot", "snapshot"]
        assert [m["othersEvery"] for m in got if m["type"] == "pace"] == [client.pace]

    asyncio.run(scenario())


def test_the_whole_gps_reports_budget_holds_in_wall_time_in_a_replay_at_20x(monkeypatch: pytest.MonkeyPatch) -> None:
    """WHOLE_BUDGET is whole GPSReports a second to a page (their bytes: 10 kB each); in a replay the hub's clock is the
    recording's (20x: 20 s of it each second), and each vehicle's whole one is due by that clock, so a page gets 20
    times the budget: at 1,000 vehicles 200 whole GPSReports (2 MB) a second, what the budget was made to stop."""
    monkeypatch.setattr(hub_module, "OTHERS_EVERY", 0.0)
    monkeypatch.setattr(hub_module, "FULL_EVERY", 1.0)
    monkeypatch.setattr(hub_module, "WHOLE_BUDGET", 2)  # 10 other vehicles: each one's whole every 5 s

    async def scenario() -> None:
        start = time.monotonic()
        hub = Hub(clock=lambda: 20 * (time.monotonic() - start))  # a replay at 20x
        got: list[dict[str, Any]] = []

        async def send(text: str) -> None:
            got.append(json.loads(text))

        hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        vehicles = ["sel"] + [f"v{i}" for i in range(10)]

        def gps() -> None:
            for p in vehicles:
                whole = {"type": "report", "providerId": p, "topic": "GPSReport", "report": {"satellites": [1]}}
                hub.publish(whole, key=(p, "GPSReport"), thin={**whole, "partial": True, "report": {"satellites": []}})

        gps()
        hub.sweep(0.0)
        hub.sweep(hub_module.STREAMS_EVERY)  # 11 vehicles with a GPSReport counted
        got.clear()
        began = time.monotonic()
        while time.monotonic() - began < 2.0:
            gps()
            await asyncio.sleep(0.05)
        wall = time.monotonic() - began
        whole = [m for m in got if m["type"] == "report" and m["providerId"] != "sel" and not m.get("partial")]
        # within the budget: 2 a second, and each vehicle's first spread over its period (at most one each)
        assert len(whole) <= hub_module.WHOLE_BUDGET * wall + 10, len(whole)

    asyncio.run(scenario())


def test_a_report_that_raises_an_alarm_is_not_held_a_pace_behind_it(monkeypatch: pytest.MonkeyPatch) -> None:
    """The console publishes a vehicle's report, then the alarm it raised (service.py: `report_changed`, then
    `_update_alarms`): the alarm, ordered, goes at once; the report of a vehicle the page does not draw waits up to its
    pace (10 s at 1,000 vehicles), so the fleet bar's chip and the vehicle list say 'INS operational' for seconds beside
    'Bravo: INS failed' in the alarms."""
    monkeypatch.setattr(hub_module, "OTHERS_BUDGET", 1)  # the others' two streams: a pace of 2 s

    async def scenario() -> None:
        hub = Hub()
        got: list[dict[str, Any]] = []

        async def send(text: str) -> None:
            got.append(json.loads(text))

        def ins(status: str) -> None:
            message = {"type": "report", "providerId": "bravo", "topic": "InertialSensorReport", "status": status}
            # as the console publishes it: unpaced when its change raised or changed an alarm (`report_changed`)
            hub.publish(message, key=("bravo", "InertialSensorReport"), unpaced=status == "FAILED")

        hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        ins("OPERATIONAL")
        hub.publish({"type": "report", "providerId": "bravo", "topic": "GPSFixReport"}, key=("bravo", "GPSFixReport"))
        hub.sweep(0.0)
        hub.sweep(hub_module.STREAMS_EVERY)
        client = next(iter(hub.clients))
        assert client.pace == 2.0
        sent = len([m for m in got if m.get("topic") == "InertialSensorReport"])
        while len([m for m in got if m.get("topic") == "InertialSensorReport"]) == sent:  # until one just went
            ins("OPERATIONAL")
            await asyncio.sleep(0.02)
        ins("FAILED")
        hub.publish({"type": "alarms", "alarms": [{"text": "bravo: INS failed"}]})
        await asyncio.sleep(0.3)
        kinds = [m.get("status") or m["type"] for m in got[-2:]]
        assert "alarms" in kinds and "FAILED" in kinds, kinds

    asyncio.run(scenario())


def test_a_client_dropped_by_the_pace_told_it_is_counted() -> None:
    """The `pace` message pushed by a `select` or a new pace (`repace`) may drop a client that stopped reading: the hub
    counts it (/api/metrics) and lets it go, as when a report or an event drops one."""

    async def scenario() -> None:
        async def send(text: str) -> None:
            await asyncio.Event().wait()  # reads nothing

        hub = Hub(max_queue=1, stall_seconds=0.0)
        client = hub.attach(send, {"type": "snapshot"}, vehicle="sel")  # its snapshot waiting, then the pace
        assert client.dropped and hub.dropped == 1 and client not in hub.clients

        hub = Hub(max_queue=2, stall_seconds=0.0)
        client = hub.attach(send, {"type": "snapshot"}, vehicle="sel")
        assert not client.dropped
        for i in range(1000):
            hub.publish({"type": "report", "providerId": f"v{i}", "topic": "GPSFixReport"}, key=(f"v{i}", "GPSFixReport"))
        hub.sweep(0.0)
        hub.sweep(hub_module.STREAMS_EVERY)  # a new pace told, behind the two it has not read
        assert client.dropped and hub.dropped == 1 and client not in hub.clients

    asyncio.run(scenario())
