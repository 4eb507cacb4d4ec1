"""sem-relay over a thin link (docs/relay.md): the bytes per vehicle per hour at the satellite defaults, commands
included, over a 600 ms link; a command's round trip over the thin link (600 ms, 5 % loss, 64 kbit/s), less the
link's round trip and the vehicle's own answer; and one relay carrying many vehicles at full rate on a LAN-class link:
its CPU per 1,000 samples.
Usage: python bench/relay.py [--seconds 120] [--commands 20] [--lan-vehicles 100] [--lan-seconds 30]
"""

from __future__ import annotations

import argparse
import contextlib
import time
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import common
from common import BIN, Proc, emit, free_port, get_json, ms, percentile, table, target, wait_http

RTT = 0.6  # the impaired link's round trip, seconds
RATE_BYTES, LOSS = 8000.0, 0.05  # the thin link the round trip is measured on: 64 kbit/s, 5 % of segments lost


def two_domains() -> tuple[int, int]:
    near = common.free_domain()
    far = common.free_domain()
    while far == near:
        far = common.free_domain()
    return near, far


@contextmanager
def relays(near: int, far: int, *args: str, via: Any = None) -> Iterator[tuple[dict[str, Proc], str]]:
    """A router, the vehicles' relay on `near` (through `via(port)`'s endpoint, if given) and the operations relay on
    `far`; yields the processes and the vehicles' relay's status URL."""
    port, status_port = free_port(), free_port()
    router = f"tcp/127.0.0.1:{port}"
    relay = [str(BIN / "sem-relay"), "--log-level", "warning"]
    procs = {"router": Proc([*relay, "--router", "--listen", router])}
    try:
        procs["near"] = Proc(
            [
                *relay,
                *("--domain", str(near), "--side", "vehicles", "--name", "ship-1"),
                *("--connect", via(port) if via else router, "--status-port", str(status_port), *args),
            ]
        )
        procs["far"] = Proc([*relay, "--domain", str(far), "--side", "operations", "--name", "ops", "--connect", router, *args])
        url = f"http://127.0.0.1:{status_port}/status"
        wait_http(url)
        yield procs, url
    finally:
        for p in procs.values():
            p.stop()


def issued_after(consumer: Any, vehicle: uuid.UUID, statuses: Any) -> tuple[float, uuid.UUID]:
    """Seconds from a GPS fix command's write to its ISSUED status seen (polled every 2 ms), and its session."""
    from sem_console.dds.topics import Service

    t0 = time.perf_counter()
    session = consumer.command(Service.GPS_FIX, vehicle)
    deadline = time.monotonic() + 20
    while statuses.ISSUED not in consumer.commands[session].statuses and time.monotonic() < deadline:
        consumer.pump()
        time.sleep(0.002)
    return time.perf_counter() - t0, session


def command_cycle(consumer: Any, vehicle: uuid.UUID) -> float:
    """A GPS fix command to its end and its cleanup (the dispose, as the console's); its ISSUED delay."""
    from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as S

    took, session = issued_after(consumer, vehicle, S)
    with contextlib.suppress(AssertionError):  # not ended in time: disposed all the same (a cancel)
        consumer.wait_terminal(session, 30)
    consumer.dispose(session)
    return took


def traffic(status: dict[str, Any]) -> dict[str, int]:
    return {v: t["sentBytes"] + t["receivedBytes"] for v, t in status["vehicles"].items()}


@contextmanager
def satellite_link(near: int, far: int, **impairment: float) -> Iterator[tuple[Any, str, Any]]:
    """`sem-sim`'s two vehicles (UMAA 3.0.1 and 6.0) at their default rates on `near`, the satellite link class's relays
    through an Impairment(rtt=RTT, **impairment) to `far`; yields the far domain's consumer, the vehicles' relay's
    status URL and the link, once vehicle 1 has crossed and the first sample of every topic is past."""
    from sem_console.dds.topics import Sem
    from sem_console.sim.provider import vehicle_guid
    from support.consumer import Consumer
    from support.impair import Impairment

    links: list[Impairment] = []

    def impaired(port: int) -> str:
        links.append(Impairment(("127.0.0.1", port), rtt=RTT, **impairment))
        return links[0].endpoint

    sim = Proc(
        [str(BIN / "sem-sim"), "--domain", str(near), "--vehicles", "2", "--umaa-6-0-vehicles", "2", "--log-level", "error"]
    )
    consumer = Consumer(far)
    try:
        with relays(near, far, via=impaired) as (_procs, url):
            consumer.wait(lambda: vehicle_guid(1) in consumer.reports[Sem.GPS_FIX_REPORT], 60, "vehicle 1 across the link")
            time.sleep(5)  # past the first samples of every topic (each instance's first goes at once)
            yield consumer, url, links[0]
    finally:
        consumer.close()
        sim.stop()
        for link in links:
            link.close()


