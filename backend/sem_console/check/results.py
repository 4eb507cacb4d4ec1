"""Test cases, their outcomes, the selection by --only/--skip and the terminal summary."""

from __future__ import annotations

import fnmatch
import time
from dataclasses import dataclass, field
from enum import Enum
from typing import TextIO


class Outcome(str, Enum):
    PASSED = "passed"
    FAILED = "failed"
    SKIPPED = "skipped"


@dataclass
class Case:
    """One test case: `name` is dotted, its first part the group (discovery, reports, commands)."""

    name: str
    outcome: Outcome = Outcome.PASSED
    reason: str = ""  # why it failed or was skipped (names the ICD section, table or figure); for a passed
    # case, what it could not check (`caveat`)
    notes: list[str] = field(default_factory=list)  # what was seen (JUnit system-out)
    seconds: float = 0.0

    @property
    def group(self) -> str:
        return self.name.split(".", 1)[0]

    def fail(self, reason: str) -> Case:
        """The first failure stays the reason (later ones become notes): it is usually the cause."""
        if self.outcome is Outcome.FAILED:
            self.notes.append(f"also: {reason}")
        else:
            self.outcome, self.reason = Outcome.FAILED, reason
        return self

    def skip(self, reason: str) -> Case:
        """A failure already found stays the outcome: skipping the rest must not hide it."""
        if self.outcome is Outcome.FAILED:
            self.notes.append(f"then not tested further: {reason}")
        else:
            self.outcome, self.reason = Outcome.SKIPPED, reason
        return self

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


class Timer:
    """Times a case: `with Timer(case): ...`."""

    def __init__(self, case: Case) -> None:
        self.case = case

    def __enter__(self) -> Case:
        self.start = time.monotonic()
        return self.case

    def __exit__(self, *_exc: object) -> None:
        self.case.seconds += time.monotonic() - self.start


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


_MARK = {Outcome.PASSED: "pass", Outcome.FAILED: "FAIL", Outcome.SKIPPED: "skip"}


def summary(cases: list[Case], seconds: float, out: TextIO) -> None:
    """The table on the terminal: one line per test, with its whole reason (a failure's ICD reference
    comes last: it must not be cut off), or what a passed test could not check."""
    name_w = max([len(c.name) for c in cases] + [4])
    print(f"{'TEST':<{name_w}}  {'RESULT':<6}  {'TIME':>6}  REASON", file=out)
    for c in cases:
        print(f"{c.name:<{name_w}}  {_MARK[c.outcome]:<6}  {c.seconds:>5.1f}s  {c.reason}".rstrip(), file=out)
    n = counts(cases)
    print(f"{len(cases)} tests: {n[Outcome.PASSED]} passed, {n[Outcome.FAILED]} failed, {n[Outcome.SKIPPED]} skipped "
          f"in {seconds:.1f} s", file=out)
