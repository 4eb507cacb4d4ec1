"""One `sem-check` run: find the provider, watch its reports, run the tests, report.

Exit codes: 0 every selected test passed (skipped ones included), 1 a test failed, 2 the run could
not test (no provider within the timeout, several and no --provider, a DDS configuration Cyclone
refused, a --only/--skip that selects nothing, every selected test skipped, a --junit or --record
file that cannot be written or was not, an internal error: cli.main), 128 + the signal a run stopped by SIGTERM
(143) or SIGINT (130), which still reports what it did.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import io
import os
import secrets
import shutil
import signal
import sys
import tempfile
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO, cast

from sem_console import __version__
from sem_console.check import commands, discovery, icd, junit, profile, reports, umaa_6_0
from sem_console.check.observe import TICK, Observer
from sem_console.check.results import Case, Outcome, Progress, Selection, Stopped, summary
from sem_console.dds.bus import Bus, DdsConfigError, bus_security
from sem_console.dds.config import describe
from sem_console.dds.security import SecurityError
from sem_console.dds.topics import Sem, Sem60

SETTLE = 1.0  # s to keep looking for more providers after the first one is found

OK, FAILED, COULD_NOT_TEST = 0, 1, 2
STOPPED = 128  # + the signal's number (143 SIGTERM, 130 SIGINT), as a shell reports a job a signal ended


@dataclass
class Options:
    domain: int = 0
    provider: uuid.UUID | None = None
    commands: bool = False
    junit: str | None = None  # a file, or a directory when it ends in / (`output`)
    timeout: float = 10.0  # finding the provider; a command's first status
    only: list[str] = field(default_factory=list)
    skip: list[str] = field(default_factory=list)
    record: str | None = None  # as junit
    window: float = 5.0  # s of reports watched before they are judged (at least 2 x max_gap for the timing tests: see run)
    max_gap: float = 5.0
    clock_offset: float = 1.0
    step_time: float = 5.0
    execute_time: float = 300.0
    interface: str = "lo"
    peers: str = "127.0.0.1"
    dds_security: Path | None = None  # the identity's folder (--dds-security), else CYCLONEDDS_URI's, else an open bus
    umaa: str | None = None  # the UMAA version to test the provider as; None: the version of its topics
    security_profile: Path | None = None  # a fleet's or identity's folder: check its documents (check/profile.py), no DDS


VERSIONS = {v.name: v for v in (icd.V3_0_1, umaa_6_0.V6_0)}
UMAA_VERSIONS = list(VERSIONS)


def version_names(version: icd.Version) -> list[str]:
    """The tests of a UMAA version, in the order they run."""
    out = [discovery.name(sem) for s in version.services for sem in s.topics]
    out += [n for sem in version.reports for n in reports.names(sem)]
    return out + commands.names(version)


def all_names() -> list[str]:
    """Every test of every UMAA version and of --security-profile, each name once (`--list`; what --only and --skip
    may name)."""
    return list(dict.fromkeys([n for v in VERSIONS.values() for n in version_names(v)] + profile.NAMES))


class CouldNotTest(Exception):
    """Why the run could not test, in one line (or a line and a list)."""


def run_name(started: dt.datetime) -> str:
    """The name of a run's files in an --junit or --record directory: its start, then a random part, so runs into
    one directory keep their files, also those started in the same second (a CI matrix, a script's `&`)."""
    return f"sem-check-{started:%Y%m%dT%H%M%SZ}-{secrets.token_hex(3)}"


def output(text: str, suffix: str, name: str) -> Path:
    """The file of --junit or --record: `text`, or when it ends in / (a directory, made when missing: its parent
    must exist, as for mkdir) the file `name`.`suffix` in it (`run_name`)."""
    path = Path(text)
    if not text.endswith(("/", os.sep)):
        return path
    if not path.is_dir():
        if not path.parent.is_dir():
            raise CouldNotTest(f"{text}: the directory {path.parent} does not exist: create it first (mkdir -p {text})")
        try:
            path.mkdir(exist_ok=True)  # another run into it may make it first
        except OSError as e:
            raise CouldNotTest(f"{text}: cannot make the directory: {e.strerror}") from None
    return path / f"{name}.{suffix}"


def find_provider(observer: Observer, opts: Options, net: str) -> uuid.UUID:
    start = time.monotonic()
    deadline = start + opts.timeout
    first: float | None = None
    while True:
        observer.pump()
        found = observer.providers()
        now = time.monotonic()
        if opts.provider is not None and opts.provider in found:
            return opts.provider
        if found and first is None:
            first = now
        if opts.provider is None and first is not None and now - first >= SETTLE:
            break
        if now >= deadline:
            break
        time.sleep(TICK)
    if opts.provider is not None:
        others = f"; providers seen: {', '.join(map(str, sorted(found, key=str)))}" if found else ""
        raise CouldNotTest(
            f"provider {opts.provider} not found on domain {opts.domain} within {opts.timeout:g} s (DDS: {net}){others}"
        )
    if not found:
        # a vehicle of another vendor may be there, unreadable: say what its operator must change
        why = "".join(f"\n  {f.message}" for f in observer.peer_findings())
        raise CouldNotTest(f"no UMAA SEM provider on domain {opts.domain} within {opts.timeout:g} s (DDS: {net}){why}")
    if len(found) > 1:
        listing = "\n".join(f"  {g}  ({', '.join(_topics_of(observer, g))})" for g in sorted(found, key=str))
        raise CouldNotTest(f"{len(found)} providers on domain {opts.domain}; choose one with --provider:\n{listing}")
    return next(iter(found))


def _topics_of(observer: Observer, source: uuid.UUID) -> list[str]:
    return [icd.short(sem) for sem in [*Sem, *Sem60] if source in observer.reports.get(sem, {})] or ["no report read yet"]


class Evidence:
    """--record: the run's samples through the console's recorder, then renamed to the file asked for."""

    def __init__(self, target: Path) -> None:
        self.target = target
        self.target.parent.mkdir(parents=True, exist_ok=True)
        # An earlier run's file must not pass for this run's when this one is killed before it moves its own in place
        self.target.unlink(missing_ok=True)
        self.dir = Path(tempfile.mkdtemp(prefix=".sem-check-", dir=self.target.parent))
        from sem_console.recording.recorder import Recorder  # the recorder's modules only for --record

        try:
            self.recorder = Recorder(self.dir, max_bytes=2**62, max_seconds=1e9, queue_size=100_000)
            self.recorder.start()
        except BaseException:  # the recorder's error, or a signal: the run cannot finish() it, and must not leave it
            shutil.rmtree(self.dir, ignore_errors=True)
            raise

    def finish(self) -> str | None:
        """Close the file and move it into place; an error message, or None."""
        status = self.recorder.stop()
        try:
            files = sorted(self.dir.glob("*.mcap"))
            if status.get("error") or len(files) != 1:
                return status.get("error") or f"the recording in {self.dir} was not written"
            shutil.move(str(files[0]), self.target)
            return None
        except OSError as e:  # the target's directory went, or a directory took its name: the run still reports
            return f"cannot move it to {self.target}: {e.strerror or e}"
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)


