"""The UMAA versions the console, the checker and the simulator speak (the `versions` room adapts each to the model)."""

from typing import Literal

UmaaVersion = Literal["3.0.1", "6.0"]
