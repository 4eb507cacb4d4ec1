"""sem-keys' documents as XML: the governance, the permissions drawn from each role and the Cyclone DDS snippet
(no files, no process)."""

from __future__ import annotations

import datetime as dt
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import Sem, Sem60
from sem_console.keys.documents import Role, cyclone_xml, governance_xml, grants, permissions_xml

ALL_ORDER = [s.spec.name for s in (*Sem, *Sem60)] + ["SEMConsole_RelayLink"]  # the SEM topics, and the relays' (dds/hops.py)
ALL = set(ALL_ORDER)
COMMANDS = {s.spec.name for s in (*Sem, *Sem60) if s.spec.cls is TopicClass.COMMAND}
T0 = dt.datetime(2026, 11, 29, 7, 0, tzinfo=dt.UTC)


def texts(root: ET.Element, path: str) -> list[str]:
    return [e.text or "" for e in root.findall(path)]


def test_the_governance_admits_only_the_authenticated_and_encrypts_every_topic() -> None:
    root = ET.fromstring(governance_xml([0, 7]))
    rules = root.findall("./domain_access_rules/domain_rule")
    assert len(rules) == 1
    rule = rules[0]
    assert texts(rule, "./domains/id") == ["0", "7"]
    assert texts(rule, "allow_unauthenticated_participants") == ["false"]
    assert texts(rule, "enable_join_access_control") == ["true"]
    for kind in ("discovery", "liveliness", "rtps"):
        assert texts(rule, f"{kind}_protection_kind") == ["ENCRYPT"]
    topics = rule.findall("./topic_access_rules/topic_rule")
    assert {t.findtext("topic_expression") for t in topics} == ALL
    assert len(topics) == len(ALL) == 17  # 10 topics of UMAA 3.0.1, 6 of 6.0, the relays' own
    for t in topics:
        assert t.findtext("data_protection_kind") == "ENCRYPT"
        assert t.findtext("metadata_protection_kind") == "ENCRYPT"
        assert t.findtext("enable_read_access_control") == "true"
        assert t.findtext("enable_write_access_control") == "true"


@pytest.mark.parametrize(
    ("role", "published", "subscribed"),
    [
        (Role.VEHICLE, ALL - COMMANDS, ALL),
        (Role.STATION, COMMANDS, ALL),  # a console reads the relays' topic, and writes only commands
        (Role.READONLY, set(), ALL),
    ],
)
def test_a_roles_permissions_grant_its_topics_and_deny_the_rest(role: Role, published: set[str], subscribed: set[str]) -> None:
    root = ET.fromstring(permissions_xml("alpha", "O=Fleet,OU=x,CN=alpha", role, [3], T0, T0 + dt.timedelta(days=2)))
    (grant,) = root.findall("./permissions/grant")
    assert grant.get("name") == f"alpha_{role.value}"
    assert grant.findtext("subject_name") == "O=Fleet,OU=x,CN=alpha"
    assert grant.findtext("validity/not_before") == "2026-11-29T07:00:00Z"
    assert grant.findtext("validity/not_after") == "2026-12-01T07:00:00Z"
    (allow,) = grant.findall("allow_rule")
    assert texts(allow, "./domains/id") == ["3"]
    assert set(texts(allow, "./publish/topics/topic")) == published
    assert set(texts(allow, "./subscribe/topics/topic")) == subscribed
    assert (allow.find("publish") is None) == (not published)
    assert grant.findall("deny_rule") == []
    assert texts(grant, "default") == ["DENY"]
    assert grants(role) == ([t for t in ALL_ORDER if t in published], [t for t in ALL_ORDER if t in subscribed])


def test_a_vehicle_writes_no_command_and_only_a_station_does() -> None:
    for role in Role:
        published, _ = grants(role)
        assert bool(COMMANDS & set(published)) == (role is Role.STATION)


def test_the_cyclone_snippet_names_every_file_as_an_absolute_file_uri(tmp_path: Path) -> None:
    names = ("ica.pem", "cert.pem", "key.pem", "pca.pem", "gov.p7s", "perm.p7s")
    root = ET.fromstring(cyclone_xml(*(tmp_path / n for n in names)))
    ns = {"c": "https://cdds.io/config"}
    assert root.tag == "{https://cdds.io/config}CycloneDDS"
    (domain,) = root.findall("c:Domain", ns)
    assert domain.get("Id") == "any"
    security = domain.find("c:Security", ns)
    assert security is not None
    got = {e.tag.split("}")[1]: e.text for e in security.iter() if len(e) == 0}
    assert got == {
        "IdentityCA": f"file:{tmp_path}/ica.pem",
        "IdentityCertificate": f"file:{tmp_path}/cert.pem",
        "PrivateKey": f"file:{tmp_path}/key.pem",
        "PermissionsCA": f"file:{tmp_path}/pca.pem",
        "Governance": f"file:{tmp_path}/gov.p7s",
        "Permissions": f"file:{tmp_path}/perm.p7s",
    }
    assert [e.tag.split("}")[1] for e in security] == ["Authentication", "AccessControl"]
