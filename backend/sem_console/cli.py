"""`sem-console`: the console backend (REST, WebSocket, dashboard) on a DDS domain."""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

from pydantic import ValidationError

from sem_console.comap.transport import parse_peers
from sem_console.core.config import Settings, parse_imc_id, parse_imc_vehicles
from sem_console.dds.bus import DdsConfigError, open_domain
from sem_console.recording.replay import check_file
from sem_console.sim.cli import _Parser


def _imc_id(text: str) -> int:
    try:
        return parse_imc_id(text, "--imc-id")
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="sem-console", description=(
        "UMAA SEM operator console: a UMAA Service Consumer for GPSFix and InertialSensor commands that "
        "streams GPS and INS state over WebSockets. Every option can also be set as an SEM_* environment "
        "variable (e.g. SEM_DOMAIN, SEM_OPERATOR_TOKENS)."))
    p.add_argument("--host", help="address to listen on (default: 127.0.0.1; anything else is only used when given)")
    p.add_argument("--port", type=int, help="HTTP port (default: 8000)")
    p.add_argument("--domain", type=int, help="DDS domain id, 0..232 (default: 0)")
    p.add_argument("--sim", type=int, help="start N simulated vehicles alongside on the same domain (default: 0)")
    p.add_argument("--sim-time-scale", type=float, help="time scale of the embedded simulator (default: 1)")
    p.add_argument("--sim-first-vehicle", type=int, help="number of the embedded simulator's first vehicle, as sem-sim --first-vehicle (default: 1)")
    p.add_argument("--db", type=Path, dest="db_path", help="SQLite command history (default: var/sem-console.sqlite3)")
    p.add_argument("--comms-lost-timeout", type=float, help="seconds without samples before a provider is lost (default: 3)")
    p.add_argument("--regained-time", type=float, help="seconds of continuous samples before a provider is regained (default: 3)")
    p.add_argument("--unanswered-timeout", type=float, help="seconds without ISSUED before a command is unanswered (default: 5)")
    p.add_argument("--track-retention-hours", type=float, help="hours of track and chart history kept per vehicle (default: 24)")
    p.add_argument("--operator-tokens", help="'name:token,...': command routes then need Authorization: Bearer <token> "
                   "(prefer SEM_OPERATOR_TOKENS or --operator-tokens-file: a command line shows in ps)")
    p.add_argument("--operator-tokens-file", type=Path, help="file of operator tokens, one 'name:token' per line")
    p.add_argument("--auth-reads", action="store_true", default=None,
                   help="reads (REST GETs, /ws) need an operator token too (needs operator tokens)")
    p.add_argument("--allowed-hosts", help="Host header names accepted, comma separated; '*' for any "
                   "(default: localhost,127.0.0.1,[::1], plus the --host address)")
    p.add_argument("--allowed-origins", help="origins allowed besides the console's own, comma separated "
                   "(e.g. https://console.example.org behind a reverse proxy)")
    p.add_argument("--forwarded-allow-ips", help="addresses of reverse proxies whose X-Forwarded-For/-Proto are trusted, "
                   "comma separated (default: none; the client address is the connection's)")
    p.add_argument("--tls-certfile", type=Path, help="PEM certificate: serve HTTPS and WSS (with --tls-keyfile)")
    p.add_argument("--tls-keyfile", type=Path, help="PEM private key of --tls-certfile")
    p.add_argument("--audit-max-rows", type=int, help="the audit trail keeps this many newest entries (default: 100000)")
    p.add_argument("--audit-refusals-per-minute", type=int, help="refused requests of one client address logged and "
                   "audited per minute; further ones that minute are only counted (default: 30)")
    p.add_argument("--record", type=Path, metavar="DIR", help="record every SEM sample to DIR/<UTC start>.mcap from the start "
                   "(the dashboard's record control and POST /api/recordings record there too)")
    p.add_argument("--recordings-dir", type=Path, help="where recordings go without --record (default: var/recordings)")
    p.add_argument("--record-max-bytes", type=int, help="roll a recording over to a new file at this size (default: 1 GiB)")
    p.add_argument("--record-max-seconds", type=float, help="roll a recording over to a new file after this long (default: 3600)")
    p.add_argument("--replay", type=Path, metavar="FILE.mcap", help="serve the dashboard from this recording instead of DDS "
                   "(read-only: commands and recording are refused; play, pause, speed and seek in the dashboard and /api/replay)")
    p.add_argument("--replay-speed", type=float, help="the replay's speed at start, 0.25 to 20 (default: 1)")
    p.add_argument("--vehicle-names", help="'GUID=name,...': names shown beside vehicle ids")
    p.add_argument("--aspn-lcm", metavar="URL", help="publish each vehicle's navigation as ASPN-23 over LCM at URL "
                   "(e.g. udpm://239.255.76.67:7667?ttl=0, or file://PATH.lcm to append to a log); off by default")
    p.add_argument("--aspn-prefix", help="first part of the ASPN channel names <prefix>/<vehicle>/<measurement> (default: aspn23)")
    p.add_argument("--aspn-log-seconds", type=float, help="seconds of ASPN messages kept per vehicle for Record ASPN log (default: 300)")
    p.add_argument("--jaus-port", type=int, nargs="?", const=3794, metavar="N",
                   help="answer JAUS queries over JUDP on UDP port N (3794 when N is left out); off by default")
    p.add_argument("--jaus-subsystem", type=int, metavar="S", help="JAUS subsystem id: vehicles are components S.1.1, S.1.2, ... (default: 1)")
    p.add_argument("--jaus-host", help="address the JAUS gateway listens on (default: --host)")
    p.add_argument("--basemap", type=Path, metavar="FILE.pmtiles", help="an offline chart (PMTiles, vector or raster) the "
                   "dashboard's map draws, served at /api/basemap.pmtiles (default: the built-in Natural Earth land only)")
    p.add_argument("--imc-port", type=int, help="CoMap over IMC: UDP port to listen on (CoMap is off without it)")
    p.add_argument("--imc-host", help="address the IMC node listens on (default: 0.0.0.0)")
    p.add_argument("--imc-peers", help="IMC peers (vehicles) the console sends to: 'host:port,...'")
    p.add_argument("--imc-id", type=_imc_id, help="the console's IMC system id, decimal or 0x hex (default: 0x4001)")
    p.add_argument("--imc-vehicles", help="'GUID=imcid,...': the IMC system id of each UMAA provider")
    p.add_argument("--frontend-dir", type=Path, help="built dashboard to serve at / (default: frontend/dist)")
    p.add_argument("--log-level", choices=("debug", "info", "warning", "error"), default="info")
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    given = {k: v for k, v in vars(args).items() if v is not None and k != "log_level"}
    try:
        settings = Settings(**given)
    except ValidationError as e:
        err = e.errors()[0]
        parser.error(f"--{str(err['loc'][0]).replace('_', '-')}: {err['msg']}")
    try:
        settings.operators()
        settings.names()
        parse_imc_vehicles(settings.imc_vehicles)
        parse_peers(settings.imc_peers)
    except ValueError as e:
        parser.error(str(e))
    if settings.auth_reads and not settings.operators():
        parser.error("--auth-reads needs operator tokens (--operator-tokens-file or SEM_OPERATOR_TOKENS)")
    if (settings.tls_certfile is None) != (settings.tls_keyfile is None):
        parser.error("--tls-certfile and --tls-keyfile go together")
    if settings.basemap is not None and not settings.basemap.is_file():
        parser.error(f"--basemap: no such file: {settings.basemap}")
    for tls_file in filter(None, (settings.tls_certfile, settings.tls_keyfile)):
        if not tls_file.is_file():
            parser.error(f"no such file: {tls_file}")
    if settings.replay is not None:
        if settings.sim or settings.record is not None:
            parser.error("--replay is read-only: it does not go with --sim or --record")
        if settings.imc_port is not None:
            parser.error("--replay is read-only: it does not go with --imc-port (CoMap sends to vehicles)")
        problem = check_file(settings.replay)
        if problem:
            parser.error(problem)
    if settings.aspn_lcm is not None:
        from sem_console.gateways.aspn.gateway import check_url

        try:  # an URL LCM cannot open is a one-line error at start, not a gateway that never publishes
            check_url(settings.aspn_lcm)
        except (OSError, RuntimeError, ValueError) as e:
            parser.error(f"--aspn-lcm {settings.aspn_lcm}: {e}")
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    for warning in start_warnings(settings):
        logging.getLogger("sem-console").warning(warning)
    if settings.replay is None:
        try:  # a DDS configuration Cyclone refuses is a one-line error here, not a traceback in the lifespan
            open_domain(settings.domain, settings.dds_interface, settings.dds_peers)
        except DdsConfigError as e:
            print(f"sem-console: {e}", file=sys.stderr)
            return 2
    import uvicorn

    from sem_console.main import create_app

    uvicorn.run(create_app(settings), host=settings.host, port=settings.port, log_level=args.log_level,
                ws_ping_interval=20, ws_ping_timeout=20, ws_per_message_deflate=settings.ws_compression,
                # X-Forwarded-For only from the proxies named: uvicorn's default trusts any process on 127.0.0.1,
                # which could then pick its own client address (the token slow-down, the audit's client)
                proxy_headers=bool(settings.forwarded_allow_ips.strip()),
                forwarded_allow_ips=settings.forwarded_allow_ips.strip() or None,
                ssl_certfile=settings.tls_certfile, ssl_keyfile=settings.tls_keyfile)
    return 0


def start_warnings(settings: Settings) -> list[str]:
    out = []
    beyond_loopback = settings.host not in ("127.0.0.1", "localhost", "::1")
    if beyond_loopback and not settings.operators():
        out.append(f"listening on {settings.host} with no operator token: anyone who reaches this port can command vehicles")
    if beyond_loopback and settings.operators() and settings.tls_certfile is None:
        out.append(f"listening on {settings.host} with operator tokens and no TLS: tokens cross the network in clear "
                   "text (--tls-certfile and --tls-keyfile, or a TLS reverse proxy)")
    if "*" in settings.host_names():
        out.append("--allowed-hosts '*' accepts any Host header: a page under a foreign DNS name that resolves to this "
                   "console (DNS rebinding) passes the Host and the Origin checks (without --auth-reads it reads the "
                   "vehicles; without operator tokens it commands them): name the hosts instead")
    f = settings.operator_tokens_file
    if f is not None and f.stat().st_mode & 0o077:
        out.append(f"{f} can be read by other users of this machine (chmod 600 it)")
    return out


if __name__ == "__main__":
    sys.exit(main())
