"""`sem-relay`: one side of a DDS domain joined to others across a WAN over Eclipse Zenoh, or (`--router`) the Zenoh
router both sides connect to (docs/relay.md)."""

from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
import threading
from pathlib import Path
from typing import Any

import zenoh
from pydantic import ValidationError

from sem_console.core.command_line import (
    Parser,
    add_dds_security,
    add_model_options,
    cli_options,
    env_name,
    from_environment,
    model_error,
    ranged,
)
from sem_console.core.config import BusSettings
from sem_console.dds.bus import Bus, DdsConfigError, bus_security
from sem_console.relay.link import parse_caps
from sem_console.relay.options import RelayOptions, endpoint_problem, status_file_problem, tls_problem
from sem_console.relay.relay import Relay, serve_status, zenoh_config

log = logging.getLogger("sem-relay")


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="sem-relay",
        description=(
            "Join a DDS domain to others across a WAN over Eclipse Zenoh: on the vehicles' side, their SEM reports, statuses "
            "and acks go out and commands come in; on the operations side, the other way. --router runs the Zenoh router "
            "both sides connect to. Every option is also a SEM_RELAY_* environment variable (--link-class: "
            "SEM_RELAY_LINK_CLASS)."
        ),
    )
    p.add_argument(
        "--domain",
        type=ranged(int, 0, 232),
        default=from_environment("sem-relay", BusSettings).domain,
        help=("DDS domain id, 0..232 (default: SEM_DOMAIN or 0)"),
    )
    add_dds_security(p, "sem-relay")
    add_model_options(p, RelayOptions)
    p.add_argument(
        "--config",
        type=Path,
        metavar="FILE",
        help=(
            "a file of SEM_RELAY_* lines in the environment's form (KEY=value: a systemd EnvironmentFile, a compose "
            "env_file), the endpoints and TLS files of one deployment in one place; the command line and the "
            "environment come before it"
        ),
    )
    p.add_argument(
        "--log-level", choices=("debug", "info", "warning", "error"), default="info", help=("log level (default: %(default)s)")
    )
    return p


def options_from(args: argparse.Namespace) -> RelayOptions:
    """The options given on the command line over the SEM_RELAY_* environment; a bad value is one line and exit 2."""
    given = {name: getattr(args, name) for name in cli_options(RelayOptions) if getattr(args, name) is not None}
    config: Path | None = getattr(args, "config", None)
    if config is not None:
        try:
            config.read_bytes()
        except OSError as e:
            print(f"sem-relay: error: --config {config}: {e.strerror or e}: give a readable file", file=sys.stderr)
            raise SystemExit(2) from None
    try:
        opts = RelayOptions(_env_file=config, **given)  # pydantic-settings reads the file under the environment
        parse_caps(opts.caps)
    except ValidationError as e:
        field = str(e.errors()[0]["loc"][0]) if e.errors() and e.errors()[0]["loc"] else ""
        where = ""
        if config is not None and field and field not in given and env_name(RelayOptions, field) not in os.environ:
            where = f" (in --config {config})"  # the value came from the file
        print(f"sem-relay: error: {model_error(RelayOptions, e, given)}{where}", file=sys.stderr)
        raise SystemExit(2) from None
    except ValueError as e:
        print(f"sem-relay: error: {'--caps' if 'caps' in given else env_name(RelayOptions, 'caps')} {e}", file=sys.stderr)
        raise SystemExit(2) from None
    return opts


def open_session(opts: RelayOptions, stopping: threading.Event) -> zenoh.Session | None:
    """The Zenoh session, once its endpoints answer (a relay started before its router waits for it, and says so
    once); None when stopped first."""
    said = False
    while not stopping.is_set():
        try:
            return zenoh.open(zenoh_config(opts))
        except zenoh.ZError as e:
            if not said:
                log.warning(
                    "cannot connect to any Zenoh endpoint yet (%s): trying again every second (a router not up yet, "
                    "or one refusing this relay's certificate)",
                    str(e).split("  at ")[0],
                )
                said = True
        stopping.wait(1.0)
    return None


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    opts = options_from(args)
    if problem := endpoint_problem(opts) or tls_problem(opts) or status_file_problem(opts):
        print(f"sem-relay: error: {problem}", file=sys.stderr)
        return 2
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    stopping = threading.Event()

    def stop(_signum: int, _frame: Any) -> None:
        stopping.set()

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    session = open_session(opts, stopping)
    if session is None:
        return 0
    try:
        if opts.router:
            log.info(
                "Zenoh router %s listening on %s%s",
                opts.name,
                ", ".join(opts.listen_endpoints),
                f", connected to {', '.join(opts.connect_endpoints)}" if opts.connect_endpoints else "",
            )
            stopping.wait()
            return 0
        settings = from_environment("sem-relay", BusSettings)
        try:
            bus = Bus(args.domain, settings.dds_interface, settings.dds_peers, bus_security(args.dds_security, args.domain))
        except DdsConfigError as e:
            print(f"sem-relay: {e}", file=sys.stderr)
            return 2
        relay = Relay(opts, bus, session)
        try:
            status = serve_status(relay, opts.status_port) if opts.status_port is not None else None
        except OSError as e:
            print(
                f"sem-relay: error: --status-port {opts.status_port}: cannot listen on it ({e.strerror or e}): give another port",
                file=sys.stderr,
            )
            relay.close()
            bus.close()
            return 2
        relay.start()
        log.info(
            "relay %s: the %s' side of domain %d, link class %s, through %s",
            opts.name,
            opts.side,
            args.domain,
            opts.link_class,
            ", ".join(opts.connect_endpoints + opts.listen_endpoints),
        )
        stopping.wait()
        if status is not None:
            status.shutdown()
        relay.report()
        relay.close()
        bus.close()
        return 0
    finally:
        session.close()


if __name__ == "__main__":
    sys.exit(main())
