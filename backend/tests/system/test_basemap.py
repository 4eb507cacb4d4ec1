"""The optional offline chart (--basemap FILE.pmtiles): served with HTTP range requests, as the dashboard's
pmtiles reader reads it, announced by /api/health, and a missing file refused at the command line."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from support import http

pytestmark = pytest.mark.process


def test_the_basemap_is_served_with_range_requests(console, tmp_path: Path) -> None:
    data = b"PMTiles\x03" + os.urandom(200_000)
    (tmp_path / "chart.pmtiles").write_bytes(data)
    c = console("--basemap", str(tmp_path / "chart.pmtiles"))
    assert http.get(f"{c.url}/api/health").json()["basemap"] is True
    r = http.get(f"{c.url}/api/basemap.pmtiles", headers={"Range": "bytes=0-16383"})
    assert r.status_code == 206
    assert r.headers["content-range"] == f"bytes 0-16383/{len(data)}"
    assert r.headers["content-type"] == "application/vnd.pmtiles"
    assert r.content == data[:16384]
    r = http.get(f"{c.url}/api/basemap.pmtiles", headers={"Range": "bytes=150000-150099"})
    assert r.status_code == 206 and r.content == data[150000:150100]
    whole = http.get(f"{c.url}/api/basemap.pmtiles")
    assert whole.status_code == 200 and whole.content == data and whole.headers["accept-ranges"] == "bytes"
    assert http.get(f"{c.url}/api/basemap.pmtiles", headers={"Range": f"bytes={len(data) + 10}-"}).status_code == 416


def test_no_basemap_is_a_404_and_health_says_so(console) -> None:
    c = console()
    assert http.get(f"{c.url}/api/health").json()["basemap"] is False
    r = http.get(f"{c.url}/api/basemap.pmtiles")
    assert r.status_code == 404 and "--basemap" in r.json()["detail"]


def test_a_missing_basemap_file_is_a_one_line_error(tmp_path: Path) -> None:
    exe = Path(sys.executable).parent / "sem-console"
    p = subprocess.run([str(exe), "--basemap", str(tmp_path / "nope.pmtiles")], capture_output=True, text=True, timeout=30)
    assert p.returncode == 2
    assert "--basemap: no such file" in p.stderr
