"""`sem-console`, `sem-sim` and `sem-relay` processes forked from a warm interpreter: a process of this pytest worker's
(multiprocessing's fork server) that has imported their modules once, and forks one child per process. A console
started by `python -m sem_console.cli` spends about 1 CPU-second of its 1.5 s start importing them (FastAPI,
SQLAlchemy, Alembic, cyclonedds, its own routes and models), a simulator about 0.6 s (cyclonedds, the UMAA types of
both versions), and the tests start hundreds of each. The child runs the command's own `main` on the test's arguments
and environment, in a process of its own, as the command does.

A process whose environment changes what an interpreter loads (PYTHONPATH, LD_LIBRARY_PATH, CYCLONEDDS_HOME: the DDS
Security build) or that coverage measures (COVERAGE_PROCESS_CONFIG) is started by the command instead: a warm
interpreter has loaded its libraries already, and coverage starts with an interpreter."""

from __future__ import annotations

import importlib
import multiprocessing
import multiprocessing.forkserver
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

_FORKSERVER = multiprocessing.get_context("forkserver")
CONSOLE, SIM, RELAY = "sem_console.cli", "sem_console.sim.sem_sim", "sem_console.relay.cli"  # the modules whose `main`
# a child runs (the relay's imports zenoh, which starts no thread before a session is opened: forking after it is safe)
KEYS = "sem_console.keys.cli"  # sem-keys (`run`): the tests run it 60 times, each start importing for about 0.4 CPU-s
# A console imports its web server only when it runs (`sem-console --help` need not): uvicorn, its HTTP, WebSocket and
# lifespan protocols, uvloop, logging.config; about 0.2 CPU-second of each forked console's start (measured), and none of
# them starts a thread on import.
_SERVER = (
    "uvicorn.main",
    "uvicorn.lifespan.on",
    "uvicorn.loops.auto",
    "uvicorn.loops.uvloop",
    "uvicorn.protocols.http.auto",
    "uvicorn.protocols.http.httptools_impl",
    "uvicorn.protocols.websockets.auto",
    "uvicorn.protocols.websockets.websockets_sansio_impl",
    "fastapi.telemetry._runtime",
    "logging.config",
    "encodings.idna",
)
# Preloaded too: the topic types' type information built (support/warm_types.py: a module of the tests, which the fork
# server finds on the PYTHONPATH it is started with, `start`; it imports its preloads before it applies any sys.path)
_FORKSERVER.set_forkserver_preload([CONSOLE, "sem_console.main", *_SERVER, SIM, RELAY, KEYS, "support.warm_types"])
_started = False


def start() -> None:
    """Start this process's fork server (once) with the tests' folder on its PYTHONPATH, this process's environment
    otherwise; a child's environment is the test's own (`_run`)."""
    global _started
    if _started:
        return
    tests = str(Path(__file__).resolve().parents[1])
    before = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join([tests, *([before] if before else [])])
    try:
        multiprocessing.forkserver.ensure_running()
    finally:
        if before is None:
            del os.environ["PYTHONPATH"]
        else:
            os.environ["PYTHONPATH"] = before
    _started = True


_AT_START = ("PYTHON", "LD_", "CYCLONEDDS_HOME", "COVERAGE_")


def forkable(env: dict[str, str]) -> bool:
    """Whether a console of this (whole) environment can be forked from the warm interpreter, which has this
    process's."""
    at_start = {k for k in {*env, *os.environ} if k.startswith(_AT_START)}
    return "COVERAGE_PROCESS_CONFIG" not in env and all(env.get(k) == os.environ.get(k) for k in at_start)


def _run(
    module: str, argv: list[str], env: dict[str, str], out: str | None, cwd: str | None = None, err: str | None = None
) -> None:
    """The child: stdout and stderr to `out` (None: the fork server's own, which are its starter's; stderr to `err`
    when given), the test's environment (and working directory, when given), then the `main` of `module` (preloaded)."""
    if cwd is not None:
        os.chdir(cwd)
    for path, fds in ((out, (1,) if err else (1, 2)), (err, (2,))):
        if path is not None:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            for to in fds:
                os.dup2(fd, to)
            os.close(fd)
    os.environ.clear()
    os.environ.update(env)
    sys.exit(importlib.import_module(module).main(argv))


class Forked:
    """What the tests use of a `subprocess.Popen` (pid, poll, send_signal, kill, wait, communicate) for a forked
    process, the `main` of `module` on `argv`; its output (stdout and stderr together, as the tests' Popen has them) is
    read from the file `out` when it has exited (`out` None: it goes to the fork server's own, and reads as empty)."""

    def __init__(
        self, argv: list[str], env: dict[str, str], out: Path | None, module: str = CONSOLE, cwd: str | None = None
    ) -> None:
        self._out, self._module = out, module
        start()
        args = (module, argv, env, None if out is None else str(out), cwd)
        self._process = _FORKSERVER.Process(target=_run, args=args, daemon=True)
        self._process.start()
        assert self._process.pid is not None
        self.pid: int = self._process.pid
        self.returncode: int | None = None

    def poll(self) -> int | None:
        if self.returncode is None:
            self.returncode = self._process.exitcode
        return self.returncode

    def send_signal(self, sig: int) -> None:
        if self.poll() is None:
            os.kill(self.pid, sig)

    def kill(self) -> None:
        self.send_signal(signal.SIGKILL)

    def wait(self, timeout: float | None = None) -> int:
        self._process.join(timeout)
        code = self.poll()
        if code is None:
            raise subprocess.TimeoutExpired(self._module, timeout or 0)
        return code

    def communicate(self, timeout: float | None = None) -> tuple[str, None]:
        self.wait(timeout)
        return "" if self._out is None else self._out.read_text(errors="replace"), None


def launch(module: str, argv: list[str], env: dict[str, str], out: Path) -> subprocess.Popen[str] | Forked:
    """`python -m module *argv` in the (whole) environment `env`: forked from the warm interpreter when it can be
    (`forkable`), its output to the file `out`; else started by the command, its output on a pipe."""
    if forkable(env):
        return Forked(argv, env, out, module)
    cmd = [sys.executable, "-m", module, *argv]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)


def run(module: str, argv: list[str], timeout: float = 60) -> subprocess.CompletedProcess[str]:
    """`python -m module *argv` in this process's environment, run to its end as `subprocess.run(capture_output=True,
    text=True)` has it (stdout and stderr apart, the exit code): forked from the warm interpreter when it can be."""
    env = dict(os.environ)
    if not forkable(env):
        cmd = [sys.executable, "-m", module, *argv]
        return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, check=False)
    start()
    with tempfile.TemporaryDirectory() as folder:
        out, err = Path(folder) / "stdout", Path(folder) / "stderr"
        args = (module, argv, env, str(out), os.getcwd(), str(err))  # this process's working directory, as a command's
        child = _FORKSERVER.Process(target=_run, args=args, daemon=True)
        child.start()
        child.join(timeout)
        if child.exitcode is None:
            child.kill()
            child.join()
            raise subprocess.TimeoutExpired([module, *argv], timeout)
        read = {p: p.read_text(errors="replace") if p.exists() else "" for p in (out, err)}
        return subprocess.CompletedProcess([module, *argv], child.exitcode, read[out], read[err])
