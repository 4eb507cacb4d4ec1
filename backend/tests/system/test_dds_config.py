"""CYCLONEDDS_URI is honoured by both programs, in each form Cyclone documents.

Each test gives a process a configuration through CYCLONEDDS_URI that binds it to loopback and
names a tracing output file: the file appears only when Cyclone read that configuration, and a
console and a simulator configured that way find each other on loopback.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from conftest import FAST
from sem_console.dds.config import loopback_config
from support import http
from test_console import wait_until

pytestmark = pytest.mark.process


def traced(path: Path) -> str:
    """The loopback config with Cyclone's tracing written to `path`."""
    tracing = f"<Tracing><Verbosity>config</Verbosity><OutputFile>{path}</OutputFile></Tracing>"
    return loopback_config().replace("</Domain>", tracing + "</Domain>")


def uri_forms(tmp_path: Path, name: str) -> dict[str, tuple[str, Path]]:
    """CYCLONEDDS_URI values in each documented form, with the trace file each one names."""
    out = {}
    for form in ("inline", "path", "file-uri"):
        trace = tmp_path / f"{name}-{form}.log"
        xml = traced(trace)
        if form == "inline":
            out[form] = (xml, trace)
        else:
            cfg = tmp_path / f"{name}-{form}.xml"
            cfg.write_text(xml)
            out[form] = (str(cfg) if form == "path" else cfg.as_uri(), trace)
    return out


@pytest.mark.parametrize("form", ["inline", "path", "file-uri"])
def test_sim_reads_cyclonedds_uri(form: str, domain: int, tmp_path: Path) -> None:
    uri, trace = uri_forms(tmp_path, "sim")[form]
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "sem_console.sim.sem_sim",
            "--domain",
            str(domain),
            "--state-file",
            str(tmp_path / "state.json"),
            *FAST,
        ],
        env={**os.environ, "CYCLONEDDS_URI": uri},
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        # Cyclone traces the configuration it read, the name of this very trace file among it.
        wait_until(lambda: trace.exists() and str(trace) in trace.read_text(errors="replace"), what="the sim's trace file")
    finally:
        proc.terminate()
        proc.communicate(timeout=15)


def test_console_and_sim_configured_by_uri_find_each_other(console, domain: int, tmp_path: Path) -> None:
    sim_uri, sim_trace = uri_forms(tmp_path, "sim")["file-uri"]
    console_uri, console_trace = uri_forms(tmp_path, "console")["inline"]
    sim = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "sem_console.sim.sem_sim",
            "--domain",
            str(domain),
            "--state-file",
            str(tmp_path / "state.json"),
            *FAST,
        ],
        env={**os.environ, "CYCLONEDDS_URI": sim_uri},
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        c = console(env={"CYCLONEDDS_URI": console_uri})
        providers = wait_until(lambda: http.get(c.url + "/api/providers").json() or None, what="the simulated vehicle")
        assert len(providers) == 1
        assert console_trace.exists() and sim_trace.exists()
    finally:
        sim.terminate()
        sim.communicate(timeout=15)


def test_uri_pointing_elsewhere_is_not_replaced_by_loopback(domain: int, tmp_path: Path) -> None:
    """A URI that names another interface is used as given, not Cyclone's defaults."""
    trace = tmp_path / "other.log"
    xml = traced(trace).replace('name="lo"', 'name="sem-no-such-interface"')
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "sem_console.sim.sem_sim",
            "--domain",
            str(domain),
            "--state-file",
            str(tmp_path / "state.json"),
            *FAST,
        ],
        env={**os.environ, "CYCLONEDDS_URI": xml},
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2
    assert "sem-no-such-interface" in trace.read_text(errors="replace")
    assert "CYCLONEDDS_URI" in proc.stderr and "Traceback" not in proc.stderr + proc.stdout


@pytest.mark.parametrize(
    "peers, says",
    [
        ("192.0.2.300", "'192.0.2.300' is not an IPv4 address"),
        ("127.0.0.1,0.0.0.0", "'0.0.0.0' is the unspecified address"),
        ("127.0.0.1:0", "the port must be 1..65535"),
        ("::1", "'::1' is not an IPv4"),
    ],
)
def test_a_peer_cyclone_cannot_use_is_one_line(peers: str, says: str, domain: int, tmp_path: Path) -> None:
    """Cyclone aborted the process on such a peer (SIGABRT, a segfault on 0.0.0.0), with no line naming the setting."""
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "sem_console.sim.sem_sim",
            "--domain",
            str(domain),
            "--state-file",
            str(tmp_path / "state.json"),
            *FAST,
        ],
        env={**os.environ, "SEM_DDS_PEERS": peers},
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.splitlines() == [proc.stderr.strip()] and proc.stderr.startswith("sem-sim: SEM_DDS_PEERS: ")
    assert says in proc.stderr


def test_a_domain_with_another_process_s_participant_is_not_taken_for_free(domain: int, sim: Any) -> None:
    """The tests' (and e2e's) free-domain check sees another process's participant on our unicast loopback
    configuration: it binds only its own unicast discovery port (7410 + 250 d + 2 i), not the multicast one
    (7400 + 250 d). This process's own participants (earlier tests' in a pytest worker) do not take a domain."""
    from sem_console.dds.bus import Bus
    from support.domains import domain_free

    assert domain_free(domain)
    bus = Bus(domain)
    assert bus.domain_id == domain and domain_free(domain)  # our own
    sim()
    wait_until(lambda: not domain_free(domain), 60, "the simulator's participant seen")
