"""A vehicle seen through a relay (console/hops.py): its age and its loss from its own time stamps, not from arrival;
a relay's link age from its samples; a vehicle lost with its relay told apart from one lost alone."""

from __future__ import annotations

import uuid

import pytest

from sem_console.console.alarms import lost_with_relay, relay_silent_text
from sem_console.console.hops import Hops, relay_silent_after, silent_relays
from sem_console.console.providers import Providers, report_stamp
from sem_console.core.messages import ReportEnvelope
from sem_console.dds.hops import NEVER, RelayLink

T0 = 1_800_000_000.0
A, B = uuid.uuid4(), uuid.uuid4()


def envelope(stamp: float, at: float) -> ReportEnvelope:
    seconds = int(stamp)
    return {
        "report": {"timeStamp": {"seconds": seconds, "nanoseconds": round((stamp - seconds) * 1e9)}},
        "invalid": [],
        "receivedAt": at,
    }


def test_a_report_s_own_time_stamp_is_read_in_utc_seconds() -> None:
    assert report_stamp({"timeStamp": {"seconds": 10, "nanoseconds": 500_000_000}}) == 10.5
    assert report_stamp({"timeStamp": None}) is None and report_stamp({}) is None
    assert report_stamp({"timeStamp": {"seconds": "10"}}) is None


def test_old_samples_released_late_by_a_relay_do_not_make_a_lost_vehicle_live() -> None:
    """Samples arriving every 0.5 s, each 30 s old by the vehicle's time stamp (a relay releasing what it held): a
    vehicle seen through the relay is lost and stays lost; the same arrivals of a vehicle heard directly keep it live."""
    links = Providers(comms_lost_timeout=5.0, regained_time=1.0)
    for t in (0.0, 0.5):
        links.seen("GPSFixReport", A, envelope(T0 + t, T0 + t), t, T0 + t, True)
        links.seen("GPSFixReport", B, envelope(T0 + t, T0 + t), t, T0 + t, True)
    links.by_id[A].relay = "ship-1"
    assert links.tick(1.0, T0 + 1.0) == []
    t = 10.0
    links.tick(t, T0 + t)
    assert links.by_id[A].link == "lost" and links.by_id[B].link == "lost"
    while t < 20.0:  # the held samples come, old
        links.seen("GPSFixReport", A, envelope(T0 + t - 30, T0 + t), t, T0 + t, True)
        links.seen("GPSFixReport", B, envelope(T0 + t - 30, T0 + t), t, T0 + t, True)
        links.tick(t, T0 + t)
        t += 0.5
    assert links.by_id[A].link == "lost"  # by its time stamps: silent for 30 s
    assert links.by_id[B].link != "lost"  # heard directly: by arrival
    assert links.by_id[A].summary(t, T0 + t)["relay"] == {
        "name": "ship-1",
        "dataTime": T0 + 0.5,
        "ageSeconds": t - 0.5,
        "quietSeconds": 0.0,
    }
    assert links.by_id[B].summary(t, T0 + t)["relay"] is None
    while t < 22.0:  # current samples again: regained after the regained time
        links.seen("GPSFixReport", A, envelope(T0 + t - 0.2, T0 + t), t, T0 + t, True)
        links.tick(t, T0 + t)
        t += 0.5
    assert links.by_id[A].link in ("regained", "live")
    assert links.by_id[A].summary(t, T0 + t)["relay"]["ageSeconds"] == 0.7  # type: ignore[index]


def test_a_relay_s_link_age_is_counted_on_the_console_s_clock_from_its_sample() -> None:
    hops = Hops()
    assert hops.seen(RelayLink("ship-1", [str(A), str(B), "not-a-guid"], 1400), T0) == {A, B}
    hop = hops.of(A)
    assert hop is not None and hop.data_at == T0 - 1.4 and round(hop.age(T0 + 1.0) or 0, 6) == 2.4
    assert hops.seen(RelayLink("ship-1", [str(A), str(B)], 200), T0 + 1) == set()  # the same relay: nothing changed
    assert hops.seen(RelayLink("ship-2", [str(B)], NEVER), T0 + 1) == {B}  # B moved to another relay
    assert hops.of(B) is not None and hops.by_relay["ship-2"].data_at is None
    assert [h.relay for h in silent_relays(hops.by_relay, T0 + 3.5, 3.0)] == []  # its last data 2.7 s old
    assert [h.relay for h in silent_relays(hops.by_relay, T0 + 5.0, 3.0)] == ["ship-1"]  # 4.2 s (ship-2: no data yet)


