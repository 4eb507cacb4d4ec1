"""Figure 4 of the ICD, without a network."""

from __future__ import annotations

import pytest

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S
from UMAA.Common.MaritimeEnumeration.CommandStatusReasonEnumType import CommandStatusReasonEnumType as R

from sem_console.umaa.flow import CommandFlow, check_transition

OK = R.SUCCEEDED


@pytest.mark.parametrize("path", [
    [(S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK), (S.COMPLETED, OK)],
    [(S.ISSUED, OK), (S.FAILED, R.RESOURCE_REJECTED)],
    [(S.ISSUED, OK), (S.COMMANDED, OK), (S.EXECUTING, OK), (S.FAILED, R.RESOURCE_FAILED)],
    [(S.ISSUED, OK), (S.COMMANDED, OK), (S.CANCELED, R.CANCELED)],
    [(S.FAILED, R.SERVICE_FAILED)],
])
def test_valid_paths(path: list[tuple[S, R]]) -> None:
    flow = CommandFlow()
    for status, reason in path:
        flow.observe(status, reason)
    assert flow.violations == [] and flow.terminal


@pytest.mark.parametrize("prev,status,reason,needle", [
    (S.ISSUED, S.EXECUTING, OK, "ISSUED -> EXECUTING"),
    (None, S.COMMANDED, OK, "(no status) -> COMMANDED"),
    (S.COMPLETED, S.EXECUTING, OK, "COMPLETED -> EXECUTING"),
    (S.CANCELED, S.COMPLETED, OK, "CANCELED -> COMPLETED"),
    (S.COMMANDED, S.COMPLETED, OK, "COMMANDED -> COMPLETED"),
    (S.EXECUTING, S.FAILED, OK, "reason SUCCEEDED"),
    (S.EXECUTING, S.CANCELED, R.TIMEOUT, "reason TIMEOUT"),
    (S.ISSUED, S.COMMANDED, R.CANCELED, "reason CANCELED"),
    (None, S.FAILED, R.RESOURCE_FAILED, "reason RESOURCE_FAILED"),
])
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
