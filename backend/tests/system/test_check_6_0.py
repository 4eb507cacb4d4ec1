"""`sem-check` on UMAA 6.0 providers: a provider written from the 6.0 ICDs (icd_provider_6_0.py) with one breach at a
time, `sem-sim --umaa 6.0`'s reports, a QoS other than RTI's UMAAQoSLib (a warning), and a bus of both versions. Each
run is short (small --timeout, --step-time and --window; a breach's run selects the tests it needs)."""

from __future__ import annotations

import io
import uuid
import xml.etree.ElementTree as ET
from collections import defaultdict
from collections.abc import Callable, Iterator
from pathlib import Path
from types import SimpleNamespace
from typing import Any, cast

import pytest

from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusEnumModule import CommandStatusEnumType as Status
from UMAA_6_0.Common.MaritimeEnumeration.CommandStatusReasonEnumModule import CommandStatusReasonEnumType as Reason
from UMAA_6_0.Common.MaritimeEnumeration.InertialSensorCmdEnumModule import InertialSensorCmdEnumType as Cmd

from sem_console.check import commands, runner, umaa_6_0
from sem_console.check.observe import Report, StatusSeen
from sem_console.check.results import Case
from sem_console.dds.topics import Sem60, Service
from sem_console.sim.options import vehicle_guid
from sem_console.versions import umaa_6_0 as versions_6_0
from support.icd_provider_6_0 import IcdProvider60
from test_check import check, failed, failure_types, wait_for_providers

COMMANDS = ("--commands", "--timeout", "2", "--step-time", "1", "--window", "0.5", "--max-gap", "0.5")
V6 = runner.version_names(umaa_6_0.V6_0)
# against sem-sim (its --time-scale 0.05: an alignment in 0.6 s): a longer first wait, for its vehicle to be found
SIM_COMMANDS = ("--commands", "--timeout", "10", "--step-time", "1", "--window", "0.5", "--max-gap", "1.5")


@pytest.fixture
def provider60(domain: int) -> Iterator[Callable[..., IcdProvider60]]:
    made: list[IcdProvider60] = []

    def make(breach: str | None = None, **options: Any) -> IcdProvider60:
        made.append(IcdProvider60(domain, breach, **options))
        return made[-1]

    yield make
    for p in made:
        p.close()


def test_the_6_0_provider_passes_every_test(provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path) -> None:
    """Found as a 6.0 provider by its topics, it passes every 6.0 test, and only 6.0 tests run; its QoS is
    UMAAQoSLib's, so no warning."""
    p = provider60()
    run = check(tmp_path, "--domain", str(domain), "--provider", str(p.guid), *COMMANDS)
    assert run.code == 0, run.out + run.err
    assert run.cases == {n: ("passed", "") for n in V6}, run.out
    assert "UMAA 6.0 (by the topics it serves)" in run.out
    assert "warn" not in run.out.split("TEST", 1)[1]
    root = ET.parse(run.report).getroot()
    assert {e.get("name"): e.get("value") for e in root.iter("property")}["umaa"] == "6.0"
    update = next(tc for tc in root.iter("testcase") if tc.get("name") == "InertialSensor.update").find("system-out")
    assert update is not None and ", then ISSUED/UPDATED +" in str(update.text), ET.tostring(root)


