"""One settings object for the whole process; every value can come from SEM_* environment variables."""

from __future__ import annotations

import uuid
from pathlib import Path
from typing import Any

from pydantic import Field, PrivateAttr, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SEM_", extra="ignore")

    # DDS
    domain: int = Field(0, ge=0, le=232, description="DDS domain id (Cyclone's default port mapping allows 0..232)")
    dds_interface: str = Field("lo", description="network interface Cyclone binds to when CYCLONEDDS_URI is not set")
    dds_peers: str = Field("127.0.0.1", description="unicast discovery peers when CYCLONEDDS_URI is not set, comma separated")

    # HTTP
    host: str = "127.0.0.1"
    port: int = Field(8000, ge=0, le=65535)
    sim: int = Field(0, ge=0, le=100, description="simulated vehicles to run inside the console on the same domain")
    sim_time_scale: float = Field(1.0, gt=0, le=100)
    sim_first_vehicle: int = Field(1, ge=1, le=9_500, description="number of the embedded simulator's first vehicle")
    frontend_dir: Path | None = Field(None, description="built dashboard to serve at / (default: frontend/dist if it exists)")
    basemap: Path | None = Field(None, description="a PMTiles chart served at GET /api/basemap.pmtiles (HTTP range requests), "
                                 "drawn by the dashboard's map over its built-in Natural Earth basemap")

    # UMAA consumer and link health
    db_path: Path = Field(Path("var/sem-console.sqlite3"), description="SQLite command history and the console's GUID")
    comms_lost_timeout: float = Field(3.0, gt=0, description="seconds without a sample before a provider is lost")
    regained_time: float = Field(3.0, ge=0, description="seconds of continuous samples before a lost provider is regained")
    unanswered_timeout: float = Field(5.0, gt=0, description="seconds without ISSUED before a command is unanswered")
    report_interval: float = Field(0.005, ge=0, le=10, description="under load, at most one take of report topics per "
                                   "this many seconds (conflation window); sparse input is taken as it arrives")
    report_burst: int = Field(8, ge=1, le=1000, description="takes of report topics allowed at once before the conflation "
                              "window applies (refilled at one per window)")
    ws_max_queue: int = Field(10_000, ge=10, description="ordered messages a WebSocket client may fall behind (while it sends "
                                                         "nothing for ws_stall_seconds) before it is dropped")
    ws_stall_seconds: float = Field(5.0, ge=0, description="seconds without a completed send that make a client over "
                                                           "ws_max_queue stalled")
    ws_compression: bool = Field(False, description="permessage-deflate on /ws when a client offers it: about a tenth of the "
                                 "bytes on a slow link, for CPU and latency on every message (off: a LAN or one machine)")
    track_retention_hours: float = Field(24.0, gt=0, le=24 * 366, description="hours of track and chart history kept per "
                                         "vehicle in the database (older points are pruned)")

    # Recording to MCAP (see README, Recording)
    record: Path | None = Field(None, description="record from the start into this directory (the dashboard's and "
                                "POST /api/recordings' recordings go there too)")
    recordings_dir: Path = Field(Path("var/recordings"), description="where recordings go when `record` is not set")
    record_max_bytes: int = Field(1 << 30, ge=65_536, description="a recording file rolls over to the next at this size")
    record_max_seconds: float = Field(3600.0, gt=0, description="a recording file rolls over to the next after this long")
    record_queue: int = Field(2_000, ge=10, description="takes (batches of samples) waiting for the recording's writer; "
                              "beyond it they are dropped and their samples counted")

    # Replay in the console (see README, Replay in the console)
    replay: Path | None = Field(None, description="serve the dashboard from this recording (MCAP) instead of DDS: read-only")
    replay_speed: float = Field(1.0, ge=0.25, le=20, description="the replay's speed at start (0.25 to 20)")

    # Operators: "name:token,name2:token2" and/or a file of "name:token" lines; both split at the
    # first colon (parse_token). None at all: no sign-in.
    operator_tokens: str = ""
    operator_tokens_file: Path | None = Field(None, description="one 'name:token' per line (# comments, blank lines)")
    auth_reads: bool = Field(False, description="reads (REST GETs and /ws) need an operator token too")

    audit_max_rows: int = Field(100_000, ge=10, description="the audit trail keeps this many newest entries")
    throttle_first_wait: float = Field(1.0, gt=0, le=60, description="seconds a client waits after its fifth wrong "
                                       "operator token in a row; each further one doubles it, up to 60 s")
    audit_refusals_per_minute: int = Field(30, ge=1, description="refused requests of one client address logged and "
                                           "recorded per minute; the rest of the minute are counted (see api/audit.py)")

    # Requests from other sites (see README, Security)
    allowed_hosts: str = Field("localhost,127.0.0.1,[::1]", description="Host header names accepted, comma separated "
                               "('*' accepts any); the --host address is added when it is a concrete address")
    allowed_origins: str = Field("", description="origins allowed beside the console's own (e.g. a reverse proxy's), "
                                 "comma separated, such as https://console.example.org")
    forwarded_allow_ips: str = Field("", description="addresses of reverse proxies whose X-Forwarded-For and "
                                     "X-Forwarded-Proto are trusted, comma separated (default: none, the headers are ignored)")
    tls_certfile: Path | None = Field(None, description="PEM certificate (chain): serve HTTPS and WSS")
    tls_keyfile: Path | None = Field(None, description="PEM private key of tls_certfile")

    # Gateways (each off unless its option is given; see README, "Gateways")
    aspn_lcm: str | None = Field(None, description="LCM URL to publish each vehicle's navigation on as ASPN-23 "
                                 "(udpm://239.255.76.67:7667?ttl=0, file://PATH.lcm, memq://); off when unset")
    aspn_prefix: str = Field("aspn23", pattern=r"^[A-Za-z0-9_.\-/]{1,64}$",
                             description="first part of every ASPN channel name: <prefix>/<vehicle>/<measurement>")
    aspn_log_seconds: float = Field(300.0, gt=0, le=86_400, description="seconds of each vehicle's ASPN messages kept "
                                    "for the dashboard's Record ASPN log (at most 8 MiB per vehicle)")
    jaus_port: int | None = Field(None, ge=0, le=65535, description="UDP port of the JAUS (JUDP, AS5669A) gateway; "
                                  "off when unset")
    jaus_subsystem: int = Field(1, ge=1, le=65534, description="JAUS subsystem id of the console's components")
    jaus_host: str | None = Field(None, description="address the JAUS gateway listens on (default: --host)")

    # Names shown beside vehicle ids: "GUID=name,GUID2=name2"
    vehicle_names: str = ""

    # CoMap over IMC (UDP); off unless imc_port is given (see README, CoMap)
    imc_port: int | None = Field(None, ge=0, le=65535, description="UDP port the console's IMC node listens on")
    imc_host: str = Field("0.0.0.0", description="address the IMC node listens on")
    imc_peers: str = Field("", description="IMC peers (vehicles) as host:port, comma separated")
    imc_id: int = Field(0x4001, ge=0, le=0xFFFE, description="the console's IMC system id")
    imc_vehicles: str = Field("", description="UMAA provider to IMC system id: 'GUID=imcid,...' (decimal or 0x hex)")

    _operators: dict[str, str] | None = PrivateAttr(None)

    @field_validator("imc_id", mode="before")
    @classmethod
    def _imc_id_hex(cls, v: Any) -> Any:
        """SEM_IMC_ID=0x4001 as --imc-id takes it."""
        return parse_imc_id(v, "imc_id") if isinstance(v, str) else v

    def operators(self) -> dict[str, str]:
        """token -> operator name, from operator_tokens and operator_tokens_file (read once).
        Raises ValueError for a file that cannot be read or a line that is not name:token."""
        if self._operators is None:
            out: dict[str, str] = {}
            for n, item in enumerate(filter(None, (x.strip() for x in self.operator_tokens.split(","))), start=1):
                add_token(out, *parse_token(item, f"operator tokens (SEM_OPERATOR_TOKENS or --operator-tokens), item {n}"))
            if self.operator_tokens_file is not None:
                for token, name in read_tokens_file(self.operator_tokens_file).items():
                    add_token(out, name, token, str(self.operator_tokens_file))
            self._operators = out
        return self._operators

    def recording_dir(self) -> Path:
        return self.record or self.recordings_dir

    def host_names(self) -> set[str]:
        """Host header names accepted (lower case, IPv6 in brackets); '*' in the set accepts any."""
        names = {x.strip().lower() for x in self.allowed_hosts.split(",") if x.strip()}
        if self.host not in ("0.0.0.0", "::", ""):
            names.add(f"[{self.host}]" if ":" in self.host else self.host.lower())
        return names

    def origins(self) -> set[str]:
        return {x.strip().rstrip("/").lower() for x in self.allowed_origins.split(",") if x.strip()}

    def names(self) -> dict[str, str]:
        """provider GUID (lower-case UUID string) -> name."""
        out = {}
        for item in filter(None, (x.strip() for x in self.vehicle_names.split(","))):
            guid, sep, name = item.partition("=")
            if not sep or not name.strip():
                raise ValueError(f"vehicle name {item!r}: expected GUID=name")
            try:
                out[str(uuid.UUID(guid.strip()))] = name.strip()
            except ValueError:
                raise ValueError(f"vehicle name {item!r}: {guid.strip()!r} is not a GUID") from None
        return out


