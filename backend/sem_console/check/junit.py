"""The JUnit XML report (`--junit FILE`), in the common layout CI servers read:

    <testsuites name tests failures errors skipped time>
      <testsuite name tests failures errors skipped time timestamp hostname>
        <properties><property name value/>...</properties>
        <testcase name classname time>
          <failure message type>details</failure> | <error message type/> | <skipped message/>
          <system-out>what was seen</system-out>
        </testcase>
      </testsuite>
    </testsuites>

A case's classname is `sem-check.<group>` and its name the rest of its dotted name, so CI
servers group the cases by discovery, reports and commands. A run that could not test (exit
code 2) is one case, `sem-check.setup`, with an <error>.
"""

from __future__ import annotations

import datetime as dt
import socket
import xml.etree.ElementTree as ET
from pathlib import Path

from sem_console.check.results import Case, Outcome, counts

SUITE = "sem-check"


def _attrs(cases: list[Case], errors: int, seconds: float) -> dict[str, str]:
    n = counts(cases)
    return {"tests": str(len(cases)), "failures": str(n[Outcome.FAILED]), "errors": str(errors),
            "skipped": str(n[Outcome.SKIPPED]), "time": f"{seconds:.3f}"}


def document(cases: list[Case], seconds: float, properties: dict[str, str], error: str | None = None,
             started: dt.datetime | None = None) -> ET.ElementTree:
    """The report of a run; `error` (could not test) makes it a single errored case."""
    if error is not None:
        cases = [Case("setup")]
    errors = 1 if error is not None else 0
    root = ET.Element("testsuites", {"name": SUITE, **_attrs(cases, errors, seconds)})
    started = started or dt.datetime.now(dt.timezone.utc)
    suite = ET.SubElement(root, "testsuite", {
        "name": SUITE, **_attrs(cases, errors, seconds),
        "timestamp": started.replace(tzinfo=None, microsecond=0).isoformat(), "hostname": socket.gethostname()})
    props = ET.SubElement(suite, "properties")
    for k, v in properties.items():
        ET.SubElement(props, "property", {"name": k, "value": v})
    for c in cases:
        group, _, rest = c.name.partition(".")
        case = ET.SubElement(suite, "testcase", {"name": rest or group, "classname": f"{SUITE}.{group}" if rest else SUITE,
                                                 "time": f"{c.seconds:.3f}"})
        if error is not None:
            ET.SubElement(case, "error", {"message": error, "type": "could-not-test"}).text = error
        elif c.outcome is Outcome.FAILED:
            ET.SubElement(case, "failure", {"message": c.reason, "type": "nonconformance"}).text = c.reason
        elif c.outcome is Outcome.SKIPPED:
            ET.SubElement(case, "skipped", {"message": c.reason})
        if c.notes:
            ET.SubElement(case, "system-out").text = "\n".join(c.notes)
    ET.indent(root)
    return ET.ElementTree(root)


def write(path: Path, cases: list[Case], seconds: float, properties: dict[str, str], error: str | None = None,
          started: dt.datetime | None = None) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    document(cases, seconds, properties, error, started).write(path, encoding="UTF-8", xml_declaration=True)