# breach -> (--only, the test that fails, the start of its reason, the 6.0 section it names, the provider's execute time)
BREACHES: dict[str, tuple[str, str, str, str, float]] = {
    "ignore-cancel": (
        "commands.InertialSensor.cancel",
        "commands.InertialSensor.cancel",
        "the provider did not dispose its InertialSensorCommandStatusType and "
        "InertialSensorCommandAckReportType within 1 s of COMPLETED",
        "(ICD 6.0 4.1.4.5, Figure 26: CANCELED, or COMPLETED when it cannot be canceled",
        0.4,
    ),
    "silent-same-state": (
        "commands.InertialSensor.INIT,commands.InertialSensor.GPS_ALIGN,commands.InertialSensor.same",
        "commands.InertialSensor.same",
        "unanswered: no status within 2 s of sending the command",
        "ICD 6.0 4.1.4 step 3: the provider publishes ISSUED when it receives a command)",
        0.4,
    ),
    "answer-any-destination": (
        "commands.InertialSensor.INIT,commands.InertialSensor.destination",
        "commands.InertialSensor.destination",
        "the provider answered the InertialSensorCommandType addressed to ",
        "ICD 6.0 4.1: a command's destination directs it at one Service Provider",
        0.4,
    ),
    "fail-after-cleanup": (
        "commands.InertialSensor.INIT,commands.InertialSensor.cleanup",
        "commands.InertialSensor.cleanup",
        "Figure 14 breach: COMPLETED -> FAILED is not a Figure 14 transition (ICD 6.0 4.1, Figure 14)",
        ", FAILED/TIMEOUT +",
        0.4,
    ),
    "ignore-update": (
        "commands.InertialSensor.update",
        "commands.InertialSensor.update",
        "no ISSUED/UPDATED within the stated 1 s of the consumer's update of the EXECUTING command",
        "(the same source and sessionID, a newer timeStamp: ICD 6.0 4.1.4.2)",
        1.2,
    ),
    "wrong-failure-reason": (
        "commands.InertialSensor.BEST_ALIGN",
        "commands.InertialSensor.BEST_ALIGN",
        "Figure 14 breach: reason RESOURCE_REJECTED is not valid for ISSUED -> FAILED (ICD 6.0 4.1, "
        "Figure 15: INTERRUPTED, RESOURCE_FAILED, SERVICE_FAILED, TIMEOUT, VALIDATION_FAILED)",
        "ISSUED/SUCCEEDED +",
        0.4,
    ),
    "attitude-in-degrees": (
        "reports.GlobalPoseReportType.values",
        "reports.GlobalPoseReportType.values",
        "GlobalPoseReportType attitude.pitch.pitch: outside -1.5708..1.5708",
        "(SA ICD 6.0 6.4, Table 67: PitchHalfAngle)",
        0.4,
    ),
}


