"""The storage room stays readable (no module over MAX_LINES, one module per aggregate), and its typed rows stay the
shape of the tables they are read from."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from sem_console.storage import comap, commands
from sem_console.storage.models import ComapTaskRecord, ComapWorldRecord, CommandRecord, TransitionRecord, table

STORAGE = Path(commands.__file__).parent
MAX_LINES = 300


def test_no_storage_module_is_over_300_lines() -> None:
    sizes = {p.relative_to(STORAGE).as_posix(): len(p.read_text(encoding="utf-8").splitlines()) for p in STORAGE.rglob("*.py")}
    assert "database.py" in sizes and "outage.py" in sizes
    assert {name: n for name, n in sizes.items() if n > MAX_LINES} == {}


@pytest.mark.parametrize(
    "row,model,extra",
    [
        (commands.CommandRow, CommandRecord, {"transitions"}),
        (commands.TransitionRow, TransitionRecord, set()),
        (comap.WorldRow, ComapWorldRecord, set()),
        (comap.TaskRow, ComapTaskRecord, set()),
    ],
)
def test_each_typed_row_has_the_columns_of_its_table(row: Any, model: Any, extra: set[str]) -> None:
    """A column added to a table and not to its row (or the other way) fails here, not in a caller."""
    assert set(row.__annotations__) - extra == {c.name for c in table(model).c}
