"""Whether the console is the one behind (console/load.py), on made-up delays."""

from __future__ import annotations

from sem_console.console.load import BEHIND_AFTER, Load


def test_behind_from_a_late_tick_until_it_has_kept_up_for_the_settle_time() -> None:
    load = Load(settle=3.0, wall=lambda: 1000.0)
    assert not load.tick(0.01, 10.0) and not load.behind
    assert load.tick(2.5, 12.5) and load.behind and load.behind_since == 1000.0
    load.handled(0.2, 13.0)
    assert not load.tick(0.01, 15.4) and load.behind  # 2.9 s since the last late one
    assert load.worst == 2.5
    assert load.tick(0.01, 15.6) and not load.behind and load.worst == 0.0
    assert load.state()["vehiclesNotChecked"] == 0


def test_a_sample_handled_late_makes_it_behind_and_a_delay_under_the_bound_does_not() -> None:
    load = Load(settle=1.0)
    load.handled(BEHIND_AFTER * 0.9, 1.0)
    assert not load.tick(0.0, 1.1)
    load.handled(BEHIND_AFTER + 0.1, 2.0)
    assert load.tick(0.0, 2.1) and load.behind
    assert load.state()["ingestLagMs"] == round((BEHIND_AFTER + 0.1) * 1000, 1)


def test_the_silence_its_delays_excuse_is_of_the_last_settle_time_not_of_the_whole_episode() -> None:
    """A wall clock stepped an hour between a take and its handling (a lag of 3600 s, once), then the console stays
    behind by 0.7 s: after the settle time the hour no longer excuses a vehicle's silence, 0.7 s does."""
    load = Load(settle=3.0)
    assert load.excuse(10.0) is None
    load.handled(3600.0, 10.0)
    assert load.tick(0.0, 10.1) and load.excuse(10.1) == 3600.0
    for t in (11.0, 12.0, 13.0, 14.0):
        load.handled(0.7, t)
        assert not load.tick(0.0, t + 0.1)
    assert load.behind and load.worst == 3600.0  # its words: the worst of the episode
    assert load.excuse(14.1) == 0.7
    assert load.tick(0.0, 17.1) and not load.behind and load.excuse(17.1) is None
