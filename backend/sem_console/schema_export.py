"""Write the console's published schemas for the frontend's type generation.

`python -m sem_console.schema_export` writes frontend/schema/openapi.json and ws-schema.json, from which
the dashboard's build generates its TypeScript types, and words.json, the operator's words the dashboard
shows (`core/words.py`); the test suite fails when they no longer match the code.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from sem_console.api.schemas import ws_schema
from sem_console.core.words import WORDS

SCHEMA_DIR = Path(__file__).resolve().parents[2] / "frontend" / "schema"


def schemas() -> dict[str, dict[str, Any]]:
    from sem_console.main import create_app

    return {"openapi.json": create_app().openapi(), "ws-schema.json": ws_schema(), "words.json": WORDS}


def render(doc: dict[str, Any]) -> str:
    return json.dumps(doc, indent=2, sort_keys=True) + "\n"


def main() -> int:
    SCHEMA_DIR.mkdir(parents=True, exist_ok=True)
    for name, doc in schemas().items():
        (SCHEMA_DIR / name).write_text(render(doc))
    print(f"wrote {', '.join(schemas())} to {SCHEMA_DIR}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
