"""Test fixtures: a fresh DDS domain per test on loopback, and real `sem-sim` processes."""

from __future__ import annotations

import contextlib
import itertools
import json
import os
import random
import signal
import socket
import ssl
import subprocess
import tarfile
import time
import uuid
from collections import deque
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from sem_console.dds.bus import Bus
from sem_console.dds.config import MAX_PARTICIPANT_INDEX
from support import http, warm
from support.consumer import Consumer
from support.domains import domain_free, udp_free

pytest_plugins = ["support.pg"]  # a real PostgreSQL server: the pg_cluster, pg_url and database_url fixtures

# Tests run on loopback whatever the shell says; those about CYCLONEDDS_URI set it themselves.
os.environ.pop("CYCLONEDDS_URI", None)

# pytest-xdist's workers (scripts/test runs pytest with -n): each takes the domain ids of its own residue
# class, so two workers never pick the same domain; without xdist, one worker with every id.
_WORKERS = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
# a worker that replaces a crashed one is numbered past the count (gw3 of 3): it takes the crashed one's class
_WORKER = int(os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw")) % _WORKERS
# Two sessions side by side (scripts/test's main pass and its DDS Security pass): each is told the classes of both
# (SEM_TEST_CLASSES) and its first (SEM_TEST_CLASS_BASE), so that no worker of one shares a class with the other's
_CLASSES = int(os.environ.get("SEM_TEST_CLASSES", str(_WORKERS)))
_CLASS = int(os.environ.get("SEM_TEST_CLASS_BASE", "0")) + _WORKER
if not 0 <= _CLASS < _CLASSES:
    raise pytest.UsageError(
        f"SEM_TEST_CLASS_BASE + this worker's number ({_CLASS}) is not below SEM_TEST_CLASSES ({_CLASSES}): "
        "give SEM_TEST_CLASSES the workers of every session that runs beside this one"
    )
# Cyclone's domain ids go to 232, but near the top the unicast discovery ports of loopback's higher participant
# indexes (7410 + 250 d + 2 i) pass 65535 ("ddsi_udp_conn_write to udp/127.0.0.1:65536 failed" on 232)
# 200..230 are the Playwright stack's (e2e/stack.ts), which runs beside pytest: a domain checked free by both at
# the same moment, before either's participant binds it, would mix a test's vehicles into the dashboard's
_OWN_DOMAINS = [d for d in range(1, 200) if (d - 1) % _CLASSES == _CLASS]
# A random start per run, then a new domain per test; a domain a participant on this host is in (another run's, or
# a process of an earlier test still there: `support.domains`) is skipped, so runs and tests never see each other.
_domains = (
    _OWN_DOMAINS[k % len(_OWN_DOMAINS)]
    for k in itertools.count(random.Random(os.getpid() ^ time.time_ns()).randrange(len(_OWN_DOMAINS)))
)


def free_domain(taken: int | None = None, strict: bool = False) -> int:
    """A DDS domain id of this worker's that no participant is in, other than `taken`; failing that (not `strict`),
    one that only this process's own participants, left by earlier tests, are in."""
    fallback = None
    for _ in range(len(_OWN_DOMAINS)):
        d = next(_domains)
        if d == taken:
            continue
        if domain_free(d, own_ok=False):
            return d
        if fallback is None and not strict and domain_free(d):
            fallback = d
    if fallback is not None:
        return fallback
    raise RuntimeError("no free DDS domain id on this host")


@pytest.fixture
def domain() -> int:
    return free_domain()


# The markers (backend/pyproject.toml) that follow from a test's fixtures; a test that starts a process by itself, or
# runs another implementation, carries its marker in its own file.
_PROCESS_FIXTURES = {"sim", "console", "pg_cluster"}


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--security",
        choices=("skip", "only"),
        help="deselect the tests marked security (the DDS Security build's), or keep only them (scripts/test's two passes)",
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    security = config.getoption("--security")
    if security is not None:
        keep = security == "only"
        deselected = [item for item in items if (item.get_closest_marker("security") is not None) != keep]
        if deselected:
            config.hook.pytest_deselected(items=deselected)
            items[:] = [item for item in items if (item.get_closest_marker("security") is not None) == keep]
    for item in items:
        names = set(getattr(item, "fixturenames", ()))
        callspec = getattr(item, "callspec", None)
        postgres = "pg_cluster" in names or (callspec is not None and callspec.params.get("database_url") == "postgresql")
        if postgres:
            item.add_marker(pytest.mark.postgres)
        if postgres or names & _PROCESS_FIXTURES:
            item.add_marker(pytest.mark.process)
    # the slow tests first (stable: each in its file's order), each worker's first tests on domains no earlier test
    # of its left a participant in: the relay's tests that assert nothing reaches a domain failed, run late without it
    items.sort(key=lambda item: item.get_closest_marker("slow") is None)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None) -> Iterator[None]:
    """With SEM_TEST_TIMELINE=FILE, each test's worker, start and end (UTC seconds) and the CPU-seconds its worker's own
    process took appended to FILE as a JSON line: where a run's time goes (docs/testing.md)."""
    timeline = os.environ.get("SEM_TEST_TIMELINE")
    start = time.time()
    cpu = time.process_time()
    try:
        return (yield)
    finally:
        if timeline:
            worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
            line = {"worker": worker, "test": item.nodeid, "start": start, "end": time.time()}
            line["cpu"] = round(time.process_time() - cpu, 3)
            with open(timeline, "a") as f:
                f.write(json.dumps(line) + "\n")


