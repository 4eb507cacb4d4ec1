"""frontend/schema/ is what the backend publishes today (the dashboard's types are generated from it)."""

from __future__ import annotations

from sem_console.schema_export import SCHEMA_DIR, render, schemas


def test_frontend_schemas_are_current() -> None:
    for name, doc in schemas().items():
        committed = (SCHEMA_DIR / name).read_text()
        assert committed == render(doc), f"frontend/schema/{name} is stale: run `python -m sem_console.schema_export`"
