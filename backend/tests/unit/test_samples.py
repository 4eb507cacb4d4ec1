"""make(): a generated struct from its members, absent ones None, a name that is no member refused."""

from __future__ import annotations

import pytest

from UMAA.Common.Measurement import DateTime
from UMAA.SEM.InertialSensorStatus import InertialSensorReportType

from sem_console.umaa.samples import make


def test_every_member_given() -> None:
    stamp = DateTime(seconds=1, nanoseconds=2)
    r = make(InertialSensorReportType, state=None, status=None, source=list(range(16)), timeStamp=stamp)
    assert r == InertialSensorReportType(state=None, status=None, source=list(range(16)), timeStamp=stamp)


def test_members_not_given_are_none() -> None:
    r = make(InertialSensorReportType, source=list(range(16)))
    assert r.state is None and r.status is None and r.timeStamp is None and list(r.source) == list(range(16))


@pytest.mark.parametrize("given", [{"sourc": [0] * 16}, {"state": None, "status": None, "source": [0] * 16, "timestamp": None}])
def test_a_name_that_is_no_member_is_refused(given: dict[str, object]) -> None:
    with pytest.raises(TypeError):
        make(InertialSensorReportType, **given)
