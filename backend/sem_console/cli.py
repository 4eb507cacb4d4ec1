"""`sem-console`: the console backend (REST, WebSocket, dashboard) on a DDS domain."""

from __future__ import annotations

import argparse
import contextlib
import errno
import logging
import socket
import sqlite3
import ssl
import sys
import tempfile
from contextlib import closing
from pathlib import Path
from typing import TYPE_CHECKING

from pydantic import ValidationError

from sem_console.core.command_line import Parser, add_model_options, model_error
from sem_console.core.config import Settings

if TYPE_CHECKING:
    from sem_console.dds.bus import Bus

WS_MAX_MESSAGE_BYTES = 64 * 1024  # a bigger message from a WebSocket client closes its socket (1009, message too big)
KEEP_ALIVE_SECONDS = 65  # an idle HTTP/1.1 connection kept open this long (uvicorn's default is 5)


def build_parser() -> argparse.ArgumentParser:
    """The options of every field of Settings that has one (core/command_line.add_model_options), then --log-level."""
    p = Parser(
        prog="sem-console",
        description=(
            "UMAA SEM operator console: a UMAA Service Consumer for GPSFix and InertialSensor commands that "
            "streams GPS and INS state over WebSockets. Every option can also be set as an SEM_* environment "
            "variable (e.g. SEM_DOMAIN, SEM_OPERATOR_TOKENS)."
        ),
    )
    add_model_options(p, Settings)
    p.add_argument("--log-level", choices=("debug", "info", "warning", "error"), default="info")  # the command line's only
    return p


