"""Storage growth: N `sem-sim` vehicles (default 50) with every report at 1 Hz and one console on SQLite for a few
minutes. Measured: the database file's growth, each table's rows per vehicle and second and its bytes per row (SQLite's
dbstat: the table's pages and its indexes'). From them, the bytes one vehicle keeps for a day of history at the
default retention (the track and series as thinned when written and rolled up after the rollup age, the other tables
as they grew), printed beside the target: at most 2 MB per vehicle per day.
Usage: python bench/storage.py [--vehicles 50] [--seconds 180] [--umaa 3.0.1|6.0] [--domain D]
"""

from __future__ import annotations

import argparse
import os
import sqlite3
import time
from pathlib import Path
from typing import Any

from common import emit, stack, table, target, wait_listed
from scale import sim_args

from sem_console.core.config import Settings

MB_TARGET = 2.0  # per vehicle per day, the "at most 2 MB per vehicle per day at the default retention"
DAY = 86_400.0
HISTORY = ("track", "series")  # thinned and rolled up; pruned after the retention


def measure(path: Path) -> dict[str, Any]:
    """The bytes of the file and its write-ahead log on disk, the bytes of the database's pages in use (the file
    less its free pages, the log's latest pages included: the log's size on disk is its high-water mark, not the
    data's), and each table's rows and bytes (its indexes' pages included)."""
    files = sum(p.stat().st_size for p in (path, path.with_name(path.name + "-wal")) if p.exists())
    db = sqlite3.connect(f"file:{path}?mode=ro", uri=True, timeout=30)
    try:
        page, count, free = (db.execute(f"PRAGMA {x}").fetchone()[0] for x in ("page_size", "page_count", "freelist_count"))
        owner = dict(db.execute("SELECT name, tbl_name FROM sqlite_master WHERE type IN ('table', 'index')").fetchall())
        pages: dict[str, int] = {}
        for name, size in db.execute("SELECT name, SUM(pgsize) FROM dbstat GROUP BY name").fetchall():
            if name in owner:
                pages[owner[name]] = pages.get(owner[name], 0) + size
        tables = [t for t in pages if not t.startswith(("sqlite_", "alembic_"))]
        rows = {t: db.execute(f'SELECT COUNT(*) FROM "{t}"').fetchone()[0] for t in tables}
    finally:
        db.close()
    return {"file": files, "used": (count - free) * page, "tables": {t: {"rows": rows[t], "bytes": pages[t]} for t in tables}}


def day_rows(table_name: str, per_s: float, s: Settings) -> float:
    """Rows one vehicle keeps for a day: the history at its rate for the rollup age, then one per rollup interval (at
    most its rate) until the retention; any other table as it grew."""
    if table_name not in HISTORY:
        return per_s * DAY
    kept = min(s.track_retention_hours * 3600.0, DAY)
    recent = min(kept, s.track_rollup_after_hours * 3600.0)
    return per_s * recent + min(per_s, 1.0 / s.track_rollup_seconds) * (kept - recent)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vehicles", type=int, default=50)
    ap.add_argument("--seconds", type=float, default=180.0, help="measured window after the fleet is listed (default: 180)")
    ap.add_argument("--umaa", choices=("3.0.1", "6.0"), default="3.0.1")
    ap.add_argument("--domain", type=int, help="DDS domain (default: a free one)")
    args = ap.parse_args()
    n, defaults = args.vehicles, Settings()
    with stack(sim_args=sim_args(n, args.umaa), domain=args.domain) as st:
        wait_listed(st["url"], n, timeout=120)
        path = st["tmp"] / "console.sqlite3"
        first, t0 = measure(path), time.monotonic()
        time.sleep(args.seconds)
        last, elapsed = measure(path), time.monotonic() - t0
    per_table: list[dict[str, Any]] = []  # the tables with rows (every other one grew by none)
    day_bytes = 0.0
    for name, end in sorted(last["tables"].items()):
        if not end["rows"]:
            continue
        per_s = (end["rows"] - first["tables"].get(name, {"rows": 0})["rows"]) / n / elapsed
        per_row = end["bytes"] / end["rows"]
        kept = day_rows(name, per_s, defaults)
        day_bytes += kept * per_row
        per_table.append(
            {
                "table": name,
                "rows": end["rows"],
                "rows_per_vehicle_s": round(per_s, 4),
                "bytes_per_row": round(per_row, 1),
                "rows_per_vehicle_day": round(kept),
                "mb_per_vehicle_day": round(kept * per_row / 1e6, 3),
            }
        )
    table(f"Tables after {elapsed:.0f} s ({n} vehicles)", list(per_table[0]), [list(r.values()) for r in per_table])
    used_per_vehicle_s = (last["used"] - first["used"]) / n / elapsed
    mb_day = round(day_bytes / 1e6, 3)
    targets = [
        target(
            "bytes per vehicle per day",
            mb_day,
            "MB",
            "<=",
            MB_TARGET,
            f"default retention {defaults.track_retention_hours:g} h",
        )
    ]
    emit(
        "storage",
        {
            "targets": targets,
            "vehicles": n,
            "umaa": args.umaa,
            "seconds": round(elapsed),
            "retention_hours": defaults.track_retention_hours,
            "thin_metres": defaults.track_thin_metres,
            "thin_seconds": defaults.track_thin_seconds,
            "rollup_after_hours": defaults.track_rollup_after_hours,
            "rollup_seconds": defaults.track_rollup_seconds,
            "database_growth_mb_per_min": round((last["used"] - first["used"]) / elapsed * 60 / 1e6, 3),
            "database_growth_mb_per_vehicle_day_not_rolled_up": round(used_per_vehicle_s * DAY / 1e6, 2),
            "file_and_log_mb_at_end": round(last["file"] / 1e6, 2),
            "load_average": round(os.getloadavg()[0], 2),
            "tables": per_table,
        },
    )


if __name__ == "__main__":
    main()
