"""The peer: the generic answer a user would otherwise build. A plain cyclonedds-python reader per
report topic feeding Foxglove's WebSocket server (`foxglove-sdk`), every sample published as JSON on
a channel per topic, as it arrives. It runs in a process of its own (so its CPU is measured apart):
    foxglove_peer.py DOMAIN PORT
`peer()` starts it; `foxglove_collect()` subscribes to every channel with the tests' client of the Foxglove WebSocket
protocol (backend/tests/support/foxglove.py) and timestamps arrivals.
"""

from __future__ import annotations

import dataclasses
import enum
import socket
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import common
from common import Proc


def jsonable(x: Any) -> Any:
    """A cyclonedds sample as plain JSON values: what a generic bridge does with any IDL type."""
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return {f.name: jsonable(getattr(x, f.name)) for f in dataclasses.fields(x)}
    if isinstance(x, enum.Enum):
        return x.name
    if isinstance(x, (bytes, bytearray)):
        return list(x)
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    return x


def main() -> None:
    import foxglove
    from cyclonedds.core import WaitSet
    from cyclonedds.util import duration

    from sem_console.codec.decode import REPORT_TOPICS
    from sem_console.dds.bus import Bus, all_samples
    from sem_console.dds.qos import reader_qos

    domain, port = int(sys.argv[1]), int(sys.argv[2])
    server = foxglove.start_server(name="generic-dds-bridge", host="127.0.0.1", port=port)
    bus = Bus(domain)
    topics = []
    for sem, name in REPORT_TOPICS.items():
        reader = bus.reader(sem, reader_qos(sem.spec.cls))  # reliable, transient-local, the latest per instance
        topics.append((reader, all_samples(reader), foxglove.Channel(name, message_encoding="json")))
    ws = WaitSet(bus.participant)
    for _r, cond, _c in topics:
        ws.attach(cond)
    try:
        while True:
            ws.wait(duration(milliseconds=200))
            for reader, cond, channel in topics:
                for sample in reader.take(N=256, condition=cond):
                    if dataclasses.is_dataclass(sample):  # not a dispose
                        channel.log(jsonable(sample))
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()


@contextmanager
def peer(domain: int) -> Iterator[tuple[Proc, str]]:
    """The peer on `domain`: its process and its WebSocket URL, once it listens."""
    port = common.free_port()
    proc = Proc([sys.executable, __file__, str(domain), str(port)])
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError as e:
                if proc.p.poll() is not None or time.monotonic() > deadline:
                    raise RuntimeError(
                        "the Foxglove peer did not start (is foxglove-sdk installed? scripts/bench installs it)"
                    ) from e
                time.sleep(0.1)
        yield proc, f"ws://127.0.0.1:{port}"
    finally:
        proc.stop()


async def foxglove_collect(
    url: str,
    seconds: float,
    on_message: Callable[[str, dict[str, Any], float], None],
    wanted: Callable[[str], bool] = lambda _topic: True,
) -> None:
    """Subscribe to every channel (or those of the topics `wanted` says) for `seconds`, calling on_message(topic,
    sample, arrival_time) per message (a JSON channel's sample decoded, a raw one's {})."""
    from support.foxglove import connect

    async with connect(url) as client:
        subscribed: set[str] = set()
        async for m in common.for_seconds(client.messages(), seconds):
            now = time.time()
            if m is None:  # a text message: subscribe to the channels advertised since
                new = [t for t in client.topics() if t not in subscribed and wanted(t)]
                if new:
                    subscribed.update(new)
                    await client.subscribe(new)
            else:  # a raw (cdr) channel's sample is handed on undecoded, as {}
                is_json = client.topics().get(m.topic, {}).get("encoding") == "json"
                on_message(m.topic, m.json() if is_json else {}, now)


def sample_latency(sample: dict[str, Any], now: float) -> float | None:
    """Seconds from a sample's timeStamp (set by its writer) to its arrival here."""
    ts = sample.get("timeStamp") or {}
    if ts.get("seconds") is None:
        return None
    return now - (ts["seconds"] + ts["nanoseconds"] / 1e9)


if __name__ == "__main__":
    main()
