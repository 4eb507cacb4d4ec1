"""One settings object for the whole process; every value can come from SEM_* environment variables, and
`sem-console`'s command line is generated from it (core/command_line.add_model_options): each field is the option
--<name> (underscores as dashes) with the field's type and its description as the help, unless its
`json_schema_extra={"cli": {...}}` says otherwise (another flag, a metavar, nargs) or is {"cli": None}
(environment only). The checks between fields are model validators, so an environment-only configuration
gets them too."""

from __future__ import annotations

import re
import socket
import uuid
from pathlib import Path
from typing import Any, Self

from pydantic import Field, PrivateAttr, field_validator, model_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

from sem_console.storage.url import DatabaseUrl, parse_database_url, sqlite_file

# printable: no control character (C0, DEL, C1) nor line or paragraph separator, and no invisible or bidirectional
# format character (zero-width, LRM/RLM, embeddings and overrides, isolates, BOM): a name with U+202E would show the
# text after it reversed in an alarm or label, and an invisible name names nothing; the same pattern is in the schema
# (json_schema_extra, so the OpenAPI document says what is accepted) and checked with a message in words, by
# api/schemas.py's VehicleName (the dashboard's names) and by Settings' --vehicle-names
PRINTABLE = r"^[^\x00-\x1f\x7f-\x9f\u200b-\u200f\u2028-\u202e\u2060-\u206f\ufeff]*$"
NOT_PRINTABLE = "a vehicle name has printable characters only (no control, invisible or bidirectional characters, no line breaks)"
MAX_NAME = 40  # characters of a vehicle name, from the dashboard or --vehicle-names
MAX_SHELF_MINUTES = 7 * 24 * 60  # no console shelves an alarm for more than a week

ENV_ONLY: dict[str, Any] = {"cli": None}  # json_schema_extra of a setting without a command-line option


