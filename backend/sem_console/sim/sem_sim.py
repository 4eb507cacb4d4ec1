"""`sem-sim`: simulated vehicles that are UMAA SEM Service Providers on a DDS domain."""

from __future__ import annotations

import argparse
import logging
import signal
import sys
from pathlib import Path

from sem_console.comap.messages import Sensor
from sem_console.core.command_line import Parser, from_environment, ranged
from sem_console.core.config import BusSettings, parse_imc_id, parse_peers
from sem_console.dds.bus import Bus, DdsConfigError
from sem_console.sim.options import MAX_VEHICLE
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


def _imc_id(text: str) -> int:
    try:
        return parse_imc_id(text, "--imc-id")
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _peers(text: str) -> list[tuple[str, int]]:
    try:
        return parse_peers(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _sensors(text: str) -> tuple[str, ...]:
    names = tuple(x.strip().upper() for x in text.split(",") if x.strip())
    bad = [n for n in names if n not in Sensor.__members__ or n == "ANY"]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"unknown sensor {', '.join(bad) or '(none)'}")
    return names


def build_parser() -> argparse.ArgumentParser:
    d = SimOptions()
    p = Parser(prog="sem-sim", description=(
        "Simulated unmanned vehicles, each a UMAA SEM Service Provider for GPSFixControl, GPSFixStatus, "
        "GPSStatus, InertialSensorControl and InertialSensorStatus. Vehicles start submerged (no GPS fix) "
        "with the INS aligning. DDS runs on loopback unless CYCLONEDDS_URI is set."))
    p.add_argument("--domain", type=ranged(int, 0, 232), default=from_environment("sem-sim", BusSettings).domain, help=(
        "DDS domain id, 0..232 (default: SEM_DOMAIN or 0)"))
    p.add_argument("--vehicles", type=ranged(int, 1, 500), default=d.vehicles, help=(
        "number of vehicles, each with its own stable source GUID (default: %(default)s)"))
    p.add_argument("--first-vehicle", type=ranged(int, 1, MAX_VEHICLE - 500), default=d.first_vehicle, help=(
        "number of the first vehicle: vehicles N, N+1, ... (their GUIDs follow from their numbers). A simulator "
        "refuses to start a vehicle another process already runs on the domain (default: %(default)s)"))
    p.add_argument("--time-scale", type=ranged(float, 0.001, 100), default=d.time_scale, help=(
        "multiply every duration below, e.g. 0.1 runs ten times faster (default: %(default)s)"))
    p.add_argument("--step-seconds", type=ranged(float, 0, 600), default=d.step_seconds, help=(
        "delay between ISSUED, COMMANDED and EXECUTING (default: %(default)s)"))
    p.add_argument("--surface-seconds", type=ranged(float, 0, 3600), default=d.surface_seconds, help=(
        "time for a GPSFix command to surface and get a fix (default: %(default)s)"))
    p.add_argument("--align-seconds", type=ranged(float, 0, 3600), default=d.align_seconds, help=(
        "INS power-on to OPERATIONAL through four alignment stages (default: %(default)s)"))
    p.add_argument("--fix-rate", type=ranged(float, 1, 10), default=d.fix_rate, help=(
        "GPSFixReport and GPSFixStatusReport rate in Hz, 1..10 (default: %(default)s)"))
    p.add_argument("--gps-rate", type=ranged(float, 0.1, 10), default=d.gps_rate, help=(
        "GPSReport (satellites) rate in Hz (default: %(default)s)"))
    p.add_argument("--ins-rate", type=ranged(float, 0.1, 50), default=d.ins_rate, help=(
        "InertialSensorReport rate in Hz (default: %(default)s)"))
    p.add_argument("--satellites", type=ranged(int, 20, 40), default=d.satellites, help=(
        "satellites per vehicle, 20..40 (default: %(default)s)"))
    p.add_argument("--sky-speed", type=ranged(float, 0, 1000), default=d.sky_speed, help=(
        "how much faster than real satellites move across the sky (default: %(default)s)"))
    p.add_argument("--on-startup", choices=("fail", "resume"), default=d.on_startup, help=(
        "a command this provider was running before a restart (known from --state-file): fail it with SERVICE_FAILED, or "
        "resume it from its last status; commands it never saw start normally (default: %(default)s)"))
    p.add_argument("--orphan-grace", type=ranged(float, 0, 3600), default=d.orphan_grace, help=(
        "seconds a command may have no live writer before it is treated as canceled (default: %(default)s)"))
    p.add_argument("--command-timeout", type=ranged(float, 0.1, 86400), default=d.command_timeout, help=(
        "an executing command that has not finished after this many seconds fails with TIMEOUT (default: %(default)s)"))
    p.add_argument(
        "--state-file",
        type=Path,
        default=None,
        help="where command states are journaled so a restarted simulator can recover them; one simulator at a time "
        "(default: $XDG_STATE_HOME/sem-sim/domain-N.json, domain-N-from-F.json with --first-vehicle F)",
    )
    p.add_argument("--health-file", type=Path, default=None, help="touch this file every second while running (for healthchecks)")
    p.add_argument("--fault", type=_fault, action="append", default=[], metavar="KIND[:VEHICLE]", help=(
        "inject a fault, for all vehicles or vehicle number N; repeatable. KIND: reject (FAILED/RESOURCE_REJECTED), "
        "fail-midway (FAILED/RESOURCE_FAILED while executing), no-answer (never answers), slow (every step "
        "--slow-factor times slower), skip-commanded (ISSUED -> EXECUTING, a Figure 4 violation), "
        "ins-failure (INS reports INERTIAL_SENSOR_FAILURE)"))
    p.add_argument("--slow-factor", type=ranged(float, 1, 1000), default=d.slow_factor, help=(
        "slow-down of the 'slow' fault (default: %(default)s)"))
    p.add_argument("--imc-port", type=ranged(int, 0, 65535), default=None, help=(
        "CoMap over IMC: UDP port the vehicles listen on (CoMap is off without it)"))
    p.add_argument("--imc-host", default=d.imc_host, help="address the IMC port listens on (default: %(default)s)")
    p.add_argument("--imc-id", type=_imc_id, default=d.imc_id, help=(
        "IMC system id of the first vehicle, decimal or 0x hex; the next ones count up (default: 0x2001)"))
    p.add_argument("--imc-peers", type=_peers, default=[], help="C2s (consoles) the vehicles send to: 'host:port,...'")
    p.add_argument(
        "--imc-sensors",
        type=_sensors,
        default=d.imc_sensors,
        help=f"survey sensors the vehicles have, comma separated, of {', '.join(n for n in Sensor.__members__ if n != 'ANY')} "
        "(default: SIDESCAN)",
    )
    p.add_argument("--survey-spacing", type=ranged(float, 1, 10_000), default=d.survey_spacing, help=(
        "metres between lawnmower lanes of a survey (default: %(default)s)"))
    p.add_argument("--survey-speed", type=ranged(float, 0.1, 100), default=d.survey_speed, help=(
        "m/s under way for a CoMap task, before --time-scale (default: %(default)s)"))
    p.add_argument("--list", action="store_true", help="print each vehicle's source GUID and exit")
    p.add_argument("--log-level", choices=("debug", "info", "warning", "error"), default="info", help=(
        "log level (default: %(default)s)"))
    return p


