"""What the commands' argument parsers share (`sem-console`, `sem-sim`, `sem-replay`, `sem-check`), and the
generator of `sem-console`'s options from the fields of `Settings` (core/config.py)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Collection
from pathlib import Path
from types import UnionType
from typing import Any, Literal, NoReturn, TypeVar, Union, get_args, get_origin

from pydantic import BaseModel, ValidationError

M = TypeVar("M", bound=BaseModel)
N = TypeVar("N", int, float)


class Parser(argparse.ArgumentParser):
    """A bad argument is one line and exit status 2: `prog: error: message`, without the usage block."""

    def error(self, message: str) -> NoReturn:
        # argparse's own "argument --x: ..." worded as the other problems of an option are: "--x: ..."
        self.exit(2, f"{self.prog}: error: {message.removeprefix('argument ')}\n")


def not_a_number(kind: type, text: object) -> str:
    """`'abc' is not a whole number` (int) or `'abc' is not a number`: how an option or variable that is no number
    of its kind is refused, on the command line and from the environment alike."""
    return f"{text!r} is not a {'whole number' if kind is int else 'number'}"


def number(kind: Callable[[str], N]) -> Callable[[str], N]:
    """An argument type: `kind` (int or float) of the text, else a one-line error (`not_a_number`)."""

    def parse(text: str) -> N:
        try:
            return kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(not_a_number(kind, text)) from None  # type: ignore[arg-type]

    return parse


def ranged(kind: Callable[[str], N], lo: float, hi: float) -> Callable[[str], N]:
    """An argument type: `kind` of the text, within lo..hi, else a one-line error naming the range."""

    def parse(text: str) -> N:
        value = number(kind)(text)
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"{text} is outside {lo:g}..{hi:g}")
        return value

    return parse


# argparse's type for a `cli(type=...)` override (a name: json_schema_extra holds JSON values)
TYPES: dict[str, type] = {"str": str, "int": int, "float": float, "Path": Path}


def cli_options(model: type[BaseModel]) -> dict[str, dict[str, Any]]:
    """field name -> its command-line option's metadata (`cli(...)` of core/config.py; {} for the defaults),
    for every field that has an option (environment-only fields, {"cli": None}, are left out)."""
    out = {}
    for name, field in model.model_fields.items():
        extra = field.json_schema_extra if isinstance(field.json_schema_extra, dict) else {}
        options = extra.get("cli", {})
        if options is not None:
            assert isinstance(options, dict), (name, options)
            out[name] = dict(options)
    return out


def flag_of(model: type[BaseModel], name: str) -> str:
    """The option of a field: --<name> with dashes, or its `cli(flag=...)`."""
    return str(cli_options(model).get(name, {}).get("flag") or "--" + name.replace("_", "-"))


def value_type(annotation: Any) -> Any:
    """int for `int | None`, Path for `Path`, ...: what argparse converts an option's text to."""
    optional = get_origin(annotation) in (Union, UnionType)
    kinds = [a for a in get_args(annotation) if a is not type(None)] if optional else [annotation]
    assert len(kinds) == 1, annotation
    return kinds[0]


def add_model_options(
    parser: argparse.ArgumentParser, model: type[BaseModel], types: dict[str, Callable[[str], Any]] | None = None
) -> None:
    """One option per field of `model` that has one, in the fields' order: its type from the annotation (a bool is a
    flag that sets True) or the `types` entry its `cli(type=...)` names, its help the field's description, default
    None (given options only: the model decides the rest, and reads the environment for it)."""
    known: dict[str, Callable[[str], Any]] = {**TYPES, **(types or {})}
    for name, options in cli_options(model).items():
        field = model.model_fields[name]
        flag = options.pop("flag", None) or "--" + name.replace("_", "-")
        kind = known[options.pop("type")] if "type" in options else value_type(field.annotation)
        if get_origin(kind) is Literal:  # one of a few words: argparse's choices, named in its error
            options["choices"] = get_args(kind)
            kind = str
        if kind is bool:
            options["action"] = "store_true"
        elif kind in (int, float):
            options["type"] = number(kind)
        elif kind is not str:
            options["type"] = kind
        parser.add_argument(flag, dest=name, default=None, help=field.description, **options)


def model_error(model: type[BaseModel], error: ValidationError, given: Collection[str] | None = None) -> str:
    """The first problem of a validation error as one line: `--port: Input should be less than or equal to 65535`,
    or a check between fields as it is worded (`--tls-certfile and --tls-keyfile go together`). With `given` (the
    fields the command line set), a field outside it is named by the variable it came from: `SEM_PORT: ...`
    (an environment-only setting has no option to name)."""
    first = error.errors()[0]
    message = str(first["ctx"]["error"]) if first["type"] == "value_error" else first["msg"]
    if first["type"] in ("int_parsing", "float_parsing"):  # as the command line says it (`number`)
        message = not_a_number(int if first["type"] == "int_parsing" else float, first["input"])
    if not first["loc"]:
        return message
    name = str(first["loc"][0])
    if first["type"] in BOUNDS:  # a number out of range: say the whole range, as `ranged` does
        message = _out_of_range(model, name, first["input"]) or message
    return f"{flag_of(model, name) if given is None or name in given else env_name(model, name)}: {message}"


def env_name(model: type[BaseModel], name: str) -> str:
    """The environment variable of a field: its model's prefix (SEM_, SEM_RELAY_) and its name."""
    return f"{model.model_config.get('env_prefix') or 'SEM_'}{name.upper()}"


BOUNDS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")


def _out_of_range(model: type[BaseModel], name: str, value: Any) -> str | None:
    """`70000 is outside 0..65535` for a field with both bounds (`above 0` and `up to 100` with one of them)."""
    lo = hi = None
    for bound in model.model_fields[name].metadata:
        lo = next((v for v in (getattr(bound, "ge", None), getattr(bound, "gt", None)) if v is not None), lo)
        hi = next((v for v in (getattr(bound, "le", None), getattr(bound, "lt", None)) if v is not None), hi)
    if lo is not None and hi is not None:
        shown = f"{value:g}" if isinstance(value, (int, float)) and not isinstance(value, bool) else str(value)
        return f"{shown} is outside {lo:g}..{hi:g}"
    return None


def from_environment(prog: str, model: type[M]) -> M:
    """`model` from the SEM_* environment alone (the commands other than sem-console), or exit 2 with one line
    naming the variable: `prog: error: SEM_DOMAIN: Input should be ...`, not a traceback."""
    try:
        return model()
    except ValidationError as e:
        print(f"{prog}: error: {model_error(model, e, given=())}", file=sys.stderr)
        raise SystemExit(2) from None


def add_dds_security(parser: argparse.ArgumentParser, prog: str) -> None:
    """--dds-security DIR on a command other than sem-console, as Settings' field says it (default SEM_DDS_SECURITY)."""
    from sem_console.core.config import BusSettings, Settings

    parser.add_argument(
        "--dds-security",
        type=Path,
        metavar="DIR",
        default=from_environment(prog, BusSettings).dds_security,
        help=Settings.model_fields["dds_security"].description,
    )