def cli(**options: Any) -> dict[str, Any]:
    """json_schema_extra of a field whose option differs from --<name> <TYPE>: `flag`, and argparse's `metavar`,
    `nargs` and `const`."""
    return {"cli": options}


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SEM_", extra="ignore")

    # Fields in the order `sem-console --help` lists their options.
    # HTTP and DDS
    host: str = Field("127.0.0.1", description="address to listen on (default: 127.0.0.1; anything else is only used when given)")
    port: int = Field(8000, ge=0, le=65535, description="HTTP port (default: 8000)")
    domain: int = Field(0, ge=0, le=232, description="DDS domain id, 0..232 (default: 0)")
    dds_interface: str = Field(
        "lo", description="network interface Cyclone binds to when CYCLONEDDS_URI is not set", json_schema_extra=ENV_ONLY
    )
    dds_peers: str = Field(
        "127.0.0.1",
        description="unicast discovery peers when CYCLONEDDS_URI is not set, comma separated",
        json_schema_extra=ENV_ONLY,
    )
    dds_security: Path | None = Field(
        None,
        json_schema_extra=cli(metavar="DIR"),
        description=(
            "join the DDS bus under DDS Security as the identity in DIR (the folder `sem-keys issue` writes; the "
            "fleet's identity_ca.pem, permissions_ca.pem and governance.p7s there or two folders up); needs the secure "
            "build (scripts/setup.sh --secure, run under scripts/secure). Default: CYCLONEDDS_URI's <Security> "
            "section if it has one, else an open bus"
        ),
    )
    sim: int = Field(0, ge=0, le=100, description="start N simulated vehicles alongside on the same domain (default: 0)")
    sim_time_scale: float = Field(1.0, ge=0.001, le=100, description="time scale of the embedded simulator (default: 1)")
    sim_first_vehicle: int = Field(
        1, ge=1, le=9_500, description="number of the embedded simulator's first vehicle, as sem-sim --first-vehicle (default: 1)"
    )

    # UMAA consumer and link health
    db_path: Path = Field(
        Path("var/sem-console.sqlite3"),
        json_schema_extra=cli(flag="--db"),
        description="SQLite database file: commands, audit, alarms, track history (default: "
        "var/sem-console.sqlite3); the shorthand of --database-url PATH",
    )
    database_url: str | None = Field(
        None,
        json_schema_extra=cli(metavar="URL"),
        description=(
            "the console's database: postgresql://user:password@host:port/database (shared by the consoles of an "
            "operations centre), or a SQLite file path or sqlite:///PATH (default: --db)"
        ),
    )
    console_name: str | None = Field(
        None,
        min_length=1,
        max_length=200,
        description=(
            "this console station's name, which keeps its UMAA source GUID in the database across restarts; unique "
            "among the consoles running on one database (default: <host name>:<HTTP port>)"
        ),
    )
    comms_lost_timeout: float = Field(3.0, gt=0, description="seconds without samples before a provider is lost (default: 3)")
    regained_time: float = Field(
        3.0, ge=0, description="seconds of continuous samples before a provider is regained (default: 3)"
    )
    unanswered_timeout: float = Field(5.0, gt=0, description="seconds without ISSUED before a command is unanswered (default: 5)")
    cancel_unheard_bound: float = Field(
        3600.0,
        gt=0,
        description="seconds after its cancel when a canceled command "
        "the vehicle never answered ends, if the vehicle is not heard again before "
        "(default: 3600)",
    )
    track_retention_hours: float = Field(
        24.0, gt=0, le=24 * 366, description="hours of track and chart history kept per vehicle (default: 24)"
    )
    track_thin_metres: float = Field(
        5.0,
        ge=0,
        le=10_000,
        description="a track point is stored when the vehicle has moved at least this many metres since the last one "
        "stored, --track-thin-seconds have passed, or its GPSLatLongValid or fixValid changed; 0: every second's point "
        "(default: 5)",
    )
    track_thin_seconds: float = Field(
        10.0,
        ge=0,
        le=3600,
        description="a track point is stored at least this often, in seconds, while the vehicle stays within "
        "--track-thin-metres (default: 10)",
    )
    track_rollup_after_hours: float = Field(
        1.0,
        gt=0,
        le=24 * 366,
        description="track and chart history older than this many hours is rolled up to the first point of each "
        "vehicle in each --track-rollup-seconds, and on the track each change of GPSLatLongValid or fixValid "
        "(default: 1)",
    )
    track_rollup_seconds: float = Field(
        60.0, ge=1, le=3600, description="the interval rolled-up history keeps one point of per vehicle (default: 60)"
    )
    report_interval: float = Field(
        0.005,
        ge=0,
        le=10,
        description="under load, at most one take of report topics per "
        "this many seconds (conflation window); sparse input is taken as it arrives",
        json_schema_extra=ENV_ONLY,
    )
    report_burst: int = Field(
        32,
        ge=1,
        le=1000,
        description="takes of report topics allowed at once before the conflation window applies (refilled at one per window)",
        json_schema_extra=ENV_ONLY,
    )
    ws_max_queue: int = Field(
        10_000,
        ge=10,
        description="ordered messages a WebSocket client may fall behind (while it sends "
        "nothing for ws_stall_seconds) before it is dropped",
        json_schema_extra=ENV_ONLY,
    )
    ws_window_bytes: int = Field(
        256 * 1024,
        ge=1024,
        description="a WebSocket client that acknowledges (/ws?ack=1, the "
        "dashboard) is sent reports only while fewer than this many bytes it was sent (any "
        "message) are unacknowledged; beyond, they wait at the console, conflated, not in the "
        "sockets' buffers (a batch under way may pass it; ordered messages are not held)",
        json_schema_extra=ENV_ONLY,
    )
    ws_stall_seconds: float = Field(
        5.0,
        ge=0,
        description="seconds without a completed send that make a client over ws_max_queue stalled",
        json_schema_extra=ENV_ONLY,
    )
    ws_cut_seconds: float = Field(
        30.0,
        ge=1,
        description="a WebSocket client one send to which has not completed for this long (it stopped reading: a "
        "laptop asleep) is cut, with the reason in its close frame, whatever waits for it; a big frame (a snapshot) is "
        "given the time its size takes at 16 kbit/s more",
        json_schema_extra=ENV_ONLY,
    )
    ws_compression: bool = Field(
        False,
        description="permessage-deflate on /ws when a client offers it: about a tenth of the "
        "bytes on a slow link, for CPU and latency on every message (off: a LAN or one machine)",
        json_schema_extra=ENV_ONLY,
    )

    # Operators: "name:token,name2:token2" and/or a file of "name:token" lines; both split at the
    # first colon (parse_token). None at all: no sign-in.
    operator_tokens: str = Field(
        "",
        description="'name:token,...': command routes then need Authorization: Bearer "
        "<token> (prefer SEM_OPERATOR_TOKENS or --operator-tokens-file: a command line shows in ps)",
    )
    operator_tokens_file: Path | None = Field(None, description="file of operator tokens, one 'name:token' per line")
    auth_reads: bool = Field(False, description="reads (REST GETs, /ws) need an operator token too (needs operator tokens)")

    # Requests from other sites (see docs/security.md)
    allowed_hosts: str = Field(
        "localhost,127.0.0.1,[::1]",
        description="Host header names accepted, comma separated; '*' "
        "for any (default: localhost,127.0.0.1,[::1], plus the --host address)",
    )
    allowed_origins: str = Field(
        "",
        description="origins allowed besides the console's own, comma separated "
        "(e.g. https://console.example.org behind a reverse proxy)",
    )
    forwarded_allow_ips: str = Field(
        "",
        description="addresses of reverse proxies whose X-Forwarded-For/-Proto are "
        "trusted, comma separated (default: none; the client address is the connection's)",
    )
    tls_certfile: Path | None = Field(None, description="PEM certificate: serve HTTPS and WSS (with --tls-keyfile)")
    tls_keyfile: Path | None = Field(None, description="PEM private key of --tls-certfile")
    audit_max_rows: int = Field(100_000, ge=10, description="the audit trail keeps this many newest entries (default: 100000)")
    audit_refusals_per_minute: int = Field(
        30,
        ge=1,
        description="refused requests of one client address logged and "
        "audited per minute; further ones that minute are only counted (default: 30)",
    )

    # Alarm management for a watch (see docs/console.md#alarms)
    shelve_min_minutes: float = Field(
        15.0,
        gt=0,
        le=MAX_SHELF_MINUTES,
        description=("the shortest time an operator may shelve an alarm for, minutes (default: 15)"),
    )
    shelve_max_minutes: float = Field(
        480.0,
        gt=0,
        le=MAX_SHELF_MINUTES,
        description=("the longest time an operator may shelve an alarm for, minutes (default: 480, 8 h)"),
    )
    silence_grace: float = Field(
        120.0,
        ge=0,
        description="seconds after the end of a vehicle's planned silence ('out of "
        "comms until') before, still not heard, it is an alarm (default: 120)",
    )
    chatter_count: int = Field(
        3,
        ge=2,
        le=100,
        description="an alarm that clears and returns this many times within "
        "--chatter-minutes is chattering: it stops sounding again until acknowledged (default: 3)",
    )
    chatter_minutes: float = Field(10.0, gt=0, le=24 * 60, description="the window of --chatter-count, minutes (default: 10)")

    # Recording to MCAP (see docs/recording.md)
    record: Path | None = Field(
        None,
        json_schema_extra=cli(metavar="DIR"),
        description=(
            "record every SEM sample, UMAA 3.0.1 and 6.0, to DIR/<UTC start>.mcap from the start "
            "(the dashboard's record control and POST /api/recordings record there too)"
        ),
    )
    recordings_dir: Path = Field(
        Path("var/recordings"), description="where recordings go without --record (default: var/recordings)"
    )
    record_max_bytes: int = Field(
        1 << 30, ge=65_536, description="roll a recording over to a new file at this size (default: 1 GiB)"
    )
    record_max_seconds: float = Field(
        3600.0, gt=0, description="roll a recording over to a new file after this long (default: 3600)"
    )
    record_queue: int = Field(
        2_000,
        ge=10,
        description="takes (batches of samples) waiting for the recording's writer; "
        "beyond it they are dropped and their samples counted",
        json_schema_extra=ENV_ONLY,
    )
    throttle_first_wait: float = Field(
        1.0,
        gt=0,
        le=60,
        description="seconds a client waits after its fifth wrong "
        "operator token in a row; each further one doubles it, up to 60 s",
        json_schema_extra=ENV_ONLY,
    )

    # Replay in the console (see docs/recording.md)
    replay: Path | None = Field(
        None,
        json_schema_extra=cli(metavar="FILE.mcap"),
        description=(
            "serve the dashboard from this recording instead of DDS (read-only: commands and recording are refused; "
            "play, pause, speed and seek in the dashboard and /api/replay)"
        ),
    )
    replay_speed: float = Field(1.0, ge=0.25, le=20, description="the replay's speed at start, 0.25 to 20 (default: 1)")

    # Names shown beside vehicle ids: "GUID=name,GUID2=name2"
    vehicle_names: str = Field(
        "",
        description="'GUID=name,...': names shown beside vehicle ids (a name set from the "
        "dashboard, stored, is over these; in a replay, a name the recording "
        "holds)",
    )

    # Gateways (each off unless its option is given; see docs/gateways.md)
    aspn_lcm: str | None = Field(
        None,
        json_schema_extra=cli(metavar="URL"),
        description=(
            "publish each vehicle's navigation as ASPN-23 over LCM at URL "
            "(e.g. udpm://239.255.76.67:7667?ttl=0, or file://PATH.lcm to append to a log); off by default"
        ),
    )
    aspn_prefix: str = Field(
        "aspn23",
        description=(
            "first part of the ASPN channel names <prefix>/<vehicle>/<measurement>, at most 11 characters (LCM over UDP "
            "takes channel names of up to 63) (default: aspn23)"
        ),
    )
    aspn_log_seconds: float = Field(
        300.0, gt=0, le=86_400, description="seconds of ASPN messages kept per vehicle for Record ASPN log (default: 300)"
    )
    jaus_port: int | None = Field(
        None,
        ge=0,
        le=65535,
        json_schema_extra=cli(nargs="?", const=3794, metavar="N"),
        description="answer JAUS queries over JUDP on UDP port N (3794 when N is left out); off by default",
    )
    jaus_subsystem: int = Field(
        1,
        ge=1,
        le=65534,
        json_schema_extra=cli(metavar="S"),
        description=("JAUS subsystem id: vehicles are components S.1.1, S.1.2, ... (default: 1)"),
    )
    jaus_host: str | None = Field(None, description="address the JAUS gateway listens on (default: --host)")
    foxglove_port: int = Field(
        0,
        ge=0,
        le=65535,
        json_schema_extra=cli(metavar="PORT"),
        description=(
            "serve the fleet, read-only, to Foxglove or Lichtblick over the Foxglove WebSocket protocol on TCP port PORT "
            "(Foxglove's usual one is 8765; see docs/foxglove.md); 0: off (default)"
        ),
    )
    foxglove_host: str = Field(
        "127.0.0.1",
        description=(
            "address the Foxglove gateway listens on (default: 127.0.0.1); the protocol has no authentication: "
            "another address is warned about at start"
        ),
    )
    basemap: Path | None = Field(
        None,
        json_schema_extra=cli(metavar="FILE.pmtiles"),
        description=(
            "an offline chart (PMTiles, vector or raster) the dashboard's map draws, served at /api/basemap.pmtiles "
            "(default: the built-in Natural Earth land only)"
        ),
    )

    # CoMap over IMC (UDP); off unless imc_port is given (see docs/comap.md)
    imc_port: int | None = Field(
        None, ge=0, le=65535, description="CoMap over IMC: UDP port to listen on (CoMap is off without it)"
    )
    imc_host: str = Field("0.0.0.0", description="address the IMC node listens on (default: 0.0.0.0)")
    imc_peers: str = Field("", description="IMC peers (vehicles) the console sends to: 'host:port,...'")
    # an int that the option and SEM_IMC_ID give as text, decimal or 0x hex (_imc_id_hex)
    imc_id: int = Field(
        0x4001,
        ge=0,
        le=0xFFFE,
        json_schema_extra=cli(type="str"),
        description=("the console's IMC system id, decimal or 0x hex (default: 0x4001)"),
    )
    imc_vehicles: str = Field("", description="'GUID=imcid,...': the IMC system id of each UMAA provider")
    frontend_dir: Path | None = Field(None, description="built dashboard to serve at / (default: frontend/dist)")

    _operators: dict[str, str] | None = PrivateAttr(None)
    _imc_peers: list[tuple[str, int]] = PrivateAttr(default_factory=list)

    @field_validator("allowed_hosts")
    @classmethod
    def _some_host(cls, v: str) -> str:
        """An empty list refused every request (403) with nothing said at start."""
        if not any(x.strip() for x in v.split(",")):
            raise ValueError(f"{v!r} names no host: give the host names the console is reached by, comma separated, or '*'")
        return v

    @field_validator("aspn_prefix")
    @classmethod
    def _aspn_prefix(cls, v: str) -> str:
        """Channels <prefix>/<16 hex digits>/<measurement> stay within LCM's 63 characters (gateways/aspn/gateway.py)."""
        if not re.fullmatch(r"[A-Za-z0-9_.\-/]{1,11}", v):
            raise ValueError(
                f"{v!r}: give 1 to 11 letters, digits or _ . - / (LCM over UDP takes channel names of up to 63 characters)"
            )
        return v

    @field_validator("foxglove_host")
    @classmethod
    def _foxglove_host(cls, v: str) -> str:
        """foxglove-sdk's server takes no empty address (every interface to the start's check of the port)."""
        if not v.strip():
            raise ValueError("an empty address: give one, 127.0.0.1 (this machine) or 0.0.0.0 (every interface)")
        return v

    @field_validator("imc_id", mode="before")
    @classmethod
    def _imc_id_hex(cls, v: Any) -> Any:
        """SEM_IMC_ID=0x4001 and --imc-id 0x4001."""
        return parse_imc_id(v) if isinstance(v, str) else v

    @model_validator(mode="after")
    def _consistent(self) -> Self:
        """The checks between fields, and of the texts that hold lists (ValueError: one line naming the option)."""
        self.operators()
        self.names()
        parse_imc_vehicles(self.imc_vehicles)
        # names resolved only where CoMap is on, once, here: the console's IMC node sends to these addresses
        self._imc_peers = parse_peers(self.imc_peers, resolve=self.imc_port is not None)
        if self.auth_reads and not self.operators():
            raise ValueError("--auth-reads needs operator tokens (--operator-tokens-file or SEM_OPERATOR_TOKENS)")
        if self.database_url is not None:
            if "db_path" in self.model_fields_set:
                raise ValueError("--db and --database-url: give one (--db PATH is the shorthand of --database-url PATH)")
            parse_database_url(self.database_url)
        if (self.tls_certfile is None) != (self.tls_keyfile is None):
            raise ValueError("--tls-certfile and --tls-keyfile go together")
        if self.shelve_min_minutes > self.shelve_max_minutes:
            raise ValueError(
                f"--shelve-min-minutes {self.shelve_min_minutes:g} is above --shelve-max-minutes "
                f"{self.shelve_max_minutes:g}: the shortest shelf must not be longer than the longest"
            )
        if self.replay is not None:
            if self.sim or self.record is not None:
                raise ValueError("--replay is read-only: it does not go with --sim or --record")
            if self.imc_port is not None:
                raise ValueError("--replay is read-only: it does not go with --imc-port (CoMap sends to vehicles)")
        return self

    def imc_peer_addresses(self) -> list[tuple[str, int]]:
        """--imc-peers as (address, port): resolved when the settings were made (with CoMap on)."""
        return self._imc_peers

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

    def database(self) -> DatabaseUrl:
        """The database given by --database-url, else the --db file."""
        return parse_database_url(self.database_url) if self.database_url is not None else sqlite_file(self.db_path)

    def station(self) -> str:
        """This console's name (--console-name, else <host name>:<HTTP port>)."""
        return self.console_name or f"{socket.gethostname()}:{self.port}"

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
                key = str(uuid.UUID(guid.strip()))
            except ValueError:
                raise ValueError(f"vehicle name {item!r}: {guid.strip()!r} is not a GUID") from None
            # the rules of a name set from the dashboard (PUT /api/providers/{id}/name), which these were spared
            if len(name.strip()) > MAX_NAME or not re.match(PRINTABLE, name):
                raise ValueError(f"vehicle name {item!r}: {NOT_PRINTABLE}, at most {MAX_NAME} of them")
            out[key] = name.strip()
        return out


