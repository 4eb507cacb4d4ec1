"""Report tests, two per report topic:

- `reports.<Topic>.timing`: reports arrive (none for longer than `max_gap`), each timeStamp is a
  valid DateTime, never goes back for one writer, and is within `clock_offset` of the checker's
  clock on arrival (the first sample of a writer may be older: its transient-local history);
- `reports.<Topic>.values`: every value within its ICD range, enum ordinals the ICD lists, GUIDs
  RFC 4122, optional members well-formed when present, and the satellite counts consistent.

Only what a consumer on the project's QoS profile received counts (observe.py). The ranges and enum checks of
the console's decoder (codec/convert.py) apply, with the stricter ones of the ICD added here. A UMAA 6.0
provider's reports (GPSReportType, GlobalPoseReportType, InertialSensorReportType) are judged by the 6.0 ICDs'
rules (`umaa_6_0.py`), each finding naming its 6.0 section.
"""

from __future__ import annotations

import math
import re
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise
from typing import Any

from sem_console.check import icd
from sem_console.check.observe import Observer, Report
from sem_console.check.results import Case, Progress, Timer
from sem_console.check.values import in_range, satellite_counts
from sem_console.dds.topics import AnySem, Sem

MAX_PROBLEMS = 5  # kinds of problem quoted per case; the rest are counted
MAX_VALUES = 3  # values quoted per kind of problem


@dataclass
class ReportLimits:
    window: float  # s the reports were watched for
    max_gap: float  # s a provider may go without a report of a topic
    clock_offset: float  # s a timeStamp may differ from the checker's clock on arrival


def names(sem: AnySem) -> tuple[str, str]:
    return f"reports.{icd.short(sem)}.timing", f"reports.{icd.short(sem)}.values"


# Where the ICD has the rules of the timing test (UMAA 6.0's: umaa_6_0.TIMING_REFS)
TIMING_REFS = {
    "stamp": "ICD 5.2.1, Table 21",
    "datetime": "ICD 5.2.6, Table 26; Table 45",
    "utc": "ICD 5.2.6",
    "publish": "ICD 4.2.1",
    "update": "ICD 4.2.1.1",
    "seconds": "seconds >= 0, ",
}


def stamp(body: dict[str, Any], refs: dict[str, str] = TIMING_REFS) -> tuple[float | None, tuple[str, str] | None]:
    """The report's timeStamp in seconds, or what makes it no DateTime (ICD 5.2.6, Table 26): its kind, and the
    sample's own text (its values differ from sample to sample; the kind does not)."""
    ts = body.get("timeStamp") or {}
    s, ns = ts.get("seconds"), ts.get("nanoseconds")
    if not isinstance(s, int) or not isinstance(ns, int):
        return None, ("missing", f"timeStamp missing or unreadable ({refs['stamp']}: every report has its timeStamp)")
    if (s < 0 and refs["seconds"]) or not 0 <= ns <= 999_999_999:
        return None, (
            "no DateTime",
            f"timeStamp {s} s {ns} ns is not a DateTime ({refs['seconds']}nanoseconds 0..999999999: {refs['datetime']})",
        )
    return s + ns / 1e9, None


def check_timing(
    sem: AnySem,
    samples: list[Report],
    start: float,
    end: float,
    limits: ReportLimits,
    case: Case,
    version: icd.Version = icd.V3_0_1,
) -> None:
    refs = dict(version.timing or TIMING_REFS)
    topic = icd.short(sem)
    live = [r for r in samples if r.alive and r.body is not None]
    if any(not r.alive for r in samples):
        case.note(f"the provider disposed its {topic} (or its writer left) during the run")
    if not live:
        case.fail(
            f"no {topic} from the provider within {end - start:.1f} s ({refs['publish']}: the provider publishes its reports)"
        )
        return
    arrivals = [start] + [r.received for r in live if r.received <= end] + [end]
    gap = max(b - a for a, b in pairwise(arrivals))
    rate = (len(arrivals) - 2) / max(end - start, 1e-9)
    offsets: list[float] = []
    last: dict[int, float] = {}
    # Each kind of problem once, with its worst and how many samples had it: a vehicle whose clock is off has it in
    # every sample, and a line per sample buried the report (thousands of lines in a long window).
    problems: dict[str, list[float]] = {}
    unreadable: dict[str, str] = {}  # a bad timeStamp's kind -> the first such sample's text
    for r in live:
        t, bad = stamp(r.body or {}, refs)
        if bad:
            kind, text = bad
            unreadable.setdefault(kind, text)
            problems.setdefault(kind, []).append(0.0)
            continue
        assert t is not None
        offset = t - r.received
        if r.writer in last and t < last[r.writer]:
            problems.setdefault("went back", []).append(last[r.writer] - t)
        first = r.writer not in last
        last[r.writer] = t
        if offset > limits.clock_offset or (not first and offset < -limits.clock_offset):
            problems.setdefault("offset", []).append(offset)
        if not first:
            offsets.append(offset)
    for kind, seen in problems.items():
        times = f" ({len(seen)} of {len(live)} samples)" if len(seen) > 1 else ""
        if kind == "went back":
            case.fail(
                f"{topic} timeStamp went back {max(seen):.3f} s{times} ({refs['stamp'].split(',')[0]}: the time the "
                "data was derived)"
            )
        elif kind == "offset":
            worst = max(seen, key=abs)
            case.fail(
                f"{topic} timeStamp {worst:+.3f} s from the checker's clock on arrival{times}, beyond the stated "
                f"{limits.clock_offset:g} s ({refs['utc']}: UTC)"
            )
        else:
            case.fail(f"{topic} {unreadable[kind]}{times}")
    if gap > limits.max_gap:
        case.fail(
            f"no {topic} for {gap:.2f} s, more than the stated {limits.max_gap:g} s ({rate:.2f} reports/s; "
            f"{refs['update']}: the provider publishes its updated reports)"
        )
    spread = f", timeStamp {min(offsets):+.3f}..{max(offsets):+.3f} s from the checker's clock" if offsets else ""
    case.note(f"{len(live)} {topic} samples, {rate:.2f}/s over {end - start:.1f} s, longest gap {gap:.2f} s{spread}")


