"""bench/probe.py's options: a fleet rate the simulator refuses is one line before any run, not a fleet that never
comes up and a probe that blames the machine after minutes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.process
@pytest.mark.parametrize("hz", ["0.5", "20"])
def test_a_fleet_rate_the_simulator_refuses_is_one_line_before_any_run(hz: str) -> None:
    r = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "probe.py"), "--vehicles", "", "--fleet", "10", "--fleet-hz", hz],
        capture_output=True,
        text=True,
        timeout=20,
    )
    assert r.returncode == 2, r.stderr
    error = r.stderr.strip().splitlines()[-1]
    assert error.startswith(f"probe.py: error: argument --fleet-hz: {hz}"), error
    assert "Traceback" not in r.stderr
