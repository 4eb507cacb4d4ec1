"""Memory over time: the console's RSS at start and over a run at the ingest rates with N=10
vehicles (40 satellites, 10 Hz reports) and one WebSocket client. Default 60 s; --soak for 10 min.
Usage: python bench/soak.py [--soak | --seconds 60]
"""

from __future__ import annotations

import argparse
import asyncio
import time

from common import emit, stack, table, ws_collect
from ingest import sim_args


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--soak", action="store_true", help="run for 10 minutes")
    args = ap.parse_args()
    seconds = 600.0 if args.soak else args.seconds
    samples = []
    with stack(sim_args=sim_args(10)) as st:
        console = st["procs"]["console"]
        time.sleep(8)  # warm up: providers seen, caches filled
        start = console.rss_mb()
        t0 = time.monotonic()
        step = max(seconds / 10, 5)

        async def run() -> None:
            task = asyncio.create_task(ws_collect(st["ws"], seconds, lambda m, t: None))
            while not task.done():
                samples.append((round(time.monotonic() - t0), round(console.rss_mb(), 1)))
                await asyncio.sleep(step)
            await task

        asyncio.run(run())
        end = console.rss_mb()
    growth = (end - start) / start * 100
    table(f"Console RSS over {seconds:.0f} s (10 vehicles, 1 WebSocket client)", ["t (s)", "RSS (MiB)"], samples)
    print(f"\nRSS start {start:.1f} MiB, end {end:.1f} MiB, growth {growth:+.1f}%")
    emit(
        "soak", {"seconds": seconds, "rss_start_mb": round(start, 1), "rss_end_mb": round(end, 1), "growth_pct": round(growth, 1)}
    )


if __name__ == "__main__":
    main()
