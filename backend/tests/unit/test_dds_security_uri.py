"""Which identity a CYCLONEDDS_URI's <Security> section names for the process's domain (dds/security.py's from_uri):
a section for another domain, or one in a comment, leaves the bus open, as Cyclone leaves it."""

from __future__ import annotations

from sem_console.dds.security import from_uri

CERTIFICATE = "<IdentityCertificate>file:/nonexistent/cert.pem</IdentityCertificate>"
SECURITY = f"<Security><Authentication>{CERTIFICATE}</Authentication></Security>"


def test_a_security_section_for_another_domain_leaves_the_bus_open() -> None:
    uri = f'<CycloneDDS><Domain Id="5">{SECURITY}</Domain></CycloneDDS>'
    assert from_uri(uri, 0) is None
    assert from_uri(uri, 5) is not None


def test_a_security_section_for_any_domain_or_outside_one_applies() -> None:
    for uri in (
        f'<?xml version="1.0"?><CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">{SECURITY}</Domain></CycloneDDS>',
        f"<CycloneDDS><Domain>{SECURITY}</Domain></CycloneDDS>",
        SECURITY,
    ):
        security = from_uri(uri, 3)
        assert security is not None and security.source == "CYCLONEDDS_URI", uri


def test_a_security_section_in_a_comment_leaves_the_bus_open() -> None:
    assert from_uri(f"<CycloneDDS><!-- {SECURITY} --><Domain/></CycloneDDS>", 0) is None
