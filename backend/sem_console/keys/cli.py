"""`sem-keys`: a fleet's DDS Security keys and documents, made with `cryptography` (docs/security.md)."""

from __future__ import annotations

import argparse
import datetime as dt
import sys
from pathlib import Path

from sem_console.core.command_line import Parser, from_environment, ranged
from sem_console.core.config import BusSettings
from sem_console.keys.documents import Role
from sem_console.keys.fleet import Fleet, KeysError


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="sem-keys",
        description=(
            "Make what a fleet needs for DDS Security: `init DIR` its identity and permissions authorities and its "
            "signed governance, `issue DIR NAME --role ROLE` an identity's key, certificate, signed permissions and "
            "Cyclone DDS configuration (DIR/identities/NAME/). Issuing a name again replaces only that identity's files."
        ),
    )
    commands = p.add_subparsers(dest="command", required=True, metavar="{init,issue}", parser_class=Parser)
    init = commands.add_parser("init", help="make the fleet's two authorities and its signed governance in DIR")
    init.add_argument("dir", type=Path, metavar="DIR", help="the fleet's folder (made when missing)")
    init.add_argument("--fleet", required=True, help="the fleet's name, in the authorities' and identities' subjects")
    init.add_argument(
        "--domain",
        type=ranged(int, 0, 232),
        action="append",
        help="a DDS domain id the governance and permissions cover, 0..232; repeat for several (default: SEM_DOMAIN or 0)",
    )
    init.add_argument(
        "--days",
        type=ranged(int, 1, 36500),
        default=3650,
        help="how long the authorities are valid, in days (default: %(default)s)",
    )
    init.add_argument("--force", action="store_true", help="replace the authorities of a fleet already in DIR")
    issue = commands.add_parser("issue", help="make or replace one identity in DIR/identities/NAME/")
    issue.add_argument("dir", type=Path, metavar="DIR", help="the fleet's folder, made by init")
    issue.add_argument("name", metavar="NAME", help="the identity's name: letters, digits, '.', '_' and '-'")
    issue.add_argument(
        "--role",
        required=True,
        choices=[r.value for r in Role],
        help=(
            "vehicle: publishes reports, statuses and acks, reads everything; station: reads everything, writes commands; "
            "readonly: reads everything, writes nothing"
        ),
    )
    issue.add_argument(
        "--days",
        type=ranged(int, 1, 36500),
        default=365,
        help="how long the certificate and permissions are valid, in days, up to the authorities' end (default: %(default)s)",
    )
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    fleet = Fleet(args.dir)
    now = dt.datetime.now(dt.UTC).replace(microsecond=0)
    try:
        if args.command == "init":
            domains = args.domain or [from_environment("sem-keys", BusSettings).domain]
            written = fleet.init(args.fleet, sorted(set(domains)), args.days, args.force, now)
        else:
            written = fleet.issue(args.name, Role(args.role), args.days, now)
    except KeysError as e:
        print(f"sem-keys: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"sem-keys: error: {e.filename or args.dir}: {e.strerror or e}", file=sys.stderr)
        return 2
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
