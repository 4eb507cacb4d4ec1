"""`sem-check --security-profile`: a fleet's documents from `sem-keys`, signed with the fleet's permissions CA and
verified with OpenSSL, held to the project's security profile; each problem made by editing a sem-keys document is
flagged under its test's name."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric import ec

from sem_console.check.cli import main
from sem_console.check.profile import BUS, COMMANDS, JOIN, NAMES, SIGNATURES, TOPICS, UNAUTHENTICATED
from sem_console.dds.qos import TopicClass
from sem_console.keys.cli import main as keys
from sem_console.keys.documents import sem_topics
from sem_console.keys.fleet import sign_smime

pytestmark = [
    pytest.mark.process,  # OpenSSL verifies the signatures, as Cyclone's access control plugin does
    pytest.mark.skipif(shutil.which("openssl") is None, reason="the openssl command is not installed"),
]

COMMAND = next(name for name, cls in sem_topics() if cls is TopicClass.COMMAND)


@pytest.fixture
def fleet(tmp_path: Path) -> Path:
    folder = tmp_path / "fleet"
    assert keys(["init", str(folder), "--fleet", "Test Fleet", "--domain", "7"]) == 0
    for name, role in (("station-1", "station"), ("usv-1", "vehicle"), ("display", "readonly")):
        assert keys(["issue", str(folder), name, "--role", role]) == 0
    return folder


def resign(fleet: Path, xml: Path, signed: Path, old: str, new: str) -> None:
    """`xml` with its first `old` made `new`, signed again by the fleet's permissions CA into `signed`."""
    text = xml.read_text(encoding="utf-8")
    assert old in text
    cert = x509.load_pem_x509_certificate((fleet / "permissions_ca.pem").read_bytes())
    key = serialization.load_pem_private_key((fleet / "permissions_ca.key").read_bytes(), None)
    assert isinstance(key, ec.EllipticCurvePrivateKey)
    signed.write_bytes(sign_smime(text.replace(old, new, 1).encode(), cert, key))


def check(folder: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, dict[str, str]]:
    """sem-check's exit code and its table's line of each test, by name."""
    code = main(["--security-profile", str(folder)])
    lines = capsys.readouterr().out.splitlines()
    return code, {line.split()[0]: line for line in lines if line.startswith("profile.")}


def failed(rows: dict[str, str]) -> set[str]:
    return {name for name, line in rows.items() if line.split()[1] == "FAIL"}


