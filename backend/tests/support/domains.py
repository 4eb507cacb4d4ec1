"""Which DDS domains are in use on this host, for the tests and the benchmarks that pick a domain of their own."""

from __future__ import annotations

import socket


def udp_free(port: int) -> bool:
    """Whether UDP `port` on 127.0.0.1 can be bound now."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind(("127.0.0.1", port))
            return True
        except OSError:
            return False


def domain_free(d: int) -> bool:
    """No Cyclone participant on this host in domain `d`: with multicast its discovery port (7400 + 250 d) is bound;
    on loopback's unicast peers (our configuration) only a participant's own unicast discovery port is,
    7410 + 250 d + 2 i for participant index i (0 for the first), so the first indexes are looked at too."""
    return all(udp_free(port) for port in [7400 + 250 * d, *(7410 + 250 * d + 2 * i for i in range(10))])
