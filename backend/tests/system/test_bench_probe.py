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


@pytest.mark.process
def test_the_probe_vehicle_writes_its_samples(domain: int) -> None:
    """The probe's own vehicle (its writer thread, on the simulator's Sensors) writes a sample every tenth of a second:
    a writer thread that died at its first step left every probe run one vehicle short, blaming the machine."""
    script = (
        "import sys, threading, time\n"
        f"sys.path.insert(0, {str(ROOT / 'bench')!r})\n"
        "import probe\n"
        "stop, written, died = threading.Event(), probe.Written(), []\n"
        "def run():\n"
        "    try:\n"
        f"        probe.probe_writer({domain}, stop, written)\n"
        "    except BaseException as e:\n"
        "        died.append(repr(e))\n"
        "t = threading.Thread(target=run)\n"
        "t.start(); time.sleep(1.5); stop.set(); t.join(10)\n"
        "print(len(written.at), died)\n"
    )
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    count, died = r.stdout.split(" ", 1)
    assert died.strip() == "[]" and int(count) >= 5, r.stdout
