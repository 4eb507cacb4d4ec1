"""Who cancelled a command from which station and when, and how the console ended a cancelled command the vehicle
never answered (console/commands.py: heard again without it, or not heard within --cancel-unheard-bound).

Revision ID: 0007
Revises: 0006
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0007"
down_revision = "0006"
branch_labels = None
depends_on = None

COLUMNS = (("canceled_on", sa.String()), ("canceled_at", sa.Float()), ("closed_unheard", sa.String()), ("closed_at", sa.Float()))


def upgrade() -> None:
    for name, kind in COLUMNS:
        op.add_column("commands", sa.Column(name, kind))


def downgrade() -> None:
    with op.batch_alter_table("commands") as batch:
        for name, _kind in COLUMNS:
            batch.drop_column(name)
