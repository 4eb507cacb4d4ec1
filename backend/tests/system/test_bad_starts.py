"""Bad starts of a real `sem-console`: a database, port, chart, recording folder, replay
file or TLS pair it cannot use is one line on stderr naming it and what to do, exit code 2, before DDS or
the application starts (no traceback, nothing from uvicorn)."""

from __future__ import annotations

import ctypes
import os
import socket
import sqlite3
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from conftest import ConsoleProcess, free_port
from support import warm
from support.pg import PASSWORD, Cluster

EXE = Path(sys.executable).parent / "sem-console"
PMTILES_V3 = b"PMTiles\x03" + bytes(119)  # a whole v3 header: magic, version, then offsets and bounds (zeros here)


def refused(args: list[str], domain: int, port: int | None = None, preexec_fn: Callable[[], None] | None = None) -> str:
    """Run the console; assert it refuses to start with exactly one line on stderr; that line."""
    argv = ["--domain", str(domain), "--port", str(port or free_port()), "--log-level", "info", *args]
    if preexec_fn is None:  # forked from the warm interpreter: the command's own `main` on these arguments
        p = warm.run(warm.CONSOLE, argv)
    else:
        p = subprocess.run([str(EXE), *argv], capture_output=True, text=True, timeout=60, preexec_fn=preexec_fn)
    assert p.returncode == 2, (args, p.returncode, p.stderr[-2000:])
    assert "Traceback" not in p.stderr and p.stdout == "", p.stderr
    lines = p.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("sem-console: error: "), p.stderr
    return lines[0]


@pytest.fixture
def busy_tcp() -> Iterator[int]:
    """A TCP port another process listens on."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        yield s.getsockname()[1]


@pytest.fixture
def busy_udp() -> Iterator[int]:
    """A UDP port another socket holds on 127.0.0.1 (0.0.0.0 cannot take it either)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        yield s.getsockname()[1]


def database(path: Path) -> Path:
    """A real console-like SQLite database of a few pages."""
    with sqlite3.connect(path) as db:
        db.execute("CREATE TABLE t (id INTEGER PRIMARY KEY, v TEXT)")
        db.executemany("INSERT INTO t (v) VALUES (?)", [("x" * 500,)] * 200)
    db.close()
    return path


# ---- the database -----------------------------------------------------------------------------------------------
def corrupt(tmp_path: Path) -> Path:
    (tmp_path / "db").write_bytes(os.urandom(8192))
    return tmp_path / "db"


def zeros(tmp_path: Path) -> Path:
    (tmp_path / "db").write_bytes(bytes(8192))
    return tmp_path / "db"


def truncated(tmp_path: Path) -> Path:
    path = database(tmp_path / "db")
    with open(path, "r+b") as f:
        f.truncate(path.stat().st_size // 2)
    return path


def a_directory(tmp_path: Path) -> Path:
    (tmp_path / "db").mkdir()
    return tmp_path / "db"


@pytest.mark.parametrize(
    "make, says",
    [
        (corrupt, "is not a SQLite database"),
        (zeros, "is not a SQLite database"),
        (truncated, "damaged"),
        (a_directory, "is a directory"),
    ],
)
def test_a_database_it_cannot_use_is_one_line(make: Callable[[Path], Path], says: str, domain: int, tmp_path: Path) -> None:
    path = make(tmp_path)
    line = refused(["--db", str(path)], domain)
    assert f"--db {path}" in line and says in line and "pass another --db" in line, line
    if make is not a_directory:
        assert "move it aside" in line


def test_a_database_given_by_url_is_named_by_that_option(domain: int, tmp_path: Path) -> None:
    """The line named --db, an option the operator never gave."""
    line = refused(["--database-url", f"sqlite:///{corrupt(tmp_path)}"], domain)
    assert f"--database-url {tmp_path / 'db'} is not a SQLite database" in line and "--db" not in line, line


def test_a_database_in_place_of_a_file_is_one_line(domain: int, tmp_path: Path) -> None:
    (tmp_path / "file").write_text("not a directory")
    line = refused(["--db", str(tmp_path / "file" / "console.sqlite3")], domain)
    assert f"{tmp_path / 'file'} (a file is in the way)" in line and "pass another --db" in line, line


def drop_file_permission_override() -> None:
    """In the child, as root: give up overriding file permissions (CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH),
    so a file its owner may not read or write is refused to it as to anyone."""
    libc = ctypes.CDLL(None, use_errno=True)
    for capability in (1, 2):
        if libc.prctl(24, capability, 0, 0, 0) != 0:  # PR_CAPBSET_DROP: gone from the bounding set at exec
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP)")


