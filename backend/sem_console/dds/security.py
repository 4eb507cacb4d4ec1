"""DDS Security of a process's participant: one identity's documents (the folder `sem-keys issue` writes) checked
before Cyclone DDS sees them, so that a bad one stops the start with one line naming it; the `<Security>`
configuration Cyclone is given; and what the process says about its bus (secured or open, under which identity)."""

from __future__ import annotations

import datetime as dt
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from email import message_from_bytes
from email.message import Message
from pathlib import Path

from cryptography import x509
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives import serialization

# the <Security> elements and the file each is in: the identity's own in its folder, the fleet's three in the folder
# itself or in its fleet's folder (`sem-keys` writes an identity to FLEET/identities/NAME/)
IDENTITY_FILES = {"IdentityCertificate": "cert.pem", "PrivateKey": "key.pem", "Permissions": "permissions.p7s"}
FLEET_FILES = {"IdentityCA": "identity_ca.pem", "PermissionsCA": "permissions_ca.pem", "Governance": "governance.p7s"}
PLUGINS = ("auth", "ac", "crypto")


class SecurityError(Exception):
    """A security document the participant cannot join with: its text is the one line the command prints."""


@dataclass(frozen=True)
class BusSecurity:
    """A secured bus: the identity the participant joins under and where its documents are."""

    identity: str  # the certificate's common name
    subject: str  # the certificate's subject (RFC 4514)
    source: str  # `--dds-security DIR` or CYCLONEDDS_URI
    not_after: dt.datetime | None  # the certificate's end, when the process read it
    config: str = ""  # the <Security> configuration given to Cyclone beside the bus's own ('' under CYCLONEDDS_URI)

    def describe(self) -> str:
        ends = f", certificate valid until {self.not_after:%Y-%m-%d %H:%M} UTC" if self.not_after else ""
        return f"DDS Security as {self.identity} ({self.subject}) from {self.source}{ends}"


OPEN_BUS = (
    "the DDS bus is open: no DDS Security, so any process on the vehicles' network can read every report and "
    "command a vehicle (give --dds-security DIR, see docs/security.md)"
)


def _file(path: Path) -> str:
    return f"file:{path.resolve()}"


def _sub(parent: ET.Element, tag: str, text: str) -> None:
    ET.SubElement(parent, tag).text = text


def _security_root(files: dict[str, Path]) -> ET.Element:
    root = ET.Element("CycloneDDS", {"xmlns": "https://cdds.io/config"})
    security = ET.SubElement(ET.SubElement(root, "Domain", {"Id": "any"}), "Security")
    auth = ET.SubElement(security, "Authentication")
    for tag in ("IdentityCertificate", "PrivateKey", "IdentityCA"):
        _sub(auth, tag, _file(files[tag]))
    access = ET.SubElement(security, "AccessControl")
    for tag in ("Governance", "Permissions", "PermissionsCA"):
        _sub(access, tag, _file(files[tag]))
    return root


