"""`sem-console`'s options are generated from `Settings`: every field has its option or is
marked environment-only, the checks between fields are model validators (so the environment gets them too, as one
line), and an option and its SEM_* variable make the same Settings. In process: no console is started."""

from __future__ import annotations

import argparse
import uuid
from pathlib import Path

import pytest
from pydantic import ValidationError

from sem_console import cli
from sem_console.core.command_line import cli_options, flag_of, model_error, value_type
from sem_console.core.config import Settings

# the options whose name is not --<field> with dashes, and the one option that is no setting
RENAMED = {"db_path": "--db"}
CLI_ONLY = {"log_level"}
ENV_ONLY = {
    "dds_interface",
    "dds_peers",
    "report_interval",
    "report_burst",
    "ws_max_queue",
    "ws_stall_seconds",
    "ws_cut_seconds",
    "ws_window_bytes",
    "ws_compression",
    "record_queue",
    "throttle_first_wait",
}


@pytest.fixture(autouse=True)
def no_sem_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    """The tests set what they need; a SEM_* variable of the caller's shell (docker compose's tokens) is not theirs."""
    import os

    for name in [n for n in os.environ if n.startswith("SEM_")]:
        monkeypatch.delenv(name)


def actions() -> dict[str, argparse.Action]:
    """dest -> action of sem-console's parser, less --help."""
    return {a.dest: a for a in cli.build_parser()._actions if a.dest != "help"}


def test_every_field_has_its_option_or_is_environment_only() -> None:
    parsed = actions()
    assert set(parsed) == (set(Settings.model_fields) - ENV_ONLY) | CLI_ONLY
    assert set(cli_options(Settings)) == set(Settings.model_fields) - ENV_ONLY
    for name, action in parsed.items():
        if name in CLI_ONLY:
            continue
        field = Settings.model_fields[name]
        assert action.option_strings == [RENAMED.get(name, "--" + name.replace("_", "-"))] == [flag_of(Settings, name)]
        assert action.default is None, name  # the model decides what is not given (and reads SEM_* for it)
        assert field.description and action.help == field.description, name
        kind = value_type(field.annotation)
        if kind is bool:
            assert action.nargs == 0 and action.const is True, name
        elif name != "imc_id":  # text: decimal or 0x hex, parsed by the model
            # a number through `number` (its one-line refusal), of the field's kind
            assert (action.type or str) is kind or (kind in (int, float) and type(action.type("7")) is kind), name
    # the fields' order is the order --help lists the options in
    assert [d for d in parsed if d not in CLI_ONLY] == [n for n in Settings.model_fields if n not in ENV_ONLY]


