"""A CoMap task's state and synch stamped apart from its progress (comap_tasks.state_at): a station's HOLD written
after a database outage no longer loses to the progress another station stored meanwhile.

Revision ID: 0006
Revises: 0005
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0006"
down_revision = "0005"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("comap_tasks") as t:
        t.add_column(sa.Column("state_at", sa.Float(), nullable=False, server_default="0"))
    op.execute("UPDATE comap_tasks SET state_at = updated_at")  # the best known: the last change of either


def downgrade() -> None:
    with op.batch_alter_table("comap_tasks") as t:
        t.drop_column("state_at")
