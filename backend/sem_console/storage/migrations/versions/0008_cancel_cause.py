"""Why a command was cancelled: an operator asked it, or its station's shutdown cancelled what it had running
(console/commands.py); null on a command not cancelled, or cancelled before the cause was recorded.

Revision ID: 0008
Revises: 0007
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0008"
down_revision = "0007"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("commands", sa.Column("cancel_cause", sa.String()))


def downgrade() -> None:
    with op.batch_alter_table("commands") as batch:
        batch.drop_column("cancel_cause")
