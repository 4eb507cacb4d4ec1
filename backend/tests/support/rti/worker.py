"""Child process of rti.connext7.RemoteParticipant: one RtiParticipant at a time, driven by JSON lines on stdin
([op, args, kwargs] in, [ok, value] out): "start" makes one, "close" deletes it, and the next "start" makes another;
the process exits at the end of its input. Whichever `rticonnextdds_connector` is first on sys.path is used."""

from __future__ import annotations

import json
import os
import sys
import traceback
from typing import Any

from support.rti.connector import RtiParticipant, sem_of


def main() -> None:
    p: RtiParticipant | None = None
    # The pipe gets its own descriptor; fd 1 (where RTI's C logging prints) goes to stderr.
    out = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    for line in sys.stdin:
        op, args, kw = json.loads(line)
        try:
            if op == "start":
                kw = {k: ([sem_of(n) for n in v] if k in ("writers", "readers") else v) for k, v in kw.items()}
                p = RtiParticipant(*args, **kw)
                value: Any = p.version
            elif op == "close":
                assert p is not None
                p.close()
                p, value = None, None
            elif op == "wait_matched":
                assert p is not None
                try:
                    p.wait_matched(sem_of(args[0]), args[1])
                    value = True
                except TimeoutError:
                    value = False
            elif op == "matched":
                assert p is not None
                value = p.matched(sem_of(args[0]), args[1])
            elif op == "write":
                assert p is not None
                p.write(sem_of(args[0]), args[1], args[2])
                value = None
            elif op == "take":
                assert p is not None
                value = p.take(sem_of(args[0]))
            elif op == "take_with_keys":
                assert p is not None
                value = p.take_with_keys(sem_of(args[0]))
            else:
                raise ValueError(op)
            out.write(json.dumps([True, value]) + "\n")
        except Exception:  # reported to the test
            out.write(json.dumps([False, traceback.format_exc()]) + "\n")
        out.flush()
    if p is not None:
        p.close()


if __name__ == "__main__":
    main()
