"""Recording cost: the console's CPU with and without recording to MCAP at the ingest benchmark's
50-vehicle rate (per vehicle 40 satellites at 1 Hz and three reports at 10 Hz), and what it writes.
Phases alternate off, on, off, on... (`--pairs` of `--seconds` each) on one running stack, so both
see the same input; the added CPU is the mean of the on phases minus the mean of the off phases,
printed with its standard error over the pairs (the console's CPU moves by a few hundredths of a
core between phases with the same input, as much as recording costs).
Usage: python bench/recording.py [--vehicles 50] [--seconds 15] [--pairs 4]
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
import urllib.request
from pathlib import Path

from common import CpuMeter, emit, get_json, stack, table, target, wait_listed
from ingest import sim_args


def post_json(url: str, body: dict) -> dict:
    req = urllib.request.Request(url, data=json.dumps(body).encode(), method="POST", headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=30) as r:
        return json.loads(r.read())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=15.0)
    ap.add_argument("--pairs", type=int, default=4, help="off/on pairs of phases")
    args = ap.parse_args()
    rec_dir = Path(tempfile.mkdtemp(prefix="sem-bench-rec-"))
    rows = []
    with stack(sim_args=sim_args(args.vehicles), console_env={"SEM_RECORDINGS_DIR": str(rec_dir)}) as st:
        console, url = st["procs"]["console"], st["url"]
        wait_listed(url, args.vehicles)
        for phase in ("off", "on") * args.pairs:
            if phase == "on":
                post_json(url + "/api/recordings", {"action": "start"})
                time.sleep(1)  # the file is opened, the transient-local history written
            m0, cpu, t0 = get_json(url + "/api/metrics"), CpuMeter(console), time.monotonic()
            s0 = get_json(url + "/api/recordings/status")
            size0 = sum(p.stat().st_size for p in rec_dir.glob("*.mcap"))
            time.sleep(args.seconds)
            elapsed = time.monotonic() - t0
            row = {
                "phase": phase,
                "console_cpu": round(cpu.read(), 3),
                "decoded_per_s": round((get_json(url + "/api/metrics")["samplesDecoded"] - m0["samplesDecoded"]) / elapsed),
            }
            if phase == "on":
                s1 = get_json(url + "/api/recordings/status")
                size1 = sum(p.stat().st_size for p in rec_dir.glob("*.mcap"))
                row.update(
                    {
                        "recorded_per_s": round((s1["messages"] - s0["messages"]) / elapsed),
                        "mb_per_min": round((size1 - size0) / 1e6 / elapsed * 60, 2),
                        "dropped": s1["dropped"],
                        "writer_cpu": round((s1["writerCpuSeconds"] - s0["writerCpuSeconds"]) / elapsed, 4),
                    }
                )
                post_json(url + "/api/recordings", {"action": "stop"})
                time.sleep(1)
            rows.append(row)
        files = get_json(url + "/api/recordings")
    off = [r["console_cpu"] for r in rows if r["phase"] == "off"]
    on = [r for r in rows if r["phase"] == "on"]
    cpu_off, cpu_on = sum(off) / len(off), sum(r["console_cpu"] for r in on) / len(on)
    differences = [r["console_cpu"] - o for r, o in zip(on, off, strict=False)]  # each on phase against the off phase before it
    stderr = statistics.stdev(differences) / len(differences) ** 0.5 if len(differences) > 1 else float("nan")
    keys = ["phase", "console_cpu", "writer_cpu", "decoded_per_s", "recorded_per_s", "mb_per_min", "dropped"]
    table(
        f"Recording at {args.vehicles} vehicles ({args.seconds:.0f} s per phase, {args.pairs} off/on pairs)",
        keys,
        [[r.get(k, "") for k in keys] for r in rows],
    )
    figures = {
        "vehicles": args.vehicles,
        "console_cpu_off": round(cpu_off, 3),
        "console_cpu_on": round(cpu_on, 3),
        "added_cpu_core": round(cpu_on - cpu_off, 3),
        "added_cpu_percent": round((cpu_on - cpu_off) / max(cpu_off, 1e-9) * 100, 1),
        "added_cpu_stderr_percent": round(stderr / max(cpu_off, 1e-9) * 100, 1),
        "pairs": args.pairs,
        "recorded_per_s": round(sum(r["recorded_per_s"] for r in on) / len(on)),
        "mb_per_min": round(sum(r["mb_per_min"] for r in on) / len(on), 2),
        "dropped": sum(r["dropped"] for r in on),
        "files": [f["state"] for f in files],
        "writer_cpu_core": round(sum(r["writer_cpu"] for r in on) / len(on), 4),
    }
    figures["writer_cpu_percent"] = round(figures["writer_cpu_core"] / max(cpu_off, 1e-9) * 100, 1)
    print(
        f"\nadded console CPU: {figures['added_cpu_core']} core ({figures['added_cpu_percent']}% of "
        f"{figures['console_cpu_off']}, standard error {figures['added_cpu_stderr_percent']}% over {args.pairs} pairs); "
        f"written: {figures['mb_per_min']} MB/min"
    )
    # the console's CPU moves by a few hundredths of a core between phases at this load; the writer
    # thread's own CPU (its thread time, /api/recordings/status) is the recording's cost without that noise
    print(
        f"the recording's writer thread: {figures['writer_cpu_core']} core ({figures['writer_cpu_percent']}% of the "
        f"console's CPU without recording); the ingest threads' tap (a tuple per sample, a queue put per take) is not in it"
    )
    figures["targets"] = [
        target("added console CPU, off/on phases", figures["added_cpu_percent"], "%", "<", 10.0),
        target("the writer thread's CPU against the console's", figures["writer_cpu_percent"], "%", "<", 10.0),
    ]
    emit("recording", figures)


if __name__ == "__main__":
    main()