def satellite_run(seconds: float, every: float) -> dict[str, Any]:
    """The bytes per vehicle per hour: the satellite class over a 600 ms link (no loss, no rate limit: a link that
    drops nothing), a GPS fix command to vehicle 1 every `every` seconds, each to its end and cleaned up."""
    from sem_console.sim.provider import vehicle_guid

    v1, v2 = vehicle_guid(1), vehicle_guid(2)  # vehicle 2 speaks UMAA 6.0
    with satellite_link(*two_domains()) as (consumer, url, link):
        s0, b0, t0 = traffic(get_json(url)), link.bytes, time.monotonic()
        commands = 0
        while time.monotonic() - t0 < seconds:
            started = time.monotonic()
            command_cycle(consumer, v1)
            commands += 1
            time.sleep(max(0.0, every - (time.monotonic() - started)))
        s1, b1, t1 = traffic(get_json(url)), link.bytes, time.monotonic()
    hours = (t1 - t0) / 3600
    per_vehicle = {v: (s1.get(v, 0) - s0.get(v, 0)) / hours / 1e6 for v in s1}
    umaa_3, umaa_6 = per_vehicle.get(str(v1), float("nan")), per_vehicle.get(str(v2), float("nan"))
    return {
        "seconds": round(t1 - t0),
        "commands": commands,
        "mb_per_hour_umaa_3_0_1_vehicle": round(umaa_3, 3),  # the one commanded
        "mb_per_hour_umaa_6_0_vehicle": round(umaa_6, 3),
        "mb_per_vehicle_hour_max": round(max(per_vehicle.values()), 3),
        "link_mb_per_vehicle_hour": round((b1 - b0) / hours / 1e6 / max(len(per_vehicle), 1), 3),
    }


def round_trip_run(commands: int, direct: int) -> dict[str, Any]:
    """A command's round trip over the issue's thin link (600 ms round trip, 5 % loss, 64 kbit/s), the satellite class:
    `commands` GPS fix commands to vehicle 1, one after the other, each to its end and cleaned up; then `direct` on the
    vehicles' own domain (the vehicle's own answer: the floor)."""
    from sem_console.sim.provider import vehicle_guid
    from support.consumer import Consumer

    v1 = vehicle_guid(1)
    near, far = two_domains()
    with satellite_link(near, far, rate_bytes=RATE_BYTES, loss=LOSS) as (consumer, _url, link):
        relayed = [command_cycle(consumer, v1) for _ in range(commands)]
        lost = link.lost
        local = Consumer(near, "bench-local")
        try:
            time.sleep(2)  # discovery
            floor = [command_cycle(local, v1) for _ in range(direct)]
        finally:
            local.close()
    return {
        "commands": len(relayed),
        "segments_lost": lost,
        "issued_p50_ms": ms(percentile(relayed, 50)),
        "issued_p99_ms": ms(percentile(relayed, 99)),
        "issued_over_rtt_p50_ms": ms(percentile(relayed, 50) - RTT),
        "direct_issued_p50_ms": ms(percentile(floor, 50)),
        "overhead_p50_ms": ms(percentile(relayed, 50) - RTT - percentile(floor, 50)),
    }


