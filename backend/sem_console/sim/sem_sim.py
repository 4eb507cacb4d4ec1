"""`sem-sim`: simulated vehicles that are UMAA SEM Service Providers on a DDS domain."""

from __future__ import annotations

import argparse
import contextlib
import errno
import logging
import os
import signal
import sys

from pydantic import ValidationError

from sem_console.comap.messages import Sensor
from sem_console.core.command_line import (
    Parser,
    add_dds_security,
    add_model_options,
    cli_options,
    from_environment,
    model_error,
    ranged,
)
from sem_console.core.config import BusSettings, parse_imc_id, parse_peers
from sem_console.dds.bus import Bus, DdsConfigError, bus_security, domain_security
from sem_console.dds.security import OPEN_BUS
from sem_console.sim.provider import FAULTS, InUse, SimOptions, Simulator, vehicle_guid


def _fault(text: str) -> tuple[str, int]:
    kind, _, target = text.partition(":")
    if kind not in FAULTS:
        raise argparse.ArgumentTypeError(f"unknown fault {kind!r} (one of {', '.join(FAULTS)})")
    if not target:
        return kind, 0
    if not target.isdigit() or int(target) < 1:
        raise argparse.ArgumentTypeError(f"fault target {target!r} must be a vehicle number from 1")
    return kind, int(target)


def _numbers(text: str) -> set[int]:
    """'2,5': vehicle numbers from 1."""
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not parts or not all(p.isdigit() and int(p) >= 1 for p in parts):
        raise argparse.ArgumentTypeError(f"{text!r} must be vehicle numbers from 1, comma separated (e.g. 2,5)")
    return {int(p) for p in parts}


def _imc_id(text: str) -> int:
    try:
        return parse_imc_id(text, "--imc-id")
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _peers(text: str) -> list[tuple[str, int]]:
    try:  # names as given: resolved in options_from when CoMap is on (a name that does not resolve stops nothing else)
        return parse_peers(text, resolve=False)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _sensors(text: str) -> tuple[str, ...]:
    names = tuple(x.strip().upper() for x in text.split(",") if x.strip())
    bad = [n for n in names if n not in Sensor.__members__ or n == "ANY"]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"unknown sensor {', '.join(bad) or '(none)'}")
    return names


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="sem-sim",
        description=(
            "Simulated unmanned vehicles, each a UMAA SEM Service Provider for GPSFixControl, GPSFixStatus, "
            "GPSStatus, InertialSensorControl and InertialSensorStatus. Vehicles start submerged (no GPS fix) "
            "with the INS aligning. DDS runs on loopback unless CYCLONEDDS_URI is set."
        ),
    )
    p.add_argument(
        "--domain",
        type=ranged(int, 0, 232),
        default=from_environment("sem-sim", BusSettings).domain,
        help=("DDS domain id, 0..232 (default: SEM_DOMAIN or 0)"),
    )
    add_dds_security(p, "sem-sim")
    # the simulator's own options: one per field of SimOptions (sim/options.py), in its order
    add_model_options(
        p, SimOptions, {"fault": _fault, "imc_id": _imc_id, "peers": _peers, "sensors": _sensors, "numbers": _numbers}
    )
    p.add_argument("--list", action="store_true", help="print each vehicle's source GUID and exit")
    p.add_argument(
        "--log-level", choices=("debug", "info", "warning", "error"), default="info", help=("log level (default: %(default)s)")
    )
    return p


def options_from(args: argparse.Namespace) -> SimOptions:
    """The options given on the command line; SimOptions' defaults for the rest. A value out of its range is
    one line and exit 2, as argparse's own errors."""
    given = {name: getattr(args, name) for name in cli_options(SimOptions) if getattr(args, name) is not None}
    try:
        opts = SimOptions(**given)
    except ValidationError as e:
        print(f"sem-sim: error: {model_error(SimOptions, e)}", file=sys.stderr)
        raise SystemExit(2) from None
    if opts.imc_port is not None:  # CoMap on: a name that does not resolve is one line now, not every send failing unseen
        try:  # resolved once, here: sent to by address, not looked up again on every send
            opts = opts.model_copy(update={"imc_peers": parse_peers(",".join(f"{h}:{p}" for h, p in opts.imc_peers))})
        except ValueError as e:
            print(f"sem-sim: error: --imc-peers: {e}", file=sys.stderr)
            raise SystemExit(2) from None
    return opts


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    opts = options_from(args)
    if args.list:
        for n in opts.numbers:
            imc = f" imc {opts.imc_id_of(n)} (0x{opts.imc_id_of(n):04X})" if opts.imc_port is not None else ""
            print(f"vehicle {n}: {vehicle_guid(n)}{imc}")
        return 0
    if opts.health_file is not None:  # touched every second, its errors ignored then: a healthcheck would only see it stale
        try:
            opts.health_file.touch()
        except OSError as e:
            print(
                f"sem-sim: error: --health-file {opts.health_file}: cannot write it ({e.strerror or e}): "
                "pass another --health-file",
                file=sys.stderr,
            )
            return 2
        with contextlib.suppress(OSError):  # stale until the running simulator touches it: not healthy while starting
            os.utime(opts.health_file, (0, 0))
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    settings = from_environment("sem-sim", BusSettings)
    stopping = False

    def stop(_signum: int, _frame: object) -> None:
        nonlocal stopping
        stopping = True

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    try:
        bus = Bus(args.domain, settings.dds_interface, settings.dds_peers, bus_security(args.dds_security, args.domain))
    except DdsConfigError as e:
        print(f"sem-sim: {e}", file=sys.stderr)
        return 2
    try:
        sim = Simulator(bus, opts)
    except OSError as e:  # the fix depends on why: "give another --imc-port" for an address not of this machine misled
        fix = {
            errno.EADDRINUSE: "give another --imc-port (or stop what holds it)",
            errno.EADDRNOTAVAIL: "give an --imc-host address of this machine (or 0.0.0.0)",
            errno.EACCES: "give an --imc-port above 1023 (or run with the right to bind it)",
        }
        print(
            f"sem-sim: error: cannot listen for IMC on {opts.imc_host}:{opts.imc_port}: {e.strerror or e}: "
            f"{fix.get(e.errno or 0, 'check --imc-host and --imc-port')}",
            file=sys.stderr,
        )
        return 2
    except DdsConfigError as e:  # a writer the identity's permissions refuse
        print(f"sem-sim: {e}", file=sys.stderr)
        return 2
    except InUse as e:
        hint = f"; run these vehicles with --first-vehicle {e.free} or on another --domain" if e.free else ""
        print(f"sem-sim: error: {e}{hint}", file=sys.stderr)
        return 1
    if domain_security(args.domain) is None:  # said once the simulator starts: a refused start is one line
        logging.getLogger("sem-sim").warning(OPEN_BUS)
    for v in sim.vehicles.values():
        logging.getLogger("sem-sim").info("vehicle %d source %s faults %s", v.number, v.guid, sorted(v.faults) or "none")
    twin = False
    try:
        sim.run(lambda: stopping)
    except InUse as e:
        twin = True
        print(f"sem-sim: error: {e}; this process stops", file=sys.stderr)
    finally:
        logging.getLogger("sem-sim").info("shutting down: failing incomplete commands, disposing reports")
        sim.shutdown(twin=twin)
    return 1 if twin else 0


if __name__ == "__main__":
    sys.exit(main())