# a sequence cut by the decoder (codec/convert.py): at the console's cap when the IDL leaves it unbounded, else at its bound
_SEQUENCE_REFS = {
    "satellites": "ICD 5.1.3.1, Table 14: satellites in view, more than every GNSS constellation has",
    "carrierToNoise": "ICD 5.1.2.2, Table 12; the IDL bounds it: sequence<double, 11>",
}


def _icd_ref(problem: str) -> str:
    if "unknown" in problem and "ordinal" in problem:
        return f"{problem} (ICD 5.3)"
    if "elements, more than" in problem:
        return f"{problem} ({_SEQUENCE_REFS.get(problem.split(':')[0], 'ICD 5.4')})"
    return f"{problem} (ICD 5.4, Table 45)"


def _guid_problem(text: Any, path: str) -> str | None:
    if text is None:
        return None
    try:
        g = uuid.UUID(str(text))
    except ValueError:
        return f"{path}: {text!r} is not a GUID"
    if g.variant != uuid.RFC_4122:
        return f"{path}: {g} is not an RFC 4122 GUID (variant 2: ICD 3.7, Table 45 NumericGUID)"
    return None


def _gps_report(b: dict[str, Any], _r: Report, _limits: ReportLimits) -> list[str | None]:
    sats = b.get("satellites") or []
    out: list[str | None] = [satellite_counts(b, "ICD 5.1.3.1, Table 14")]
    for i, s in enumerate(sats):
        if not s:
            continue
        p = f"satellites[{i}]"
        out.append(in_range(s.get("azimuth"), -math.pi, math.pi, f"{p}.azimuth", "ICD 5.4, Table 45: Angle is -pi..pi"))
        out.append(
            in_range(s.get("carrierFrequency"), 0, 1e10, f"{p}.carrierFrequency", "ICD 5.4, Table 45: RadioFrequency_Hertz")
        )
        out.append(_guid_problem(s.get("satelliteId"), f"{p}.satelliteId"))
    clock = b.get("clock") or {}
    out.append(
        in_range(
            clock.get("referenceCarrierFrequency"),
            0,
            1e10,
            "clock.referenceCarrierFrequency",
            "ICD 5.4, Table 45: RadioFrequency_Hertz",
        )
    )
    return out


def _fix_status(b: dict[str, Any], _r: Report, _limits: ReportLimits) -> list[str | None]:
    # carrierToNoise is a sequence<Size_Numeral> (Table 12), "nonnegative", -1e12..1e12 (Table 45); the 0..1e6 dB-Hz
    # of CarrierToNoiseDensityRatio is the satellites' C/N0 type, checked by the decoder.
    cn0 = b.get("carrierToNoise") or []
    return [
        in_range(v, 0, 1e12, f"carrierToNoise[{i}]", "ICD 5.1.2.2, Table 12; Table 45: Size_Numeral, nonnegative")
        for i, v in enumerate(cn0)
    ]


def _fix(b: dict[str, Any], r: Report, limits: ReportLimits) -> list[str | None]:
    t = (b.get("position2DWithTime") or {}).get("timeAtPosition")
    if isinstance(t, (int, float)) and t - r.received > limits.clock_offset:
        return [f"position2DWithTime.timeAtPosition is {t - r.received:.1f} s in the future (ICD 5.2.14, Table 34)"]
    if isinstance(t, (int, float)) and t < 0:
        return [f"position2DWithTime.timeAtPosition {t} is before the epoch (ICD 5.2.14, Table 34)"]
    return []


_MORE: dict[Sem, Callable[[dict[str, Any], Report, ReportLimits], list[str | None]]] = {
    Sem.GPS_REPORT: _gps_report,
    Sem.GPS_FIX_STATUS_REPORT: _fix_status,
    Sem.GPS_FIX_REPORT: _fix,
}


