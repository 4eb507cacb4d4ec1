"""docker-compose.yml is valid and fails fast on missing settings (no Docker engine needed)."""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

pytestmark = pytest.mark.process

REPO = Path(__file__).resolve().parents[3]


def compose() -> list[str] | None:
    if shutil.which("docker") and subprocess.run(["docker", "compose", "version"], capture_output=True).returncode == 0:
        return ["docker", "compose"]
    if shutil.which("docker-compose"):
        return ["docker-compose"]
    return None


def run(env: dict[str, str], *options: str) -> subprocess.CompletedProcess[str]:
    cmd = compose()
    if cmd is None:
        pytest.skip("no docker compose client on this machine")
    clean = {k: v for k, v in os.environ.items() if not k.startswith("SEM_")}
    return subprocess.run([*cmd, *options, "config"], cwd=REPO, env={**clean, **env}, capture_output=True, text=True, timeout=60)


def test_the_operations_centre_profile_has_postgres_and_two_stations() -> None:
    out = run({"SEM_DOMAIN": "7", "SEM_OPERATOR_TOKENS": "alice:s3cret", "SEM_DB_PASSWORD": "pw"}, "--profile", "opscentre")
    assert out.returncode == 0, out.stderr
    assert "postgres:15" in out.stdout and out.stdout.count("postgresql://sem:pw@postgres:5432/sem_console") == 2
    assert "SEM_CONSOLE_NAME: watch" in out.stdout and "SEM_CONSOLE_NAME: relief" in out.stdout
    assert "127.0.0.1:8001:8000" in out.stdout and "127.0.0.1:8002:8000" in out.stdout


def test_compose_config_is_valid() -> None:
    out = run({"SEM_DOMAIN": "7", "SEM_OPERATOR_TOKENS": "alice:s3cret"})
    assert out.returncode == 0, out.stderr
    assert "127.0.0.1:8000:8000" in out.stdout  # published on loopback only
    assert "service_healthy" in out.stdout and "sim.Dockerfile" in out.stdout and "console.Dockerfile" in out.stdout


@pytest.mark.parametrize("missing", ["SEM_DOMAIN", "SEM_OPERATOR_TOKENS"])
def test_required_settings_fail_fast(missing: str) -> None:
    env = {"SEM_DOMAIN": "7", "SEM_OPERATOR_TOKENS": "alice:s3cret"}
    del env[missing]
    out = run(env)
    assert out.returncode != 0 and f"set {missing}" in out.stderr
