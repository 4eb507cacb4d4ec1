"""`sem-check`: test a UMAA SEM Service Provider on a DDS domain against ICD 3.0.1, headless, with a
JUnit report for CI. See docs/sem-check.md."""

from __future__ import annotations

import argparse
import sys
import traceback
import uuid
from pathlib import Path

from sem_console.check.results import Stopped
from sem_console.check.runner import COULD_NOT_TEST, STOPPED, UMAA_VERSIONS, Options, all_names, run
from sem_console.core.command_line import Parser, add_dds_security, from_environment, ranged
from sem_console.core.config import BusSettings


def _domain(text: str) -> int:
    if not text.isdigit() or not 0 <= int(text) <= 232:
        raise argparse.ArgumentTypeError(f"{text!r} is not a domain id 0..232")
    return int(text)


def _guid(text: str) -> uuid.UUID:
    try:
        return uuid.UUID(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a GUID (e.g. 0d9ca6b5-2f4e-5b3a-9c61-1b7c1f7f2a10)") from None


def _names(text: str) -> list[str]:
    return [n.strip() for n in text.split(",") if n.strip()]


def build_parser() -> argparse.ArgumentParser:
    d = Options()
    p = Parser(
        prog="sem-check",
        description=(
            "Test one UMAA SEM Service Provider (a vehicle or a simulator) on a DDS domain against ICD 3.0.1, or a UMAA 6.0 "
            "provider against the 6.0 ICDs: the topics it serves (types and keys; QoS against the project's profile, or for 6.0 "
            "against RTI's UMAAQoSLib, a warning), its reports and, with --commands, the command flow of section 4.1. "
            "Read-only unless --commands is given. Exit code "
            "0: all passed, 1: a test failed, 2: could not test, 143/130: stopped by SIGTERM/SIGINT (the reports say "
            "what was done). DDS runs on loopback unless CYCLONEDDS_URI or SEM_DDS_INTERFACE/SEM_DDS_PEERS say otherwise."
        ),
    )
    p.add_argument("--domain", type=_domain, default=None, help="DDS domain id, 0..232 (default: SEM_DOMAIN or 0)")
    add_dds_security(p, "sem-check")
    p.add_argument(
        "--provider", type=_guid, default=None, help="the provider's source GUID; needed when several providers are on the domain"
    )
    p.add_argument(
        "--commands",
        action="store_true",
        help=(
            "run the command tests: sends GPSFix commands (the vehicle surfaces) and InertialSensor OFF/ON/RESTARTING "
            "commands, and one of each addressed to another GUID (UMAA 6.0: InertialSensor INIT, each alignment, a cancel, "
            "an update, GPS_ALIGN); what will be sent is printed first. Without it no command writer is created"
        ),
    )
    p.add_argument(
        "--umaa",
        choices=UMAA_VERSIONS,
        default=None,
        help=("test the provider as this UMAA version (default: the version of the topics its samples come on)"),
    )
    p.add_argument(
        "--junit",
        default=None,
        metavar="FILE",
        help=(
            "write a JUnit XML report to FILE; a name ending in / is a directory (made if missing) to write "
            "sem-check-<start, UTC>-<random>.xml in"
        ),
    )
    p.add_argument(
        "--timeout",
        type=ranged(float, 0.1, 3600),
        default=d.timeout,
        metavar="S",
        help=("seconds to wait for the provider, and for the first status (ISSUED) of each command (default: %(default)s)"),
    )
    p.add_argument(
        "--only",
        type=_names,
        action="append",
        default=[],
        metavar="NAMES",
        help=("run only these tests: comma separated names, dotted prefixes (reports, commands.GPSFix) or globs (*.values)"),
    )
    p.add_argument(
        "--skip", type=_names, action="append", default=[], metavar="NAMES", help="leave these tests out (same forms as --only)"
    )
    p.add_argument(
        "--record",
        default=None,
        metavar="FILE.mcap",
        help=(
            "record every sample of the run to an MCAP file as evidence; a name ending in / is a directory (made if "
            "missing) to write sem-check-<start, UTC>-<random>.mcap in"
        ),
    )
    p.add_argument(
        "--window",
        type=ranged(float, 0.5, 3600),
        default=d.window,
        metavar="S",
        help="seconds of reports watched before they are judged (default: %(default)s)",
    )
    p.add_argument(
        "--max-gap",
        type=ranged(float, 0.01, 3600),
        default=d.max_gap,
        metavar="S",
        help="longest a report topic may go without a report (default: %(default)s)",
    )
    p.add_argument(
        "--clock-offset",
        type=ranged(float, 0.001, 3600),
        default=d.clock_offset,
        metavar="S",
        help=("largest difference between a report's timeStamp and the checker's clock on arrival (default: %(default)s)"),
    )
    p.add_argument(
        "--step-time",
        type=ranged(float, 0.01, 3600),
        default=d.step_time,
        metavar="S",
        help=(
            "seconds allowed for each command step after ISSUED (COMMANDED, EXECUTING, the ack, CANCELED after a cancel, "
            "the disposes of the cleanup); every command to the provider is watched this long after its dispose "
            "(default: %(default)s)"
        ),
    )
    p.add_argument(
        "--execute-time",
        type=ranged(float, 0.01, 86400),
        default=d.execute_time,
        metavar="S",
        help=("seconds allowed from EXECUTING to COMPLETED (surfacing, INS alignment) (default: %(default)s)"),
    )
    p.add_argument(
        "--security-profile",
        type=Path,
        default=None,
        metavar="DIR",
        help=(
            "check a fleet's DDS Security documents against the project's security profile instead of testing a provider "
            "(no DDS): DIR is the fleet's folder (sem-keys init: its governance and every identity's permissions) or one "
            "identity's folder (sem-keys issue); the profile.* tests (docs/sem-check.md)"
        ),
    )
    p.add_argument("--list", action="store_true", help="print the test names and exit")
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if args.list:
        print("\n".join(all_names()))
        return 0
    settings = from_environment("sem-check", BusSettings)
    opts = Options(
        domain=settings.domain if args.domain is None else args.domain,
        provider=args.provider,
        commands=args.commands,
        junit=args.junit,
        timeout=args.timeout,
        only=[n for group in args.only for n in group],
        skip=[n for group in args.skip for n in group],
        record=args.record,
        window=args.window,
        max_gap=args.max_gap,
        clock_offset=args.clock_offset,
        step_time=args.step_time,
        execute_time=args.execute_time,
        interface=settings.dds_interface,
        peers=settings.dds_peers,
        dds_security=args.dds_security,
        umaa=args.umaa,
        security_profile=args.security_profile,
    )
    # SIGTERM (a CI job canceled or out of time) and Ctrl-C stop the run through its finally blocks, so every
    # command sent is disposed (Service Consumer Shutdown, ICD 4.1.6.2), and it reports what it did (runner.run).
    try:
        return run(opts)
    except Stopped as e:  # before the run had anything to report
        print(f"sem-check: stopped by {e.name}", file=sys.stderr)
        return STOPPED + e.signum
    except Exception:  # a crash is not a test failure: exit 1 would tell CI the vehicle failed
        traceback.print_exc()
        print("sem-check: could not test: internal error (above)", file=sys.stderr)
        return COULD_NOT_TEST


if __name__ == "__main__":
    sys.exit(main())
