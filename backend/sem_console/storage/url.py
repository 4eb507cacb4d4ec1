"""--database-url and --db as an operator types them -> the SQLAlchemy URL of the console's database."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # SQLAlchemy imported where a URL is made: the simulator reads Settings and needs none (0.09 s a start)
    from sqlalchemy.engine import URL

DRIVER = "postgresql+psycopg"  # psycopg 3: the one PostgreSQL driver installed (LISTEN/NOTIFY, binary wheels)


@dataclass(frozen=True)
class DatabaseUrl:
    url: URL
    path: Path | None  # the SQLite file; None for PostgreSQL

    @property
    def shown(self) -> str:
        """For logs and messages: the file, or the URL with its password hidden."""
        return str(self.path) if self.path is not None else self.url.render_as_string(hide_password=True)

    @property
    def postgresql(self) -> bool:
        return self.path is None


def sqlite_file(path: Path) -> DatabaseUrl:
    from sqlalchemy.engine import URL

    return DatabaseUrl(URL.create("sqlite", database=str(path)), path)


def parse_database_url(text: str) -> DatabaseUrl:
    """'postgresql://user:pass@host:port/db' (or postgres://, postgresql+psycopg://), 'sqlite:///PATH', or a path.
    ValueError: one line saying what is accepted."""
    from sqlalchemy.engine import make_url
    from sqlalchemy.exc import ArgumentError

    text = text.strip()
    if "://" not in text:
        if not text:
            raise ValueError("--database-url is empty: give a postgresql:// URL or a SQLite file path")
        return sqlite_file(Path(text))
    try:
        url = make_url(text)
    except (ArgumentError, ValueError):  # ValueError: a port that is not a number
        raise ValueError(
            "--database-url is not a URL: give postgresql://user:password@host:port/database (a "
            "number for the port; %-escape @ : / in the password) or a SQLite file path"
        ) from None
    if url.drivername in ("postgresql", "postgres", DRIVER):
        if not url.database:
            raise ValueError("--database-url names no database: postgresql://user:password@host:port/DATABASE")
        return DatabaseUrl(url.set(drivername=DRIVER), None)
    if url.drivername == "sqlite":
        if not url.database or url.database == ":memory:":
            raise ValueError("--database-url sqlite:// needs a file: sqlite:///relative/path or sqlite:////absolute/path")
        return sqlite_file(Path(url.database))
    raise ValueError(f"--database-url: {url.drivername!r} is not supported: give a postgresql:// URL or a SQLite file path")