def options_from(args: argparse.Namespace) -> SimOptions:
    faults: dict[int, set[str]] = {}
    for kind, target in args.fault:
        faults.setdefault(target, set()).add(kind)
    return SimOptions(
        vehicles=args.vehicles, first_vehicle=args.first_vehicle, time_scale=args.time_scale, step_seconds=args.step_seconds,
        surface_seconds=args.surface_seconds, align_seconds=args.align_seconds, fix_rate=args.fix_rate,
        gps_rate=args.gps_rate, ins_rate=args.ins_rate, satellites=args.satellites, sky_speed=args.sky_speed,
        on_startup=args.on_startup, orphan_grace=args.orphan_grace, slow_factor=args.slow_factor, faults=faults,
        command_timeout=args.command_timeout, state_file=args.state_file, health_file=args.health_file,
        imc_port=args.imc_port, imc_host=args.imc_host, imc_id=args.imc_id, imc_peers=args.imc_peers,
        imc_sensors=args.imc_sensors, survey_spacing=args.survey_spacing, survey_speed=args.survey_speed,
    )


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    opts = options_from(args)
    if args.list:
        for n in opts.numbers:
            imc = f" imc {opts.imc_id_of(n)} (0x{opts.imc_id_of(n):04X})" if opts.imc_port is not None else ""
            print(f"vehicle {n}: {vehicle_guid(n)}{imc}")
        return 0
    logging.basicConfig(level=args.log_level.upper(), format="%(asctime)s %(name)s %(levelname)s %(message)s")
    settings = from_environment("sem-sim", BusSettings)
    stopping = False

    def stop(_signum: int, _frame: object) -> None:
        nonlocal stopping
        stopping = True

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    try:
        bus = Bus(args.domain, settings.dds_interface, settings.dds_peers)
    except DdsConfigError as e:
        print(f"sem-sim: {e}", file=sys.stderr)
        return 2
    try:
        sim = Simulator(bus, opts)
    except OSError as e:
        print(f"sem-sim: cannot listen for IMC on {opts.imc_host}:{opts.imc_port}: {e.strerror or e}", file=sys.stderr)
        return 2
    except InUse as e:
        hint = f"; run these vehicles with --first-vehicle {e.free} or on another --domain" if e.free else ""
        print(f"sem-sim: error: {e}{hint}", file=sys.stderr)
        return 1
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