def command_writers_allowed(bus: Bus) -> None:
    """The console's command writers (console/sources.py makes them at its start) made once and closed with `bus`:
    DdsConfigError (one line) when the identity's permissions do not let it write commands."""
    from sem_console.versions.commands import COMMAND_TOPICS

    try:
        for topic in COMMAND_TOPICS:
            bus.writer(topic)
    finally:
        bus.close()


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    given = {k: v for k, v in vars(args).items() if v is not None and k != "log_level"}
    try:  # the checks between options too: model validators of Settings
        settings = Settings(**given)
    except ValidationError as e:
        parser.error(model_error(Settings, e, given))  # a value from the environment named by its SEM_* variable
    if settings.basemap is not None and (problem := check_basemap(settings.basemap)):
        parser.error(problem)
    if settings.frontend_dir is not None and not (settings.frontend_dir / "index.html").is_file():
        # the console served no dashboard then, and / answered {"detail": "Not Found"} with nothing said at start
        parser.error(
            f"--frontend-dir {settings.frontend_dir} has no index.html: build the dashboard into it "
            "(cd frontend && npx vite build --outDir DIR) or pass another --frontend-dir"
        )
    for tls_file in filter(None, (settings.tls_certfile, settings.tls_keyfile)):
        if not tls_file.is_file():
            parser.error(f"no such file: {tls_file}")
    if (
        settings.tls_certfile is not None
        and settings.tls_keyfile is not None
        and (problem := check_tls(settings.tls_certfile, settings.tls_keyfile))
    ):
        parser.error(problem)
    if settings.replay is not None:
        from sem_console.recording.reader import check_file

        if problem := check_file(settings.replay):
            parser.error(problem)
    if settings.aspn_lcm is not None:
        from sem_console.gateways.aspn.gateway import check_url

        try:  # an URL LCM cannot open is a one-line error at start, not a gateway that never publishes
            check_url(settings.aspn_lcm)
        except (OSError, RuntimeError, ValueError) as e:
            parser.error(f"--aspn-lcm {settings.aspn_lcm}: {e}")
    # files and ports before DDS and the application start: each problem is one line and exit code 2 here,
    # not a traceback from the application's start-up (or uvicorn's "startup complete" and then a bind error)
    database = settings.database()
    if settings.replay is None:  # a replay keeps its state in a temporary database and records nothing
        db_option = "--database-url" if settings.database_url is not None else "--db"  # the option the operator gave
        named = settings.database_url is not None or "db_path" in settings.model_fields_set  # else the default file
        for problem in (
            check_database(database.path, db_option, named) if database.path is not None else None,
            check_directory("--record", settings.record) if settings.record else None,
            # a folder given for the record control; the default one only gets a warning below
            check_directory("--recordings-dir", settings.recordings_dir)
            if "recordings_dir" in settings.model_fields_set
            else None,
        ):
            if problem:
                parser.error(problem)
    try:
        listeners = listen(settings.host, settings.port)
        check_udp_ports(settings)
        if settings.foxglove_port:  # bound by foxglove-sdk's own server once the application starts: checked here
            for sock in listen(settings.foxglove_host, settings.foxglove_port, "--foxglove-port", "--foxglove-host"):
                sock.close()
    except StartError as e:
        parser.error(str(e))
    # the database's and DDS's modules (about 0.3 s) once the checks above passed: a bad start is told before them
    # (before logging is set up: alembic logs its plugins as it is imported)
    from sem_console.dds.bus import Bus, DdsConfigError, bus_security, open_domain
    from sem_console.dds.security import OPEN_BUS
    from sem_console.storage.database import Database, StorageError

    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    store = None
    new_file = database.path is not None and not (database.path.exists() and database.path.stat().st_size)
    if settings.replay is None:
        try:  # reached, upgraded and this console's name held here: a problem is one line, not a lifespan traceback
            store = Database(database, settings.audit_max_rows)
            store.claim(settings.station())
        except StorageError as e:
            if store is not None:
                store.close()
            parser.error(str(e))
        logging.getLogger("sem-console").info("database %s, console name %r", database.shown, settings.station())
        if new_file:  # a typo in --db would otherwise start an empty history unnoticed
            logging.getLogger("sem-console").warning("new database %s: no history there before this start", database.shown)
    for warning in start_warnings(settings):
        logging.getLogger("sem-console").warning(warning)
    if settings.replay is None:
        try:  # a DDS configuration Cyclone refuses is a one-line error here, not a traceback in the lifespan
            security = bus_security(settings.dds_security, settings.domain)
            open_domain(settings.domain, settings.dds_interface, settings.dds_peers, security)
            if security is not None:  # documents Cyclone's plugins refuse (a domain the governance does not cover)
                command_writers_allowed(Bus(settings.domain))
            else:
                logging.getLogger("sem-console").warning(OPEN_BUS)
        except DdsConfigError as e:
            print(f"sem-console: {e}", file=sys.stderr)
            return 2
    import uvicorn

    from sem_console.main import create_app

    config = uvicorn.Config(
        create_app(settings, store),
        host=settings.host,
        port=settings.port,
        log_level=args.log_level,
        ws_ping_interval=20,
        ws_ping_timeout=20,
        ws_per_message_deflate=settings.ws_compression,
        # an idle HTTP connection kept 65 s, not uvicorn's 5: clients that pool connections without reading the
        # Keep-Alive header (Node's agent, Playwright's requests, a script's session) reused one just as the console
        # closed it and got a reset; kept longer than they idle between requests, the client is the side that closes
        timeout_keep_alive=KEEP_ALIVE_SECONDS,
        # a client's messages are small (ping, resync, ack, select: under 200 bytes); uvicorn's
        # default of 16 MiB let any client have megabytes parsed on the event loop, message after message
        ws_max_size=WS_MAX_MESSAGE_BYTES,
        # X-Forwarded-For only from the proxies named: uvicorn's default trusts any process on
        # 127.0.0.1, which could then pick its own client address (the token slow-down, the audit's client)
        proxy_headers=bool(settings.forwarded_allow_ips.strip()),
        forwarded_allow_ips=settings.forwarded_allow_ips.strip() or None,
        ssl_certfile=settings.tls_certfile,
        ssl_keyfile=settings.tls_keyfile,
    )
    server = uvicorn.Server(config)
    scheme = "https" if settings.tls_certfile else "http"
    for sock in listeners:  # uvicorn names no address for sockets it is given
        address, port = sock.getsockname()[:2]
        logging.getLogger("sem-console").info(
            "listening on %s://%s:%d", scheme, f"[{address}]" if ":" in address else address, port
        )
    # on the sockets bound above: no other process can take the port between the check and the start
    with contextlib.suppress(KeyboardInterrupt):
        server.run(sockets=listeners)
    return 0 if server.started else 3  # 3: the application's start-up failed (uvicorn's code for it)


