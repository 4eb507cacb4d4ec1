"""A fleet's keys on disk: its two authorities, its signed governance and one folder per identity."""

from __future__ import annotations

import datetime as dt
import json
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.hazmat.primitives.serialization import pkcs7
from cryptography.x509.oid import NameOID

from sem_console.keys.documents import Role, cyclone_xml, governance_xml, permissions_xml

FLEET_FILE = "fleet.json"
IDENTITY_CA, PERMISSIONS_CA = "identity_ca", "permissions_ca"
GOVERNANCE = "governance"
IDENTITIES = "identities"
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}")  # a folder's name, and a subject's CN with nothing to escape
# X.509 allows 64 characters in a common name, and the longest authority's is "FLEET permissions CA".
FLEET = re.compile(r"[A-Za-z0-9][A-Za-z0-9 ._-]{0,48}")


class KeysError(Exception):
    """A problem the operator fixes: its text is the one line sem-keys prints."""


def _write(path: Path, data: bytes, secret: bool = False) -> None:
    """Replace `path` with `data` at once (a reader never sees half a file); a secret is the owner's only (0600)."""
    # mkstemp makes a new file of its own (O_EXCL, 0600): never one someone else put there, nor a link to one.
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as out:
            os.fchmod(out.fileno(), 0o600 if secret else 0o644)
            out.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _pem(cert: x509.Certificate) -> bytes:
    return cert.public_bytes(serialization.Encoding.PEM)


def _key_pem(key: ec.EllipticCurvePrivateKey) -> bytes:
    return key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption())


def _name(common: str, fleet: str, unit: str | None = None) -> x509.Name:
    parts = [x509.NameAttribute(NameOID.COMMON_NAME, common)]
    if unit is not None:
        parts.append(x509.NameAttribute(NameOID.ORGANIZATIONAL_UNIT_NAME, unit))
    return x509.Name([*parts, x509.NameAttribute(NameOID.ORGANIZATION_NAME, fleet)])


def _usage(ca: bool) -> x509.KeyUsage:
    return x509.KeyUsage(
        digital_signature=True,
        content_commitment=False,
        key_encipherment=False,
        data_encipherment=False,
        key_agreement=not ca,
        key_cert_sign=ca,
        crl_sign=ca,
        encipher_only=False,
        decipher_only=False,
    )


def sign_smime(document: bytes, cert: x509.Certificate, key: ec.EllipticCurvePrivateKey) -> bytes:
    """`document` signed as `openssl smime -sign -text` signs it: S/MIME, a detached PKCS#7 signature of the
    document as text/plain, what DDS Security's builtin access control reads."""
    return (
        pkcs7.PKCS7SignatureBuilder()
        .set_data(document)
        .add_signer(cert, key, hashes.SHA256())
        .sign(serialization.Encoding.SMIME, [pkcs7.PKCS7Options.DetachedSignature, pkcs7.PKCS7Options.Text])
    )