def parse_imc_id(text: str, where: str = "") -> int:
    """An IMC system id, decimal or 0x hex, 0..0xFFFE (0xFFFF is broadcast); ValueError starting with `where`, if any."""
    prefix = f"{where}: " if where else ""
    try:
        value = int(text.strip(), 0)
    except ValueError:
        raise ValueError(f"{prefix}{text.strip()!r} is not an IMC system id (decimal or 0x hex)") from None
    if not 0 <= value <= 0xFFFE:
        raise ValueError(f"{prefix}IMC system id {value} is not in 0..0xFFFE")
    return value


def parse_peers(text: str, resolve: bool = True) -> list[tuple[str, int]]:
    """'host:port,host:port' -> [(IPv4 address, port)]; ValueError with the item that is wrong. A host name is resolved
    here, once: the console's asyncio transport sends only to addresses (a name raised ValueError on every send, a 500
    from PUT /api/worldmodel and POST /api/tasks), and the IMC sockets are IPv4. `resolve=False`: the form only (peers
    of a console without CoMap, never sent to: a name that does not resolve there must not stop it)."""
    out: list[tuple[str, int]] = []
    for item in filter(None, (x.strip() for x in text.split(","))):
        host, sep, port = item.rpartition(":")
        if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
            raise ValueError(f"IMC peer {item!r} is not host:port")
        if not resolve:
            out.append((host.strip("[]"), int(port)))
            continue
        try:
            address = socket.getaddrinfo(host.strip("[]"), int(port), socket.AF_INET, socket.SOCK_DGRAM)[0][4][0]
        except (socket.gaierror, UnicodeError) as e:
            raise ValueError(
                f"IMC peer {item!r}: {host} is not an IPv4 address or a host name this machine resolves "
                f"({getattr(e, 'strerror', None) or e})"
            ) from None
        out.append((str(address), int(port)))
    return out


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


class BusSettings(BaseSettings):
    """What the commands other than sem-console take from the SEM_* environment: the DDS domain and network
    (the same fields as `Settings`, without the console's cross-field checks, so a console's tokens file or
    TLS pair never stops `sem-sim`, `sem-replay` or `sem-check`)."""

    model_config = SettingsConfigDict(env_prefix="SEM_", extra="ignore")

    # Settings' own field definitions (one definition each); pydantic takes a FieldInfo as the field, mypy's
    # plugin types only Field(...) calls
    domain: int = Settings.model_fields["domain"]  # type: ignore[assignment]  # a FieldInfo: see above
    dds_interface: str = Settings.model_fields["dds_interface"]  # type: ignore[assignment]  # a FieldInfo
    dds_peers: str = Settings.model_fields["dds_peers"]  # type: ignore[assignment]  # a FieldInfo
    dds_security: Path | None = Settings.model_fields["dds_security"]  # type: ignore[assignment]  # a FieldInfo