def start_warnings(settings: Settings) -> list[str]:
    from sem_console.main import DEFAULT_FRONTEND

    out = []
    if settings.frontend_dir is None and not (DEFAULT_FRONTEND / "index.html").is_file():
        if DEFAULT_FRONTEND.parent.is_dir():  # a source checkout: the dashboard is not built yet
            out.append(
                f"no dashboard built in {DEFAULT_FRONTEND}: / answers 404 (build it: cd frontend && npm run build, "
                "or pass --frontend-dir); the API and /ws work"
            )
        else:  # installed from a wheel: the dashboard is not in the package, and the checkout's path means nothing here
            out.append(
                "this installation has no dashboard: / answers 404 (pass --frontend-dir DIR, a build of the "
                "project's frontend/: npm run build writes frontend/dist); the API and /ws work"
            )
    beyond_loopback = settings.host not in ("127.0.0.1", "localhost", "::1")
    if beyond_loopback and not settings.operators():
        out.append(f"listening on {settings.host} with no operator token: anyone who reaches this port can command vehicles")
    if beyond_loopback and settings.operators() and settings.tls_certfile is None:
        out.append(
            f"listening on {settings.host} with operator tokens and no TLS: tokens cross the network in clear "
            "text (--tls-certfile and --tls-keyfile, or a TLS reverse proxy)"
        )
    if settings.foxglove_port and settings.foxglove_host not in ("127.0.0.1", "localhost", "::1"):
        out.append(
            f"--foxglove-host {settings.foxglove_host}: the Foxglove WebSocket protocol has no authentication: anyone who "
            f"reaches port {settings.foxglove_port} reads the whole fleet (keep 127.0.0.1 and reach it over an SSH tunnel: "
            "docs/foxglove.md)"
        )
    if "*" in settings.host_names():
        out.append(
            "--allowed-hosts '*' accepts any Host header: a page under a foreign DNS name that resolves to this "
            "console (DNS rebinding) passes the Host and the Origin checks (without --auth-reads it reads the "
            "vehicles; without operator tokens it commands them): name the hosts instead"
        )
    if (
        settings.replay is None
        and settings.record is None
        and "recordings_dir" not in settings.model_fields_set
        and (problem := check_directory("--recordings-dir", settings.recordings_dir))
    ):
        out.append(f"{problem} (the record control fails until then)")
    f = settings.operator_tokens_file
    if f is not None and f.stat().st_mode & 0o077:
        out.append(f"{f} can be read by other users of this machine (chmod 600 it)")
    return out


# ---- start-up checks: a problem is one line naming the file or port and what to do -----------------------------
class StartError(Exception):
    """A port the console cannot listen on: its message is the one line the operator reads."""


def check_database(path: Path, option: str = "--db", given: bool = True) -> str | None:
    """Why the console cannot keep its history in `path`, or None. SQLite itself reads it (read-only,
    `PRAGMA quick_check`, about 0.3 s for 300 MB): the store would otherwise fail in the application's
    start-up with a long traceback. A missing or empty file is a new database; its folder must exist when the
    operator named the file (`given`: a typo is not a new history), else it is made (the default file)."""
    fix = f"move it aside or pass another {option}"
    if path.is_dir():
        return f"{option} {path} is a directory, not a database file: pass another {option}"
    if given and not path.parent.exists():
        return f"{option} {path}: the folder {path.parent} does not exist: create it (mkdir -p {path.parent}) or fix the path"
    # the store creates the directory, and WAL mode writes -wal and -shm files beside the database
    if problem := writable_directory(path.parent):
        return f"{option} {path}: {problem}: pass another {option}"
    if not path.exists():
        return None
    try:
        with open(path, "r+b"):  # the console writes to it: readable is not enough
            pass
    except OSError as e:
        return f"{option} {path}: cannot open it to read and write ({e.strerror or e}): fix its permissions, or {fix}"
    try:
        with closing(sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True, timeout=10)) as db:
            problems = [str(row[0]) for row in db.execute("PRAGMA quick_check")]
    except sqlite3.DatabaseError as e:
        if getattr(e, "sqlite_errorname", "") in ("SQLITE_BUSY", "SQLITE_LOCKED"):
            return f"{option} {path} is locked by another process: stop it, or pass another {option}"
        return f"{option} {path} is not a SQLite database or is damaged ({e}): {fix}"
    if problems != ["ok"]:
        return f"{option} {path} is damaged ({problems[0] if problems else 'no answer to PRAGMA quick_check'}): {fix}"
    return None


def check_directory(option: str, directory: Path) -> str | None:
    """Why recordings cannot be written into `directory`, or None. A missing directory is left to the
    recorder to make (when it first records): its nearest existing parent must take files."""
    existing = next((d for d in (directory, *directory.parents) if d.exists()), Path("."))
    if not existing.is_dir():
        return f"{option} {directory}: {existing} is a file, not a directory: pass another directory"
    problem = writable_directory(existing)
    return f"{option} {directory}: {problem}: pass another directory" if problem else None


def writable_directory(directory: Path) -> str | None:
    """Why no file can be written in `directory` (made if missing), or None."""
    try:
        directory.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):  # nothing is left behind, even on a crash
            pass
    except (FileExistsError, NotADirectoryError):
        return f"cannot make the directory {directory} (a file is in the way)"
    except OSError as e:
        return f"cannot write in {directory} ({e.strerror or e})"
    return None


PMTILES_HEADER = 127  # bytes of a PMTiles v3 header, which starts with b"PMTiles" and the version byte 3


