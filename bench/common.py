"""Shared parts of the benchmarks: the real stack on a spare DDS domain, WebSocket clients,
process CPU and memory from /proc, percentiles, and the output format (a table, then one
JSON line). Figures, never assertions: a benchmark prints what it measured."""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import platform
import random
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import AsyncIterator, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
BIN = ROOT / ".venv" / "bin"
sys.path.insert(0, str(ROOT / "backend"))
sys.path.insert(0, str(ROOT / "backend" / "tests"))

from support.domains import domain_free  # noqa: E402

CLK_TCK = os.sysconf("SC_CLK_TCK")
PAGE = os.sysconf("SC_PAGE_SIZE")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def free_domain() -> int:
    """A DDS domain no participant on this host is in: on loopback's unicast peers a Cyclone participant binds only
    its own unicast discovery port (7410 + 250 d + 2 i, participant index i), with multicast 7400 + 250 d too."""
    start = random.randrange(1, 200)
    for i in range(230):
        d = (start + i) % 230 + 1  # 1..230: above, loopback's unicast discovery ports pass 65535
        if domain_free(d):
            return d
    raise RuntimeError("no free DDS domain")


def percentile(values: list[float], p: float) -> float:
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, int(p / 100 * len(v)))]


def ms(x: float) -> float:
    return round(x * 1000, 2)


def cpu_seconds(pid: int) -> float:
    """User plus system CPU seconds a process has used (from /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLK_TCK


class Proc:
    """A child process whose CPU time and RSS we can read."""

    def __init__(self, args: list[str], env: dict[str, str] | None = None) -> None:
        self.p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env={**os.environ, **(env or {})})

    def cpu_seconds(self) -> float:
        return cpu_seconds(self.p.pid)

    def rss_mb(self) -> float:
        return int(Path(f"/proc/{self.p.pid}/statm").read_text().split()[1]) * PAGE / 2**20

    def stop(self) -> None:
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGINT)
            try:
                self.p.wait(10)
            except subprocess.TimeoutExpired:
                self.p.kill()


class CpuMeter:
    """Share of one core a process used between start() and read()."""

    def __init__(self, proc: Proc) -> None:
        self.proc = proc
        self.start()

    def start(self) -> None:
        self.t0, self.c0 = time.monotonic(), self.proc.cpu_seconds()

    def read(self) -> float:
        return (self.proc.cpu_seconds() - self.c0) / max(time.monotonic() - self.t0, 1e-9)


@contextmanager
def stack(
    sim_args: list[str] | None = None,
    console_env: dict[str, str] | None = None,
    console_args: list[str] | None = None,
    sim_env: dict[str, str] | None = None,
    domain: int | None = None,
) -> Iterator[dict[str, Any]]:
    """A console (and, unless sim_args is None, a separate simulator) on a spare domain (or `domain`) and port."""
    domain, port = domain if domain is not None else free_domain(), free_port()
    tmp = Path(tempfile.mkdtemp(prefix="sem-bench-"))
    procs: dict[str, Proc] = {}
    try:
        if sim_args is not None:
            procs["sim"] = Proc(
                [
                    str(BIN / "sem-sim"),
                    "--domain",
                    str(domain),
                    "--state-file",
                    str(tmp / "sim.json"),
                    "--log-level",
                    "warning",
                    *sim_args,
                ],
                sim_env,
            )
        procs["console"] = Proc(
            [
                str(BIN / "sem-console"),
                "--domain",
                str(domain),
                "--port",
                str(port),
                "--db",
                str(tmp / "console.sqlite3"),
                "--log-level",
                "warning",
                *(console_args or []),
            ],
            console_env,
        )
        url = f"http://127.0.0.1:{port}"
        wait_http(url + "/api/health")
        yield {"domain": domain, "port": port, "url": url, "ws": f"ws://127.0.0.1:{port}/ws", "procs": procs, "tmp": tmp}
    finally:
        for p in procs.values():
            p.stop()


def wait_http(url: str, timeout: float = 30) -> None:
    import urllib.request

    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            urllib.request.urlopen(url, timeout=1)
            return
        except OSError:
            time.sleep(0.1)
    raise RuntimeError(f"{url} did not answer")


def get_json(url: str, method: str = "GET", timeout: float = 10) -> Any:
    import urllib.request

    req = urllib.request.Request(url, method=method)
    with urllib.request.urlopen(req, timeout=timeout) as r:
        return json.loads(r.read())


def wait_listed(url: str, vehicles: int, timeout: float = 30) -> None:
    """Wait until the console at `url` lists `vehicles` vehicles, then 3 s of warm-up; a figure measured on fewer is
    not the one asked for, so that is one line (SystemExit)."""
    deadline = time.monotonic() + timeout
    while get_json(url + "/api/metrics")["providers"] < vehicles and time.monotonic() < deadline:
        time.sleep(0.5)
    seen = get_json(url + "/api/metrics")["providers"]
    if seen < vehicles:
        raise SystemExit(f"only {seen} of {vehicles} simulated vehicles appeared within {timeout:.0f} s (is sem-sim running?)")
    time.sleep(3)


def report_latency(msg: dict[str, Any], now: float) -> float | None:
    """Seconds from a report's timeStamp (set by its writer) to its arrival here."""
    if msg.get("type") != "report":
        return None
    ts = (msg["report"]["report"] or {}).get("timeStamp") or {}
    if ts.get("seconds") is None:
        return None
    return now - (ts["seconds"] + ts["nanoseconds"] / 1e9)


