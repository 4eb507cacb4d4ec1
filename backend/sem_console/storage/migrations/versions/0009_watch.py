"""Alarm shelving and planned silences (alarm_shelves, planned_silences): what an operator shelved or declared, shared
by the consoles of one database and kept over restarts.

Revision ID: 0008
Revises: 0007
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0009"
down_revision = "0008"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "alarm_shelves",
        sa.Column("id", sa.String(), primary_key=True),
        sa.Column("key", sa.String(), nullable=False),
        sa.Column("kind", sa.String(), nullable=False),
        sa.Column("provider_id", sa.String()),
        sa.Column("session_id", sa.String()),
        sa.Column("severity", sa.String(), nullable=False),
        sa.Column("text", sa.String(), nullable=False),
        sa.Column("reason", sa.String(), nullable=False),
        sa.Column("shelved_by", sa.String()),
        sa.Column("station", sa.String()),
        sa.Column("shelved_at", sa.Float(), nullable=False),
        sa.Column("until", sa.Float(), nullable=False),
        sa.Column("ended_at", sa.Float()),
        sa.Column("ended_by", sa.String()),
        sa.Column("end_reason", sa.String()),
    )
    op.create_index("alarm_shelves_open", "alarm_shelves", ["ended_at"])
    op.create_table(
        "planned_silences",
        sa.Column("id", sa.String(), primary_key=True),
        sa.Column("provider_id", sa.String(), nullable=False),
        sa.Column("reason", sa.String(), nullable=False),
        sa.Column("set_by", sa.String()),
        sa.Column("station", sa.String()),
        sa.Column("set_at", sa.Float(), nullable=False),
        sa.Column("until", sa.Float(), nullable=False),
        sa.Column("ended_at", sa.Float()),
        sa.Column("ended_by", sa.String()),
        sa.Column("end_reason", sa.String()),
    )
    op.create_index("planned_silences_open", "planned_silences", ["ended_at"])


def downgrade() -> None:
    op.drop_table("planned_silences")
    op.drop_table("alarm_shelves")
