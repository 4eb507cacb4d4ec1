"""The Playwright suite's warm launcher: `sem-console` and `sem-sim` processes forked from a warm interpreter
(`support/warm.py`, as pytest's are), asked for by the e2e stack (`e2e/stack.ts`) over a Unix socket. A console started
by its command spends about 1.5 CPU-seconds importing its modules, a simulator about 0.5; the suite starts about 45
consoles and 30 simulators beside pytest on two cores.

    python -m support.launcher SOCKET    (from backend/tests: the folder is then on sys.path, not on PYTHONPATH)

One request per connection, a line of JSON: {"command": "sem-console" | "sem-sim", "argv": [...], "env": {...}}; the
answer a line: {"pid": N}, or {"pid": null} when the process cannot be forked (an environment that changes what an
interpreter loads, `warm.forkable`): the stack then starts the command itself. A forked process writes to this
launcher's stdout and stderr (the suite's output), as a command the stack starts does. The fork server reaps each
process when it exits, so the stack sees it gone (`kill(pid, 0)` fails). SIGTERM or SIGINT ends the launcher and the
processes it forked that still run."""

from __future__ import annotations

import json
import os
import signal
import socket
import sys
from types import FrameType

from support import warm

COMMANDS = {"sem-console": warm.CONSOLE, "sem-sim": warm.SIM}


def _answer(conn: socket.socket, forked: list[warm.Forked]) -> None:
    with conn, conn.makefile("rwb") as f:
        request = json.loads(f.readline())
        module = COMMANDS[request["command"]]
        env = {str(k): str(v) for k, v in request["env"].items()}
        pid: int | None = None
        if warm.forkable(env):
            process = warm.Forked([str(a) for a in request["argv"]], env, None, module)
            forked.append(process)
            pid = process.pid
        f.write(json.dumps({"pid": pid}).encode() + b"\n")


def main(argv: list[str]) -> int:
    (path,) = argv

    def stop(signum: int, frame: FrameType | None) -> None:
        raise SystemExit(0)  # multiprocessing's exit handler then ends the (daemonic) processes still running

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    forked: list[warm.Forked] = []
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as server:
        # bound and listening under another name, then renamed: the stack connects once the socket is there
        for stale in (path, path + ".tmp"):
            if os.path.exists(stale):
                os.unlink(stale)
        server.bind(path + ".tmp")
        server.listen()
        warm.start()  # the fork server and its preloads now, before the stack asks
        os.rename(path + ".tmp", path)
        while True:
            conn, _ = server.accept()
            try:
                _answer(conn, forked)
            except (OSError, ValueError, KeyError) as e:  # a request the stack garbled: it starts the command itself
                print(f"launcher: a request refused ({e})", file=sys.stderr, flush=True)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
