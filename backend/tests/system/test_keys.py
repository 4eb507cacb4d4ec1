"""`sem-keys` round-trips through an implementation we did not write: OpenSSL verifies what it signs (the S/MIME
documents against the permissions CA, the identities' certificates against the identity CA), as DDS Security's
builtin plugins do."""

from __future__ import annotations

import datetime as dt
import re
import shutil
import stat
import subprocess
import time
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from cryptography import x509
from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication, BuiltinTopicDcpsSubscription

from sem_console.dds.bus import Bus
from sem_console.dds.qos import TopicClass
from sem_console.dds.topics import Sem, Sem60
from sem_console.keys.documents import Role, grants
from sem_console.keys.fleet import Fleet
from support import warm
from test_console import wait_until

pytestmark = [
    pytest.mark.process,
    pytest.mark.skipif(shutil.which("openssl") is None, reason="the openssl command is not installed"),
]

ALL = {s.spec.name for s in (*Sem, *Sem60)} | {"SEMConsole_RelayLink"}  # the SEM topics and the relays' (dds/hops.py)
COMMANDS = {s.spec.name for s in (*Sem, *Sem60) if s.spec.cls is TopicClass.COMMAND}


def keys(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return warm.run(warm.KEYS, list(map(str, args)))


def openssl(*args: str | Path) -> subprocess.CompletedProcess[bytes]:
    return subprocess.run(["openssl", *map(str, args)], capture_output=True, timeout=60)


def smime_verified(fleet: Path, signed: Path) -> bytes:
    """The document `signed` holds, as `openssl smime -verify` returns it once the permissions CA vouches for it."""
    done = openssl("smime", "-verify", "-text", "-CAfile", fleet / "permissions_ca.pem", "-in", signed)
    assert done.returncode == 0, done.stderr
    assert b"Verification successful" in done.stderr
    return done.stdout.replace(b"\r\n", b"\n")


def identity_verifies(fleet: Path, name: str) -> None:
    done = openssl("verify", "-CAfile", fleet / "identity_ca.pem", fleet / "identities" / name / "cert.pem")
    assert done.returncode == 0 and done.stdout.strip().endswith(b": OK"), done


@pytest.fixture
def fleet(tmp_path: Path) -> Path:
    folder = tmp_path / "fleet"
    done = keys("init", folder, "--fleet", "Blue", "--domain", "4", "--domain", "9")
    assert done.returncode == 0, done.stderr
    for name, role in (("vehicle-1", "vehicle"), ("ops", "station"), ("wall", "readonly")):
        done = keys("issue", folder, name, "--role", role)
        assert done.returncode == 0, done.stderr
    return folder


def test_openssl_verifies_the_governance_and_returns_its_document(fleet: Path) -> None:
    document = smime_verified(fleet, fleet / "governance.p7s")
    assert document == (fleet / "governance.xml").read_bytes()
    rule = ET.fromstring(document).find("./domain_access_rules/domain_rule")
    assert rule is not None
    assert [e.text for e in rule.findall("./domains/id")] == ["4", "9"]
    assert rule.findtext("allow_unauthenticated_participants") == "false"
    assert {t.text for t in rule.findall("./topic_access_rules/topic_rule/topic_expression")} == ALL


def test_openssl_verifies_each_identity_and_its_permissions_name_its_certificate(fleet: Path) -> None:
    for name, published, subscribed in (
        ("vehicle-1", ALL - COMMANDS, ALL),
        ("ops", COMMANDS, ALL),
        ("wall", set(), ALL),
    ):
        identity_verifies(fleet, name)
        folder = fleet / "identities" / name
        document = smime_verified(fleet, folder / "permissions.p7s")
        assert document == (folder / "permissions.xml").read_bytes()
        cert = x509.load_pem_x509_certificate((folder / "cert.pem").read_bytes())
        grant = ET.fromstring(document).find("./permissions/grant")
        assert grant is not None
        assert grant.findtext("subject_name") == cert.subject.rfc4514_string()
        assert grant.findtext("validity/not_after") == cert.not_valid_after_utc.strftime("%Y-%m-%dT%H:%M:%SZ")
        assert {t.text for t in grant.findall("./allow_rule/publish/topics/topic")} == published
        assert {t.text for t in grant.findall("./allow_rule/subscribe/topics/topic")} == subscribed
        assert [e.text for e in grant.findall("./allow_rule/domains/id")] == ["4", "9"]
        assert grant.findtext("default") == "DENY"


def test_keys_are_the_owners_only_and_the_snippet_names_the_identitys_files(fleet: Path) -> None:
    for key in (fleet / "identity_ca.key", fleet / "permissions_ca.key", fleet / "identities" / "ops" / "key.pem"):
        assert stat.S_IMODE(key.stat().st_mode) == 0o600, key
    root = ET.fromstring((fleet / "identities" / "ops" / "cyclonedds.xml").read_bytes())
    files = {e.tag.split("}")[1]: e.text for e in root.iter() if len(e) == 0}
    assert files["IdentityCertificate"] == f"file:{fleet / 'identities' / 'ops' / 'cert.pem'}"
    assert files["Governance"] == f"file:{fleet / 'governance.p7s'}"
    for uri in files.values():
        assert uri is not None and Path(uri.removeprefix("file:")).is_file(), uri


def test_reissuing_one_identity_replaces_its_files_only(fleet: Path) -> None:
    def contents() -> dict[Path, tuple[bytes, int]]:
        """Each file's bytes and when it was written: a reissue in the fixture's second writes the same
        permissions.xml (its validity starts at that second), which is still a file written again."""
        return {p: (p.read_bytes(), p.stat().st_mtime_ns) for p in sorted(fleet.rglob("*")) if p.is_file()}

    before = contents()
    done = keys("issue", fleet, "vehicle-1", "--role", "vehicle")
    assert done.returncode == 0, done.stderr
    after = contents()
    assert after.keys() == before.keys()
    written = {p.relative_to(fleet) for p in before if before[p] != after[p]}
    assert {p.parent for p in written} == {Path("identities/vehicle-1")}  # its files only
    assert {"cert.pem", "key.pem", "permissions.xml", "permissions.p7s"} <= {p.name for p in written}
    for name in ("vehicle-1", "ops", "wall"):
        identity_verifies(fleet, name)
        smime_verified(fleet, fleet / "identities" / name / "permissions.p7s")


def test_a_tampered_governance_fails_openssls_verify(fleet: Path) -> None:
    signed = (fleet / "governance.p7s").read_bytes()
    tampered = fleet / "tampered.p7s"
    assert signed.count(b"<allow_unauthenticated_participants>false<") == 1
    tampered.write_bytes(
        signed.replace(b"<allow_unauthenticated_participants>false<", b"<allow_unauthenticated_participants>true<")
    )
    done = openssl("smime", "-verify", "-text", "-CAfile", fleet / "permissions_ca.pem", "-in", tampered)
    assert done.returncode != 0
    assert b"Verification successful" not in done.stderr


def test_a_fleet_of_another_permissions_ca_does_not_verify(fleet: Path, tmp_path: Path) -> None:
    other = tmp_path / "other"
    assert keys("init", other, "--fleet", "Red").returncode == 0
    done = openssl("smime", "-verify", "-text", "-CAfile", other / "permissions_ca.pem", "-in", fleet / "governance.p7s")
    assert done.returncode != 0


def test_the_certificate_lasts_as_asked_within_the_authorities(tmp_path: Path) -> None:
    folder = tmp_path / "short"
    assert keys("init", folder, "--fleet", "Short", "--days", "10").returncode == 0
    assert keys("issue", folder, "a", "--role", "station", "--days", "3").returncode == 0
    assert keys("issue", folder, "b", "--role", "station", "--days", "365").returncode == 0
    ca = x509.load_pem_x509_certificate((folder / "identity_ca.pem").read_bytes())
    a, b = (x509.load_pem_x509_certificate((folder / "identities" / n / "cert.pem").read_bytes()) for n in "ab")
    assert a.not_valid_after_utc - a.not_valid_before_utc == dt.timedelta(days=3)
    assert b.not_valid_after_utc == ca.not_valid_after_utc


def test_bad_input_is_one_line_and_exit_2(fleet: Path, tmp_path: Path) -> None:
    def refusal(*args: str | Path) -> str:
        done = keys(*args)
        assert done.returncode == 2, done
        assert done.stdout == "" and done.stderr.count("\n") == 1 and "Traceback" not in done.stderr, done.stderr
        said = re.fullmatch(r"sem-keys( init| issue)?: error: (.*)\n", done.stderr)
        assert said is not None, done.stderr
        return said.group(2)

    assert refusal("issue", fleet, "x", "--role", "admiral").startswith("--role: invalid choice: 'admiral'")
    empty = tmp_path / "empty"
    assert refusal("issue", empty, "x", "--role", "station") == (
        f"{empty} has no fleet: run `sem-keys init {empty} --fleet NAME` first"
    )
    ca = (fleet / "identity_ca.pem").read_bytes()
    assert refusal("init", fleet, "--fleet", "Blue").startswith(f"{fleet} has a fleet's authorities already: give --force")
    assert (fleet / "identity_ca.pem").read_bytes() == ca
    assert refusal("issue", fleet, "../escape", "--role", "station").startswith("'../escape' is no identity name")
    assert refusal("init", tmp_path / "f2", "--fleet", "a,b").startswith("--fleet 'a,b': use letters")
    assert refusal("init", tmp_path / "f3", "--fleet", "a", "--domain", "300") == "--domain: 300 is outside 0..232"


def test_init_with_force_makes_new_authorities(fleet: Path) -> None:
    old = (fleet / "identity_ca.pem").read_bytes()
    assert keys("init", fleet, "--fleet", "Blue", "--force").returncode == 0
    assert (fleet / "identity_ca.pem").read_bytes() != old
    assert openssl("verify", "-CAfile", fleet / "identity_ca.pem", fleet / "identities" / "ops" / "cert.pem").returncode != 0


def test_expired_or_damaged_authorities_are_one_line_and_exit_2(tmp_path: Path) -> None:
    old = tmp_path / "old"
    Fleet(old).init("Old", [0], 1, False, dt.datetime.now(dt.UTC) - dt.timedelta(days=2))
    done = keys("issue", old, "a", "--role", "station")
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done
    assert done.stderr.startswith(f"sem-keys: error: the fleet's authorities in {old} expired at ")
    assert not (old / "identities" / "a").exists()
    damaged = tmp_path / "damaged"
    assert keys("init", damaged, "--fleet", "D").returncode == 0
    (damaged / "permissions_ca.key").write_text("not a key\n")
    done = keys("issue", damaged, "a", "--role", "station")
    assert (done.returncode, done.stderr) == (
        2,
        f"sem-keys: error: {damaged}/permissions_ca.pem and .key are not what `sem-keys init` writes: run init again "
        "with --force\n",
    )


def test_a_fleet_name_too_long_for_the_authorities_subject_is_one_line_and_writes_nothing(tmp_path: Path) -> None:
    longest, too_long = tmp_path / "longest", tmp_path / "too-long"
    done = keys("init", longest, "--fleet", "F" * 49)
    assert done.returncode == 0, done.stderr
    assert (
        "CN=" + "F" * 49 + " permissions CA"
        in x509.load_pem_x509_certificate((longest / "permissions_ca.pem").read_bytes()).subject.rfc4514_string()
    )
    done = keys("init", too_long, "--fleet", "F" * 50)
    assert (done.returncode, done.stdout) == (2, ""), done
    assert done.stderr.startswith(f"sem-keys: error: --fleet '{'F' * 50}': use letters") and done.stderr.count("\n") == 1
    assert not too_long.exists()


def test_a_link_planted_where_a_key_is_written_gets_no_key(fleet: Path, tmp_path: Path) -> None:
    """A folder others can write to (a shared mount): a name planted where sem-keys writes a key before it takes its
    place must not receive the key, nor become the key's file."""
    loot = tmp_path / "loot"
    loot.write_bytes(b"")
    folder = fleet / "identities" / "vehicle-1"
    for planted in (folder / ".key.pem.tmp", fleet / ".identity_ca.key.tmp"):
        planted.symlink_to(loot)
    assert keys("issue", fleet, "vehicle-1", "--role", "vehicle").returncode == 0
    assert keys("init", fleet, "--fleet", "Blue", "--force").returncode == 0
    assert loot.read_bytes() == b""
    for key in (folder / "key.pem", fleet / "identity_ca.key"):
        assert not key.is_symlink() and stat.S_IMODE(key.stat().st_mode) == 0o600, key
        assert key.read_bytes().startswith(b"-----BEGIN PRIVATE KEY-----")


def test_an_authority_key_kept_encrypted_is_one_line_and_issues_nothing(tmp_path: Path) -> None:
    folder = tmp_path / "fleet"
    assert keys("init", folder, "--fleet", "Blue").returncode == 0
    key = folder / "identity_ca.key"
    plain = key.read_bytes()
    encrypted = openssl("pkey", "-in", key, "-aes256", "-passout", "pass:secret")
    assert encrypted.returncode == 0, encrypted.stderr
    key.write_bytes(encrypted.stdout)
    done = keys("issue", folder, "a", "--role", "station")
    assert (done.returncode, done.stdout) == (2, ""), done
    assert done.stderr.startswith(f"sem-keys: error: {key} is encrypted: ") and done.stderr.count("\n") == 1, done.stderr
    assert not (folder / "identities" / "a").exists()
    key.write_bytes(plain)
    assert keys("issue", folder, "a", "--role", "station").returncode == 0
    identity_verifies(folder, "a")


def test_an_authority_key_that_is_not_its_certificates_is_one_line_and_issues_nothing(tmp_path: Path) -> None:
    """A pair left mismatched (init stopped between a key and its certificate, a key copied over another) signed
    identities no participant would accept."""
    folder = tmp_path / "fleet"
    assert keys("init", folder, "--fleet", "Blue").returncode == 0
    (folder / "identity_ca.key").write_bytes((folder / "permissions_ca.key").read_bytes())
    done = keys("issue", folder, "a", "--role", "station")
    assert (done.returncode, done.stderr) == (
        2,
        f"sem-keys: error: {folder}/identity_ca.pem and .key are not what `sem-keys init` writes: run init again with --force\n",
    )
    assert not (folder / "identities" / "a").exists()


def test_a_vehicle_identity_grants_every_topic_sem_sim_reads_and_writes(
    sim: Callable[..., Any], domain: int, new_bus: Callable[[int], Bus]
) -> None:
    """What the vehicles' program subscribes and publishes, as discovery shows it (Cyclone's DCPSSubscription and
    DCPSPublication), on both UMAA versions: under DDS Security a reader or writer its permissions do not grant is
    refused at creation, and the simulator would not start."""
    bus = new_bus(domain)
    readers = {
        kind: BuiltinDataReader(bus.participant, topic)
        for kind, topic in (("subscribe", BuiltinTopicDcpsSubscription), ("publish", BuiltinTopicDcpsPublication))
    }
    seen: dict[str, set[str]] = {"subscribe": set(), "publish": set()}

    def sim_endpoints() -> bool:
        for kind, reader in readers.items():
            seen[kind] |= {
                e.topic_name
                for e in reader.take(N=1000)
                if e.sample_info.valid_data and e.participant_key != bus.participant.guid
            }
        return seen["subscribe"] >= COMMANDS

    sim("--vehicles", "2", "--umaa-6-0-vehicles", "2")
    wait_until(sim_endpoints, timeout=30, what="the simulator's command readers")
    time.sleep(1)
    sim_endpoints()
    published, subscribed = grants(Role.VEHICLE)
    assert seen["subscribe"] - set(subscribed) == set()
    assert seen["publish"] - set(published) == set()
