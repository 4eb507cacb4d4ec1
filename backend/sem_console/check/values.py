"""Rules on report values that the report tests of every UMAA version apply (reports.py for 3.0.1, umaa_6_0.py for
6.0), each finding naming the reference its caller gives."""

from __future__ import annotations

from typing import Any


def in_range(v: Any, lo: float, hi: float, path: str, ref: str) -> str | None:
    """A number outside lo..hi, said with its path and reference; None otherwise (and for what is no number)."""
    if isinstance(v, (int, float)) and not isinstance(v, bool) and not lo <= v <= hi:
        return f"{path}: {v} outside {lo:g}..{hi:g} ({ref})"
    return None


def satellite_counts(report: dict[str, Any], ref: str) -> str | None:
    """A GPS report's numberSatellitesInView negative, or fewer than its satellites usedInFix; None otherwise."""
    sats = report.get("satellites") or []
    n = report.get("numberSatellitesInView")
    used = sum(1 for s in sats if s and s.get("usedInFix"))
    if isinstance(n, int) and n < 0:
        return f"numberSatellitesInView {n} is negative ({ref})"
    if isinstance(n, int) and used > n:
        return f"{used} satellites usedInFix but numberSatellitesInView is {n} ({ref})"
    return None
