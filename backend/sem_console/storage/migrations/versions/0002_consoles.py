"""Console identities (a name per station, its source GUID), and the station that issued each command.

The first schema kept one source GUID in meta('source'); it stays there and becomes the identity of the first
console name that opens the database (storage.database.Database.claim), so an upgraded station keeps it.

Revision ID: 0002
Revises: 0001
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "consoles",
        sa.Column("name", sa.String(), primary_key=True),
        sa.Column("guid", sa.String(), nullable=False, unique=True),
        sa.Column("created_at", sa.Float(), nullable=False),
    )
    op.add_column("commands", sa.Column("console", sa.String()))


def downgrade() -> None:
    with op.batch_alter_table("commands") as batch:
        batch.drop_column("console")
    op.drop_table("consoles")
