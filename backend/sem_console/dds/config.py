"""Cyclone DDS configuration: loopback by default, CYCLONEDDS_URI honoured when set.

On loopback Linux offers no multicast, so discovery is unicast to the listed peers.
Participants then need a participant index (``auto``) so that peers know which
ports to probe; 100 indices leave room for many processes on one host per domain.
"""

from __future__ import annotations

import os
from xml.sax.saxutils import quoteattr

MAX_PARTICIPANT_INDEX = 100


def loopback_config(interface: str = "lo", peers: str = "127.0.0.1") -> str:
    peer_xml = "".join(f"<Peer address={quoteattr(p.strip())}/>" for p in peers.split(",") if p.strip())
    return (
        '<CycloneDDS><Domain Id="any">'
        f"<General><Interfaces><NetworkInterface name={quoteattr(interface)}/></Interfaces>"
        "<AllowMulticast>false</AllowMulticast></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
        f"<MaxAutoParticipantIndex>{MAX_PARTICIPANT_INDEX}</MaxAutoParticipantIndex>"
        f"<Peers>{peer_xml}</Peers></Discovery>"
        "</Domain></CycloneDDS>"
    )


def dds_config(interface: str = "lo", peers: str = "127.0.0.1") -> str | None:
    """The config to create the Domain with, or None to let Cyclone read CYCLONEDDS_URI."""
    if os.environ.get("CYCLONEDDS_URI"):
        return None
    return loopback_config(interface, peers)