@dataclass(frozen=True)
class Fleet:
    folder: Path

    def file(self, name: str) -> Path:
        return self.folder / name

    def identity_folder(self, name: str) -> Path:
        return self.folder / IDENTITIES / name

    def _authority(self, stem: str) -> tuple[x509.Certificate, ec.EllipticCurvePrivateKey]:
        try:
            cert = x509.load_pem_x509_certificate(self.file(f"{stem}.pem").read_bytes())
            key = serialization.load_pem_private_key(self.file(f"{stem}.key").read_bytes(), None)
        except ValueError:
            key = None
        except TypeError:  # a key kept encrypted at rest: cryptography asks for the password it was not given
            raise KeysError(
                f"{self.file(stem)}.key is encrypted: sem-keys reads it as init writes it; decrypt it to issue "
                f"(openssl pkey -in ENCRYPTED.key -out {self.file(stem)}.key)"
            ) from None
        if not isinstance(key, ec.EllipticCurvePrivateKey) or key.public_key() != cert.public_key():
            raise KeysError(f"{self.file(stem)}.pem and .key are not what `sem-keys init` writes: run init again with --force")
        return cert, key

    def settings(self) -> tuple[str, list[int]]:
        """The fleet's name and domains, as `init` wrote them; KeysError when it has not run in this folder."""
        path = self.file(FLEET_FILE)
        try:
            written = json.loads(path.read_text(encoding="utf-8"))
            return str(written["fleet"]), [int(d) for d in written["domains"]]
        except FileNotFoundError:
            raise KeysError(f"{self.folder} has no fleet: run `sem-keys init {self.folder} --fleet NAME` first") from None
        except (ValueError, KeyError, TypeError):
            raise KeysError(f"{path} is not what `sem-keys init` writes: run init again with --force") from None

    def init(self, fleet: str, domains: list[int], days: int, force: bool, now: dt.datetime) -> list[Path]:
        """The fleet's identity and permissions authorities and its signed governance; the files written."""
        if not FLEET.fullmatch(fleet):
            raise KeysError(
                f"--fleet {fleet!r}: use letters, digits, spaces, '.', '_' and '-' (up to 49, a letter or digit first)"
            )
        if not force and any(self.file(f).exists() for f in (FLEET_FILE, f"{IDENTITY_CA}.pem", f"{PERMISSIONS_CA}.pem")):
            raise KeysError(
                f"{self.folder} has a fleet's authorities already: give --force to replace them "
                "(every identity they signed must then be issued again)"
            )
        self.folder.mkdir(parents=True, exist_ok=True)
        written = []
        for stem, what in ((IDENTITY_CA, "identity CA"), (PERMISSIONS_CA, "permissions CA")):
            key = ec.generate_private_key(ec.SECP256R1())
            subject = _name(f"{fleet} {what}", fleet)
            cert = (
                x509.CertificateBuilder()
                .subject_name(subject)
                .issuer_name(subject)
                .public_key(key.public_key())
                .serial_number(x509.random_serial_number())
                .not_valid_before(now)
                .not_valid_after(now + dt.timedelta(days=days))
                .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
                .add_extension(_usage(ca=True), critical=True)
                .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
                .sign(key, hashes.SHA256())
            )
            _write(self.file(f"{stem}.key"), _key_pem(key), secret=True)
            _write(self.file(f"{stem}.pem"), _pem(cert))
            written += [self.file(f"{stem}.pem"), self.file(f"{stem}.key")]
        cert, key = self._authority(PERMISSIONS_CA)
        document = governance_xml(domains)
        _write(self.file(f"{GOVERNANCE}.xml"), document)
        _write(self.file(f"{GOVERNANCE}.p7s"), sign_smime(document, cert, key))
        _write(self.file(FLEET_FILE), json.dumps({"fleet": fleet, "domains": domains}, indent=2).encode() + b"\n")
        return [*written, self.file(f"{GOVERNANCE}.xml"), self.file(f"{GOVERNANCE}.p7s"), self.file(FLEET_FILE)]

    def issue(self, name: str, role: Role, days: int, now: dt.datetime) -> list[Path]:
        """An identity's key, its certificate from the identity CA, its permissions signed by the permissions CA and
        its Cyclone DDS configuration, in identities/NAME/ (replacing only that folder's files); the files written."""
        if not NAME.fullmatch(name):
            raise KeysError(
                f"{name!r} is no identity name: use letters, digits, '.', '_' and '-' (up to 64, a letter or digit first)"
            )
        fleet, domains = self.settings()
        id_cert, id_key = self._authority(IDENTITY_CA)
        perm_cert, perm_key = self._authority(PERMISSIONS_CA)
        ends = min(id_cert.not_valid_after_utc, perm_cert.not_valid_after_utc)
        if ends <= now:
            raise KeysError(
                f"the fleet's authorities in {self.folder} expired at {ends:%Y-%m-%d %H:%M} UTC: run init again with --force"
            )
        not_after = min(now + dt.timedelta(days=days), ends)
        key = ec.generate_private_key(ec.SECP256R1())
        cert = (
            x509.CertificateBuilder()
            .subject_name(_name(name, fleet, role.value))
            .issuer_name(id_cert.subject)
            .public_key(key.public_key())
            .serial_number(x509.random_serial_number())
            .not_valid_before(now)
            .not_valid_after(not_after)
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(_usage(ca=False), critical=True)
            .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(id_key.public_key()), critical=False)
            .sign(id_key, hashes.SHA256())
        )
        folder = self.identity_folder(name)
        folder.mkdir(parents=True, exist_ok=True)
        files = {
            k: folder / f
            for k, f in (
                ("cert", "cert.pem"),
                ("key", "key.pem"),
                ("xml", "permissions.xml"),
                ("p7s", "permissions.p7s"),
                ("cyclone", "cyclonedds.xml"),
            )
        }
        document = permissions_xml(name, cert.subject.rfc4514_string(), role, domains, now, not_after)
        _write(files["key"], _key_pem(key), secret=True)
        _write(files["cert"], _pem(cert))
        _write(files["xml"], document)
        _write(files["p7s"], sign_smime(document, perm_cert, perm_key))
        config = cyclone_xml(
            self.file(f"{IDENTITY_CA}.pem"),
            files["cert"],
            files["key"],
            self.file(f"{PERMISSIONS_CA}.pem"),
            self.file(f"{GOVERNANCE}.p7s"),
            files["p7s"],
        )
        _write(files["cyclone"], config)
        return list(files.values())