async def ws_collect(url: str, seconds: float, on_message: Any) -> None:
    """Read the console's WebSocket for `seconds` as the dashboard does (/ws?batch=1: the reports that waited for the
    sender come as one JSON array; not its ack=1, whose window never holds a client that keeps up), calling
    on_message(msg, arrival_time) for each message, those of an array with the array's arrival time."""
    import websockets

    async with websockets.connect(url + ("&" if "?" in url else "?") + "batch=1", max_size=2**26) as ws:
        async for text in for_seconds(ws, seconds):
            now = time.time()  # on arrival, before parsing (as the peer's client does)
            msg = json.loads(text)
            for m in msg if isinstance(msg, list) else [msg]:
                on_message(m, now)


async def for_seconds(ws: Any, seconds: float) -> AsyncIterator[Any]:
    """A websockets connection's messages for `seconds`. One timeout for the whole run, not asyncio.wait_for per
    message: that wraps every recv() in a task of its own, a turn of the event loop or two between a message's
    arrival and its stamp (both latency clients read this way, on one loop)."""
    with contextlib.suppress(TimeoutError):
        async with asyncio.timeout(seconds):
            async for message in ws:
                yield message


def table(title: str, header: list[str], rows: list[list[Any]]) -> None:
    widths = [max(len(str(x)) for x in col) for col in zip(header, *rows, strict=True)]
    print(f"\n{title}")
    print("  ".join(str(h).ljust(w) for h, w in zip(header, widths, strict=True)))
    print("  ".join("-" * w for w in widths))
    for r in rows:
        print("  ".join(str(x).ljust(w) for x, w in zip(r, widths, strict=True)))


RESULTS = Path(os.environ.get("SEM_BENCH_RESULTS", ROOT / "bench" / "results"))  # the docs' benchmark page reads them


def machine() -> dict[str, Any]:
    """What the figures were measured on: they mean little without it."""
    model = next(
        (
            line.split(":", 1)[1].strip()
            for line in Path("/proc/cpuinfo").read_text().splitlines()
            if line.startswith("model name")
        ),
        platform.machine(),
    )
    mem_kib = next(
        int(line.split()[1]) for line in Path("/proc/meminfo").read_text().splitlines() if line.startswith("MemTotal:")
    )
    try:
        from importlib.metadata import version

        cyclone = version("cyclonedds")
    except Exception:  # not installed: the benchmark still reports
        cyclone = None
    return {
        "cores": os.cpu_count(),
        "cpu": model,
        "memoryGiB": round(mem_kib / 2**20, 1),
        "os": f"{platform.system()} {platform.release()}",
        "python": platform.python_version(),
        "cyclonedds": cyclone,
        "loadAverage1m": round(os.getloadavg()[0], 2),
    }


def emit(name: str, figures: dict[str, Any]) -> None:
    """The one JSON line a benchmark ends with, also kept as bench/results/<name>.json (with the date and the
    machine) for the docs' benchmark page (bench/figures.py renders it)."""
    stamped = {
        "bench": name,
        "cores": os.cpu_count(),
        **figures,
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "machine": machine(),
        "command": " ".join(["python", *sys.argv]),
    }
    print(json.dumps(stamped, separators=(",", ":")))
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / f"{name}.json").write_text(json.dumps(stamped, indent=1) + "\n")


def target(name: str, value: float | None, unit: str, op: str, limit: float | None, against: str = "") -> dict[str, Any]:
    """Print one figure beside its target and whether it holds; returns it for the JSON line."""
    ok = (
        value is not None
        and limit is not None
        and value == value
        and limit == limit
        and (value < limit if op == "<" else value <= limit if op == "<=" else value > limit)
    )
    bound = f"{op} {limit} {unit}" + (f" ({against})" if against else "")
    print(f"target  {name}: {value} {unit}, target {bound}: {'holds' if ok else 'MISSED'}")
    return {"name": name, "value": value, "unit": unit, "target": f"{op} {limit}", "holds": ok}
