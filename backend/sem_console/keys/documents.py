"""The DDS Security 1.1 documents as XML: the fleet's governance, an identity's permissions drawn from its role, and
the Cyclone DDS configuration that points a participant at them."""

from __future__ import annotations

import datetime as dt
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from enum import Enum
from pathlib import Path

from sem_console.dds.hops import TOPIC as RELAY_LINK
from sem_console.dds.qos import TopicClass
from sem_console.dds.security import cyclone_xml as security_config
from sem_console.dds.topics import Sem, Sem60

PERMISSIONS_XSD = "http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd"
GOVERNANCE_XSD = "http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd"
XSI = "http://www.w3.org/2001/XMLSchema-instance"


# The project's security profile: what the fleet's governance sets for each domain and for every SEM topic (in
# this order, the governance schema's), and what `sem-check --security-profile` holds a governance to.
DOMAIN_PROFILE = {
    "allow_unauthenticated_participants": "false",
    "enable_join_access_control": "true",
    "discovery_protection_kind": "ENCRYPT",
    "liveliness_protection_kind": "ENCRYPT",
    "rtps_protection_kind": "ENCRYPT",
}
TOPIC_PROFILE = {
    "enable_discovery_protection": "true",
    "enable_liveliness_protection": "true",
    "enable_read_access_control": "true",
    "enable_write_access_control": "true",
    "metadata_protection_kind": "ENCRYPT",
    "data_protection_kind": "ENCRYPT",
}


class Role(str, Enum):
    """What an identity may do on the bus."""

    VEHICLE = "vehicle"  # publishes its reports, statuses and acks; reads everything
    STATION = "station"  # reads everything; writes commands
    READONLY = "readonly"  # reads everything; writes nothing


def sem_topics() -> list[tuple[str, TopicClass]]:
    """Every SEM topic of both UMAA versions and its class, in the topic tables' order."""
    return [(s.spec.name, s.spec.cls) for s in (*Sem, *Sem60)]


def grants(role: Role) -> tuple[list[str], list[str]]:
    """(topics published, topics subscribed) of a role. Every role reads every SEM topic: a vehicle's program reads
    the reports (a second process must not speak for its vehicles) and its command statuses (where a command stood
    when it restarted) besides the commands (sim/provider.py). The project's own topic of the relays (dds/hops.py) is
    read by every role (a console marks the vehicles a relay carries) and written by a vehicle identity: an operations
    side's sem-relay speaks for the vehicles it carries, as a vehicle."""
    topics = sem_topics()
    commands = [name for name, cls in topics if cls is TopicClass.COMMAND]
    everything = [name for name, _ in topics] + [RELAY_LINK]
    if role is Role.VEHICLE:
        return [name for name, cls in topics if cls is not TopicClass.COMMAND] + [RELAY_LINK], everything
    return (commands if role is Role.STATION else []), everything


def _sub(parent: ET.Element, tag: str, text: str | None = None) -> ET.Element:
    child = ET.SubElement(parent, tag)
    if text is not None:
        child.text = text
    return child


def _root(schema: str) -> ET.Element:
    return ET.Element("dds", {"xmlns:xsi": XSI, "xsi:noNamespaceSchemaLocation": schema})


def _domains(parent: ET.Element, domains: Iterable[int]) -> None:
    node = _sub(parent, "domains")
    for d in domains:
        _sub(node, "id", str(d))


def _text(root: ET.Element) -> bytes:
    ET.indent(root)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n").encode()


def governance_xml(domains: Sequence[int]) -> bytes:
    """The fleet's governance: only authenticated participants that its permissions let join, discovery, liveliness,
    every RTPS message and every SEM topic's data encrypted, reads and writes under access control."""
    root = _root(GOVERNANCE_XSD)
    rule = _sub(_sub(root, "domain_access_rules"), "domain_rule")
    _domains(rule, domains)
    for tag, value in DOMAIN_PROFILE.items():
        _sub(rule, tag, value)
    rules = _sub(rule, "topic_access_rules")
    for name in [name for name, _cls in sem_topics()] + [RELAY_LINK]:
        topic = _sub(rules, "topic_rule")
        _sub(topic, "topic_expression", name)
        for tag, value in TOPIC_PROFILE.items():
            _sub(topic, tag, value)
    return _text(root)


def _instant(t: dt.datetime) -> str:
    """DDS Security's validity instant, CCYY-MM-DDThh:mm:ssZ in UTC."""
    return t.astimezone(dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def permissions_xml(
    name: str, subject: str, role: Role, domains: Sequence[int], not_before: dt.datetime, not_after: dt.datetime
) -> bytes:
    """An identity's permissions: one grant for its certificate's subject, valid as long as the certificate, allowing
    its role's topics on the fleet's domains and denying everything else."""
    root = _root(PERMISSIONS_XSD)
    grant = ET.SubElement(_sub(root, "permissions"), "grant", {"name": f"{name}_{role.value}"})
    _sub(grant, "subject_name", subject)
    validity = _sub(grant, "validity")
    _sub(validity, "not_before", _instant(not_before))
    _sub(validity, "not_after", _instant(not_after))
    allow = _sub(grant, "allow_rule")
    _domains(allow, domains)
    publish, subscribe = grants(role)
    for kind, topics in (("publish", publish), ("subscribe", subscribe)):
        if topics:
            node = _sub(_sub(allow, kind), "topics")
            for topic in topics:
                _sub(node, "topic", topic)
    _sub(grant, "default", "DENY")
    return _text(root)


def cyclone_xml(
    identity_ca: Path, certificate: Path, private_key: Path, permissions_ca: Path, governance: Path, permissions: Path
) -> bytes:
    """A Cyclone DDS configuration (a CYCLONEDDS_URI fragment) with one identity's `<Security>` section (the one a
    participant joins with: dds/security.py)."""
    return security_config(
        {
            "IdentityCA": identity_ca,
            "IdentityCertificate": certificate,
            "PrivateKey": private_key,
            "PermissionsCA": permissions_ca,
            "Governance": governance,
            "Permissions": permissions,
        }
    )
