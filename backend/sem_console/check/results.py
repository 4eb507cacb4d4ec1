"""Test cases, their outcomes, the selection by --only/--skip and the terminal summary."""

from __future__ import annotations

import fnmatch
import re
import signal
import time
from dataclasses import dataclass, field
from enum import Enum
from typing import TextIO


class Outcome(str, Enum):
    PASSED = "passed"
    FAILED = "failed"
    SKIPPED = "skipped"
    ERROR = "error"  # the run was stopped (SIGTERM, Ctrl-C) while the case ran: neither passed nor failed


@dataclass
class Case:
    """One test case: `name` is dotted, its first part the group (discovery, reports, commands)."""

    name: str
    outcome: Outcome = Outcome.PASSED
    reason: str = ""  # why it failed or was skipped (names the ICD section, table or figure); for a passed
    # case, what it could not check (`caveat`)
    notes: list[str] = field(default_factory=list)  # what was seen (JUnit system-out)
    seconds: float = 0.0
    profile: bool = False  # each of its failures breaks a choice of the project's QoS profile, none an ICD rule
    warnings: list[str] = field(default_factory=list)  # what differs from a reference no rule mandates (UMAA 6.0 QoS)

    @property
    def group(self) -> str:
        return self.name.split(".", 1)[0]

    def _end(self, outcome: Outcome, reason: str, after_failure: str) -> Case:
        """A failure already found stays the outcome and reason (it is usually the cause): what came after it
        becomes a note."""
        if self.outcome is Outcome.FAILED:
            self.notes.append(after_failure)
        else:
            self.outcome, self.reason = outcome, reason
        return self

    def fail(self, reason: str, profile: bool = False) -> Case:
        """`profile`: the reason is a choice of the project's QoS profile (docs/dds.md), not an ICD rule."""
        self.profile = profile and (self.profile or self.outcome is not Outcome.FAILED)
        return self._end(Outcome.FAILED, reason, f"also: {reason}")

    def skip(self, reason: str) -> Case:
        """Skipping the rest must not hide a failure."""
        return self._end(Outcome.SKIPPED, reason, f"then not tested further: {reason}")

    def stop(self, reason: str) -> Case:
        """The run was stopped while this case ran: an error, unless it had already failed."""
        return self._end(Outcome.ERROR, reason, f"then {reason}")

    def caveat(self, text: str) -> Case:
        """Part of the test could not be done (the case can still pass): shown as its reason on the
        terminal, so a pass never hides what was not checked."""
        self.notes.append(text)
        if self.outcome is Outcome.PASSED and not self.reason:
            self.reason = text
        return self

    def note(self, text: str) -> Case:
        self.notes.append(text)
        return self

    def warn(self, text: str) -> Case:
        """A difference from a reference that no rule mandates (UMAA 6.0's QoS against RTI's UMAAQoSLib): the case
        still passes; the first warning is its reason on the terminal, and the JUnit report lists them all."""
        self.warnings.append(text)
        if self.outcome is Outcome.PASSED and not self.reason:
            self.reason = f"warning: {text}"
        return self