def test_options_and_environment_make_the_same_settings(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    tokens = tmp_path / "tokens"
    tokens.write_text("alice:s3cret\n")
    values = {
        "host": "0.0.0.0",
        "port": "8123",
        "domain": "7",
        "db_path": str(tmp_path / "db"),
        "comms_lost_timeout": "1.5",
        "operator_tokens_file": str(tokens),
        "auth_reads": None,
        "imc_port": "6002",
        "imc_id": "0x4002",
        "imc_peers": "127.0.0.1:6001",
        "jaus_port": "3795",
        "record_max_bytes": "1000000",
        "aspn_prefix": "nav",
    }
    argv: list[str] = []
    for name, value in values.items():
        argv += [flag_of(Settings, name)] + ([value] if value is not None else [])
    args = vars(cli.build_parser().parse_args(argv))
    from_options = Settings(**{k: v for k, v in args.items() if v is not None and k != "log_level"})
    for name, value in values.items():
        monkeypatch.setenv(f"SEM_{name.upper()}", value if value is not None else "true")
    from_environment = Settings()
    assert from_options == from_environment
    assert from_options.imc_id == 0x4002 and from_options.auth_reads and from_options.operators() == {"s3cret": "alice"}


@pytest.mark.parametrize(
    "given, line",
    [
        ({"auth_reads": True}, "--auth-reads needs operator tokens (--operator-tokens-file or SEM_OPERATOR_TOKENS)"),
        ({"tls_keyfile": "key.pem"}, "--tls-certfile and --tls-keyfile go together"),
        ({"replay": "run.mcap", "sim": 2}, "--replay is read-only: it does not go with --sim or --record"),
        (
            {"replay": "run.mcap", "imc_port": 6002},
            "--replay is read-only: it does not go with --imc-port (CoMap sends to vehicles)",
        ),
        ({"imc_peers": "nope"}, "IMC peer 'nope' is not host:port"),
        ({"vehicle_names": "not-a-guid=Alpha"}, "vehicle name 'not-a-guid=Alpha': 'not-a-guid' is not a GUID"),
        ({"operator_tokens": "alice:s3cret,bob:"}, "item 2: expected name:token"),
        ({"imc_id": "0xZZ"}, "--imc-id: '0xZZ' is not an IMC system id (decimal or 0x hex)"),
        ({"port": 70000}, "--port: 70000 is outside 0..65535"),
        ({"db_path": 5.5}, "--db: Input is not a valid path"),
        ({"allowed_hosts": " , "}, "--allowed-hosts: ' , ' names no host"),  # every request was a 403, nothing said
        # LCM over UDP refuses a channel name over 63 characters: nothing was sent on those (docs/gateways.md)
        ({"aspn_prefix": "navigation-1"}, "--aspn-prefix: 'navigation-1': give 1 to 11 letters, digits or _ . - /"),
    ],
)
def test_a_check_fails_as_one_line_from_options_and_environment(
    given: dict[str, object], line: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    with pytest.raises(ValidationError) as e:
        Settings(**given)  # type: ignore[arg-type]
    message = model_error(Settings, e.value)
    assert line in message and "\n" not in message, message
    if all(isinstance(v, str | int) for v in given.values()):
        for name, value in given.items():
            monkeypatch.setenv(f"SEM_{name.upper()}", str(value))
        with pytest.raises(ValidationError) as e:
            Settings()
        assert line in model_error(Settings, e.value)


def test_a_bad_option_stops_sem_console_with_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        cli.main(["--replay", "run.mcap", "--imc-port", "6002"])
    assert e.value.code == 2
    assert capsys.readouterr().err == (
        "sem-console: error: --replay is read-only: it does not go with --imc-port (CoMap sends to vehicles)\n"
    )


@pytest.mark.parametrize("name", ["a\u202egnp.exe", "x" * 41, "two\nlines"])
def test_vehicle_names_follow_the_dashboard_s_rules(name: str) -> None:
    """A name the dashboard's PUT /api/providers/{id}/name refuses (bidirectional override, over 40, a line break)
    was taken from --vehicle-names and shown in every label and alarm."""
    with pytest.raises(ValidationError) as e:
        Settings(vehicle_names=f"{uuid.UUID(int=1)}={name}")
    assert "printable characters only" in model_error(Settings, e.value)


@pytest.mark.parametrize(
    "variable, value, line",
    [
        ("SEM_REPORT_INTERVAL", "-1", "SEM_REPORT_INTERVAL: -1 is outside 0..10"),  # no option: --report-interval does not exist
        ("SEM_PORT", "http", "SEM_PORT: 'http' is not a whole number"),
        ("SEM_DOMAIN", "xyz", "SEM_DOMAIN: 'xyz' is not a whole number"),  # as --domain abc says it (test_bad_starts.py)
    ],
)
def test_a_bad_environment_variable_of_sem_console_is_named(
    variable: str, value: str, line: str, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """The line named the option of the field (one that does not exist for an environment-only setting)."""
    monkeypatch.setenv(variable, value)
    with pytest.raises(SystemExit) as e:
        cli.main([])
    assert e.value.code == 2
    assert capsys.readouterr().err.startswith(f"sem-console: error: {line}")


def test_the_other_commands_refuse_a_bad_domain_in_one_line(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """sem-sim, sem-replay and sem-check read their DDS settings from the environment (from_environment)."""
    from sem_console.sim import sem_sim

    monkeypatch.setenv("SEM_DOMAIN", "999")
    with pytest.raises(SystemExit) as e:
        sem_sim.build_parser()
    assert e.value.code == 2
    assert capsys.readouterr().err == "sem-sim: error: SEM_DOMAIN: 999 is outside 0..232\n"


@pytest.mark.parametrize(
    "env",
    [
        {"SEM_TLS_KEYFILE": "key.pem"},
        {"SEM_AUTH_READS": "1"},
        {"SEM_OPERATOR_TOKENS_FILE": "/nonexistent/tokens"},
    ],
)
def test_the_console_s_own_settings_never_stop_the_other_commands(env: dict[str, str], monkeypatch: pytest.MonkeyPatch) -> None:
    """A console's environment (its TLS pair, tokens file, --auth-reads) shared with sem-sim is not sem-sim's concern:
    the other commands read only the DDS settings (BusSettings)."""
    from sem_console.sim import sem_sim

    monkeypatch.setenv("SEM_DOMAIN", "7")
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    assert sem_sim.build_parser().parse_args([]).domain == 7


def test_the_missing_dashboard_warning_names_a_path_that_exists_here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """In a checkout without a build it names frontend/dist and how to build it; installed from a wheel (no checkout
    beside the package) it names --frontend-dir, not a path under site-packages that means nothing there."""
    from sem_console import main

    (tmp_path / "frontend").mkdir()
    monkeypatch.setattr(main, "DEFAULT_FRONTEND", tmp_path / "frontend" / "dist")
    (checkout,) = [w for w in cli.start_warnings(Settings()) if "dashboard" in w]
    assert str(tmp_path / "frontend" / "dist") in checkout and "npm run build" in checkout
    monkeypatch.setattr(main, "DEFAULT_FRONTEND", tmp_path / "site-packages" / "frontend" / "dist")
    (wheel,) = [w for w in cli.start_warnings(Settings()) if "dashboard" in w]
    assert "site-packages" not in wheel and "--frontend-dir DIR" in wheel


def test_every_embedded_simulator_the_settings_allow_starts() -> None:
    """--sim-first-vehicle and --sim are handed to sem-sim's options: their largest values make a simulator, and a
    fleet that would run past the last vehicle number is one line naming where to start instead."""
    from sem_console.sim.options import MAX_VEHICLE, SimOptions

    def largest(name: str) -> int:
        return next(b.le for b in Settings.model_fields[name].metadata if getattr(b, "le", None) is not None)

    first, fleet = largest("sim_first_vehicle"), largest("sim")
    assert SimOptions(first_vehicle=first, vehicles=fleet).numbers[-1] == first + fleet - 1
    assert SimOptions(first_vehicle=MAX_VEHICLE, vehicles=1).numbers[-1] == MAX_VEHICLE
    with pytest.raises(ValidationError) as e:
        SimOptions(first_vehicle=MAX_VEHICLE - 9, vehicles=20)
    assert model_error(SimOptions, e.value) == (
        f"--first-vehicle {MAX_VEHICLE - 9} with --vehicles 20 runs past vehicle {MAX_VEHICLE}: "
        f"start at {MAX_VEHICLE - 19} or lower"
    )
