"""Zenoh access control on a `sem-relay --router` (docs/relay.md#security): which relay, known by its TLS certificate's
common name, may send and receive what. A vehicles' relay has only its own key space (`sem/<name>/**`: its vehicles'
samples out, their commands in), its liveliness token and those of the vehicles it carries, and watches the operations
relays' tokens (with its vehicles listed, `--vehicle-relays NAME=GUID+GUID`, the keys and tokens of those vehicles
only); an operations relay has every key; any other certificate, nothing."""

from __future__ import annotations

import uuid
from collections.abc import Mapping, Sequence
from typing import Any

from sem_console.relay.hops import LIVELINESS, carries_prefix
from sem_console.relay.wire import PREFIX

_MESSAGES = [
    "put",
    "delete",
    "declare_subscriber",
    "query",
    "declare_queryable",
    "reply",
    "liveliness_token",
    "declare_liveliness_subscriber",
    "liveliness_query",
]


def _rule(
    rule_id: str, key_exprs: list[str], messages: list[str], flows: tuple[str, ...] = ("ingress", "egress")
) -> dict[str, Any]:
    return {"id": rule_id, "permission": "allow", "flows": list(flows), "messages": messages, "key_exprs": key_exprs}


def access_control(vehicle_relays: Mapping[str, Sequence[uuid.UUID] | None], operations_relays: list[str]) -> dict[str, Any]:
    """The `access_control` section of the router's Zenoh configuration; everything not allowed here is denied.
    `vehicle_relays`: each vehicles' relay's name and the vehicles it may carry (None: any, under its name)."""
    rules = [
        _rule("operations", ["**"], _MESSAGES),
        # a vehicles' relay watches the operations relays come and go (it sends again what they missed): it asks
        # (ingress) and is told (egress), but never declares a token there itself, which would pass for a new one
        _rule(
            "watch operations",
            [f"{LIVELINESS}/operations/**"],
            ["declare_liveliness_subscriber", "liveliness_query"],
            ("ingress",),
        ),
        _rule("told operations", [f"{LIVELINESS}/operations/**"], ["liveliness_token", "reply"], ("egress",)),
    ]
    subjects = [{"id": "operations", "cert_common_names": operations_relays}] if operations_relays else []
    policies = [{"id": "operations", "rules": ["operations"], "subjects": ["operations"]}] if operations_relays else []
    for name, vehicles in vehicle_relays.items():
        # its key space, its own token, and the tokens of the vehicles it carries (relay/hops.py) under its own name;
        # with its vehicles listed, only theirs: no other relay's vehicle can be claimed, reported for or commanded
        mine = [f"vehicles {name}"]
        if vehicles is None:
            own = [f"{PREFIX}/{name}/**", f"{LIVELINESS}/vehicles/{name}/**", f"{carries_prefix(name)}/**"]
        else:
            own = [
                f"{LIVELINESS}/vehicles/{name}/**",
                *(f"{PREFIX}/{name}/*/{v}/**" for v in vehicles),
                *(f"{carries_prefix(name)}/*/{v}/**" for v in vehicles),
            ]
            # it subscribes to its whole key space (`sem/<name>/<domain>/**`, relay.py); what reaches it there is
            # still only its vehicles' (the puts the router delivers are those of the keys above)
            rules.append(_rule(f"subscribes {name}", [f"{PREFIX}/{name}/**"], ["declare_subscriber"], ("ingress",)))
            mine.append(f"subscribes {name}")
        rules.append(_rule(f"vehicles {name}", own, _MESSAGES))
        subjects.append({"id": f"vehicles {name}", "cert_common_names": [name]})
        policies.append(
            {
                "id": f"vehicles {name}",
                "rules": [*mine, "watch operations", "told operations"],
                "subjects": [f"vehicles {name}"],
            }
        )
    return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects, "policies": policies}
