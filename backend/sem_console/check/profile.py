"""`sem-check --security-profile DIR`: a fleet's DDS Security governance and permissions held to the project's
security profile (what `sem-keys` writes: keys/documents.py), without DDS. Each finding is one line saying the problem
and the fix, under the test case that names it."""

from __future__ import annotations

import fnmatch
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from sem_console.check.results import Case
from sem_console.dds.hops import TOPIC as RELAY_LINK
from sem_console.dds.qos import TopicClass
from sem_console.dds.security import IDENTITY_FILES, SecurityError, fleet_file, rdns, verify_smime
from sem_console.keys.documents import DOMAIN_PROFILE, TOPIC_PROFILE, Role, sem_topics
from sem_console.keys.fleet import Fleet, KeysError

SIGNATURES = "profile.signatures"  # every document verifies against the fleet's permissions CA
UNAUTHENTICATED = "profile.unauthenticated_participants"
JOIN = "profile.join_access_control"
BUS = "profile.bus_protection"  # discovery, liveliness and RTPS messages
TOPICS = "profile.topic_protection"
COMMANDS = "profile.command_grants"
NAMES = [SIGNATURES, UNAUTHENTICATED, JOIN, BUS, TOPICS, COMMANDS]
# the case of each domain setting of the profile
DOMAIN_CASES = {
    "allow_unauthenticated_participants": UNAUTHENTICATED,
    "enable_join_access_control": JOIN,
    "discovery_protection_kind": BUS,
    "liveliness_protection_kind": BUS,
    "rtps_protection_kind": BUS,
}
RESIGN = "then sign it again with the fleet's permissions CA (sem-keys init --force writes the profile's)"


@dataclass(frozen=True)
class Documents:
    """What is checked: the governance and the permissions documents, signed, and the CA they must verify against."""

    governance: Path
    permissions: list[Path]
    permissions_ca: Path
    domains: list[int] | None = None  # the fleet's domains (sem-keys init's fleet.json beside the governance), if known


def documents(folder: Path) -> Documents:
    """A fleet's folder (`sem-keys init`: its governance and every identity's permissions) or one identity's folder
    (`sem-keys issue`, as --dds-security takes it: its permissions, the fleet's governance and permissions CA beside
    them or in its fleet's folder); SecurityError (one line) when the documents are not there."""
    if not folder.is_dir():
        raise SecurityError(
            f"--security-profile {folder}: no such folder: "
            "give a fleet's folder (sem-keys init) or an identity's (sem-keys issue)"
        )
    own = folder / IDENTITY_FILES["Permissions"]
    governance, ca = fleet_file(folder, "Governance"), fleet_file(folder, "PermissionsCA")
    for path in (governance, ca):
        if not path.is_file():
            raise SecurityError(
                f"--security-profile {folder}: no {path.name} there: give the folder "
                "sem-keys init wrote (the fleet's) or sem-keys issue wrote (an identity's, its fleet's files beside it "
                "or two folders up)"
            )
    try:
        domains: list[int] | None = Fleet(governance.parent).settings()[1]
    except KeysError:
        domains = None
    if own.is_file():
        return Documents(governance, [own], ca, domains)
    permissions = sorted((folder / "identities").glob(f"*/{IDENTITY_FILES['Permissions']}"))
    return Documents(governance, permissions, ca, domains)


def _signed(path: Path, ca: Path, signatures: Case) -> ET.Element | None:
    """The document in `path` once its signature verifies and it is XML; else a finding under `signatures`."""
    try:
        return ET.fromstring(verify_smime(path, ca))
    except SecurityError as e:
        signatures.fail(str(e))
    except ET.ParseError as e:
        signatures.fail(f"{path}: its document is not XML ({e}): write it again with sem-keys")
    return None


def _text(node: ET.Element, tag: str) -> str:
    return (node.findtext(tag) or "").strip()


