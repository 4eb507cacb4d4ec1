"""The Playwright suite's warm launcher (support/launcher.py): it forks what it is asked for, says when it cannot, keeps
serving after a garbled request, and takes what it forked with it when it ends."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

TESTS = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.process


def ask(path: Path, request: bytes) -> dict[str, Any] | None:
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
        s.settimeout(60)  # the first fork waits for the fork server's imports
        s.connect(str(path))
        s.sendall(request)
        line = s.makefile("rb").readline()
    return json.loads(line) if line else None


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


def test_the_launcher_forks_refuses_what_it_cannot_and_ends_what_it_forked(tmp_path: Path, domain: int) -> None:
    path = tmp_path / "socket"
    out = (tmp_path / "launcher.out").open("wb")
    # coverage's subprocess patch (pytest --cov) marks an environment unforkable: the launcher's and its requests' go
    # without it, as the Playwright suite's do
    env = {k: v for k, v in os.environ.items() if not k.startswith("COVERAGE_")}
    launcher = subprocess.Popen(
        [sys.executable, "-m", "support.launcher", str(path)], cwd=TESTS, env=env, stdout=out, stderr=subprocess.STDOUT
    )
    try:
        deadline = time.monotonic() + 60  # a start-up wait: the launcher's imports
        while not path.exists():
            assert launcher.poll() is None and time.monotonic() < deadline, (tmp_path / "launcher.out").read_text()
            time.sleep(0.1)
        sim = ["--domain", str(domain), "--log-level", "warning"]
        answer = ask(path, json.dumps({"command": "sem-sim", "argv": sim, "env": env}).encode() + b"\n")
        assert answer is not None and isinstance(answer["pid"], int)
        pid = answer["pid"]
        assert alive(pid)
        # an environment that changes what an interpreter loads: the stack starts the command instead
        other = {**env, "PYTHONPATH": str(tmp_path)}
        assert ask(path, json.dumps({"command": "sem-sim", "argv": sim, "env": other}).encode() + b"\n") == {"pid": None}
        assert ask(path, b"not json\n") is None  # refused, and the launcher goes on
        assert ask(path, json.dumps({"command": "sem-relay", "argv": [], "env": env}).encode() + b"\n") is None
        assert alive(pid) and launcher.poll() is None
        launcher.send_signal(signal.SIGTERM)
        assert launcher.wait(30) == 0
        deadline = time.monotonic() + 30
        while alive(pid):  # the fork server reaps it once it has ended
            assert time.monotonic() < deadline, "the forked simulator outlived the launcher"
            time.sleep(0.1)
    finally:
        if launcher.poll() is None:  # a failed test: what it forked is ended with it, then it is
            launcher.send_signal(signal.SIGTERM)
            try:
                launcher.wait(30)
            except subprocess.TimeoutExpired:
                launcher.kill()
        out.close()
