"""The Playwright suite's warm launcher: `sem-console` and `sem-sim` processes forked from a warm interpreter
(`support/warm.py`, as pytest's are), asked for by the e2e stack (`e2e/stack.ts`) over a Unix socket. A console started
by its command spends about 1.5 CPU-seconds importing its modules, a simulator about 0.5; the suite starts about 25
consoles and 35 simulators through the stack (the specs' own with `startSpecSim`), beside pytest on two cores.

    python -m support.launcher SOCKET    (from backend/tests: the folder is then on sys.path, not on PYTHONPATH)

One request per connection, a line of JSON: {"command": "sem-console" | "sem-sim", "argv": [...], "env": {...},
"cwd": "..."}; the answer a line: {"pid": N}, or {"pid": null} when the process cannot be forked (an environment that
changes what an interpreter loads, `warm.forkable`): the stack then starts the command itself. A request it cannot read
is closed unanswered (the stack then fails the start) and the launcher goes on. A forked process writes to this
launcher's stdout and stderr, the suite's output. The fork server reaps each process when it exits, so the stack sees
it gone (`kill(pid, 0)` fails). SIGTERM or SIGINT ends the launcher and, within `STOP_S`, the processes it forked that
still run: SIGTERM, then SIGKILL."""

from __future__ import annotations

import json
import multiprocessing
import os
import signal
import socket
import sys
import time
import traceback
from types import FrameType

from support import warm

COMMANDS = {"sem-console": warm.CONSOLE, "sem-sim": warm.SIM}
STOP_S = 10.0  # e2e/stack.ts's stopLauncher waits longer before it kills the launcher


def _answer(conn: socket.socket) -> None:
    with conn, conn.makefile("rwb") as f:
        request = json.loads(f.readline())
        module = COMMANDS[request["command"]]
        env = {str(k): str(v) for k, v in request["env"].items()}
        cwd = request.get("cwd")
        pid: int | None = None
        if warm.forkable(env):
            pid = warm.Forked([str(a) for a in request["argv"]], env, None, module, None if cwd is None else str(cwd)).pid
        f.write(json.dumps({"pid": pid}).encode() + b"\n")


def _end_children() -> None:
    """The forked processes still running: SIGTERM (a console's orderly stop), then SIGKILL after STOP_S."""
    children = multiprocessing.active_children()
    for child in children:
        child.terminate()
    deadline = time.monotonic() + STOP_S
    for child in children:
        child.join(max(0.0, deadline - time.monotonic()))
        if child.is_alive():
            child.kill()
            child.join(1)


def main(argv: list[str]) -> int:
    (path,) = argv

    def stop(signum: int, frame: FrameType | None) -> None:
        raise SystemExit(0)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    try:
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as server:
            # bound and listening under another name, then renamed: the stack connects once the socket is there
            for stale in (path, path + ".tmp"):
                if os.path.exists(stale):
                    os.unlink(stale)
            server.bind(path + ".tmp")
            server.listen()
            warm.start()  # the fork server now: it imports its preloads while the stack gets ready
            os.rename(path + ".tmp", path)
            while True:
                conn, _ = server.accept()
                try:
                    _answer(conn)
                except Exception:  # one garbled request must not end the processes forked before it
                    print(f"launcher: a request refused\n{traceback.format_exc()}", file=sys.stderr, flush=True)
    finally:
        _end_children()


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
