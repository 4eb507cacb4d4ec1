"""What the commands' argument parsers share (`sem-console`, `sem-sim`, `sem-replay`, `sem-check`)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import NoReturn, TypeVar

N = TypeVar("N", int, float)


class Parser(argparse.ArgumentParser):
    """A bad argument is one line and exit status 2: `prog: error: message`, without the usage block."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message}\n")


def ranged(kind: Callable[[str], N], lo: float, hi: float) -> Callable[[str], N]:
    """An argument type: `kind` of the text, within lo..hi, else a one-line error naming the range."""
    def parse(text: str) -> N:
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"{text} is outside {lo:g}..{hi:g}")
        return value
    return parse
