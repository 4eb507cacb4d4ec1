"""Figure 4 of the ICD, without a network."""

from __future__ import annotations

import pytest

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as R

from sem_console.umaa.flow import CommandFlow, check_transition

OK = R.SUCCEEDED


@pytest.mark.parametrize(
    "path",
    [
        [(S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK), (S.COMPLETED, OK)],
        [(S.ISSUED, OK), (S.FAILED, R.RESOURCE_REJECTED)],
        [(S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK), (S.FAILED, R.RESOURCE_FAILED)],
        [(S.ISSUED, OK), (S.COMMANDED, OK), (S.CANCELED, R.CANCELED)],
        [(S.FAILED, R.SERVICE_FAILED)],
    ],
)
def test_valid_paths(path: list[tuple[S, R]]) -> None:
    flow = CommandFlow()
    for status, reason in path:
        flow.observe(status, reason)
    assert flow.violations == [] and flow.terminal


@pytest.mark.parametrize(
    "prev,status,reason,needle",
    [
        (S.ISSUED, S.EXECUTING, OK, "ISSUED -> EXECUTING"),
        (None, S.COMMANDED, OK, "(no status) -> COMMANDED"),
        (S.COMPLETED, S.EXECUTING, OK, "COMPLETED -> EXECUTING"),
        (S.CANCELED, S.COMPLETED, OK, "CANCELED -> COMPLETED"),
        (S.COMMANDED, S.COMPLETED, OK, "COMMANDED -> COMPLETED"),
        (S.EXECUTING, S.FAILED, OK, "reason SUCCEEDED"),
        (S.EXECUTING, S.CANCELED, R.TIMEOUT, "reason TIMEOUT"),
        (S.ISSUED, S.COMMANDED, R.CANCELED, "reason CANCELED"),
        (None, S.FAILED, R.RESOURCE_FAILED, "reason RESOURCE_FAILED"),
    ],
)
def test_violations(prev: S | None, status: S, reason: R, needle: str) -> None:
    problem = check_transition(prev, status, reason)
    assert problem is not None and needle in problem


def test_repeat_is_not_a_transition_and_violation_is_recorded() -> None:
    flow = CommandFlow()
    assert flow.observe(S.ISSUED, OK) is not None
    assert flow.observe(S.ISSUED, OK) is None
    t = flow.observe(S.EXECUTING, OK)
    assert t is not None and t.violation
    assert flow.status is S.EXECUTING and len(flow.violations) == 1


def test_unknown_ordinals_are_violations_and_do_not_move_the_state() -> None:
    from sem_console.umaa.flow import name, parse

    flow = CommandFlow()
    flow.observe(S.ISSUED, OK)
    t = flow.observe(99, OK)
    assert t is not None and t.violation == "unknown commandStatus ordinal 99"
    t = flow.observe(S.COMMANDED, 77)
    assert t is not None and t.violation == "unknown commandStatusReason ordinal 77"
    assert flow.status is S.ISSUED
    assert flow.observe(S.COMMANDED, OK).violation is None  # type: ignore[union-attr]
    assert name(99) == "UNKNOWN(99)" and parse(S, "UNKNOWN(99)") == 99 and parse(R, "TIMEOUT") is R.TIMEOUT


def test_each_update_is_a_new_step_and_a_redelivered_one_a_repeat() -> None:
    """ISSUED/UPDATED twice in a row, stamped apart: two updates (the command was updated again before it moved on);
    the same status again (its stamp too) is a repeat."""
    from sem_console.umaa.flow import UPDATED

    f = CommandFlow()
    for i, (st, r) in enumerate([(S.ISSUED, R.SUCCEEDED), (S.COMMANDED, R.SUCCEEDED), (S.EXECUTING, R.SUCCEEDED)]):
        assert f.observe(st, r, "", 10.0 + i) is not None
    first = f.observe(S.ISSUED, UPDATED, "", 13.0)
    second = f.observe(S.ISSUED, UPDATED, "", 14.0)
    assert first is not None and second is not None and first.violation is None and second.violation is None
    assert f.observe(S.ISSUED, UPDATED, "", 14.0) is None
    assert [(t.status, t.reason) for t in f.transitions][-2:] == [(S.ISSUED, UPDATED), (S.ISSUED, UPDATED)]


def test_a_command_s_statuses_delivered_again_are_repeats_and_a_new_one_still_counts() -> None:
    """A relay that restarts writes a running command's statuses again (ISSUED, COMMANDED, EXECUTING, their own time
    stamps, older than the last's): nothing new, no violation; the command's next status is its next transition, and a
    status of a state seen before but stamped anew is one (a violation)."""
    f = CommandFlow()
    path = [(S.ISSUED, OK, 10.0), (S.COMMANDED, OK, 11.0), (S.EXECUTING, OK, 12.0)]
    for st, r, stamp in path:
        assert f.observe(st, r, "", stamp) is not None
    for st, r, stamp in path:
        assert f.observe(st, r, "", stamp) is None
    assert f.observe(S.COMPLETED, OK, "", 13.0) is not None
    assert [t.status for t in f.transitions] == [S.ISSUED, S.COMMANDED, S.EXECUTING, S.COMPLETED] and f.violations == []
    again = f.observe(S.EXECUTING, OK, "", 14.0)
    assert again is not None and again.violation is not None
    tied = CommandFlow()  # a provider repeating itself at the last status's time: a transition, not a redelivery
    for st in (S.ISSUED, S.COMMANDED, S.ISSUED):
        assert tied.observe(st, OK, "", 5.0) is not None
