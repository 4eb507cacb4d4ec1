"""Vehicle names set from the dashboard (PUT /api/providers/{id}/name), shared by the consoles of one database.

Revision ID: 0004
Revises: 0003
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0004"
down_revision = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "vehicle_names",
        sa.Column("provider_id", sa.String(), primary_key=True),
        sa.Column("name", sa.String(), nullable=False),
        sa.Column("set_by", sa.String()),
        sa.Column("set_at", sa.Float(), nullable=False),
    )


def downgrade() -> None:
    op.drop_table("vehicle_names")