def parse_imc_id(text: str, where: str) -> int:
    """An IMC system id, decimal or 0x hex, 0..0xFFFE (0xFFFF is broadcast)."""
    try:
        value = int(text.strip(), 0)
    except ValueError:
        raise ValueError(f"{where}: {text.strip()!r} is not an IMC system id (decimal or 0x hex)") from None
    if not 0 <= value <= 0xFFFE:
        raise ValueError(f"{where}: IMC system id {value} is not in 0..0xFFFE")
    return value


def parse_imc_vehicles(text: str) -> dict[uuid.UUID, int]:
    """'GUID=imcid,...' -> {provider GUID: IMC system id}; ValueError naming the item that is wrong."""
    out: dict[uuid.UUID, int] = {}
    for item in filter(None, (x.strip() for x in text.split(","))):
        guid, sep, imc = item.partition("=")
        if not sep:
            raise ValueError(f"IMC vehicle {item!r}: expected GUID=imcid")
        try:
            key = uuid.UUID(guid.strip())
        except ValueError:
            raise ValueError(f"IMC vehicle {item!r}: {guid.strip()!r} is not a GUID") from None
        value = parse_imc_id(imc, f"IMC vehicle {item!r}")
        if value in out.values():
            raise ValueError(f"IMC vehicle {item!r}: IMC system id {value} is given to two vehicles")
        out[key] = value
    return out


def parse_token(item: str, where: str) -> tuple[str, str, str]:
    """(name, token, where) from "name:token": the name ends at the first colon, both are stripped.
    A token must be visible ASCII (an HTTP header carries nothing else reliably: a browser cannot
    send other characters and Starlette reads headers as latin-1, so such a token could never match)."""
    name, sep, token = item.partition(":")
    name, token = name.strip(), token.strip()
    if not sep or not name or not token:
        raise ValueError(f"{where}: expected name:token")
    if not all("!" <= ch <= "~" for ch in token):
        raise ValueError(f"{where}: the token of {name!r} must be visible ASCII characters (no spaces, no accents)")
    return name, token, where


def add_token(out: dict[str, str], name: str, token: str, where: str) -> None:
    if out.get(token, name) != name:
        raise ValueError(f"{where}: {name!r} has the same token as {out[token]!r}")
    out[token] = name


def read_tokens_file(path: Path) -> dict[str, str]:
    """token -> name from a file of "name:token" lines (parse_token; # comments, blank lines)."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise ValueError(f"cannot read operator tokens file {path}: {getattr(e, 'strerror', None) or e}") from None
    out: dict[str, str] = {}
    for n, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        add_token(out, *parse_token(line, f"{path}:{n}"))
    return out
