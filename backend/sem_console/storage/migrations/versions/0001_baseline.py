"""Baseline: the schema of the raw sqlite3 storage (release 8592e59 and before), as it was.

A database written by that code has these tables and no alembic_version: this revision then creates only
what is missing (tables of features newer than the file, the columns canceled_by and acked_at that the
old code added itself), so the file is upgraded in place with its rows.

Revision ID: 0001
Revises:
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None

S, F, N, B = sa.String, sa.Float, sa.Integer, sa.Boolean  # the column types


def _tables() -> list[tuple[str, list[sa.Column[object]], dict[str, object]]]:
    false = sa.false()
    return [
        ("meta", [sa.Column("key", S(), primary_key=True), sa.Column("value", S(), nullable=False)], {}),
        (
            "commands",
            [
                sa.Column("session_id", S(), primary_key=True),
                sa.Column("service", S(), nullable=False),
                sa.Column("provider_id", S(), nullable=False),
                sa.Column("state", S()),
                sa.Column("operator", S()),
                sa.Column("created_at", F(), nullable=False),
                sa.Column("command", S(), nullable=False),
                sa.Column("unanswered", B(), nullable=False, server_default=false),
                sa.Column("cancel_requested", B(), nullable=False, server_default=false),
                sa.Column("canceled_by", S()),
                sa.Column("cleaned_up", B(), nullable=False, server_default=false),
                sa.Column("acked_at", F()),
            ],
            {},
        ),
        (
            "transitions",
            [
                sa.Column("session_id", S(), sa.ForeignKey("commands.session_id"), primary_key=True),
                sa.Column("seq", N(), primary_key=True),
                sa.Column("status", S(), nullable=False),
                sa.Column("reason", S(), nullable=False),
                sa.Column("log_message", S(), nullable=False),
                sa.Column("violation", S()),
                sa.Column("provider_time", F()),
                sa.Column("received_at", F(), nullable=False),
            ],
            {},
        ),
        (
            "audit",
            [
                sa.Column("id", N(), primary_key=True, autoincrement=True),
                sa.Column("at", F(), nullable=False),
                sa.Column("outcome", S(), nullable=False),
                sa.Column("status", N(), nullable=False),
                sa.Column("method", S(), nullable=False),
                sa.Column("path", S(), nullable=False),
                sa.Column("client", S()),
                sa.Column("origin", S()),
                sa.Column("operator", S()),
                sa.Column("session_id", S()),
                sa.Column("reason", S(), nullable=False),
            ],
            {"sqlite_autoincrement": True},
        ),
        ("link_config", [sa.Column("provider_id", S(), primary_key=True), sa.Column("config", S(), nullable=False)], {}),
        (
            "alarms",
            [
                sa.Column("id", N(), primary_key=True, autoincrement=True),
                sa.Column("key", S(), nullable=False),
                sa.Column("kind", S(), nullable=False),
                sa.Column("severity", S(), nullable=False),
                sa.Column("provider_id", S()),
                sa.Column("vehicle", S()),
                sa.Column("session_id", S()),
                sa.Column("text", S(), nullable=False),
                sa.Column("since", F(), nullable=False),
                sa.Column("cleared_at", F()),
                sa.Column("acked_at", F()),
                sa.Column("acked_by", S()),
                sa.Column("normal_at", F()),
            ],
            {"sqlite_autoincrement": True},
        ),
        (
            "track",
            [
                sa.Column("providerId", S(), primary_key=True),
                sa.Column("time", F(), primary_key=True),
                sa.Column("positionTime", F()),
                sa.Column("latitude", F(), nullable=False),
                sa.Column("longitude", F(), nullable=False),
                sa.Column("altitudeMsl", F()),
                sa.Column("course", F()),
                sa.Column("sog", F()),
                sa.Column("latLongValid", B(), nullable=False),
                sa.Column("fixValid", B()),
            ],
            {},
        ),
        (
            "series",
            [
                sa.Column("providerId", S(), primary_key=True),
                sa.Column("time", F(), primary_key=True),
                sa.Column("cn0Mean", F()),
                sa.Column("satellitesUsed", N(), nullable=False),
                sa.Column("satellitesInView", N(), nullable=False),
            ],
            {},
        ),
    ]


INDEXES = [("alarms_open", "alarms", "normal_at"), ("ix_track_time", "track", "time"), ("ix_series_time", "series", "time")]


def upgrade() -> None:
    inspector = sa.inspect(op.get_bind())
    have = set(inspector.get_table_names())
    for name, columns, options in _tables():
        if name not in have:
            op.create_table(name, *columns, **options)  # type: ignore[arg-type]  # dialect options as keywords
        elif name == "commands":  # the oldest files lack the two columns the old code added at start
            present = {c["name"] for c in inspector.get_columns(name)}
            for column in ("canceled_by", "acked_at"):
                if column not in present:
                    op.add_column(name, next(c for c in columns if c.name == column))
    for index, table, column in INDEXES:
        if table not in have or index not in {i["name"] for i in inspector.get_indexes(table)}:
            op.create_index(index, table, [column])


def downgrade() -> None:
    for name, _columns, _options in reversed(_tables()):
        op.drop_table(name)