FAST = ["--time-scale", "0.05", "--fix-rate", "10", "--ins-rate", "10", "--gps-rate", "4"]


class Process:
    """A child process of a test, stopped with a signal (SIGINT runs its shutdown sequence)."""

    proc: subprocess.Popen[str] | warm.Forked | None = None

    def stop(self, sig: int = signal.SIGINT, timeout: float = 15) -> str:
        assert self.proc is not None
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        out, _ = self.proc.communicate(timeout=timeout)
        return out

    def kill(self) -> None:
        self.stop(signal.SIGKILL)

    def end(self) -> None:
        """Stopped after its test: killed; but while coverage measures child processes (`--cov`, patch =
        subprocess in pyproject.toml) asked first (SIGINT), so that it writes what was measured."""
        if self.proc is None or self.proc.poll() is not None:
            return
        if "COVERAGE_PROCESS_CONFIG" in os.environ:
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.stop(signal.SIGINT, timeout=10)
        if self.proc.poll() is None:
            self.kill()


class SimProcess(Process):
    def __init__(self, domain: int, args: list[str], state_file: Path, env: dict[str, str] | None = None) -> None:
        self.domain, self.args, self.state_file, self.env = domain, args, state_file, env or {}
        self.proc: subprocess.Popen[str] | warm.Forked | None = None

    def start(self) -> SimProcess:
        argv = ["--domain", str(self.domain), "--state-file", str(self.state_file), *FAST, *self.args]
        out = self.state_file.parent / f"sem-sim-{uuid.uuid4().hex[:8]}.out"
        self.proc = warm.launch(warm.SIM, argv, {**os.environ, **self.env}, out)  # forked when it can be: no imports
        return self


@pytest.fixture
def sim(domain: int, tmp_path: Path) -> Iterator[Callable[..., SimProcess]]:
    """Start `sem-sim` processes on the test's domain; they share one state file, like restarts of one simulator."""
    started: list[SimProcess] = []

    def start(*args: str, env: dict[str, str] | None = None) -> SimProcess:
        p = SimProcess(domain, list(args), tmp_path / "sim-state.json", env).start()
        started.append(p)
        return p

    yield start
    for p in started:
        p.end()


@pytest.fixture
def new_bus() -> Iterator[Callable[[int], Bus]]:
    """A Bus (a participant of this process) in a domain, closed after the test: one left open keeps its writers'
    transient-local samples in the domain, where a later test of this worker taking the same id would meet them."""
    made: list[Bus] = []

    def make(domain: int) -> Bus:
        made.append(Bus(domain))
        return made[-1]

    yield make
    for b in made:
        b.close()


@pytest.fixture
def consumer(domain: int) -> Iterator[Consumer]:
    c = Consumer(domain)
    yield c
    c.close()


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


_GIVEN_UDP: deque[int] = deque(maxlen=100)


