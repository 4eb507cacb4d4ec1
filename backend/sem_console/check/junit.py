"""The JUnit XML report (`--junit FILE`), in the common layout CI servers read:

    <testsuites name tests failures errors time>
      <testsuite name tests failures errors skipped time timestamp hostname>
        <properties><property name value/>...</properties>
        <testcase name classname time>
          <failure message type="icd|profile">reason, then what was seen</failure>
            | <error message type>..</error> | <skipped message/>
          <system-out>what was seen (passed and skipped cases)</system-out>
          <system-err>warning: ... (one line per warning: a UMAA 6.0 QoS that differs from RTI's UMAAQoSLib)</system-err>
        </testcase>
      </testsuite>
    </testsuites>

(<testsuites> carries no `skipped`: the common schema, Jenkins xUnit's junit-10.xsd, does not
allow it there.) A case's classname is `sem-check.<group>` and its name the rest of its dotted
name, so CI servers group the cases by discovery, reports and commands. A failure's message is
its one-line reason and its text the reason followed by what was seen (the status sequence, the
other problems), which is what a CI's test view shows under the failure; its type is `icd` when a failure of the case
breaks an ICD 3.0.1 rule and `profile` when each breaks a choice of the project's QoS profile (docs/dds.md:
reliability, durability, ownership, partition, deadline, data representation), which the ICD
leaves open (the common schema has no properties per test case; the type is what CIs show). A UMAA 6.0
provider's QoS is compared with RTI's UMAAQoSLib, since 6.0 mandates none: a difference is a warning, not a failure,
one `warning: ...` line each in the case's <system-err>, which CIs show beside a passed test. A run that could not
test (exit code 2) is one case, `sem-check.setup`, with an <error>: the first line as its
message, the whole message (e.g. the list of providers to choose from) as its text. A run stopped
by SIGTERM or SIGINT lists every selected test: those finished as they ended, the one running with
an <error type="stopped"> (`sem-check.setup` when no test had started), the rest <skipped>.
"""

from __future__ import annotations

import datetime as dt
import re
import socket
import xml.etree.ElementTree as ET
from pathlib import Path

from sem_console.check.results import Case, Outcome, counts

SUITE = "sem-check"
# What XML 1.0 cannot hold (control characters but tab and newline, lone surrogates): a vehicle's logMessage, type
# or participant name may carry them, and ElementTree writes them as they are, which no CI's parser then reads.
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def _xml_safe(text: str) -> str:
    """`text` with each character XML cannot hold shown as its Python escape (ESC as \\x1b)."""
    return _NOT_XML.sub(lambda m: repr(m.group())[1:-1], text)


def _attrs(cases: list[Case], error: bool, seconds: float, skipped: bool = True) -> dict[str, str]:
    n = counts(cases)
    return {
        "tests": str(len(cases)),
        "failures": str(n[Outcome.FAILED]),
        "errors": str(n[Outcome.ERROR] + error),
        **({"skipped": str(n[Outcome.SKIPPED])} if skipped else {}),
        "time": f"{seconds:.3f}",
    }


def document(
    cases: list[Case], seconds: float, properties: dict[str, str], error: str | None = None, started: dt.datetime | None = None
) -> ET.ElementTree:
    """The report of a run; `error` (could not test) makes it a single errored case."""
    if error is not None:
        cases = [Case("setup")]
    root = ET.Element("testsuites", {"name": SUITE, **_attrs(cases, error is not None, seconds, skipped=False)})
    started = started or dt.datetime.now(dt.UTC)
    suite = ET.SubElement(
        root,
        "testsuite",
        {
            "name": SUITE,
            **_attrs(cases, error is not None, seconds),
            "timestamp": started.replace(tzinfo=None, microsecond=0).isoformat(),
            "hostname": socket.gethostname(),
        },
    )
    props = ET.SubElement(suite, "properties")
    for k, v in properties.items():
        ET.SubElement(props, "property", {"name": k, "value": v})
    for c in cases:
        group, _, rest = c.name.partition(".")
        case = ET.SubElement(
            suite,
            "testcase",
            {"name": rest or group, "classname": f"{SUITE}.{group}" if rest else SUITE, "time": f"{c.seconds:.3f}"},
        )
        if error is not None:
            ET.SubElement(case, "error", {"message": error.splitlines()[0], "type": "could-not-test"}).text = error
        elif c.outcome is Outcome.FAILED:
            ET.SubElement(case, "failure", {"message": c.reason, "type": "profile" if c.profile else "icd"}).text = "\n".join(
                [c.reason, *c.notes]
            )
        elif c.outcome is Outcome.SKIPPED:
            ET.SubElement(case, "skipped", {"message": c.reason})
        elif c.outcome is Outcome.ERROR:
            ET.SubElement(case, "error", {"message": c.reason, "type": "stopped"}).text = "\n".join([c.reason, *c.notes])
        if c.notes and c.outcome not in (Outcome.FAILED, Outcome.ERROR):
            ET.SubElement(case, "system-out").text = "\n".join(c.notes)
        if c.warnings:  # a difference from a reference no rule mandates (UMAA 6.0 QoS): the case still passes
            ET.SubElement(case, "system-err").text = "\n".join(f"warning: {w}" for w in c.warnings)
    for el in root.iter():
        el.attrib = {k: _xml_safe(v) for k, v in el.attrib.items()}
        el.text = el.text and _xml_safe(el.text)
    ET.indent(root)
    return ET.ElementTree(root)


UNFINISHED = (
    "sem-check did not finish: it was killed (SIGKILL, out of memory) or crashed before it wrote its "
    "results; this report was written when it started"
)


def start(path: Path, properties: dict[str, str], started: dt.datetime) -> str | None:
    """Before the run: write the report of a run that did not finish in `path`, which the run's own report
    replaces; why it cannot be written (None: it can). A run killed outright (a CI's SIGKILL after its grace
    time) leaves that report, not an earlier run's, which a runner that keeps its workspace would show as this
    run's. Written, not asked of the permission bits, which do not tell root on /proc, NFS or FUSE."""
    if path.is_dir():
        return "it is a directory"
    try:
        write(path, [], 0.0, properties, error=UNFINISHED, started=started)
    except OSError as e:
        return e.strerror or str(e)
    return None


def write(
    path: Path,
    cases: list[Case],
    seconds: float,
    properties: dict[str, str],
    error: str | None = None,
    started: dt.datetime | None = None,
) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    document(cases, seconds, properties, error, started).write(path, encoding="UTF-8", xml_declaration=True)