def test_a_vehicle_lost_with_its_relay_is_the_relay_s_alarm_one_lost_alone_its_own() -> None:
    links = Providers(comms_lost_timeout=5.0, regained_time=1.0)
    links.seen("GPSFixReport", A, envelope(T0, T0), 0.0, T0, True)
    p = links.by_id[A]
    hops = Hops()
    hops.seen(RelayLink("ship-1", [str(A), str(B)], 0), T0 + 0.5)  # data over the link at T0 + 0.5
    p.relay = "ship-1"
    assert lost_with_relay(p, hops.by_relay, T0 + 20, 10.0)  # nothing came over the link since A went silent
    hops.seen(RelayLink("ship-1", [str(A), str(B)], 0), T0 + 6.0)  # B's data still comes after A was lost (T0 + 5)
    assert not lost_with_relay(p, hops.by_relay, T0 + 20, 10.0)
    p.relay = None
    assert not lost_with_relay(p, hops.by_relay, T0 + 20, 10.0)  # heard directly: lost alone


def test_the_relay_s_alarm_names_it_and_counts_its_vehicles() -> None:
    assert relay_silent_text("ship-1", 12) == "relay ship-1 silent: 12 vehicles"
    assert relay_silent_text("ship-1", 1) == "relay ship-1 silent: 1 vehicle"


def test_a_vehicle_lost_under_a_relay_that_carried_no_data_yet_is_its_own_loss() -> None:
    """An operations side's relay just restarted says its relay carried no data yet (NEVER): that relay is never
    silent, so a vehicle lost under it must raise its own link-lost, or nothing would say it."""
    links = Providers(comms_lost_timeout=5.0, regained_time=1.0)
    links.seen("GPSFixReport", A, envelope(T0, T0), 0.0, T0, True)
    p = links.by_id[A]
    p.relay = "ship-1"
    hops = Hops()
    hops.seen(RelayLink("ship-1", [str(A)], NEVER), T0 + 20)
    assert silent_relays(hops.by_relay, T0 + 30, 10.0) == []
    assert not lost_with_relay(p, hops.by_relay, T0 + 30, 10.0)


def test_a_relayed_vehicle_s_clock_apart_from_the_console_s_neither_loses_it_while_heard_nor_keeps_it_when_silent() -> None:
    """Vehicles seen through a relay, their reports arriving fresh every 0.5 s for 20 s: one's clock an hour behind the
    console's, one's an hour ahead, one's jumping an hour ahead midway, and one with a single bad time stamp far in the
    future. Each is live while heard
    and lost a comms-lost timeout after it goes silent, as the same vehicle with the console's clock."""
    links = Providers(comms_lost_timeout=5.0, regained_time=1.0)
    skews = {uuid.uuid4(): lambda t: -3600.0, uuid.uuid4(): lambda t: 3600.0, uuid.uuid4(): lambda t: 3600.0 * (t > 10)}
    bad = uuid.uuid4()
    t = 0.0
    while t < 20.0:
        for v, skew in skews.items():
            links.seen("GPSFixReport", v, envelope(T0 + t - 0.2 + skew(t), T0 + t), t, T0 + t, True)
        links.seen("GPSFixReport", bad, envelope(T0 + t - 0.2 + (1e9 if t == 1.0 else 0), T0 + t), t, T0 + t, True)
        for p in links.by_id.values():
            p.relay = "ship-1"
        links.tick(t, T0 + t)
        assert {p.link for p in links.by_id.values()} == {"live"}, t
        t += 0.5
    links.tick(24.0, T0 + 24.0)  # silent for 4.5 s
    assert {p.link for p in links.by_id.values()} == {"live"}
    links.tick(26.0, T0 + 26.0)  # silent for 6.5 s
    assert {p.link for p in links.by_id.values()} == {"lost"}
    hops = Hops()  # the relay's link quiet since their last data: each is lost with it, whatever its clock
    hops.seen(RelayLink("ship-1", [str(v) for v in links.by_id], 6500), T0 + 26.0)
    assert all(lost_with_relay(p, hops.by_relay, T0 + 26.0, 5.0) for p in links.by_id.values())


