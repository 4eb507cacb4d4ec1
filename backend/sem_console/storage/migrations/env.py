"""Alembic's environment: run in code by storage.engine.migrate on a connection it passes in
(config.attributes["connection"]); never from the alembic command line with an ini file."""

from __future__ import annotations

from alembic import context
from sqlmodel import SQLModel

from sem_console.storage import models  # noqa: F401  # the tables, registered on SQLModel.metadata

connection = context.config.attributes["connection"]
# SQLite changes most columns only by copying the table (batch mode); PostgreSQL alters them in place
context.configure(connection=connection, target_metadata=SQLModel.metadata, render_as_batch=connection.dialect.name == "sqlite")
with context.begin_transaction():
    context.run_migrations()