def test_a_fleet_before_its_first_identity_checks_its_governance(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert keys(["init", str(tmp_path / "fleet"), "--fleet", "Test Fleet"]) == 0
    code, rows = check(tmp_path / "fleet", capsys)
    assert code == 0 and rows[COMMANDS].split()[1] == "skip", rows


def test_sem_keys_own_fleet_and_each_identity_pass(fleet: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, rows = check(fleet, capsys)
    assert code == 0, rows
    assert sorted(rows) == sorted(NAMES) and all(line.split()[1] == "pass" for line in rows.values())
    for name in ("station-1", "usv-1", "display"):
        assert check(fleet / "identities" / name, capsys)[0] == 0


@pytest.mark.parametrize(
    ("old", "new", "name", "says"),
    [
        (
            "<allow_unauthenticated_participants>false",
            "<allow_unauthenticated_participants>true",
            UNAUTHENTICATED,
            "allow_unauthenticated_participants is true",
        ),
        ("<enable_join_access_control>true", "<enable_join_access_control>false", JOIN, "enable_join_access_control is false"),
        ("<rtps_protection_kind>ENCRYPT", "<rtps_protection_kind>NONE", BUS, "rtps_protection_kind is NONE"),
        ("<discovery_protection_kind>ENCRYPT", "<discovery_protection_kind>NONE", BUS, "discovery_protection_kind is NONE"),
        (
            "<enable_write_access_control>true",
            "<enable_write_access_control>false",
            TOPICS,
            "has enable_write_access_control false",
        ),
        ("<enable_read_access_control>true", "<enable_read_access_control>false", TOPICS, "has enable_read_access_control false"),
        ("<data_protection_kind>ENCRYPT", "<data_protection_kind>NONE", TOPICS, "has data_protection_kind NONE"),
        (
            "<topic_access_rules>",
            "<topic_access_rules><topic_rule><topic_expression>*</topic_expression>"
            "<enable_read_access_control>false</enable_read_access_control></topic_rule>",
            TOPICS,
            "the topic rule '*'",
        ),
    ],
)
def test_a_governance_off_the_profile_is_flagged_by_name(
    fleet: Path, capsys: pytest.CaptureFixture[str], old: str, new: str, name: str, says: str
) -> None:
    resign(fleet, fleet / "governance.xml", fleet / "governance.p7s", old, new)
    code, rows = check(fleet, capsys)
    assert code == 1
    assert failed(rows) == {name}, rows
    assert says in rows[name] and "sign it again with the fleet's permissions CA" in rows[name]


@pytest.mark.parametrize(
    ("old", "new", "name", "says"),
    [
        ("<id>7</id>", "<id>8</id>", JOIN, "no domain_rule covers the domain 7"),
        ("<domain_rule>", "<domain_rule_off>", JOIN, "no domain_rule covers the domain 7"),
        (f"<topic_expression>{COMMAND}<", "<topic_expression>Other<", TOPICS, f"no topic rule covers {COMMAND},"),
    ],
)
def test_a_governance_that_leaves_the_fleet_s_domain_or_a_topic_without_a_rule_is_flagged(
    fleet: Path, capsys: pytest.CaptureFixture[str], old: str, new: str, name: str, says: str
) -> None:
    xml = fleet / "governance.xml"
    if old == "<domain_rule>":
        xml.write_text(xml.read_text(encoding="utf-8").replace("</domain_rule>", "</domain_rule_off>"), encoding="utf-8")
    resign(fleet, xml, fleet / "governance.p7s", old, new)
    code, rows = check(fleet, capsys)
    assert code == 1 and name in failed(rows), rows
    assert says in rows[name], rows


def test_a_command_topic_granted_to_an_identity_not_a_station_is_flagged(fleet: Path, capsys: pytest.CaptureFixture[str]) -> None:
    display = fleet / "identities" / "display"
    grant = f"<publish><topics><topic>{COMMAND}</topic></topics></publish><subscribe>"
    resign(fleet, display / "permissions.xml", display / "permissions.p7s", "<subscribe>", grant)
    code, rows = check(fleet, capsys)
    assert code == 1
    assert failed(rows) == {COMMANDS}, rows
    assert "'display_readonly'" in rows[COMMANDS] and f"command topic {COMMAND}" in rows[COMMANDS]
    assert check(display, capsys)[0] == 1
    # a vehicle granted every topic by a wildcard publishes every command topic
    usv = fleet / "identities" / "usv-1"
    resign(fleet, usv / "permissions.xml", usv / "permissions.p7s", "<publish>\n", "<publish><topics><topic>*</topic></topics>")
    assert "(vehicle, not a station)" in check(usv, capsys)[1][COMMANDS]
    # a station may
    assert check(fleet / "identities" / "station-1", capsys)[0] == 0


@pytest.mark.parametrize(("domains", "flagged"), [("<id>99</id>", True), ("<id_range><min>5</min></id_range>", False)])
def test_a_deny_rule_holds_a_command_topic_only_on_its_domains(
    fleet: Path, capsys: pytest.CaptureFixture[str], domains: str, flagged: bool
) -> None:
    display = fleet / "identities" / "display"
    xml = display / "permissions.xml"
    deny = f"<deny_rule><domains>{domains}</domains><publish><topics><topic>{COMMAND}</topic></topics></publish></deny_rule>"
    xml.write_text(xml.read_text(encoding="utf-8").replace("<allow_rule>", deny + "<allow_rule>", 1), encoding="utf-8")
    grant = f"<publish><topics><topic>{COMMAND}</topic></topics></publish><subscribe>"
    resign(fleet, xml, display / "permissions.p7s", "<subscribe>", grant)
    code, rows = check(display, capsys)
    assert (code, failed(rows)) == ((1, {COMMANDS}) if flagged else (0, set())), rows


def test_a_tampered_document_is_one_line_naming_it(fleet: Path, capsys: pytest.CaptureFixture[str]) -> None:
    signed = fleet / "governance.p7s"
    text = signed.read_text(encoding="utf-8")
    signed.write_text(text.replace("<rtps_protection_kind>ENCRYPT", "<rtps_protection_kind>NONE", 1), encoding="utf-8")
    code = main(["--security-profile", str(fleet)])
    out = capsys.readouterr().out
    assert code == 1
    rows = [line for line in out.splitlines() if line.startswith(SIGNATURES)]
    assert len(rows) == 1 and "FAIL" in rows[0]
    assert re.search(r"governance\.p7s: its signature does not verify against the permissions CA", rows[0])
    skipped = {line.split()[0] for line in out.splitlines() if line.startswith("profile.") and line.split()[1] == "skip"}
    assert skipped == {UNAUTHENTICATED, JOIN, BUS, TOPICS}


def test_a_permissions_document_that_cannot_be_read_is_one_line(fleet: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (fleet / "identities" / "stray" / "permissions.p7s").mkdir(parents=True)
    code, rows = check(fleet, capsys)
    assert code == 1 and failed(rows) == {SIGNATURES}, rows
    assert "stray/permissions.p7s cannot be read (Is a directory): write it again with sem-keys" in rows[SIGNATURES]


def test_a_folder_without_documents_is_one_line_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--security-profile", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"sem-check: --security-profile {tmp_path}: no governance.p7s there: give the folder sem-keys init wrote (the "
        "fleet's) or sem-keys issue wrote (an identity's, its fleet's files beside it or two folders up)"
    ]
