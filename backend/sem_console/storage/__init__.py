"""Storage: the console's tables (models), its database on SQLAlchemy (database) with Alembic migrations
(migrations/), and the database URL an operator gives (url). Below the console's running logic (console/):
it imports nothing of it."""
