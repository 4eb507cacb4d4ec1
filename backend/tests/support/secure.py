"""The DDS Security build (scripts/secure-build.sh, cached once per machine) for the tests: the environment
scripts/secure gives a command, or why there is none (the tests that need it skip, saying so)."""

from __future__ import annotations

import functools
import os
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]


@functools.cache
def secure_env() -> dict[str, str] | str:
    """The variables scripts/secure sets (the secure binding first on PYTHONPATH, its libraries), or the reason
    there is no secure build."""
    # scripts/test's unoptimised build (SEM_SECURE_FOR_TESTS=1), else the one `scripts/setup.sh --secure` makes: pytest
    # run by itself finds whichever this machine has
    given = os.environ.get("SEM_SECURE_FOR_TESTS")
    for flavour in [given] if given is not None else ["1", "0"]:
        env = {**os.environ, "SEM_SECURE_FOR_TESTS": flavour}
        done = subprocess.run(
            [ROOT / "scripts" / "secure", "env", "-0"], capture_output=True, text=True, timeout=30, check=False, env=env
        )
        if done.returncode == 0:
            break
    if done.returncode != 0:
        return done.stderr.strip() or f"scripts/secure exited {done.returncode}"
    pairs = (item.partition("=") for item in done.stdout.split("\0") if item)
    wanted = ("PYTHONPATH", "CYCLONEDDS_HOME", "LD_LIBRARY_PATH")
    return {k: v for k, _, v in pairs if k in wanted}