@pytest.mark.parametrize("mode", [0o000, 0o444])
def test_a_database_without_permission_is_one_line(mode: int, domain: int, tmp_path: Path) -> None:
    path = database(tmp_path / "db")
    path.chmod(mode)
    preexec = drop_file_permission_override if os.geteuid() == 0 else None
    if preexec is not None:
        try:
            subprocess.run(["true"], preexec_fn=preexec, check=True)
        except (subprocess.SubprocessError, OSError):
            pytest.skip("root here cannot give up overriding file permissions")
    line = refused(["--db", str(path)], domain, preexec_fn=preexec)
    assert f"--db {path}: cannot open it to read and write (Permission denied)" in line, line


@pytest.mark.parametrize("content", [b"", None])
def test_an_empty_or_sound_database_passes_the_check(content: bytes | None, domain: int, tmp_path: Path, busy_tcp: int) -> None:
    """An empty file is a new database, a sound one is used: what stops these starts is the port, checked after."""
    path = tmp_path / "db"
    path.write_bytes(content) if content is not None else database(path)
    assert "--port" in refused(["--db", str(path)], domain, port=busy_tcp)


@pytest.mark.parametrize(
    "case, says, fix",
    [
        ("no server", "cannot reach the PostgreSQL server", "start it, or fix the host and port in --database-url"),
        ("wrong password", 'password authentication failed for user "postgres"', "fix the user name or password"),
        ("no such database", 'database "nope" does not exist', "create it (createdb, or CREATE DATABASE)"),
    ],
)
def test_a_postgresql_it_cannot_use_is_one_line_without_the_password(
    case: str, says: str, fix: str, domain: int, pg_cluster: Cluster
) -> None:
    url = {
        "no server": f"postgresql://postgres:{PASSWORD}@127.0.0.1:{free_port()}/console",
        "wrong password": pg_cluster.url("postgres", password="not-it-42"),
        "no such database": pg_cluster.url("nope"),
    }[case]
    line = refused(["--database-url", url], domain)
    assert says in line and fix in line and "--database-url postgresql+psycopg://postgres:***@127.0.0.1:" in line, line
    assert PASSWORD not in line and "not-it-42" not in line


def test_db_and_database_url_together_is_one_line(domain: int, tmp_path: Path) -> None:
    line = refused(["--db", str(tmp_path / "db"), "--database-url", str(tmp_path / "other")], domain)
    assert "--db and --database-url: give one" in line, line


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["sqlite", "postgresql"])
def test_a_second_console_of_the_same_name_on_one_database_is_one_line(
    backend: str, domain: int, tmp_path: Path, console: Callable[..., ConsoleProcess], request: pytest.FixtureRequest
) -> None:
    url = str(tmp_path / "console.sqlite3") if backend == "sqlite" else request.getfixturevalue("pg_url")
    console("--database-url", url, "--console-name", "watch")
    line = refused(["--database-url", url, "--console-name", "watch"], domain)
    if backend == "sqlite":
        assert f"another console ('watch') is running on {url}" in line and "--database-url" in line, line
    else:
        shown = "postgresql+psycopg://postgres:***@"
        assert f"another console named 'watch' is running on {shown}" in line and "another --console-name" in line, line
    assert PASSWORD not in line


@pytest.mark.slow
def test_a_second_console_on_one_sqlite_file_is_refused_whatever_its_name(
    domain: int, tmp_path: Path, console: Callable[..., ConsoleProcess]
) -> None:
    """SQLite tells a console nothing of another's commands, alarms or names: two on one file looked shared and were not."""
    path = tmp_path / "console.sqlite3"
    first = console("--database-url", str(path), "--console-name", "watch")
    line = refused(["--db", str(path), "--console-name", "relief"], domain)
    assert f"another console ('watch') is running on {path}" in line, line
    assert "consoles cannot share a SQLite file" in line and "--database-url" in line, line
    lock = path.with_name(path.name + ".lock")
    assert lock.exists()
    first.stop()
    assert not lock.exists(), sorted(p.name for p in tmp_path.iterdir())  # a clean stop leaves no lock file behind
    assert not [p for p in tmp_path.iterdir() if ".lock" in p.name]