def test_a_relay_s_sample_naming_a_vehicle_that_is_not_a_guid_is_one_warning_not_one_a_second(
    caplog: pytest.LogCaptureFixture,
) -> None:
    hops = Hops()
    for t in range(5):  # a relay's samples, once a second
        assert hops.seen(RelayLink("ship-1", [str(A), "not-a-guid"], 0), T0 + t) == ({A} if t == 0 else set())
    assert [r.getMessage() for r in caplog.records] == ["relay ship-1 names a vehicle that is not a GUID: 'not-a-guid'"]


def test_vehicles_moved_to_another_relay_leave_their_old_relay_which_is_then_silent_about_none() -> None:
    """Both vehicles of ship-1 now come through ship-2: the operations side's relay writes no more samples of ship-1
    (it carries none), so the console must not keep calling ship-1 silent with them."""
    hops = Hops()
    hops.seen(RelayLink("ship-1", [str(A), str(B)], 0), T0)
    assert hops.seen(RelayLink("ship-2", [str(A), str(B)], 0), T0 + 19) == {A, B}
    assert hops.by_relay["ship-1"].vehicles == frozenset()
    assert [h.relay for h in silent_relays(hops.by_relay, T0 + 20, 10.0)] == []


def test_a_vehicle_behind_the_satellite_caps_is_not_lost_between_its_capped_reports_but_is_when_silent() -> None:
    """At the satellite caps a relayed vehicle's fix comes every 5 s: with the console's 3 s comms-lost timeout alone
    it went lost and regained at every fix. Its relay says how long its data may be quiet by the caps (quietMs), and
    the console adds it: lost only once silent for 3 + 5 s; a vehicle heard directly keeps the 3 s."""
    hops = Hops()
    hops.seen(RelayLink("ship-1", [str(A)], 0, [5000]), T0)
    hop = hops.of(A)
    assert hop is not None and hop.quiet == {A: 5.0}
    links = Providers(comms_lost_timeout=3.0, regained_time=1.0)
    events = []
    for step in range(301):  # 30 s in steps of 0.1 s: a fix every 5 s, each 0.6 s on its way
        t = step / 10
        if step % 50 == 6:
            for v in (A, B):
                links.seen("GPSFixReport", v, envelope(T0 + t - 0.6, T0 + t), t, T0 + t, True)
            links.by_id[A].relay, links.by_id[A].quiet = "ship-1", hop.quiet[A]
        events += [(e, p.id) for p, e in links.tick(t, T0 + t)]
    assert [e for e, pid in events if pid == A] == []  # never lost between its capped reports
    assert ("lost", B) in events  # the same arrivals heard directly: lost at 3 s, as before
    last = 25.6  # its last fix, made at 25.0 and received then: its data counts from 25.6 on the console's clock
    for t in (last + 7.0, last + 7.9):  # within 3 + 5 s
        assert [e for p, e in links.tick(t, T0 + t) if p.id == A] == []
    t = last + 8.1
    assert [e for p, e in links.tick(t, T0 + t) if p.id == A] == ["lost"]


def test_a_relay_whose_caps_keep_its_vehicles_quiet_is_silent_only_past_that_quiet() -> None:
    hops = Hops()
    hops.seen(RelayLink("ship-1", [str(A), str(B)], 0, [5000, 60000]), T0)
    hops.seen(RelayLink("ship-2", [str(uuid.uuid4())], 0), T0)  # an earlier relay: no quiet said
    assert [h.relay for h in silent_relays(hops.by_relay, T0 + 62.0, 3.0)] == ["ship-2"]
    assert [h.relay for h in silent_relays(hops.by_relay, T0 + 63.5, 3.0)] == ["ship-1", "ship-2"]


