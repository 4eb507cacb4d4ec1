"""What the three commands' argument parsers share (`sem-console`, `sem-sim`, `sem-replay`)."""

from __future__ import annotations

import argparse
from typing import NoReturn


class Parser(argparse.ArgumentParser):
    """A bad argument is one line and exit status 2: `prog: error: message`, without the usage block."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message}\n")