def test_a_db_in_a_folder_that_does_not_exist_is_one_line(domain: int, tmp_path: Path) -> None:
    """A typo in the folder made it, and a new empty history in it, unsaid."""
    path = tmp_path / "typo" / "deeper" / "x.sqlite3"
    for option in ("--db", "--database-url"):
        line = refused([option, str(path)], domain)
        assert f"{option} {path}: the folder {path.parent} does not exist" in line, line
        assert f"mkdir -p {path.parent}" in line, line
    assert not (tmp_path / "typo").exists()


@pytest.mark.slow
def test_a_new_database_file_is_said_in_one_line_at_start(tmp_path: Path, console: Callable[..., ConsoleProcess]) -> None:
    path = tmp_path / "new.sqlite3"
    out = console("--database-url", str(path)).stop()
    said = [line for line in out.splitlines() if "new database" in line]
    assert len(said) == 1 and f"new database {path}: no history there before this start" in said[0], out
    again = console("--database-url", str(path)).stop()  # the same file again: nothing to say
    assert "new database" not in again, again


@pytest.mark.parametrize(
    "args, env, line",
    [
        (["--domain", "abc"], {}, "sem-console: error: --domain: 'abc' is not a whole number"),
        ([], {"SEM_DOMAIN": "xyz"}, "sem-console: error: SEM_DOMAIN: 'xyz' is not a whole number"),
        (["--unanswered-timeout", "soon"], {}, "sem-console: error: --unanswered-timeout: 'soon' is not a number"),
        (["--domain", "999"], {}, "sem-console: error: --domain: 999 is outside 0..232"),  # the style they follow
    ],
)
def test_a_value_that_is_no_number_is_one_line_in_the_style_of_the_others(
    args: list[str], env: dict[str, str], line: str, tmp_path: Path
) -> None:
    p = subprocess.run(
        [str(EXE), "--db", str(tmp_path / "db"), *args], capture_output=True, text=True, timeout=60, env={**os.environ, **env}
    )
    assert (p.returncode, p.stdout, p.stderr) == (2, "", line + "\n")


# ---- ports ------------------------------------------------------------------------------------------------------
def test_a_port_in_use_is_one_line_before_the_application_starts(domain: int, tmp_path: Path, busy_tcp: int) -> None:
    line = refused(["--db", str(tmp_path / "db")], domain, port=busy_tcp)
    assert f"127.0.0.1:{busy_tcp} is already in use" in line and "pass another --port" in line, line
    assert not (tmp_path / "db").exists()  # refused before the store opened it


def test_a_host_that_is_not_here_is_one_line(domain: int, tmp_path: Path) -> None:
    line = refused(["--db", str(tmp_path / "db"), "--host", "192.0.2.1"], domain)  # TEST-NET-1: no machine's address
    assert "192.0.2.1" in line and "pass another --host" in line, line


def test_a_jaus_port_in_use_is_one_line(domain: int, tmp_path: Path, busy_udp: int) -> None:
    line = refused(["--db", str(tmp_path / "db"), "--jaus-port", str(busy_udp)], domain)
    assert f"UDP 127.0.0.1:{busy_udp} is already in use" in line and "pass another --jaus-port" in line, line


def test_an_imc_port_in_use_is_one_line(domain: int, tmp_path: Path, busy_udp: int) -> None:
    line = refused(["--db", str(tmp_path / "db"), "--imc-port", str(busy_udp)], domain)
    assert f"UDP 0.0.0.0:{busy_udp} is already in use" in line and "pass another --imc-port" in line, line


def test_the_same_port_for_jaus_and_imc_is_one_line(domain: int, tmp_path: Path) -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:  # a free UDP port, released for the console
        s.bind(("0.0.0.0", 0))
        port = s.getsockname()[1]
    line = refused(
        ["--db", str(tmp_path / "db"), "--jaus-port", str(port), "--jaus-host", "0.0.0.0", "--imc-port", str(port)], domain
    )
    assert f"UDP 0.0.0.0:{port} is already in use" in line and "--imc-port" in line, line


