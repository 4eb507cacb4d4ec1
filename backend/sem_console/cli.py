"""`sem-console`: the console backend (REST, WebSocket, dashboard) on a DDS domain."""

from __future__ import annotations

import argparse
import logging
import sys
from pathlib import Path

from pydantic import ValidationError

from sem_console.core.config import Settings
from sem_console.dds.bus import DdsConfigError, open_domain
from sem_console.sim.cli import _Parser


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
    p.add_argument("--operator-tokens", help="'name:token,...': command routes then need Authorization: Bearer <token>")
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
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    if settings.host not in ("127.0.0.1", "localhost", "::1") and not settings.operators():
        logging.getLogger("sem-console").warning(
            "listening on %s with no operator token: anyone who reaches this port can command vehicles", settings.host)
    try:  # a DDS configuration Cyclone refuses is a one-line error here, not a traceback in the lifespan
        open_domain(settings.domain, settings.dds_interface, settings.dds_peers)
    except DdsConfigError as e:
        print(f"sem-console: {e}", file=sys.stderr)
        return 2
    import uvicorn

    from sem_console.main import create_app

    uvicorn.run(create_app(settings), host=settings.host, port=settings.port, log_level=args.log_level,
                ws_ping_interval=20, ws_ping_timeout=20)
    return 0


if __name__ == "__main__":
    sys.exit(main())