def check_basemap(path: Path) -> str | None:
    """Why `path` is not a PMTiles v3 archive the dashboard's map can read, or None (only the header is read)."""
    if not path.exists():
        return f"--basemap: no such file: {path}"
    if path.is_dir():
        return f"--basemap {path} is a directory, not a PMTiles file"
    try:
        with open(path, "rb") as f:
            head = f.read(PMTILES_HEADER)
    except OSError as e:
        return f"--basemap {path}: cannot read it ({e.strerror or e})"
    if not head.startswith(b"PMTiles"):
        return (
            f"--basemap {path} is not a PMTiles file (it does not start with 'PMTiles'): "
            "convert it (pmtiles convert FILE.mbtiles FILE.pmtiles) or pass another --basemap"
        )
    if len(head) < PMTILES_HEADER or head[7] != 3:
        found = f"version {head[7]}" if len(head) > 7 else "no version"
        return (
            f"--basemap {path} is not a whole PMTiles version 3 file ({found}, {len(head)} header bytes): pass another --basemap"
        )
    return None


def check_tls(certfile: Path, keyfile: Path) -> str | None:
    """Why uvicorn could not serve TLS with these files, or None."""
    try:
        ssl.create_default_context(ssl.Purpose.CLIENT_AUTH).load_cert_chain(certfile, keyfile)
    except (OSError, ssl.SSLError) as e:
        return f"--tls-certfile {certfile} and --tls-keyfile {keyfile}: not a PEM certificate and its private key ({e})"
    return None


def listen(host: str, port: int, option: str = "--port", host_option: str = "--host") -> list[socket.socket]:
    """Sockets bound to every address of `host` at `port`, as uvicorn (asyncio's create_server) binds them,
    to hand to uvicorn: a busy port is then found before anything starts, and nothing takes it meanwhile.
    StartError names the host and port (as `option` and `host_option`) and what to do."""
    where = f"{host}:{port}" if ":" not in host else f"[{host}]:{port}"
    try:
        infos = socket.getaddrinfo(host or None, port, socket.AF_UNSPEC, socket.SOCK_STREAM, 0, socket.AI_PASSIVE)
    except socket.gaierror as e:
        raise StartError(
            f"{host_option} {host}: not an address of this machine ({e.strerror}): pass another {host_option}"
        ) from None
    sockets: list[socket.socket] = []
    for family, kind, proto, _name, address in dict.fromkeys(infos):
        sock = socket.socket(family, kind, proto)
        sockets.append(sock)
        try:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            if family == socket.AF_INET6:  # one family per socket, as asyncio does
                sock.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
            sock.bind(address)
        except OSError as e:
            for s in sockets:
                s.close()
            raise StartError(port_problem(option, host_option, "TCP", where, e)) from None
    return sockets


def check_udp_ports(settings: Settings) -> None:
    """StartError when the JAUS gateway's or the IMC node's UDP port cannot be bound (bound together, so
    the two given the same port is found too, then released for them)."""
    wanted: list[tuple[str, str, str, int, int]] = []  # option, its host option, host, port, address family
    if settings.jaus_port is not None:
        host_option = "--jaus-host" if settings.jaus_host else "--host"
        wanted.append(("--jaus-port", host_option, settings.jaus_host or settings.host, settings.jaus_port, socket.AF_UNSPEC))
    if settings.imc_port is not None and settings.replay is None:  # comap/transport.py binds IPv4
        wanted.append(("--imc-port", "--imc-host", settings.imc_host, settings.imc_port, socket.AF_INET))
    taken: list[socket.socket] = []
    try:
        for option, host_option, host, port, family in wanted:
            where = f"{host}:{port}" if ":" not in host else f"[{host}]:{port}"
            try:
                info = socket.getaddrinfo(host, port, family, socket.SOCK_DGRAM)[0]
                sock = socket.socket(info[0], info[1], info[2])
                taken.append(sock)
                sock.bind(info[4])
            except socket.gaierror as e:
                raise StartError(
                    f"{host_option} {host}: not an address of this machine ({e.strerror}): pass another {host_option}"
                ) from None
            except OSError as e:
                raise StartError(port_problem(option, host_option, "UDP", where, e)) from None
    finally:
        for sock in taken:
            sock.close()


def port_problem(option: str, host_option: str, protocol: str, where: str, e: OSError) -> str:
    if e.errno == errno.EADDRINUSE:
        return f"{option}: {protocol} {where} is already in use (another sem-console?): stop it, or pass another {option}"
    if e.errno == errno.EACCES:
        return (
            f"{option}: no permission to listen on {protocol} {where} (ports below 1024 need privileges): pass another {option}"
        )
    if e.errno == errno.EADDRNOTAVAIL:
        return (
            f"{host_option}: cannot listen on {protocol} {where}: the address is not one of this machine's: "
            f"pass another {host_option}"
        )
    return f"{option}: cannot listen on {protocol} {where} ({e.strerror or e})"


if __name__ == "__main__":
    sys.exit(main())