def test_a_lost_vehicle_behind_the_satellite_caps_is_regained_with_a_regained_time_longer_than_the_timeout() -> None:
    """A relayed vehicle back after a loss, its fixes every 5 s by the caps (quiet 5 s), its regained time 6 s: its
    samples are continuous by its lost_after (3 + 5 s), so it is regained about 6 s after it is heard again; a gap
    between two capped fixes longer than the bare 3 s timeout must not start the regaining again at every fix."""
    links = Providers(comms_lost_timeout=3.0, regained_time=6.0)
    links.seen("GPSFixReport", A, envelope(T0, T0 + 0.6), 0.6, T0 + 0.6, True)
    links.by_id[A].relay, links.by_id[A].quiet = "ship-1", 5.0
    events = [e for p, e in links.tick(20.0, T0 + 20.0) if p.id == A]
    assert events == ["lost"]
    for step in range(200, 601):  # from 20 s to 60 s in steps of 0.1 s: a fix every 5 s again, each 0.6 s on its way
        t = step / 10
        if step % 50 == 6:
            links.seen("GPSFixReport", A, envelope(T0 + t - 0.6, T0 + t), t, T0 + t, True)
        events += [e for p, e in links.tick(t, T0 + t) if p.id == A]
    assert "regained" in events, events


def test_a_vehicle_lost_with_its_relay_is_said_by_some_alarm_whatever_the_quiet_of_the_relay_s_other_vehicles() -> None:
    """A relay carrying a 3.0.1 vehicle (quiet 5 s) and a 6.0 one whose caps keep it quiet 30 s (`--caps
    GlobalPoseReport=30`): its link goes at T0 + 10. The 3.0.1 vehicle is lost 3 + 5 s after its last data, with its
    relay (no link-lost of its own); the relay's alarm must then say it, not 25 s later."""
    hops = Hops()
    links = Providers(comms_lost_timeout=3.0, regained_time=1.0)
    for t in (0.0, 5.0, 10.0):  # its capped fixes, the last as the link goes
        links.seen("GPSFixReport", A, envelope(T0 + t, T0 + t + 0.2), t + 0.2, T0 + t + 0.2, True)
    hops.seen(RelayLink("ship-1", [str(A), str(B)], 0, [5000, 30000]), T0 + 10.2)
    p = links.by_id[A]
    p.relay, p.quiet = "ship-1", 5.0
    t = 10.2 + 8.5
    assert [e for q, e in links.tick(t, T0 + t) if q.id == A] == ["lost"]
    after = relay_silent_after(3.0)
    said_by_relay = [h.relay for h in silent_relays(hops.by_relay, T0 + t, after)] == ["ship-1"]
    said_by_vehicle = not lost_with_relay(p, hops.by_relay, T0 + t, after)
    assert said_by_relay or said_by_vehicle, "a lost vehicle that no alarm says"


def test_vehicles_lost_as_their_relay_s_link_goes_wait_for_the_relay_s_alarm_rather_than_say_their_own() -> None:
    """A LAN-class relay (no caps: no quiet) and the console's 3 s timeout: the link goes, and each vehicle is lost 3 s
    after its last data, a moment before the relay is silent by its own last data (which came just after the
    vehicles', and which the console learns from the relay's samples, once a second). The relay's one alarm says it:
    no link-lost per vehicle in between (a run under load raised both, and the watch read three alarms for one
    cause)."""
    hops = Hops()
    links = Providers(comms_lost_timeout=3.0, regained_time=1.0)
    for v in (A, B):
        links.seen("GPSFixReport", v, envelope(T0 + 10.0, T0 + 10.1), 10.1, T0 + 10.1, True)
    hops.seen(RelayLink("ship-1", [str(A), str(B)], 0, [0, 0]), T0 + 10.6)  # data over the link up to then
    after = relay_silent_after(3.0)
    for p in links.by_id.values():
        p.relay = "ship-1"
    for step in range(132, 200):  # from 13.2 s, each vehicle lost, to 20 s
        t = step / 10
        links.tick(t, T0 + t)
        assert {p.link for p in links.by_id.values()} == {"lost"}, t
        relay_said = bool(silent_relays(hops.by_relay, T0 + t, after))
        assert all(lost_with_relay(p, hops.by_relay, T0 + t, after) for p in links.by_id.values()), t
        assert relay_said == (t > 13.6), t  # its alarm comes half a second later: no vehicle's own meanwhile
