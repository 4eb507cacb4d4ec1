"""RTI Connext 7.x for the interop tests: the native libraries of the npm package
`rticonnextdds-connector` under the Python Connector's own code, in a process of its own.

The PyPI Connector (Connext 6.1.2 core) loads `../rticonnextdds-connector/lib/<platform>/`
relative to its module file. A copy of its module next to the npm package's `lib/` loads
Connext 7.x instead. Both cores export the same C symbols, so one process holds one of them:
the 6.1.2 participants run inside pytest (rti.connector), the 7.x ones in a child process
(rti.worker) driven over a pipe, with the same methods.

The libraries are test-only, fetched with `npm pack` into ~/.cache/sem-console/rti (or
$SEM_RTI_CACHE) under the Connector's terms for non-commercial use; the product neither ships
nor needs RTI code.
"""

from __future__ import annotations

import atexit
import fcntl
import json
import os
import platform
import shutil
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path
from typing import Any

from .connector import sem_key

NPM_VERSION = "1.5.0"  # Connext 7.7.0
CONNEXT7 = "7.7.0"
_PLATFORM = {"x86_64": "linux-x64", "aarch64": "linux-arm64"}
_TESTS = Path(__file__).resolve().parents[2]
_BACKEND = _TESTS.parent


def cache_dir() -> Path:
    return Path(os.environ.get("SEM_RTI_CACHE", Path.home() / ".cache" / "sem-console" / "rti"))


def connector7() -> Path:
    """A directory to put first on sys.path so that `import rticonnextdds_connector` loads Connext 7.x;
    fetched once. Raises RuntimeError (with the reason) when it cannot be had."""
    plat = _PLATFORM.get(platform.machine())
    if platform.system() != "Linux" or plat is None:
        raise RuntimeError(f"no Connext 7 libraries for {platform.system()} {platform.machine()} in this set-up")
    cache_dir().mkdir(parents=True, exist_ok=True)
    # one fetch at a time: pytest-xdist's workers ask at once, and half-extracted libraries must not be loaded
    with open(cache_dir() / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return _fetch(plat)


def _fetch(plat: str) -> Path:
    root = cache_dir() / f"connector-{NPM_VERSION}"
    lib = root / "rticonnextdds-connector" / "lib" / plat
    if not (lib / "librtiddsconnector.so").exists():
        npm = shutil.which("npm")
        if npm is None:
            raise RuntimeError("npm is not installed: cannot fetch rticonnextdds-connector (Connext 7)")
        with tempfile.TemporaryDirectory() as tmp:
            # well inside pytest's 120 s per test (the fixture fetches in the first test that asks): a slow or
            # silent registry is a skip with its reason, not a timeout failing every Connext 7 case
            try:
                r = subprocess.run(
                    [
                        npm,
                        "pack",
                        f"rticonnextdds-connector@{NPM_VERSION}",
                        "--silent",
                        "--fetch-timeout=60000",
                        "--fetch-retries=0",
                    ],
                    cwd=tmp,
                    capture_output=True,
                    text=True,
                    timeout=90,
                )
            except subprocess.TimeoutExpired:
                raise RuntimeError("npm pack rticonnextdds-connector took over 90 s (a slow registry)") from None
            if r.returncode != 0:
                raise RuntimeError(f"npm pack rticonnextdds-connector@{NPM_VERSION} failed: {r.stderr.strip()[-300:]}")
            tgz = Path(tmp) / r.stdout.strip().splitlines()[-1]
            with tarfile.open(tgz) as t:
                prefix = f"package/rticonnextdds-connector/lib/{plat}/"
                members = [m for m in t.getmembers() if m.name.startswith(prefix) and m.isfile()]
                lib.mkdir(parents=True, exist_ok=True)
                for m in members:
                    m.name = m.name[len(prefix) :]
                    t.extract(m, lib)
    pkg = root / "rticonnextdds_connector"
    if not (pkg / "rticonnextdds_connector.py").exists():
        import importlib.util

        spec = importlib.util.find_spec("rticonnextdds_connector")  # the PyPI package's Python code
        if spec is None or spec.origin is None:
            raise RuntimeError("rticonnextdds-connector (PyPI) is not installed")
        shutil.copytree(Path(spec.origin).parent, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    return root


# Workers whose participant was closed, by the environment they run in, waiting for the next participant: a worker
# costs an interpreter, its imports and RTI's libraries to start (about half the 1 s a participant takes), and the
# Connext 7 tests make some twenty. The same process makes one participant after another, as pytest does with 6.1.2.
_IDLE: dict[tuple[tuple[str, str], ...], list[subprocess.Popen[str]]] = {}


@atexit.register
def _end_idle() -> None:
    for procs in _IDLE.values():
        for proc in procs:
            _end(proc)
    _IDLE.clear()


def _end(proc: subprocess.Popen[str]) -> None:
    """End a worker: its stdin closed, it exits at the end of input; killed if it does not within 10 s."""
    if proc.stdin:
        proc.stdin.close()
    try:
        proc.wait(10)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


class RemoteParticipant:
    """An RtiParticipant (rti.connector) in a child process loading Connext 7.x; the process is reused for the next
    participant in the same environment once this one is closed."""

    def __init__(self, domain: int, env: dict[str, str] | None = None, **kw: Any) -> None:
        root = connector7()
        self._env = tuple(sorted((env or {}).items()))
        idle = _IDLE.get(self._env)
        if idle:
            self.proc = idle.pop()
        else:
            pythonpath = os.pathsep.join([str(root), str(_TESTS), str(_BACKEND)])
            self.proc = subprocess.Popen(
                [sys.executable, "-m", "support.rti.worker"],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                text=True,
                cwd=_TESTS,
                env={**os.environ, **(env or {}), "PYTHONPATH": pythonpath},
            )
        self.writers = set(kw.get("writers", ()))
        kw = {k: ([sem_key(s) for s in v] if k in ("writers", "readers") else v) for k, v in kw.items()}
        try:
            self.version = self._call("start", domain, **kw)
        except BaseException:
            _end(self.proc)
            raise

    def _call(self, op: str, *args: Any, **kw: Any) -> Any:
        assert self.proc.stdin and self.proc.stdout
        self.proc.stdin.write(json.dumps([op, args, kw]) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"the Connext 7 worker exited ({self.proc.wait()})")
        ok, value = json.loads(line)
        if not ok:
            raise RuntimeError(f"Connext 7 worker: {value}")
        return value

    def wait_matched(self, sem: Any, timeout: float = 30.0) -> None:
        if not self._call("wait_matched", sem_key(sem), timeout):
            raise TimeoutError(f"RTI 7 {sem.spec.name} matched nothing")

    def matched(self, sem: Any, writer: bool) -> list[Any]:
        return self._call("matched", sem_key(sem), writer)

    def write(self, sem: Any, sample: dict[str, Any], action: str = "write") -> None:
        self._call("write", sem_key(sem), sample, action)

    def take(self, sem: Any) -> list[tuple[dict[str, Any] | None, str]]:
        return [tuple(x) for x in self._call("take", sem_key(sem))]  # type: ignore[misc]

    def take_with_keys(self, sem: Any) -> list[tuple[dict[str, Any], str, bool]]:
        return [tuple(x) for x in self._call("take_with_keys", sem_key(sem))]  # type: ignore[misc]

    def close(self) -> None:
        if self.proc.poll() is not None:
            return
        try:
            self._call("close")
        except BaseException:
            _end(self.proc)
            raise
        _IDLE.setdefault(self._env, []).append(self.proc)  # ready for the next participant
