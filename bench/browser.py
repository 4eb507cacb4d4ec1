"""Browser: the dashboard in headless Chromium with 3 vehicles of 40 satellites, every report at
10 Hz: frame time p50/p95 from requestAnimationFrame over 20 s, and JS heap (after GC) at start
and end. Needs the built dashboard and Debian's chromium (scripts/bench sees to both).
Usage: python bench/browser.py [--seconds 20]
"""

from __future__ import annotations

import argparse
import json
import subprocess

import common
from common import emit, stack, table

SIM = ["--vehicles", "3", "--satellites", "40", "--gps-rate", "10", "--fix-rate", "10", "--ins-rate", "10"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=20.0)
    args = ap.parse_args()
    with stack(sim_args=SIM) as st:
        out = subprocess.run(["node", "scripts/frames.mjs", st["url"], str(args.seconds)], cwd=common.ROOT / "frontend",
                             capture_output=True, text=True, timeout=args.seconds + 120, check=True).stdout
    fig = json.loads(out.strip().splitlines()[-1])
    table("Dashboard in headless Chromium (3 vehicles x 40 satellites, 10 Hz)", list(fig), [list(fig.values())])
    emit("browser", fig)


if __name__ == "__main__":
    main()