class StopSignals:
    """SIGTERM (a CI job canceled or out of time) and SIGINT (Ctrl-C) raise Stopped in the main thread, once: a
    second signal while the run disposes its commands and writes its reports is noted, not raised (it would cut
    the recording and the reports short). A SIGINT ignored when started (a shell's background job) stays ignored."""

    SIGNALS = (signal.SIGTERM, signal.SIGINT)

    def __init__(self, err: TextIO) -> None:
        self.err = err
        self.raising = True

    def __enter__(self) -> StopSignals:
        self.previous = {s: signal.getsignal(s) for s in self.SIGNALS}
        for s in self.SIGNALS:
            if self.previous[s] is not signal.SIG_IGN:
                signal.signal(s, self._handle)
        return self

    def __exit__(self, *_exc: object) -> None:
        for s, handler in self.previous.items():
            signal.signal(s, handler)

    def hold(self) -> None:
        """From here on the run only finishes: a signal no longer stops it."""
        self.raising = False

    def _handle(self, signum: int, _frame: object) -> None:
        if not self.raising:
            print(
                f"sem-check: {signal.Signals(signum).name}: stopping already (disposing the commands sent, writing the reports)",
                file=self.err,
                flush=True,
            )
            return
        self.raising = False
        raise Stopped(signum)