def cyclone_xml(files: dict[str, Path]) -> bytes:
    """A Cyclone DDS configuration file (a CYCLONEDDS_URI fragment) with one identity's `<Security>` section, each
    file (by its element's name: IDENTITY_FILES and FLEET_FILES) an absolute file: URI; the security plugins load by
    their default names (dds_security_auth, _ac, _crypto)."""
    root = _security_root(files)
    ET.indent(root)
    return ('<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n").encode()


def fleet_file(folder: Path, tag: str) -> Path:
    """The fleet's file of <Security> element `tag` (FLEET_FILES) for the identity in `folder`: beside its files, else
    in its fleet's folder; the one beside them when neither is there."""
    name = FLEET_FILES[tag]
    return next((f for f in (folder / name, folder.parent.parent / name) if f.is_file()), folder / name)


def identity_files(folder: Path) -> dict[str, Path]:
    """The files of the identity in `folder`, by their <Security> element's name."""
    if not folder.is_dir():
        raise SecurityError(f"--dds-security {folder}: no such folder: give the folder `sem-keys issue` wrote for this identity")
    found = {tag: folder / name for tag, name in IDENTITY_FILES.items()}
    for tag in FLEET_FILES:
        found[tag] = fleet_file(folder, tag)
    for tag, path in found.items():
        if not path.is_file():
            where = "" if tag in IDENTITY_FILES else f" nor in its fleet's folder {folder.parent.parent}"
            raise SecurityError(
                f"--dds-security {folder}: no {path.name} there{where}: copy the fleet's identity_ca.pem, "
                "permissions_ca.pem and governance.p7s beside the identity's files (docs/security.md)"
            )
    return found


def _certificate(path: Path) -> x509.Certificate:
    try:
        return x509.load_pem_x509_certificate(path.read_bytes())
    except (ValueError, OSError) as e:
        raise SecurityError(f"{path} is not a PEM certificate ({e})") from None


def _valid(path: Path, cert: x509.Certificate, what: str, now: dt.datetime, fix: str) -> None:
    if cert.not_valid_after_utc <= now:
        raise SecurityError(f"{path}: the {what} expired at {cert.not_valid_after_utc:%Y-%m-%d %H:%M} UTC: {fix}")
    if cert.not_valid_before_utc > now:
        raise SecurityError(
            f"{path}: the {what} is not valid before {cert.not_valid_before_utc:%Y-%m-%d %H:%M} UTC (check this machine's clock)"
        )


def verify_smime(path: Path, ca: Path) -> bytes:
    """The document signed in `path` once its S/MIME signature verifies against `ca` (with OpenSSL's command, as
    Cyclone's plugin verifies it with OpenSSL's library; without the command, Cyclone's own check is the only one)."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise SecurityError(f"{path} cannot be read ({e.strerror}): write it again with sem-keys") from None
    message = message_from_bytes(data)
    parts = message.get_payload() if message.is_multipart() else None
    if not isinstance(parts, list) or not parts or not isinstance(parts[0], Message):
        raise SecurityError(f"{path} is not an S/MIME signed document: sign it again (sem-keys)")
    document = parts[0].get_payload(decode=True)
    openssl = shutil.which("openssl")
    if openssl is not None:
        run = subprocess.run(
            [openssl, "smime", "-verify", "-CAfile", str(ca), "-in", str(path), "-out", os.devnull],
            capture_output=True,
            check=False,
        )
        if run.returncode != 0:
            raise SecurityError(
                f"{path}: its signature does not verify against the permissions CA {ca} (changed after it was "
                "signed, or signed by another fleet): sign it again with sem-keys"
            )
    return document if isinstance(document, bytes) else b""


def rdns(subject: str) -> set[tuple[str, str]]:
    """A distinguished name as a set of (attribute, value), the way DDS Security compares a grant's subject."""
    return {(k.strip().upper(), v.strip()) for k, _, v in (p.partition("=") for p in re.split(r"(?<!\\),", subject) if p.strip())}


def _instant(text: str | None) -> dt.datetime | None:
    try:
        return dt.datetime.strptime((text or "").strip(), "%Y-%m-%dT%H:%M:%SZ").replace(tzinfo=dt.UTC)
    except ValueError:
        return None


def _granted(path: Path, document: bytes, subject: x509.Name, now: dt.datetime) -> None:
    """A grant of the permissions names the certificate's subject and is valid now."""
    try:
        root = ET.fromstring(document)
    except ET.ParseError as e:
        raise SecurityError(f"{path}: its permissions are not XML ({e})") from None
    wanted = rdns(subject.rfc4514_string())
    for grant in root.iter("grant"):
        if rdns(grant.findtext("subject_name") or "") != wanted:
            continue
        start, end = _instant(grant.findtext("validity/not_before")), _instant(grant.findtext("validity/not_after"))
        if end is not None and end <= now:
            raise SecurityError(
                f"{path}: the grant of {subject.rfc4514_string()} ended at {end:%Y-%m-%d %H:%M} UTC: issue the identity again"
            )
        if start is not None and start > now:
            raise SecurityError(
                f"{path}: the grant of {subject.rfc4514_string()} starts at {start:%Y-%m-%d %H:%M} UTC "
                "(check this machine's clock)"
            )
        return
    raise SecurityError(
        f"{path}: no grant for the certificate's subject {subject.rfc4514_string()}: "
        "the permissions and the certificate are of different identities (issue the identity again)"
    )


def load(folder: Path, now: dt.datetime | None = None) -> BusSecurity:
    """The identity in `folder`, its documents checked as Cyclone's plugins will check them; SecurityError (one line)
    for the first that would keep the participant off the bus."""
    now = now or dt.datetime.now(dt.UTC)
    files = identity_files(folder)
    fix = "issue the identity again (sem-keys issue FLEET NAME --role ROLE) and hand it over"
    ca = _certificate(files["IdentityCA"])
    _valid(files["IdentityCA"], ca, "identity CA", now, "the fleet needs new authorities (sem-keys init --force)")
    cert = _certificate(files["IdentityCertificate"])
    _valid(files["IdentityCertificate"], cert, "identity's certificate", now, fix)
    try:
        cert.verify_directly_issued_by(ca)
    except (ValueError, TypeError, InvalidSignature):
        raise SecurityError(
            f"{files['IdentityCertificate']} is not signed by the identity CA {files['IdentityCA']}: {fix}"
        ) from None
    try:
        key = serialization.load_pem_private_key(files["PrivateKey"].read_bytes(), None)
    except (ValueError, TypeError, OSError) as e:
        raise SecurityError(f"{files['PrivateKey']} is not an unencrypted PEM private key ({e})") from None
    if key.public_key() != cert.public_key():
        raise SecurityError(f"{files['PrivateKey']} is not the key of {files['IdentityCertificate']}: {fix}")
    perm_ca = _certificate(files["PermissionsCA"])
    _valid(files["PermissionsCA"], perm_ca, "permissions CA", now, "the fleet needs new authorities (sem-keys init --force)")
    verify_smime(files["Governance"], files["PermissionsCA"])
    _granted(files["Permissions"], verify_smime(files["Permissions"], files["PermissionsCA"]), cert.subject, now)
    names = cert.subject.get_attributes_for_oid(x509.NameOID.COMMON_NAME)
    return BusSecurity(
        identity=str(names[0].value) if names else cert.subject.rfc4514_string(),
        subject=cert.subject.rfc4514_string(),
        source=f"--dds-security {folder}",
        not_after=cert.not_valid_after_utc,
        config=ET.tostring(_security_root(files), encoding="unicode"),
    )


def _uri_certificate(text: str, domain_id: int) -> str | None:
    """The <IdentityCertificate> of a configuration's <Security> that applies to `domain_id` (outside any <Domain>, or
    in one whose Id is `any`, absent or this id, as Cyclone applies them), or None; in a text that is not XML, its
    first such element."""
    try:
        root = ET.fromstring(f"<uri>{re.sub(r'^<[?]xml[^>]*[?]>', '', text.strip())}</uri>")
    except ET.ParseError:
        match = re.search(r"<IdentityCertificate>\s*([^<]*?)\s*</IdentityCertificate>", text)
        return match.group(1) if match else None
    parents = {child: parent for parent in root.iter() for child in parent}
    for element in root.iter():
        if element.tag.rpartition("}")[2] != "IdentityCertificate" or not (element.text or "").strip():
            continue
        domain = parents.get(element)
        while domain is not None and domain.tag.rpartition("}")[2] != "Domain":
            domain = parents.get(domain)
        if domain is None or domain.get("Id", "any") in ("any", str(domain_id)):
            return (element.text or "").strip()
    return None


def from_uri(uri: str, domain_id: int) -> BusSecurity | None:
    """The identity a CYCLONEDDS_URI's <Security> section for `domain_id` names (its certificate's subject when it can
    be read), or None when the URI has none for that domain. Only inline XML and files are looked in; Cyclone checks
    the documents."""
    for item in (i.strip() for i in uri.split(",")):
        text = item
        if not item.startswith("<"):
            try:
                text = Path(item.removeprefix("file://")).read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                continue
        location = _uri_certificate(text, domain_id)
        if location is None:
            continue
        subject, identity, not_after = "", "(unknown)", None
        if location.startswith("file:"):
            try:
                cert = x509.load_pem_x509_certificate(Path(location.removeprefix("file:")).read_bytes())
                subject = cert.subject.rfc4514_string()
                names = cert.subject.get_attributes_for_oid(x509.NameOID.COMMON_NAME)
                identity = str(names[0].value) if names else subject
                not_after = cert.not_valid_after_utc
            except (OSError, ValueError):
                pass
        return BusSecurity(identity=identity, subject=subject, source="CYCLONEDDS_URI", not_after=not_after)
    return None


def plugins_missing() -> str | None:
    """Why this process's Cyclone DDS cannot run DDS Security (PyPI's wheel has no security plugins), or None."""
    from cyclonedds import __library__

    lib = Path(str(__library__.library_path)).resolve()
    have = {p: any(lib.parent.glob(f"libdds_security_{p}.so*")) for p in PLUGINS}
    if all(have.values()):
        return None
    return (
        f"this Cyclone DDS ({lib}) has no DDS Security plugins (PyPI's wheel has none): build the secure one with "
        "scripts/setup.sh --secure and run the command with scripts/secure (docs/security.md)"
    )
