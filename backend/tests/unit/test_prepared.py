"""sem-sim's prepared reports (sim/prepared.py): the bytes a layout packs are the bytes cyclonedds serialises, for
every report type of both UMAA versions in both encodings, and a sample of another shape is not packed by it."""

from __future__ import annotations

import copy
import enum
import random
from dataclasses import fields, is_dataclass, replace
from typing import Any

import pytest

from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import Sem, Sem60
from sem_console.sim.options import SimOptions, vehicle_guid
from sem_console.sim.prepared import Layout
from sem_console.sim.reports import Sensors
from support.samplegen import random_sample

REPORTS = [sem for sem in [*Sem, *Sem60] if sem.spec.cls is TopicClass.REPORT]


def _cyclone(sample: Any, v2: bool) -> bytes:
    data: bytes = sample.serialize(use_version_2=v2)
    return data.ljust((len(data) + 3) & ~3, b"\0")


def _bounded(sample: Any) -> Any:
    if getattr(sample, "satellites", None):  # a few hundred satellites would take a layout seconds to learn
        sample.satellites = sample.satellites[:12]
    return sample


def _redrawn(value: Any, rng: random.Random) -> Any:
    """The same shape (strings, absent members, sequence lengths) with every value member drawn again, the awkward
    values among them (NaN, infinities, -0.0, the ends of the 32-bit range)."""
    if is_dataclass(value) and not isinstance(value, type):
        return replace(value, **{f.name: _redrawn(getattr(value, f.name), rng) for f in fields(value)})
    if isinstance(value, list):
        return [_redrawn(v, rng) for v in value]
    if isinstance(value, bool):
        return rng.random() < 0.5
    if isinstance(value, enum.Enum):
        return rng.choice(list(type(value)))
    if isinstance(value, int):
        return rng.choice([0, 2**31 - 1, -(2**31), rng.randrange(-(2**31), 2**31)]) if value < 0 else rng.randrange(2**31)
    if isinstance(value, float):
        return rng.choice([float("nan"), float("inf"), -float("inf"), -0.0, rng.uniform(-1e6, 1e6)])
    if isinstance(value, bytes):
        return rng.randbytes(len(value))
    return value


@pytest.mark.parametrize("v2", [True, False])
@pytest.mark.parametrize("sem", REPORTS, ids=lambda s: s.name)
def test_a_layout_packs_what_cyclonedds_serialises(sem: Any, v2: bool) -> None:
    rng = random.Random(f"{sem.name}{v2}")
    for _ in range(12):
        sample = _bounded(random_sample(sem.spec.type, rng))
        layout = Layout(sample, v2)
        assert layout.encode(sample) == _cyclone(sample, v2)
        for _ in range(4):  # the same shape, other values
            same = _redrawn(sample, rng)
            assert layout.encode(same) == _cyclone(same, v2)


@pytest.mark.parametrize("umaa", ["3.0.1", "6.0"])
def test_the_simulators_reports_pack_as_cyclonedds_serialises_them(umaa: str) -> None:
    """A vehicle's reports over a minute of its time: one layout per shape, each packing every later report."""
    from sem_console.sim.umaa_6_0 import global_pose, gps_report, ins_report

    opts = SimOptions(umaa=umaa, fix_rate=1, gps_rate=1, ins_rate=1)  # type: ignore[arg-type]
    sensors = Sensors(opts, 1, vehicle_guid(1), set())
    layouts: dict[str, list[Layout]] = {}
    written: list[Any] = []

    def write(sem: Any, sample: Any) -> None:
        if umaa == "6.0":
            convert = {Sem.GPS_REPORT: gps_report, Sem.GPS_FIX_REPORT: global_pose, Sem.INS_REPORT: lambda r: ins_report(r, {})}
            if sem not in convert:
                return
            sample = convert[sem](sample)
        written.append(sample)

    for second in range(60):
        now = sensors.t0 + second
        sensors.surfacing = second > 20
        sensors.step(now)
        sensors.publish(now, write)
    for sample in written:
        mine = layouts.setdefault(type(sample).__name__, [])
        data = next((d for d in (layout.encode(sample) for layout in mine) if d is not None), None)
        if data is None:
            mine.append(Layout(sample, True))
            data = mine[-1].encode(sample)
        assert data == _cyclone(sample, True)
    assert sum(len(x) for x in layouts.values()) < len(written) / 4  # most reports packed by a layout made before


def test_a_sample_of_another_shape_is_not_packed() -> None:
    rng = random.Random(3)
    sample = random_sample(Sem.GPS_FIX_STATUS_REPORT.spec.type, rng, absent=0.0)
    sample.carrierToNoise = [30.0, 31.0]
    layout = Layout(sample, True)
    longer = copy.deepcopy(sample)
    longer.carrierToNoise = [30.0, 31.0, 32.0]
    assert layout.encode(longer) is None
    absent = copy.deepcopy(sample)
    absent.timeOut = None
    assert layout.encode(absent) is None
    wrong = copy.deepcopy(sample)
    wrong.fixValid = 1  # not a boolean: cyclonedds, not the layout, says what it makes of it
    assert layout.encode(wrong) is None


@pytest.mark.parametrize("v2", [True, False])
def test_every_change_of_shape_is_refused(v2: bool) -> None:
    """A layout holds its strings, lengths, presences and value types as constants: a sample that differs in any of
    them is not packed by it (PreparedWriter then serialises it by cyclonedds)."""
    rng = random.Random(5)
    sample = random_sample(Sem.GPS_REPORT.spec.type, rng, absent=0.0)
    while len(sample.satellites) < 3:
        sample = random_sample(Sem.GPS_REPORT.spec.type, rng, absent=0.0)
    sample.satellites = sample.satellites[:3]
    sample.clock.referenceCodeTypeFor = "GPS_L1"
    layout = Layout(sample, v2)
    assert layout.encode(copy.deepcopy(sample)) == _cyclone(sample, v2)
    changes: dict[str, Any] = {
        "a string of another length": lambda s: setattr(s.clock, "referenceCodeTypeFor", "GPS_L1CA"),
        "another string of the same length": lambda s: setattr(s.clock, "referenceCodeTypeFor", "GPS_L5"),
        "an enumeration given as its number": lambda s: setattr(s.clock, "referenceConstellationType", 1),
        "a GUID of another length": lambda s: setattr(s, "source", bytes(s.source) + b"\0"),
        "a boolean given as a number": lambda s: setattr(s.satellites[0], "usedInFix", 1),
        "one satellite fewer": lambda s: s.satellites.pop(),
    }
    for what, change in changes.items():
        other = copy.deepcopy(sample)
        change(other)
        assert layout.encode(other) is None, what