def free_udp_port() -> int:
    """A UDP port no DDS participant or ephemeral socket will take, nor any DDS datagram reach, between now and its
    use: below the kernel's ephemeral range (32768 up), and in the gap of each 250-port DDS domain block (7400 + 250 d
    uses offsets 0, 1 and 10 + 2 i, 11 + 2 i for participant index i; unicast discovery pings every index up to
    MaxAutoParticipantIndex, so the gap starts past the last of them). Not one of the last ports it gave: a test takes
    several before it binds any (two consoles given one port, the second could not start)."""
    rng = random.Random()
    # this xdist worker's blocks: two workers never pick one port; 80..100 are the Playwright stack's (e2e/stack.ts)
    blocks = [d for d in _OWN_DOMAINS if d < 80]
    first = 12 + 2 * MAX_PARTICIPANT_INDEX  # offsets 150..211 took discovery pings: a JAUS station read 'RTPS'
    for _ in range(200):
        port = 7400 + 250 * rng.choice(blocks) + rng.randrange(first, 250)
        if port not in _GIVEN_UDP and udp_free(port):
            _GIVEN_UDP.append(port)
            return port
    raise RuntimeError("no free UDP port in the DDS gaps")


class ConsoleProcess(Process):
    """A real `sem-console` (uvicorn) process on the test's domain."""

    def __init__(self, domain: int, db: Path, args: list[str], env: dict[str, str]) -> None:
        self.domain, self.db, self.args, self.env = domain, db, args, env
        self.port = free_port()
        tls = "--tls-certfile" in args
        # httpx's verify (and the websockets client's ssl) for a console with a certificate of its own
        self.verify: ssl.SSLContext | bool = (
            ssl.create_default_context(cafile=args[args.index("--tls-certfile") + 1]) if tls else True
        )
        self.url = f"{'https' if tls else 'http'}://127.0.0.1:{self.port}"
        self.ws_url = f"{'wss' if tls else 'ws'}://127.0.0.1:{self.port}/ws"
        self.proc: subprocess.Popen[str] | warm.Forked | None = None

    def start(self) -> ConsoleProcess:
        import httpx

        argv = [
            "--port",
            str(self.port),
            "--domain",
            str(self.domain),
            # the database: --db unless the test gives --database-url; the one console name of the test, so a restart
            # (on another HTTP port) keeps its identity, unless the test names its consoles
            *([] if "--database-url" in self.args else ["--db", str(self.db)]),
            *([] if "--console-name" in self.args else ["--console-name", "test-console"]),
            "--recordings-dir",
            str(self.db.parent / "recordings"),
            "--comms-lost-timeout",
            "1",
            "--regained-time",
            "1",
            "--unanswered-timeout",
            "2",
            "--log-level",
            "warning",
            *self.args,
        ]
        out = self.db.parent / f"sem-console-{self.port}.out"
        self.proc = warm.launch(warm.CONSOLE, argv, {**os.environ, **self.env}, out)  # forked: no second of imports
        # a wait for start-up, not a timed assertion: generous, since pytest-xdist's workers start consoles at once
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"sem-console exited: {self.proc.communicate()[0]}")
            try:
                if http.get(self.url + "/api/health", timeout=1, verify=self.verify).status_code == 200:
                    return self
            except httpx.HTTPError:
                pass
            time.sleep(0.1)
        self.kill()  # not left running after the test: the fixture keeps only consoles that started
        raise RuntimeError("sem-console did not start")


@pytest.fixture
def console(domain: int, tmp_path: Path) -> Iterator[Callable[..., ConsoleProcess]]:
    """Start `sem-console` processes on the test's domain; they share one database, like restarts."""
    started: list[ConsoleProcess] = []

    def start(*args: str, env: dict[str, str] | None = None) -> ConsoleProcess:
        c = ConsoleProcess(domain, tmp_path / "console.sqlite3", list(args), env or {}).start()
        started.append(c)
        return c

    yield start
    for c in started:
        c.end()


@pytest.fixture(scope="session")
def connext7() -> None:
    """Connext 7.x for the RTI interop tests (the npm Connector's native libraries, tests/support/rti/connext7.py), fetched
    once; skipped when it cannot be had."""
    from support.rti.connext7 import connector7  # here: the module loads RTI's Connector, which only these tests need

    try:
        connector7()
    except (RuntimeError, OSError, subprocess.SubprocessError, tarfile.TarError, IndexError) as e:
        pytest.skip(f"Connext 7 unavailable: {e}")