def _source_problem(source: Any) -> str | None:
    """The report's source: a NumericGUID (3.0.1), or UMAA 6.0's IdentifierType, whose `id` is one."""
    if isinstance(source, dict):
        return _guid_problem(source.get("id"), "source.id")
    return _guid_problem(source, "source")


def check_values(sem: AnySem, samples: list[Report], limits: ReportLimits, case: Case, version: icd.Version = icd.V3_0_1) -> None:
    topic = icd.short(sem)
    live = [r for r in samples if r.alive and r.body is not None]
    if not live:
        case.fail(f"no {topic} from the provider to check (see reports.{topic}.timing)")
        return
    problems: list[str] = []
    bad_samples = 0
    for r in live:
        assert r.body is not None
        finding = version.decoder_finding or _icd_ref
        found: list[str | None] = [finding(p) for p in r.invalid]
        found.append(_source_problem(r.body.get("source")))
        extra = _MORE.get(sem) if isinstance(sem, Sem) else version.value_checks.get(sem)
        if extra is not None:
            found += extra(r.body, r, limits)
        kept = [p for p in found if p]
        bad_samples += bool(kept)
        problems += kept
    if problems:
        listed = group(problems)
        case.fail(f"{topic} {listed[0]}")
        for p in listed[1:MAX_PROBLEMS]:
            case.note(f"also: {p}")
        more = len(listed) - MAX_PROBLEMS
        case.note(f"{bad_samples} of {len(live)} samples had problems" + (f"; {more} more kinds not listed" if more > 0 else ""))
    else:
        case.note(f"{len(live)} {topic} samples, every value within the ICD")


# A problem's text is "path: value rest" or "path: unknown <enum> ordinal value rest" (codec/convert.py, in_range,
# _guid_problem): its kind is the path without its indices and the rest, the same for every sample that has it.
_INDEX = re.compile(r"\[\d+\]")
_VALUE_FIRST = re.compile(r"(?P<path>[^:]+): (?P<value>\S+) (?P<rest>(?:outside|is not|elements,) .*)")
_VALUE_LAST = re.compile(r"(?P<path>[^:]+): (?P<head>unknown \w+ ordinal) (?P<value>\S+)(?P<rest>.*)")


def _kind(problem: str) -> tuple[str, str, str]:
    """(kind, what the line says of the kind, the value of this occurrence) of a problem; its ICD reference stays
    last in what the line says."""
    m = _VALUE_FIRST.fullmatch(problem)
    if m is not None:
        path, value, said = m["path"], m["value"], m["rest"]
    elif (m := _VALUE_LAST.fullmatch(problem)) is not None:
        path, value, said = m["path"], m["value"], m["head"] + m["rest"]
    else:
        kind = _INDEX.sub("[]", problem)
        return kind, kind, ""
    general = _INDEX.sub("[]", path)
    kind = f"{general}: {said}"
    return kind, kind, value if general == path else f"{path} {value}"


def group(problems: list[str]) -> list[str]:
    """One line per kind of problem, in the order first seen: a problem seen once as it is, a repeated one with how
    often and its first values (an angle in degrees was a line for each satellite of each sample, hundreds)."""
    kinds: dict[str, tuple[str, list[str], dict[str, None], str]] = {}  # kind -> (says, occurrences, values, first)
    for p in problems:
        kind, says, value = _kind(p)
        entry = kinds.setdefault(kind, (says, [], {}, p))
        entry[1].append(p)
        if value:
            entry[2].setdefault(value, None)
    lines = []
    for says, seen, values, first in kinds.values():
        if len(seen) == 1:
            lines.append(first)
            continue
        head, ref = says, ""
        if says.endswith(")") and " (" in says:  # the ICD reference, which stays last
            at = says.rindex(" (")
            head, ref = says[:at], says[at:]
        shown = list(values)[:MAX_VALUES]
        more = ", …" if len(values) > MAX_VALUES else ""
        example = f": {', '.join(shown)}{more}" if shown else ""
        lines.append(f"{head}, {len(seen)} times{example}{ref}")
    return lines


def run(
    observer: Observer,
    provider: uuid.UUID,
    offered: set[str],
    start: float,
    end: float,
    limits: ReportLimits,
    selected: Callable[[str], bool],
    progress: Progress | None = None,
    version: icd.Version = icd.V3_0_1,
) -> list[Case]:
    cases = []
    undecodable = observer.decoder.undecodable
    for sem in version.reports:
        service = version.service_of[sem].name
        samples = observer.reports.get(sem, {}).get(provider, [])
        for test, check in zip(names(sem), ("timing", "values"), strict=True):
            if not selected(test):
                continue
            case = Case(test)
            with Timer(case, progress):
                if service not in offered and not samples:
                    case.skip(f"the provider does not offer the {service} service")
                elif check == "timing":
                    check_timing(sem, samples, start, end, limits, case, version)
                else:
                    if undecodable.get(sem.spec.name):
                        case.note(
                            f"{undecodable[sem.spec.name]} {icd.short(sem)} samples on the bus (any provider) could "
                            f"not be decoded as the {version.idl} type"
                        )
                    check_values(sem, samples, limits, case, version)
            cases.append(case)
    return cases
