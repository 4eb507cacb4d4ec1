"""The CoMap world model and tasks, shared by the consoles of one database, and the task id counter.

Revision ID: 0005
Revises: 0004
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0005"
down_revision = "0004"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "comap_world",
        sa.Column("id", sa.Integer(), primary_key=True, autoincrement=False),
        sa.Column("features", sa.String(), nullable=False),
        sa.Column("updated_at", sa.Float(), nullable=False),
        sa.Column("source", sa.String()),
        sa.Column("highest_feature", sa.Integer(), nullable=False),
        sa.Column("station", sa.String()),
    )
    op.create_table(
        "comap_tasks",
        sa.Column("task_id", sa.Integer(), primary_key=True, autoincrement=False),
        sa.Column("kind", sa.String(), nullable=False),
        sa.Column("vehicle", sa.String(), nullable=False),
        sa.Column("imc_id", sa.Integer(), nullable=False),
        sa.Column("operator", sa.String()),
        sa.Column("feature_id", sa.Integer()),
        sa.Column("sensor", sa.String()),
        sa.Column("resolution", sa.Float()),
        sa.Column("deadline", sa.Float()),
        sa.Column("point", sa.String()),
        sa.Column("state", sa.String(), nullable=False),
        sa.Column("progress", sa.Integer(), nullable=False),
        sa.Column("quality", sa.Integer()),
        sa.Column("created_at", sa.Float(), nullable=False),
        sa.Column("updated_at", sa.Float(), nullable=False),
        sa.Column("last_synch", sa.String()),
        sa.Column("station", sa.String()),
    )
    ids = op.create_table(
        "comap_task_ids",
        sa.Column("id", sa.Integer(), primary_key=True, autoincrement=False),
        sa.Column("next_task", sa.Integer(), nullable=False),
    )
    op.bulk_insert(ids, [{"id": 1, "next_task": 1}])  # the row a console locks to take an id (never inserted twice)


def downgrade() -> None:
    op.drop_table("comap_task_ids")
    op.drop_table("comap_tasks")
    op.drop_table("comap_world")