# ---- the chart, recordings, replay, TLS -------------------------------------------------------------------------
@pytest.mark.parametrize(
    "content, says",
    [
        (None, "no such file"),
        (b"<html>not a chart</html>", "is not a PMTiles file"),
        (b"PM\x02\x00" + bytes(200), "is not a PMTiles file"),  # a PMTiles v2 archive
        (b"PMTiles\x02" + bytes(200), "version 2"),
        (PMTILES_V3[:60], "not a whole PMTiles version 3 file"),
    ],
)
def test_a_basemap_that_is_not_pmtiles_v3_is_one_line(content: bytes | None, says: str, domain: int, tmp_path: Path) -> None:
    chart = tmp_path / "chart.pmtiles"
    if content is not None:
        chart.write_bytes(content)
    line = refused(["--db", str(tmp_path / "db"), "--basemap", str(chart)], domain)
    assert str(chart) in line and says in line and "--basemap" in line, line


def test_a_basemap_directory_is_one_line(domain: int, tmp_path: Path) -> None:
    line = refused(["--db", str(tmp_path / "db"), "--basemap", str(tmp_path)], domain)
    assert f"--basemap {tmp_path} is a directory" in line, line


def test_a_pmtiles_v3_basemap_passes_the_check(domain: int, tmp_path: Path, busy_tcp: int) -> None:
    (tmp_path / "chart.pmtiles").write_bytes(PMTILES_V3 + os.urandom(1000))
    line = refused(["--db", str(tmp_path / "db"), "--basemap", str(tmp_path / "chart.pmtiles")], domain, port=busy_tcp)
    assert "--port" in line, line


@pytest.mark.parametrize("option", ["--record", "--recordings-dir"])
def test_a_recording_folder_it_cannot_write_is_one_line(option: str, domain: int, tmp_path: Path) -> None:
    (tmp_path / "file").write_text("not a directory")
    folder = tmp_path / "file" / "recordings"
    line = refused(["--db", str(tmp_path / "db"), option, str(folder)], domain)
    assert f"{option} {folder}: {tmp_path / 'file'} is a file, not a directory" in line, line


def test_a_missing_recording_folder_is_not_made_before_it_is_needed(domain: int, tmp_path: Path, busy_tcp: int) -> None:
    assert "--port" in refused(
        ["--db", str(tmp_path / "db"), "--recordings-dir", str(tmp_path / "a" / "b")], domain, port=busy_tcp
    )
    assert not (tmp_path / "a").exists()


@pytest.mark.parametrize(
    "content, says",
    [
        (None, "cannot read"),
        (b"not a recording", "is not an MCAP file"),
        (b"", "is not an MCAP file: it ends before an MCAP header"),
    ],
)
def test_a_replay_file_it_cannot_read_is_one_line(content: bytes | None, says: str, domain: int, tmp_path: Path) -> None:
    recording = tmp_path / "run.mcap"
    if content is not None:
        recording.write_bytes(content)
    line = refused(["--replay", str(recording)], domain)
    assert str(recording) in line and says in line, line


def test_a_frontend_dir_without_a_dashboard_is_one_line(domain: int, tmp_path: Path) -> None:
    """It started, and / answered {"detail": "Not Found"} with nothing said."""
    line = refused(["--db", str(tmp_path / "db"), "--frontend-dir", str(tmp_path / "nowhere")], domain)
    assert f"--frontend-dir {tmp_path / 'nowhere'} has no index.html" in line, line


def test_tls_files_that_are_not_a_certificate_and_key_are_one_line(domain: int, tmp_path: Path) -> None:
    pem = tmp_path / "not.pem"
    pem.write_text("-----BEGIN CERTIFICATE-----\nnot base64\n-----END CERTIFICATE-----\n")
    line = refused(["--db", str(tmp_path / "db"), "--tls-certfile", str(pem), "--tls-keyfile", str(pem)], domain)
    assert f"--tls-certfile {pem} and --tls-keyfile {pem}" in line, line


def test_the_default_recording_folder_unwritable_is_only_a_warning(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Without --record or --recordings-dir a console that cannot write var/recordings still starts (the
    operator may never record), with a warning naming the folder; given explicitly, it is refused (above)."""
    from sem_console.cli import start_warnings
    from sem_console.core.config import Settings

    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("SEM_RECORDINGS_DIR", raising=False)
    (tmp_path / "dist").mkdir()
    (tmp_path / "dist" / "index.html").write_text("<!doctype html>")
    monkeypatch.setenv("SEM_FRONTEND_DIR", str(tmp_path / "dist"))  # a built dashboard, whether this tree has one or not
    assert start_warnings(Settings()) == []
    (tmp_path / "var").write_text("a file where the folder would go")
    assert start_warnings(Settings()) == [
        "--recordings-dir var/recordings: var is a file, not a directory: pass another directory "
        "(the record control fails until then)"
    ]
