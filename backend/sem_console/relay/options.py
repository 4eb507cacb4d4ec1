"""What a `sem-relay` process runs: its options (each also a SEM_RELAY_* environment variable), and the safety check of
its endpoints. `sem-relay`'s options are generated from these fields (relay/cli.py through
core/command_line.add_model_options), so the ranges, defaults and help are written once, here."""

from __future__ import annotations

import ipaddress
import os
import socket
import ssl
import uuid
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"
_TLS_PROTOCOLS = ("tls", "quic")


class RelayOptions(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SEM_RELAY_", extra="ignore")

    router: bool = Field(
        False,
        description=("run a Zenoh router session (no DDS): the relays of both sides connect to it (--listen: where it listens)"),
    )
    side: Literal["vehicles", "operations"] = Field(
        "vehicles",
        description=(
            "vehicles: read the vehicles' reports, statuses and acks on --domain and send them; write the commands that come "
            "back. operations: write the vehicles' samples into --domain for the consoles there; send their commands "
            "(default: vehicles)"
        ),
    )
    name: str = Field(
        default_factory=socket.gethostname,
        min_length=1,
        description=(
            "this relay's name in its log and status, and a vehicles' relay's key space (sem/NAME/...): behind a router's "
            "access control, its certificate's common name (default: the host name)"
        ),
    )
    connect: str = Field(
        "",
        description=(f"Zenoh endpoints to connect to, comma separated (default for a relay: {DEFAULT_ENDPOINT}; a router: none)"),
    )
    listen: str = Field(
        "",
        description=(f"Zenoh endpoints to listen on, comma separated (default for a router: {DEFAULT_ENDPOINT}; a relay: none)"),
    )
    link_class: Literal["satellite", "lan"] = Field(
        "satellite",
        description=(
            "the link's rate caps on reports: satellite (GPSReport once a minute, GlobalPoseReport, GPSFixReport and "
            "GPSFixStatusReport every 5 s, a fix lost or regained at once, InertialSensorReport on change) or lan (no "
            "caps); commands, statuses and acks are never capped (default: satellite)"
        ),
    )
    caps: str = Field(
        "",
        description=(
            "caps over the link class's, comma separated: TOPIC=SECONDS (0: no cap) or TOPIC=change, TOPIC the type's "
            "name without `Type` (GPSReport, GlobalPoseReport, GPSFixReport, GPSFixStatusReport, InertialSensorReport)"
        ),
    )
    lease_seconds: float = Field(
        10.0,
        ge=1,
        le=600,
        description=(
            "Zenoh's lease: a link silent this long is closed and opened again, and each side then sends again what the "
            "other may have missed (default: 10)"
        ),
    )
    vehicle_gone_seconds: float = Field(
        600.0,
        ge=10,
        le=86400,
        description=(
            "a vehicles' relay: a vehicle not heard on its domain this long is no longer said to be carried here, so "
            "that the relay of the ship whose network it moved to may carry it and get its commands (default: 600)"
        ),
    )
    stats_seconds: float = Field(
        60.0, ge=0.1, le=3600, description=("how often the bytes per vehicle are logged and --status-file written (default: 60)")
    )
    status_file: Path | None = Field(None, description="write the relay's link status (bytes per vehicle) here as JSON")
    status_port: int | None = Field(
        None,
        ge=1,
        le=65535,
        description=("serve the relay's link status as JSON at http://127.0.0.1:PORT/status (this machine only)"),
    )
    insecure: bool = Field(False, description="allow an endpoint that is not loopback without TLS (sent in the clear)")
    tls_root_ca: Path | None = Field(
        None, description=("PEM certificate of the authority that signs the other side's certificate: TLS on tls/ endpoints")
    )
    tls_certificate: Path | None = Field(
        None, description=("PEM certificate of this relay (with --tls-private-key): mutual TLS, the other side checks it")
    )
    tls_private_key: Path | None = Field(None, description="PEM private key of --tls-certificate")
    vehicle_relays: str = Field(
        "",
        description=(
            "a router's access control (with mutual TLS): the vehicles' relays, comma separated, each by its name, which is "
            "its certificate's common name: each sends and receives only on its own key space (its vehicles' samples, "
            "their commands); a certificate named in neither list gets nothing. NAME=GUID+GUID...: that relay carries "
            "only those vehicles (their source GUIDs): it cannot say it carries, report for or take the commands of "
            "another vehicle, whichever relay declares first"
        ),
    )
    operations_relays: str = Field(
        "",
        description=(
            "a router's access control (with mutual TLS): the operations relays' certificate common names, comma "
            "separated: they receive every vehicles' relay's samples and send commands to any"
        ),
    )

    @model_validator(mode="after")
    def _consistent(self) -> RelayOptions:
        if (self.tls_certificate is None) != (self.tls_private_key is None):
            raise ValueError("--tls-certificate and --tls-private-key go together")
        if self.tls_certificate is not None and self.tls_root_ca is None:
            raise ValueError("--tls-certificate needs --tls-root-ca (the authority the other side's certificate is checked by)")
        if bad := key_chunk_problem(self.name):
            raise ValueError(f"--name {self.name!r}: {bad}")
        if self.vehicle_relays or self.operations_relays:
            if not self.router or self.tls_certificate is None:
                raise ValueError(
                    "--vehicle-relays and --operations-relays are a router's access control: give them with --router and "
                    "--tls-root-ca, --tls-certificate, --tls-private-key (the relays are known by their certificates)"
                )
            vehicles = [item.partition("=")[0].strip() for item in endpoints(self.vehicle_relays)]
            operations = endpoints(self.operations_relays)
            for name in vehicles:
                if bad := key_chunk_problem(name):
                    raise ValueError(f"--vehicle-relays {name!r}: {bad}")
            named = vehicles + operations
            if twice := sorted({name for name in named if named.count(name) > 1}):
                raise ValueError(
                    f"--vehicle-relays, --operations-relays: {', '.join(map(repr, twice))} named twice: each relay's "
                    "certificate once, in one list"
                )
            owners: dict[uuid.UUID, str] = {}
            for name, carried in vehicle_relays(self.vehicle_relays).items():
                for vehicle in carried or ():
                    if vehicle in owners:
                        raise ValueError(
                            f"--vehicle-relays: vehicle {vehicle} is given to {owners[vehicle]!r} and {name!r}: a vehicle "
                            "is carried by one relay"
                        )
                    owners[vehicle] = name
            for flag, given in (("--listen", self.listen_endpoints), ("--connect", self.connect_endpoints)):
                for endpoint in given:
                    if (protocol := endpoint.partition("/")[0]) not in _TLS_PROTOCOLS:
                        raise ValueError(
                            f"{flag} {endpoint}: --vehicle-relays and --operations-relays know the relays by their "
                            f"certificates, which a {protocol}/ endpoint carries none of (a relay through it would get "
                            "nothing): give tls/ or quic/ endpoints only"
                        )
        return self

    @property
    def access_controlled(self) -> bool:
        return bool(self.vehicle_relays or self.operations_relays)

    @property
    def connect_endpoints(self) -> list[str]:
        given = endpoints(self.connect)
        return given or ([] if self.router else [DEFAULT_ENDPOINT])

    @property
    def listen_endpoints(self) -> list[str]:
        given = endpoints(self.listen)
        return given or ([DEFAULT_ENDPOINT] if self.router else [])

    @property
    def tls(self) -> bool:
        return self.tls_root_ca is not None


def key_chunk_problem(name: str) -> str | None:
    """Why a relay's name cannot be a chunk of its Zenoh keys (`sem/<name>/...`), or None."""
    if not name or any(c in name for c in "/*$?#") or name.startswith("@") or name.strip() != name:
        return (
            "a relay's name is one Zenoh key chunk: no '/', '*', '$', '?', '#', no leading '@' (a chunk no wildcard "
            "matches) and no surrounding spaces"
        )
    return None


def endpoints(text: str) -> list[str]:
    return [e.strip() for e in text.split(",") if e.strip()]


def vehicle_relays(text: str) -> dict[str, tuple[uuid.UUID, ...] | None]:
    """`--vehicle-relays`: each relay's name and the vehicles it alone may carry (None: any under its name), in order;
    a ValueError naming the bad item and the fix."""
    out: dict[str, tuple[uuid.UUID, ...] | None] = {}
    for item in endpoints(text):
        name, sep, listed = item.partition("=")
        name = name.strip()
        if not sep:
            out[name] = None
            continue
        try:
            out[name] = tuple(dict.fromkeys(uuid.UUID(v.strip()) for v in listed.split("+") if v.strip()))
        except ValueError:
            raise ValueError(
                f"--vehicle-relays {item!r}: give NAME or NAME=GUID+GUID..., each GUID a vehicle's source GUID"
            ) from None
        if not out[name]:
            raise ValueError(f"--vehicle-relays {item!r}: no vehicle after '=': give NAME alone, or NAME=GUID+GUID...")
    return out


def endpoint_host(endpoint: str) -> str:
    """The host of a Zenoh endpoint: `tcp/10.0.0.1:7447#iface=eth0` -> 10.0.0.1, `tcp/[::1]:7447` -> ::1."""
    address = endpoint.partition("/")[2].split("#", 1)[0].split("?", 1)[0]
    host = address.rpartition(":")[0] if ":" in address else address
    return host.strip("[]")


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False  # a name: not known to stay on this machine


def endpoint_problem(options: RelayOptions) -> str | None:
    """Why the relay must not open its endpoints, as one line naming the fix, or None. An endpoint off this machine
    goes over TLS (a tls/ or quic/ endpoint with --tls-root-ca) unless --insecure says clear text is meant."""
    for flag, given in (("--connect", options.connect_endpoints), ("--listen", options.listen_endpoints)):
        for endpoint in given:
            protocol = endpoint.partition("/")[0]
            if protocol in _TLS_PROTOCOLS and not options.tls:
                return f"{flag} {endpoint}: a TLS endpoint needs --tls-root-ca (and --tls-certificate, --tls-private-key)"
            if protocol in _TLS_PROTOCOLS or is_loopback(endpoint_host(endpoint)) or options.insecure:
                continue
            return (
                f"{flag} {endpoint} leaves this machine without TLS: use a tls/ endpoint with --tls-root-ca, or give "
                "--insecure to send the fleet's traffic in the clear"
            )
    return None


def tls_problem(options: RelayOptions) -> str | None:
    """Why the TLS files cannot serve, as one line naming the fix, or None: Zenoh would refuse them at every attempt
    to connect, and the relay would wait for its router for ever."""
    if options.tls_root_ca is not None:
        try:
            ssl.create_default_context(cafile=str(options.tls_root_ca))
        except (OSError, ssl.SSLError) as e:
            return (
                f"--tls-root-ca {options.tls_root_ca}: cannot read it as PEM certificates "
                f"({getattr(e, 'strerror', None) or e}): give the fleet authority's certificate"
            )
    if options.tls_certificate is not None and options.tls_private_key is not None:
        try:
            ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT).load_cert_chain(options.tls_certificate, options.tls_private_key)
        except (OSError, ssl.SSLError) as e:
            return (
                f"--tls-certificate {options.tls_certificate} and --tls-private-key {options.tls_private_key}: not a "
                f"readable PEM certificate and its private key ({getattr(e, 'strerror', None) or e})"
            )
    return None


def status_file_problem(options: RelayOptions) -> str | None:
    """Why --status-file cannot be written, as one line, or None: found at start, not as a warning every
    --stats-seconds while the relay runs."""
    path = options.status_file
    if path is None:
        return None
    folder = path.parent
    if path.is_dir() or not folder.is_dir() or not os.access(folder, os.W_OK):
        why = "a folder" if path.is_dir() else f"no folder {folder}" if not folder.is_dir() else f"{folder} is not writable"
        return f"--status-file {path}: {why}: give a file in a folder the relay may write"
    return None