@pytest.mark.parametrize("breach", list(BREACHES))
def test_each_6_0_breach_fails_its_test(
    breach: str, provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """The four breaches of the 3.0.1 command tests in their 6.0 form, an update ignored, a FAILED reason Figure 15
    does not list for its transition, and a report value out of its 6.0 range: each fails its test alone, with the 6.0
    reason and section."""
    only, test, reason, section, execute = BREACHES[breach]
    p = provider60(breach, execute=execute)
    run = check(tmp_path, "--domain", str(domain), "--provider", str(p.guid), *COMMANDS, "--only", only)
    assert run.code == 1, run.out + run.err
    assert set(failed(run)) == {test}, run.out
    assert failed(run)[test].startswith(reason) and section in failed(run)[test], failed(run)[test]
    assert failure_types(run.report) == {test: "icd"}


@pytest.mark.parametrize("terminal_update", ["ignore", "fail"])
def test_an_update_that_crosses_the_end_is_ignored_or_failed(
    terminal_update: str, provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """ICD 6.0 4.1.4.2 has an update of a command in a terminal state ignored (its first paragraph) and answered FAILED
    (its step 2). A provider that reads the update sent at EXECUTING only after COMPLETED passes either way; the
    FAILED is noted with the step it follows, and the second command, updated at ISSUED, is the one tested."""
    p = provider60(execute=0.3, terminal_update=terminal_update, busy=True)
    run = check(
        tmp_path,
        "--domain",
        str(domain),
        "--provider",
        str(p.guid),
        *COMMANDS,
        "--only",
        "commands.InertialSensor.update,commands.InertialSensor.cleanup",
    )
    assert run.code == 0, run.out + run.err
    assert run.cases == {"commands.InertialSensor.update": ("passed", ""), "commands.InertialSensor.cleanup": ("passed", "")}, (
        run.out
    )
    notes = {tc.get("name"): tc.findtext("system-out") or "" for tc in ET.parse(run.report).getroot().iter("testcase")}
    assert "COMPLETED before the checker could update it" in notes["InertialSensor.update"], notes
    step_2 = (
        "FAILED/VALIDATION_FAILED after COMPLETED: the answer to the consumer's update that crossed the end of the "
        "command, as ICD 6.0 4.1.4.2 step 2 has it"
    )
    assert (step_2 in notes["InertialSensor.update"] + notes["InertialSensor.cleanup"]) == (terminal_update == "fail"), notes


def test_a_qos_other_than_umaaqoslib_is_a_warning(provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path) -> None:
    """6.0 mandates no QoS: reliable, transient-local report writers pass, each with a warning naming RTI's UMAAQoSLib
    as the reference, on the terminal and in the JUnit report (system-err), and the run exits 0."""
    p = provider60("reliable-reports")
    run = check(
        tmp_path, "--domain", str(domain), "--provider", str(p.guid), "--only", "discovery", "--timeout", "2", "--window", "0.5"
    )
    assert run.code == 0, run.out + run.err
    assert failed(run) == {}
    reports = ("discovery.GPSReportType", "discovery.GlobalPoseReportType", "discovery.InertialSensorReportType")
    lines = {line.split()[0]: line for line in run.out.splitlines() if line.startswith("discovery.")}
    for name in reports:
        assert lines[name].split()[1] == "warn", run.out
        assert (
            "RELIABLE reliability; UMAAQoSLib::TelemetryQoS has BEST_EFFORT (RTI's UMAAQoSLib, the reference "
            "sem-check compares with: UMAA 6.0 mandates no QoS)" in lines[name]
        )
    assert lines["discovery.InertialSensorCommandType"].split()[1] == "pass"
    assert "(3 with warnings)" in run.out
    err = {tc.get("name"): tc.findtext("system-err") or "" for tc in ET.parse(run.report).getroot().iter("testcase")}
    assert (
        "warning: writer " in err["GPSReportType"]
        and "TRANSIENT_LOCAL durability; UMAAQoSLib::TelemetryQoS has VOLATILE" in err["GPSReportType"]
    ), err
    assert err["InertialSensorCommandType"] == ""


def test_best_effort_statuses_are_a_warning_and_still_read(
    provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """Best-effort status and ack writers (UMAAQoSLib's CommandQoS is reliable; 6.0 mandates none) pass discovery with a
    warning naming the reference, and the checker still follows the command through them."""
    p = provider60("best-effort-statuses")
    run = check(
        tmp_path,
        "--domain",
        str(domain),
        "--provider",
        str(p.guid),
        *COMMANDS,
        "--only",
        "discovery,commands.InertialSensor.INIT",
    )
    assert run.code == 0, run.out + run.err
    assert failed(run) == {}
    lines = {line.split()[0]: line for line in run.out.splitlines() if line.startswith(("discovery.", "commands."))}
    for name in ("discovery.InertialSensorCommandStatusType", "discovery.InertialSensorCommandAckReportType"):
        assert lines[name].split()[1] == "warn", run.out
        assert "BEST_EFFORT reliability; UMAAQoSLib::CommandQoS has RELIABLE (RTI's UMAAQoSLib" in lines[name], run.out
    assert run.cases["commands.InertialSensor.INIT"] == ("passed", ""), run.out


def test_a_writer_no_reader_of_the_checker_can_match_says_why(
    provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """A GPSReportType writer of EXCLUSIVE ownership: a warning (no rule), and a failure that names the ownership, not
    the type, as what keeps the checker's readers from it."""
    p = provider60("exclusive-gps")
    run = check(
        tmp_path,
        "--domain",
        str(domain),
        "--provider",
        str(p.guid),
        "--only",
        "discovery.GPSReportType",
        "--timeout",
        "5",
        "--window",
        "0.5",
    )
    assert run.code == 1, run.out + run.err
    reason = failed(run)["discovery.GPSReportType"]
    assert reason.endswith(
        "a reader that accepts any QoS (best-effort, volatile, XCDR1 and XCDR2) did not match it (its "
        "EXCLUSIVE ownership: the checker's readers are SHARED, in the default partition)"
    ), reason


@pytest.mark.slow
def test_sem_sim_6_0_passes_every_6_0_test(sim: Callable[..., Any], domain: int, tmp_path: Path) -> None:
    """A `sem-sim --umaa 6.0` vehicle passes every 6.0 test, its InertialSensorControl flow included (each alignment,
    the update, cancel and cleanup), and only 6.0 tests run."""
    sim("--umaa", "6.0")
    wait_for_providers(domain, 1, sem=Sem60.INS_REPORT)
    run = check(tmp_path, "--domain", str(domain), *SIM_COMMANDS)
    assert run.code == 0, run.out + run.err
    assert run.cases == {n: ("passed", "") for n in V6}, run.out
    assert "UMAA 6.0 (by the topics it serves)" in run.out


@pytest.mark.slow
def test_a_mixed_sem_sim_checks_each_vehicle_in_its_version(sim: Callable[..., Any], domain: int, tmp_path: Path) -> None:
    """One `sem-sim --vehicles 2 --umaa-6-0-vehicles 2`: vehicle 1 passes every 3.0.1 test, vehicle 2 every 6.0 test,
    each found by the topics it serves."""
    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2")
    wait_for_providers(domain, 1)
    wait_for_providers(domain, 1, sem=Sem60.INS_REPORT)
    new = check(tmp_path, "--domain", str(domain), "--provider", str(vehicle_guid(2)), *SIM_COMMANDS)
    assert new.code == 0 and "UMAA 6.0 (by the topics it serves)" in new.out, new.out + new.err
    assert new.cases == {n: ("passed", "") for n in V6}, new.out
    old = check(tmp_path, "--domain", str(domain), "--provider", str(vehicle_guid(1)), *SIM_COMMANDS)
    assert old.code == 0 and "UMAA 3.0.1 (by the topics it serves)" in old.out, old.out + old.err
    assert old.cases == {n: ("passed", "") for n in runner.version_names(runner.VERSIONS["3.0.1"])}, old.out


# sem-sim fault -> the start of the reason commands.InertialSensor.GPS_ALIGN fails with, and the 6.0 section it names
SIM_FAULTS: dict[str, tuple[str, str]] = {
    "reject": ('the provider failed the command: FAILED/RESOURCE_REJECTED "resource rejected the command', "(ICD 6.0 4.1.4.4)"),
    "fail-midway": (
        'the provider failed the command: FAILED/RESOURCE_FAILED "resource failed during execution',
        "(ICD 6.0 4.1.4.4)",
    ),
    "no-answer": (
        "unanswered: no status within 5 s of sending the command",
        "ICD 6.0 4.1.4 step 3: the provider publishes ISSUED when it receives a command",
    ),
    "slow": ("no COMMANDED after ISSUED (ICD 6.0 4.1.4.1 step 2) within the stated 1 s", "ICD 6.0 4.1.4.1 step 2"),
    "skip-commanded": ("Figure 14 breach: ISSUED -> EXECUTING is not a Figure 14 transition", "(ICD 6.0 4.1, Figure 14)"),
    "ins-failure": ('the provider failed the command: FAILED/RESOURCE_FAILED "inertial sensor failure"', "(ICD 6.0 4.1.4.4)"),
}


@pytest.mark.slow
@pytest.mark.parametrize("fault", list(SIM_FAULTS))
def test_each_sem_sim_fault_fails_the_6_0_test_with_its_reason(
    fault: str, sim: Callable[..., Any], domain: int, tmp_path: Path
) -> None:
    """Each fault of `sem-sim --umaa 6.0` fails the GPS_ALIGN command test (an alignment: it runs long enough to fail
    midway) with the 6.0 reason and ICD 6.0 section; discovery and reports are not blamed. A rejection comes after
    COMMANDED, the one state Figure 15 allows RESOURCE_REJECTED after, so it is a failed command, not a breach."""
    sim("--umaa", "6.0", "--fault", fault, "--slow-factor", "200")  # slow: 5 s a step
    wait_for_providers(domain, 1, sem=Sem60.INS_REPORT)  # started: the check's own --timeout is for its discovery
    run = check(
        tmp_path,
        "--domain",
        str(domain),
        "--commands",
        "--timeout",
        "5",
        "--step-time",
        "1",
        "--window",
        "0.5",
        "--max-gap",
        "1.5",
        "--only",
        "discovery,reports,commands.InertialSensor.GPS_ALIGN",
    )
    reason, section = SIM_FAULTS[fault]
    assert run.code == 1, run.out + run.err
    assert set(failed(run)) == {"commands.InertialSensor.GPS_ALIGN"}, run.out
    got = failed(run)["commands.InertialSensor.GPS_ALIGN"]
    assert got.startswith(reason) and section in got, got
    if fault == "reject":  # after COMMANDED, where Figure 15 allows RESOURCE_REJECTED: no breach of the flow
        assert "breach" not in got, got
    assert failure_types(run.report) == {"commands.InertialSensor.GPS_ALIGN": "icd"}


@pytest.mark.slow
def test_a_mixed_bus_checks_each_provider_in_its_version(
    sim: Callable[..., Any], provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """A 3.0.1 `sem-sim` vehicle and a 6.0 provider on one domain: both are listed, and each passes in its own version;
    --umaa forces a version (the 6.0 provider tested as 3.0.1 offers none of its services: nothing tested, exit 2)."""
    sim()
    (three,) = wait_for_providers(domain, 1)
    p = provider60()
    several = check(tmp_path, "--domain", str(domain), "--timeout", "20", "--only", "discovery")
    assert several.code == 2 and str(p.guid) in several.err and str(three) in several.err, several.err
    old = check(
        tmp_path,
        "--domain",
        str(domain),
        "--provider",
        str(three),
        "--only",
        "discovery,reports",
        "--window",
        "0.5",
        "--max-gap",
        "1.5",
    )
    assert old.code == 0 and "UMAA 3.0.1 (by the topics it serves)" in old.out, old.out
    assert set(old.cases) == set(runner.version_names(runner.VERSIONS["3.0.1"])) - set(commands.names()), old.out
    # the gap bound of the 3.0.1 run above: beside a simulator, on a loaded machine, the in-process provider's reports
    # paused 0.53 s once (the test is of the versions, not of its timing)
    new = check(tmp_path, "--domain", str(domain), "--provider", str(p.guid), *COMMANDS[:-1], "1.5")
    assert new.code == 0 and new.cases == {n: ("passed", "") for n in V6}, new.out
    forced = check(
        tmp_path,
        "--domain",
        str(domain),
        "--provider",
        str(p.guid),
        "--umaa",
        "3.0.1",
        "--only",
        "discovery,reports",
        "--window",
        "0.5",
    )
    assert forced.code == 2 and "UMAA 3.0.1 (as --umaa says)" in forced.out, forced.out + forced.err
    assert {o for o, _ in forced.cases.values()} == {"skipped"}


def test_only_tests_of_the_other_version_is_one_clear_line(
    provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """--only naming 3.0.1 tests only, on a 6.0 provider: nothing to test, said as such (exit 2), not as skipped tests."""
    p = provider60()
    run = check(tmp_path, "--domain", str(domain), "--provider", str(p.guid), "--only", "commands.GPSFix", "--window", "0.5")
    assert run.code == 2, run.out + run.err
    assert run.err.strip().splitlines()[-1] == (
        "sem-check: --only/--skip select no UMAA 6.0 test, and the provider is tested as UMAA 6.0 (by the topics it "
        "serves): sem-check --list shows the tests of each version"
    ), run.err


def test_a_6_0_run_that_leaves_the_sensor_unaligned_says_so(
    provider60: Callable[..., IcdProvider60], domain: int, tmp_path: Path
) -> None:
    """INIT alone leaves a GPS-aligned sensor initializing: the plan says so before anything is sent, and the run ends
    with a warning naming the command that sets it back."""
    p = provider60()
    run = check(tmp_path, "--domain", str(domain), "--provider", str(p.guid), *COMMANDS, "--only", "commands.InertialSensor.INIT")
    assert run.code == 0, run.out + run.err
    assert "InertialSensorCommandType: INIT (the inertial sensor is left initializing)" in run.out
    assert (
        "sem-check: warning: the inertial sensor reports INIT now; it reported FINE_GPS_ALIGNMENT_COMPLETE before the "
        "InertialSensor commands: command GPS_ALIGN to set it back"
    ) in run.err


def test_6_0_satellites_are_bounded_at_300() -> None:
    """The decoder keeps a 6.0 report's satellites up to its type's bound, 300, and says how many came past it: 300 are
    within 6.0's bound, 301 are not (ICD 6.0 5.1.1.1, Table 9)."""
    sats = [{"azimuth": 0.0, "elevation": 0.1, "carrierFrequency": 1.5e9, "satelliteID": 1.0, "usedInFix": False}] * 300
    body = {"satellites": sats, "numberSatellitesInView": 300, "clock": {}, "source": {"parentID": None}}

    def problems(invalid: list[str]) -> list[str]:
        found = [umaa_6_0.decoder_finding(p) for p in invalid]
        found += umaa_6_0.gps_values(body, Report(0.0, body, invalid, True, 0), None)
        return [p for p in found if p]

    assert problems([]) == []
    assert problems(["satellites: 301 elements, more than 300; the first 300 kept"]) == [
        "satellites: 301 elements, more than 300 (ICD 6.0 5.1.1.1, Table 9: max size = 300)"
    ]


def test_each_6_0_breach_of_a_command_fails_its_test_once() -> None:
    """An ISSUED/UPDATED the consumer did not cause, after a Figure 14 breach already reported, is reported in its turn,
    and the earlier breach is not reported again."""
    statuses: dict[uuid.UUID, list[StatusSeen]] = defaultdict(list)
    observer = SimpleNamespace(statuses=statuses, acks={})  # what Consumer.update reads of the bus
    provider, session = uuid.uuid4(), uuid.uuid4()
    consumer = commands.Consumer(
        cast(Any, observer), provider, commands.CommandLimits(1, 1, 1), io.StringIO(), version=umaa_6_0.V6_0
    )
    sample = consumer.commanding(Service.INERTIAL_SENSOR).build(consumer.source, provider, session, Cmd.GPS_ALIGN.name, (1, 0))
    sent = commands.Sent(Service.INERTIAL_SENSOR, session, sample, 0.0, provider, umaa_6_0.V6_0, "InertialSensorCommandType")
    case = Case("commands.InertialSensor.GPS_ALIGN")

    def publish(status: Status, reason: Reason) -> None:
        status_type = Sem60.INS_COMMAND_STATUS.spec.type
        statuses[session].append(
            StatusSeen(
                len(statuses[session]),
                provider,
                status_type(
                    timeStamp=sample.timeStamp,
                    source=versions_6_0.identifier(provider),
                    sessionID=session.bytes,
                    commandStatus=status,
                    commandStatusReason=reason,
                    logMessage="",
                ),
            )
        )
        consumer.update(sent)
        commands.breaches(sent, case)

    publish(Status.ISSUED, Reason.SUCCEEDED)
    publish(Status.EXECUTING, Reason.SUCCEEDED)
    publish(Status.ISSUED, Reason.UPDATED)
    assert case.reason.startswith("Figure 14 breach: ISSUED -> EXECUTING is not a Figure 14 transition"), case.reason
    also = [n for n in case.notes if n.startswith("also: ")]
    assert len(also) == 1 and also[0].startswith(
        "also: Figure 14 breach: ISSUED/UPDATED after ISSUED/SUCCEEDED +0.00 s, "
        "EXECUTING/SUCCEEDED +1.00 s, though the consumer did not update the "
        "command (ICD 6.0 4.1.4.2"
    ), also
