"""Which DDS domains are in use on this host, for the tests and the benchmarks that pick a domain of their own."""

from __future__ import annotations

import os
import socket


def udp_free(port: int) -> bool:
    """Whether UDP `port` on 127.0.0.1 can be bound now."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("127.0.0.1", port))
            return True
        except OSError:
            return False


def own_udp_ports() -> set[int]:
    """The UDP ports this process has bound (Linux: its socket inodes in /proc/net/udp), e.g. by the participants of
    earlier tests in this pytest worker, which live as long as the worker."""
    inodes = set()
    for fd in os.listdir("/proc/self/fd"):
        try:
            link = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:
            continue
        if link.startswith("socket:["):
            inodes.add(link[8:-1])
    ports = set()
    for table in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(table, encoding="ascii") as f:
                rows = f.read().splitlines()[1:]
        except OSError:
            continue
        for row in rows:
            fields = row.split()
            if len(fields) > 9 and fields[9] in inodes:
                ports.add(int(fields[1].rsplit(":", 1)[1], 16))
    return ports


def domain_ports(d: int) -> list[int]:
    """The ports a Cyclone participant in domain `d` binds first: with multicast its discovery port (7400 + 250 d); on
    loopback's unicast peers (our configuration) only its own unicast discovery port, 7410 + 250 d + 2 i for
    participant index i (0 for the first, then up)."""
    return [7400 + 250 * d, *(7410 + 250 * d + 2 * i for i in range(4))]


def domain_free(d: int, own_ok: bool = True) -> bool:
    """No other process on this host has a participant in domain `d`; with `own_ok` False, none of this process's
    either (participants left by earlier tests in a pytest worker live as long as the worker, and some keep
    writing)."""
    ports = domain_ports(d)
    if all(udp_free(p) for p in ports):
        return True
    if not own_ok:
        return False
    own = own_udp_ports()
    return all(p in own or udp_free(p) for p in ports)