def lan_run(vehicles: int, seconds: float) -> dict[str, Any]:
    """`vehicles` simulated vehicles at their default (full) rates through one relay pair, LAN class: no caps."""
    near, far = two_domains()
    sim = Proc([str(BIN / "sem-sim"), "--domain", str(near), "--vehicles", str(vehicles), "--log-level", "warning"])
    try:
        with relays(near, far, "--link-class", "lan") as (procs, url):
            deadline = time.monotonic() + 120
            while len(get_json(url)["vehicles"]) < vehicles and time.monotonic() < deadline:
                time.sleep(1)
            time.sleep(5)

            def sent() -> int:
                return sum(t["sentMessages"] for t in get_json(url)["vehicles"].values())

            m0, c0, f0, t0 = sent(), procs["near"].cpu_seconds(), procs["far"].cpu_seconds(), time.monotonic()
            time.sleep(seconds)
            m1, c1, f1, t1 = sent(), procs["near"].cpu_seconds(), procs["far"].cpu_seconds(), time.monotonic()
            heard = len(get_json(url)["vehicles"])
    finally:
        sim.stop()
    samples = max(m1 - m0, 1)
    return {
        "vehicles": heard,
        "seconds": round(t1 - t0),
        "samples_per_s": round(samples / (t1 - t0), 1),
        "near_cpu_ms_per_1000": round((c1 - c0) / samples * 1e6, 1),
        "far_cpu_ms_per_1000": round((f1 - f0) / samples * 1e6, 1),
        "near_cpu_share": round((c1 - c0) / (t1 - t0), 2),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=120, help="the bytes run's measured window")
    ap.add_argument("--command-every", type=float, default=10, help="the bytes run: a GPS fix command every this many seconds")
    ap.add_argument("--commands", type=int, default=20, help="the round-trip run's GPS fix commands over the thin link")
    ap.add_argument("--direct", type=int, default=10, help="commands on the vehicles' own domain (the floor)")
    ap.add_argument("--lan-vehicles", type=int, default=100)
    ap.add_argument("--lan-seconds", type=float, default=30)
    args = ap.parse_args()
    sat = satellite_run(args.seconds, args.command_every)
    rtt = round_trip_run(args.commands, args.direct)
    lan = lan_run(args.lan_vehicles, args.lan_seconds)
    table(
        f"Satellite class, 600 ms link (no loss, no rate limit), {sat['seconds']} s, {sat['commands']} commands",
        ["figure", "value"],
        [
            ["MB per hour, UMAA 3.0.1 vehicle, commanded (relay's count)", sat["mb_per_hour_umaa_3_0_1_vehicle"]],
            ["MB per hour, UMAA 6.0 vehicle (relay's count)", sat["mb_per_hour_umaa_6_0_vehicle"]],
            ["MB per vehicle per hour on the link's TCP", sat["link_mb_per_vehicle_hour"]],
        ],
    )
    table(
        f"Satellite class, 600 ms, 5 % loss, 64 kbit/s link, {rtt['commands']} commands ({rtt['segments_lost']} segments lost)",
        ["figure", "value"],
        [
            ["command to ISSUED p50 / p99 ms", f"{rtt['issued_p50_ms']} / {rtt['issued_p99_ms']}"],
            ["command to ISSUED less the link's RTT p50 ms", rtt["issued_over_rtt_p50_ms"]],
            ["same on the vehicles' domain p50 ms", rtt["direct_issued_p50_ms"]],
            ["relay overhead (less RTT and the vehicle's answer) p50 ms", rtt["overhead_p50_ms"]],
        ],
    )
    table(
        f"LAN class, {lan['vehicles']} vehicles at full rate, {lan['seconds']} s",
        ["samples/s", "vehicles' relay CPU ms / 1,000", "operations relay CPU ms / 1,000", "vehicles' relay cores"],
        [[lan["samples_per_s"], lan["near_cpu_ms_per_1000"], lan["far_cpu_ms_per_1000"], lan["near_cpu_share"]]],
    )
    targets = [
        target("bytes per vehicle per hour", sat["mb_per_vehicle_hour_max"], "MB", "<=", 2.0),
        # the relays' overhead: the round trip less the link's and the vehicle's own answer (the same command on its own
        # domain); what is left still holds the command's and its status's time on the 64 kbit/s wire
        target("relay overhead over the link's RTT, p50", rtt["overhead_p50_ms"], "ms", "<=", 50.0),
    ]
    emit("relay", {"satellite": sat, "round_trip": rtt, "lan": lan, "targets": targets})


if __name__ == "__main__":
    main()
