"""Where the dashboard's time goes: a CPU profile (V8's sampling profiler over the Chrome DevTools Protocol) of the
page in headless Chromium, with bench/probe.py's vehicles (the probe and the simulator's), over a window after it
settled, and of a new client's first screen. Prints the functions by self and by total time and the heaviest stacks
inside long tasks (frontend/scripts/profile.mjs), as one JSON line; the profile itself is kept as a .cpuprofile file
(DevTools' Performance panel opens it). Build the dashboard without minifying for names (vite build --minify false).
Not a benchmark: no targets, nothing kept in bench/results.
Usage: python bench/profile.py [--vehicles 50] [--fleet] [--seconds 10] [--out /tmp/dashboard.cpuprofile]
"""

from __future__ import annotations

import argparse
import subprocess
import threading
import time

import common
import probe


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=50)
    ap.add_argument("--fleet", action="store_true", help="the simulator's default rates (probe.py's fleet run), not 10 Hz")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--out", default="/tmp/dashboard.cpuprofile")
    args = ap.parse_args()
    written = probe.Written()
    stop = threading.Event()
    with common.stack(sim_args=probe.sim_args(args.vehicles, not args.fleet)) as st:
        writer = threading.Thread(target=probe.probe_writer, args=(st["domain"], stop, written), daemon=True)
        writer.start()
        try:
            time.sleep(3.0)  # discovery, the simulator's vehicles up
            out = subprocess.run(
                ["node", "scripts/profile.mjs", st["url"], str(probe.PROBE), str(args.seconds), args.out],
                cwd=common.ROOT / "frontend",
                capture_output=True,
                text=True,
                check=True,
                timeout=args.seconds + 240,
            ).stdout
        finally:
            stop.set()
            writer.join(5)
    print(out.strip().splitlines()[-1])


if __name__ == "__main__":
    main()