class Stopped(BaseException):
    """SIGTERM (a CI job canceled or out of time) or SIGINT (Ctrl-C) stopped the run. A BaseException, as
    KeyboardInterrupt: the `except Exception` of a step (a reader that just left) must not swallow it."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum
        self.name = signal.Signals(signum).name


@dataclass
class Progress:
    """The cases as they finish and the one running: what a run stopped before its end reports."""

    finished: dict[str, Case] = field(default_factory=dict)
    running: Case | None = None
    since: float = 0.0  # time.monotonic() when `running` started
    doing: str = ""  # what the run does when no test case runs (`running` is then the case `setup`)

    def add(self, cases: list[Case]) -> None:
        self.finished.update((c.name, c) for c in cases)

    def setup(self, doing: str) -> None:
        """Between test cases: looking for the provider, watching its reports."""
        self.running, self.since, self.doing = Case("setup"), time.monotonic(), doing

    def stopped(self, names: list[str], signal_name: str) -> list[Case]:
        """Every selected test (`names`) as it stands: those finished as they ended, the one running (else the
        first not run) an error, the rest skipped. The case running comes first when it is not selected (`setup`,
        or a command test run for the cleanup test after it)."""
        running = self.running if self.running is not None and self.running.name not in self.finished else None
        order = names if running is None or running.name in names else [running.name, *names]
        cases = [running if running is not None and n == running.name else self.finished.get(n) or Case(n) for n in order]
        if running is not None:
            running.seconds += time.monotonic() - self.since
        unfinished = [c for c in cases if c.name not in self.finished]
        # the case running is the one stopped, wherever it is in the order (earlier cases may have ended without a
        # Timer); none running (between two cases): the first not finished
        first = running or (unfinished[0] if unfinished else None)
        for c in unfinished:
            if c is not first:
                c.skip(f"not run: the run was stopped by {signal_name}")
        if first is not None:
            doing = f"while {self.doing}, before any test ran" if first.name == "setup" else "before it finished"
            first.stop(f"stopped by {signal_name} {doing}")
        return cases


class Timer:
    """Times a case: `with Timer(case, progress): ...`; `progress` learns which case runs and which finished."""

    def __init__(self, case: Case, progress: Progress | None = None) -> None:
        self.case, self.progress = case, progress

    def __enter__(self) -> Case:
        self.start = time.monotonic()
        if self.progress is not None:
            self.progress.running, self.progress.since = self.case, self.start
        return self.case

    def __exit__(self, exc_type: type[BaseException] | None, *_exc: object) -> None:
        if self.progress is not None and exc_type is Stopped:
            return  # the case did not finish: Progress.stopped times it and reports it stopped
        self.case.seconds += time.monotonic() - self.start
        if self.progress is not None and exc_type is None:
            self.progress.add([self.case])


def matches(name: str, pattern: str) -> bool:
    """A test name matches a pattern that is the name, a dotted prefix of it (`reports`,
    `commands.GPSFix`) or a shell glob (`*.values`)."""
    return name == pattern or name.startswith(pattern + ".") or fnmatch.fnmatchcase(name, pattern)


@dataclass
class Selection:
    only: list[str] = field(default_factory=list)
    skip: list[str] = field(default_factory=list)

    def __call__(self, name: str) -> bool:
        if self.only and not any(matches(name, p) for p in self.only):
            return False
        return not any(matches(name, p) for p in self.skip)

    def unknown(self, names: list[str]) -> list[str]:
        """Patterns of --only and --skip that select no test at all (a typo would silently test nothing)."""
        return [p for p in self.only + self.skip if not any(matches(n, p) for n in names)]


def counts(cases: list[Case]) -> dict[Outcome, int]:
    return {o: sum(c.outcome is o for c in cases) for o in Outcome}


# Control characters in a reason (a vehicle's logMessage may hold a terminal colour, a bell, a newline) would
# recolour, hide or split the table's lines: shown as their escapes (ESC as \x1b), as the JUnit report shows them.
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f]")


def printable(text: str) -> str:
    return _CONTROL.sub(lambda m: repr(m.group())[1:-1], text)


_MARK = {Outcome.PASSED: "pass", Outcome.FAILED: "FAIL", Outcome.SKIPPED: "skip", Outcome.ERROR: "ERROR"}


def summary(cases: list[Case], seconds: float, out: TextIO) -> None:
    """The table on the terminal: one line per test, with its whole reason (a failure's ICD reference
    comes last: it must not be cut off), or what a passed test could not check."""
    name_w = max([len(c.name) for c in cases] + [4])
    print(f"{'TEST':<{name_w}}  {'RESULT':<6}  {'TIME':>6}  REASON", file=out)
    for c in cases:
        mark = "warn" if c.outcome is Outcome.PASSED and c.warnings else _MARK[c.outcome]
        more = f" (+{len(c.warnings) - 1} more warnings)" if c.outcome is Outcome.PASSED and len(c.warnings) > 1 else ""
        print(f"{c.name:<{name_w}}  {mark:<6}  {c.seconds:>5.1f}s  {printable(c.reason)}{more}".rstrip(), file=out)
    n = counts(cases)
    errors = f", {n[Outcome.ERROR]} stopped" if n[Outcome.ERROR] else ""
    warned = sum(1 for c in cases if c.outcome is Outcome.PASSED and c.warnings)
    warnings = f" ({warned} with warnings)" if warned else ""
    print(
        f"{len(cases)} tests: {n[Outcome.PASSED]} passed{warnings}, {n[Outcome.FAILED]} failed, {n[Outcome.SKIPPED]} skipped"
        f"{errors} in {seconds:.1f} s",
        file=out,
    )