class Unbroken(io.TextIOBase):
    """A stream the run prints to that a reader gone away does not stop: `sem-check ... | tee log` in a CI job that
    is canceled or out of time, where tee gets the signal too and goes first. What cannot be printed is dropped and
    the run goes on to its JUnit report and exit code; the file descriptor is pointed at /dev/null, as Python's
    documentation advises (signal, "Note on SIGPIPE"), so the interpreter's last flush does not fail either."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self.broken = False

    def write(self, text: str) -> int:
        if not self.broken:
            try:
                self.stream.write(text)
            except BrokenPipeError:
                self._gone()
        return len(text)

    def flush(self) -> None:
        if not self.broken:
            try:
                self.stream.flush()
            except BrokenPipeError:
                self._gone()

    def _gone(self) -> None:
        self.broken = True
        with contextlib.suppress(OSError, ValueError, io.UnsupportedOperation):  # a stream with no descriptor
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self.stream.fileno())
            os.close(devnull)


def run(opts: Options, out: TextIO | None = None, err: TextIO | None = None) -> int:
    out, err = cast("TextIO", Unbroken(out or sys.stdout)), cast("TextIO", Unbroken(err or sys.stderr))
    try:
        with StopSignals(err) as signals:
            return _run(opts, out, err, signals)
    finally:  # what is still buffered, now: a pipe's reader gone makes the interpreter's flush at exit fail (exit 120)
        out.flush()
        err.flush()


def _profile(
    folder: Path,
    selection: Selection,
    report: Path | None,
    properties: dict[str, str],
    started: dt.datetime,
    t0: float,
    out: TextIO,
    could_not: Callable[[str], int],
) -> int:
    """--security-profile: the documents' test cases (no DDS), reported as a run's."""
    try:
        docs = profile.documents(folder)
    except SecurityError as e:
        return could_not(str(e))
    cases = [c for c in profile.check(docs) if selection(c.name)]
    if not cases:
        return could_not("--only/--skip leaves no test of --security-profile to run (sem-check --list shows them)")
    seconds = time.monotonic() - t0
    summary(cases, seconds, out)
    if report is not None:
        try:
            junit.write(report, cases, seconds, {**properties, "security_profile": str(folder)}, started=started)
        except OSError as e:
            return could_not(f"cannot write the JUnit report {report}: {e}")
        print(f"sem-check: JUnit report {report}", file=out)
    return FAILED if any(c.outcome is Outcome.FAILED for c in cases) else OK


def _run(opts: Options, out: TextIO, err: TextIO, signals: StopSignals) -> int:
    started, t0 = dt.datetime.now(dt.UTC), time.monotonic()
    name = run_name(started)  # of its --junit and --record files in a directory: the same for both
    selection = Selection(opts.only, opts.skip)
    names = all_names()
    # the tests a stop reports: the version's once the provider is found (until then 3.0.1's, or --umaa's)
    run_names = version_names(VERSIONS[opts.umaa or icd.V3_0_1.name])
    properties = {
        "domain": str(opts.domain),
        "dds": describe(opts.interface, opts.peers),
        "commands": str(opts.commands).lower(),
        "version": __version__,
    }

    report: Path | None = None  # --junit's file, once known

    def could_not(message: str) -> int:
        print(f"sem-check: {message}", file=err, flush=True)
        if report is not None:
            try:
                junit.write(report, [], time.monotonic() - t0, properties, error=message, started=started)
            except OSError as e:
                print(f"sem-check: cannot write the JUnit report {report}: {e}", file=err)
        return COULD_NOT_TEST

    if opts.junit is not None:  # found out before a long run (or commands sent), not after it
        try:
            path = output(opts.junit, "xml", name)
        except CouldNotTest as e:
            return could_not(f"cannot write the JUnit report {e}")
        problem = junit.start(path, properties, started)
        if problem:
            print(f"sem-check: cannot write the JUnit report {path}: {problem}", file=err)
            return COULD_NOT_TEST
        report = path
    record: Path | None = None
    if opts.record is not None:
        try:
            record = output(opts.record, "mcap", name)
        except CouldNotTest as e:
            return could_not(f"cannot record to {e}")
        if record.is_dir():  # the file would be moved into it under another name
            return could_not(
                f"cannot record to {record}: it is a directory: give a file name (e.g. "
                f"{record / 'sem-check.mcap'}), or {record}/ to record into it"
            )
    unknown = selection.unknown(names)
    if unknown:
        return could_not(f"--only/--skip {', '.join(unknown)} selects no test (sem-check --list shows them)")
    if not any(selection(n) for n in names):  # each pattern selects some, but --skip takes away all --only gives
        return could_not(
            f"--only {','.join(opts.only)} --skip {','.join(opts.skip)} leaves no test to run (sem-check --list shows them)"
        )
    if opts.security_profile is not None:
        return _profile(opts.security_profile, selection, report, properties, started, t0, out, could_not)
    net = describe(opts.interface, opts.peers)
    progress = Progress()
    progress.setup("starting DDS")
    stopped: Stopped | None = None
    evidence: Evidence | None = None
    bus: Bus | None = None
    observer: Observer | None = None
    lost: str | None = None  # why the --record file was not written
    consumer: commands.Consumer | None = None
    ins_before: str | None = None  # the inertial sensor's state before the command tests
    cases: list[Case] = []
    try:
        try:
            bus = Bus(opts.domain, opts.interface, opts.peers, bus_security(opts.dds_security, opts.domain))
        except DdsConfigError as e:
            return could_not(str(e))
        if record is not None:
            from sem_console.recording.recorder import RecordingError

            try:
                evidence = Evidence(record)
            except (OSError, RecordingError) as e:
                return could_not(f"cannot record to {record}: {e}")
        observer = Observer(bus, evidence.recorder if evidence else None)
        progress.setup("looking for the provider")
        try:
            provider = find_provider(observer, opts, net)
        except CouldNotTest as e:
            return could_not(str(e))
        properties["provider"] = str(provider)
        version = VERSIONS[opts.umaa or observer.version(provider)]
        properties["umaa"] = version.name
        run_names = version_names(version)
        how = "as --umaa says" if opts.umaa else "by the topics it serves"
        print(f"sem-check: provider {provider} on domain {opts.domain} ({net}), UMAA {version.name} ({how})", file=out)
        if not any(selection(n) for n in run_names):  # the patterns name tests of the other version only
            return could_not(
                f"--only/--skip select no UMAA {version.name} test, and the provider is tested as UMAA "
                f"{version.name} ({how}): sem-check --list shows the tests of each version"
            )
        print(
            "sem-check: "
            + (
                "--commands: the command tests send commands to the provider"
                if opts.commands
                else "read-only: no command is sent (--commands runs the command tests)"
            ),
            file=out,
            flush=True,
        )
        # A gap longer than --max-gap shows for sure only in a window of twice that (a provider that
        # reports every 1.5 x max-gap may show one report mid-window, with shorter gaps either side).
        timing = any(selection(n) for n in run_names if n.startswith("reports.") and n.endswith(".timing"))
        window = max(opts.window, 2 * opts.max_gap) if timing else opts.window
        progress.setup(f"watching the provider's reports ({window:g} s)")  # before it is said: a signal may follow
        print(f"sem-check: watching its reports for {window:g} s", file=out, flush=True)
        window_start = observer.alive_sources[provider]
        observer.idle(max(0.0, window_start + window - time.time()))
        window_end = time.time()
        progress.running = None
        unclaimed = observer.unclaimed_controls()
        if unclaimed and len(observer.providers()) == 1:  # on a domain of several, whose they are is a guess
            observer.source_participants[provider] |= unclaimed
            print(
                f"sem-check: taken as the provider's, the only one on the domain: participant "
                f"{', '.join(sorted(map(str, unclaimed)))}, which writes command statuses but has sent none yet",
                file=out,
                flush=True,
            )
        offered = discovery.offered_services(observer, provider, version)
        cases += discovery.run(observer, provider, selection, progress, version)
        limits = reports.ReportLimits(window, opts.max_gap, opts.clock_offset)
        cases += reports.run(observer, provider, offered, window_start, window_end, limits, selection, progress, version)
        progress.add(cases)
        if opts.commands:
            command_limits = commands.CommandLimits(opts.timeout, opts.step_time, opts.execute_time)
            consumer = commands.Consumer(observer, provider, command_limits, out, progress, version)
            ins_before = commands.ins_state(consumer)
            lines = commands.plan(consumer, offered, selection)
            if lines:
                print(f"sem-check: sending to provider {provider}:", file=out)
                for line in lines:
                    print(f"  {line}", file=out)
                out.flush()
            cases += commands.run(consumer, offered, selection)
        else:
            reason = "read-only run: --commands sends commands (a real vehicle's INS may be switched off, or realigned)"
            cases += [Case(n).skip(reason) for n in commands.names(version) if selection(n)]
    except DdsConfigError as e:  # --commands under an identity whose permissions refuse a command writer
        return could_not(str(e))
    except Stopped as e:  # every command sent is disposed by now (commands.run)
        stopped = e
        cases = progress.stopped([n for n in run_names if selection(n)], e.name)
    finally:
        signals.hold()  # a second signal must not cut the recording short
        changed = commands.ins_changed(consumer, ins_before) if consumer is not None else None
        if evidence is not None:
            if observer is not None:  # the last samples: the disposes of the commands sent (commands.run), the
                observer.pump()  # command itself when the run was stopped right after sending it
            lost = evidence.finish()
            if lost:
                print(f"sem-check: recording not written: {lost}", file=err)
            else:
                print(f"sem-check: samples recorded in {record}", file=out)
        if bus is not None:
            bus.close()
    seconds = time.monotonic() - t0
    summary(cases, seconds, out)
    if changed:
        print(f"sem-check: warning: {changed}", file=err, flush=True)
    if stopped is not None:
        print(f"sem-check: stopped by {stopped.name}: the tests not finished are reported as such", file=err, flush=True)
    if report is not None:
        try:
            junit.write(report, cases, seconds, properties, started=started)
        except OSError as e:
            print(f"sem-check: cannot write the JUnit report {report}: {e}", file=err)
            return COULD_NOT_TEST
        print(f"sem-check: JUnit report {report}", file=out)
    if stopped is not None:
        return STOPPED + stopped.signum
    if lost:  # the evidence asked for is missing: as a report that cannot be written, not a pass
        print("sem-check: exit code 2: the recording asked for (--record) was not written (the results above stand)", file=err)
        return COULD_NOT_TEST
    if any(c.outcome is Outcome.FAILED for c in cases):
        return FAILED
    if all(c.outcome is Outcome.SKIPPED for c in cases):  # a green CI run must mean something was tested
        print("sem-check: nothing was tested: every selected test was skipped (the reasons are above)", file=err)
        return COULD_NOT_TEST
    return OK