def _governance(path: Path, root: ET.Element, domains: list[int] | None, cases: dict[str, Case]) -> None:
    topics = [name for name, _ in sem_topics()] + [RELAY_LINK]
    rules = list(root.iter("domain_rule"))
    joined = set[int]().union(*(_domain_ids(rule) for rule in rules))
    outside = [str(d) for d in sorted(set(domains or []) - joined)] or ([] if rules else ["of the fleet"])
    if outside:
        cases[JOIN].fail(
            f"{path}: no domain_rule covers the domain {', '.join(outside)}, so no participant may join it: "
            f"add the profile's, {RESIGN}",
            profile=True,
        )
    for number, rule in enumerate(rules, 1):
        where = f"{path}: domain_rule {number}"
        for tag, wanted in DOMAIN_PROFILE.items():
            value = _text(rule, tag)
            if value.lower() != wanted.lower():
                cases[DOMAIN_CASES[tag]].fail(
                    f"{where}: {tag} is {value or 'missing'}, the profile's is {wanted}: set it, {RESIGN}", profile=True
                )
        expressions = [_text(topic, "topic_expression") for topic in rule.iter("topic_rule")]
        missing = [t for t in topics if not any(fnmatch.fnmatchcase(t, e) for e in expressions)]
        if missing:
            cases[TOPICS].fail(
                f"{where}: no topic rule covers {missing[0]}"
                f"{f' and {len(missing) - 1} more' if len(missing) > 1 else ''}, so no participant may use it: "
                f"add the profile's, {RESIGN}",
                profile=True,
            )
        for topic in rule.iter("topic_rule"):
            expression = _text(topic, "topic_expression")
            covered = [t for t in topics if fnmatch.fnmatchcase(t, expression)]
            if not covered:
                continue
            for tag, wanted in TOPIC_PROFILE.items():
                value = _text(topic, tag)
                if value.lower() != wanted.lower():
                    cases[TOPICS].fail(
                        f"{where}: the topic rule {expression!r} (covering {covered[0]}"
                        f"{f' and {len(covered) - 1} more' if len(covered) > 1 else ''}) has {tag} {value or 'missing'}, "
                        f"the profile's is {wanted}: set it, {RESIGN}",
                        profile=True,
                    )


DOMAIN_IDS = range(233)  # the DDS domain ids a participant can join (0..232)


def _int(text: str | None, default: int) -> int:
    return int(text.strip()) if text is not None and text.strip().isdigit() else default


def _domain_ids(rule: ET.Element) -> set[int]:
    """The domain ids a rule's <domains> covers: its ids and id ranges (a range without min or max is open)."""
    ids = {_int(i.text, -1) for i in rule.findall("domains/id")}
    for r in rule.findall("domains/id_range"):
        low, high = _int(r.findtext("min"), 0), _int(r.findtext("max"), DOMAIN_IDS[-1])
        ids.update(range(low, high + 1))
    return ids & set(DOMAIN_IDS)


def _publishes(rule: ET.Element, topic: str) -> bool:
    return any(fnmatch.fnmatchcase(topic, (t.text or "").strip()) for t in rule.findall("publish/topics/topic"))


def _may_publish(grant: ET.Element, topic: str) -> bool:
    """Whether a grant lets its subject publish `topic` on some domain: on each, the first allow or deny rule that
    covers the domain and names the topic decides, else the grant's default, as the access control plugin applies them."""
    rules = [(r.tag, _domain_ids(r)) for r in grant if r.tag in ("allow_rule", "deny_rule") and _publishes(r, topic)]
    default = _text(grant, "default").upper() == "ALLOW"
    return any(next((tag == "allow_rule" for tag, ids in rules if d in ids), default) for d in DOMAIN_IDS)


def _permissions(path: Path, root: ET.Element, case: Case) -> None:
    """A grant may publish a command topic only for a station: the role is its subject's OU, as sem-keys writes it in
    the identity's certificate (signed by the identity CA) and the grant."""
    commands = [name for name, cls in sem_topics() if cls is TopicClass.COMMAND]
    for grant in root.iter("grant"):
        roles = {v for k, v in rdns(_text(grant, "subject_name")) if k == "OU"}
        if Role.STATION.value in roles:
            continue
        allowed = [topic for topic in commands if _may_publish(grant, topic)]
        if allowed:
            role = ", ".join(sorted(roles)) or "no role (OU)"
            case.fail(
                f"{path}: grant {grant.get('name', '?')!r} lets {_text(grant, 'subject_name')} ({role}, not a station) "
                f"publish the command topic {allowed[0]}{f' and {len(allowed) - 1} more' if len(allowed) > 1 else ''}: "
                "only a station writes commands: issue the identity again (sem-keys issue FLEET NAME --role ROLE)",
                profile=True,
            )


def check(docs: Documents) -> list[Case]:
    """The profile's test cases, each failed by its findings (the first is its reason, the rest notes)."""
    cases = {name: Case(name) for name in NAMES}
    governance = _signed(docs.governance, docs.permissions_ca, cases[SIGNATURES])
    if governance is not None:
        _governance(docs.governance, governance, docs.domains, cases)
    else:
        for name in (UNAUTHENTICATED, JOIN, BUS, TOPICS):
            cases[name].skip(f"not checked: the governance {docs.governance} did not verify")
    verified = 0
    for path in docs.permissions:
        permissions = _signed(path, docs.permissions_ca, cases[SIGNATURES])
        if permissions is not None:
            verified += 1
            _permissions(path, permissions, cases[COMMANDS])
    if not verified:
        cases[COMMANDS].skip("not checked: no identity's permissions.p7s that verifies (sem-keys issue writes them)")
    checked = [docs.governance, *docs.permissions]
    cases[SIGNATURES].note(f"documents: {', '.join(map(str, checked))}")
    return list(cases.values())
