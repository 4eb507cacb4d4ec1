"""The console station whose alarm each row is: consoles sharing a database each keep their own alarms (and share
the acknowledgements, storage/notify.py); the first release's rows go to the first console name (Database.claim).

Revision ID: 0003
Revises: 0002
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0003"
down_revision = "0002"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("alarms", sa.Column("console", sa.String()))


def downgrade() -> None:
    with op.batch_alter_table("alarms") as batch:
        batch.drop_column("console")
