"""Cyclone DDS configuration: loopback by default, CYCLONEDDS_URI honoured when set.

CYCLONEDDS_URI, when set and not empty, is the whole configuration, exactly as Cyclone
documents it: a comma-separated list of file paths, `file://` URIs and inline XML fragments,
later ones overriding earlier ones. cyclonedds-python's Domain passes a NULL config to
`dds_create_domain` when given None, and Cyclone then uses its built-in defaults without
reading the variable; so the text of the variable is handed to the Domain here.

Two modes, from the interface and peers settings (SEM_DDS_INTERFACE, SEM_DDS_PEERS):
- peers given (the default, 127.0.0.1): unicast discovery to those peers with multicast
  off. Loopback offers no multicast on Linux, so this is how processes on one host find
  each other; participants take an index (`auto`) so peers know which ports to probe, and
  100 indices leave room for many processes per domain and host.
- no peers (SEM_DDS_PEERS=""): multicast discovery on the interface, as on most vehicle
  networks and on a Docker Compose bridge network.
"""

from __future__ import annotations

import ipaddress
import os
import socket
from xml.sax.saxutils import quoteattr

MAX_PARTICIPANT_INDEX = 100


def loopback_config(interface: str = "lo", peers: str = "127.0.0.1") -> str:
    peer_list = [p.strip() for p in peers.split(",") if p.strip()]
    general = f"<Interfaces><NetworkInterface name={quoteattr(interface)}/></Interfaces>"
    if not peer_list:
        return (
            f'<CycloneDDS><Domain Id="any"><General>{general}<AllowMulticast>true</AllowMulticast></General>'
            '</Domain></CycloneDDS>'
        )
    peer_xml = "".join(f"<Peer address={quoteattr(p)}/>" for p in peer_list)
    return (
        '<CycloneDDS><Domain Id="any">'
        f"<General>{general}<AllowMulticast>false</AllowMulticast></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
        f"<MaxAutoParticipantIndex>{MAX_PARTICIPANT_INDEX}</MaxAutoParticipantIndex>"
        f"<Peers>{peer_xml}</Peers></Discovery>"
        "</Domain></CycloneDDS>"
    )


def peer_problem(peer: str) -> str | None:
    """Why Cyclone could not use `peer` (host, host:port or udp/host:port, IPv4 as the config's transport), or None.
    Cyclone 11 aborts the whole process on such a peer (SIGABRT after "add_peer_address: ...: unknown address",
    a segfault on 0.0.0.0) instead of failing the domain, so the peers are checked before it sees them."""
    host, sep, port = peer.removeprefix("udp/").rpartition(":")
    if not sep:
        host, port = port, ""
    elif not (port.isascii() and port.isdigit() and 0 < int(port) < 65536):
        return f"peer {peer!r}: the port must be 1..65535"
    try:
        addresses = {info[4][0] for info in socket.getaddrinfo(host, None, socket.AF_INET, socket.SOCK_DGRAM)}
    except (socket.gaierror, UnicodeError) as e:
        return f"peer {peer!r} is not an IPv4 address or a host name this machine resolves ({e})"
    if any(ipaddress.ip_address(a).is_unspecified for a in addresses):
        return f"peer {peer!r} is the unspecified address: name the host of a peer"
    return None


def peers_problem(peers: str) -> str | None:
    """The first problem of the peers setting, as one line naming SEM_DDS_PEERS and its fix, or None."""
    for peer in (p.strip() for p in peers.split(",")):
        if peer and (problem := peer_problem(peer)):
            return (
                f"SEM_DDS_PEERS: {problem}: give IPv4 addresses or host names, comma separated (or empty for multicast discovery)"
            )
    return None


def dds_config(interface: str = "lo", peers: str = "127.0.0.1") -> str:
    """The config to create the Domain with: CYCLONEDDS_URI when set, else the loopback/peers config."""
    uri = os.environ.get("CYCLONEDDS_URI", "").strip()
    return uri or loopback_config(interface, peers)


def describe(interface: str = "lo", peers: str = "127.0.0.1") -> str:
    """The configuration `dds_config` gives, in one line for an operator."""
    uri = os.environ.get("CYCLONEDDS_URI", "").strip()
    if uri:
        return f"CYCLONEDDS_URI ({uri if len(uri) <= 80 else uri[:77] + '...'})"
    peer_list = [p.strip() for p in peers.split(",") if p.strip()]
    if peer_list:
        return f"interface {interface}, unicast discovery to {', '.join(peer_list)}"
    return f"interface {interface}, multicast discovery"
