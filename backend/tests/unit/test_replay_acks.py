"""A replay's alarm acknowledgements (`sem-console/alarm-acks`) against the alarms it derives again: a real console
replaying a file written as the recorder writes one, sought to its end (no DDS, no processes)."""

from __future__ import annotations

import asyncio
import json
import uuid
from pathlib import Path
from typing import Any

from cyclonedds.core import InstanceState

from sem_console.console.replay_source import TICK
from sem_console.console.service import Console
from sem_console.core.config import Settings
from sem_console.dds.topics import Sem
from sem_console.recording.reader import ALARM_ACKS, INSTANCES
from sem_console.recording.recorder import _File, _instance_event
from test_relay_link import fix_status

VEHICLE = uuid.UUID(int=1)  # fix_status's
START = 1_800_000_000.0  # the recording's first message, UTC seconds


def ns(at: float) -> int:
    """`at` seconds after the recording's start, as a log time."""
    return round((START + at) * 1e9)


def replayed(path: Path, comms_lost_timeout: float) -> tuple[list[Any], str]:
    """The active alarms of a console replaying `path`, sought to its end, and the vehicle's link there."""

    async def run() -> tuple[list[Any], str]:
        console = Console(Settings(replay=path, comms_lost_timeout=comms_lost_timeout))
        await console.start()
        try:
            replay = console.playback()
            assert replay is not None
            replay.pause()
            await replay.seek(replay.end)
            return list(console.active_alarms()), console.providers.by_id[VEHICLE].link
        finally:
            await console.stop()

    return asyncio.run(run())


def replayed_alarms(path: Path, comms_lost_timeout: float) -> list[Any]:
    """The active alarms of a console replaying `path`, sought to its end."""
    return replayed(path, comms_lost_timeout)[0]


def test_an_ack_recorded_before_the_replays_tick_finds_the_vehicle_lost_acknowledges_its_alarm(tmp_path: Path) -> None:
    """The vehicle is last heard 0.3 s into the recording and lost after 1 s of silence. Live, the console's ticker (of
    its own phase) found it lost at 1.32 s and bob acknowledged the alarm on another station, which the recording
    console learned at 1.35 s. The replay ticks every TICK from the recording's start: at 1.2 s, silent for 0.9 s, then
    at 1.4 s. It showed the alarm never acknowledged: the acknowledgement came before the alarm, and matched nothing."""
    assert TICK == 0.2  # the grid of ticks this recording's instants fall between
    sample = fix_status(True, 40.0).data
    path = tmp_path / "run.mcap"
    f = _File(path, "relief")
    for at in (0.0, 0.1, 0.2, 0.3):
        f.add_samples(Sem.GPS_FIX_STATUS_REPORT, [(sample, True, int(InstanceState.Alive), 0)], ns(at))
    ack = {
        "type": "alarm-ack",
        "key": f"link-lost|{VEHICLE}||",
        "kind": "link-lost",
        "providerId": str(VEHICLE),
        "sessionId": None,
        "ackedAt": START + 1.34,
        "ackedBy": "bob",
        "station": "watch",
    }
    f.add(ALARM_ACKS, json.dumps(ack).encode(), ns(1.35), ns(1.35))
    # its writers' lease ran out later: the recording goes on past the replay's tick at 1.4 s
    gone = _instance_event(Sem.GPS_FIX_STATUS_REPORT, sample, True, int(InstanceState.NotAliveNoWriters))
    f.add(INSTANCES, json.dumps(gone).encode(), ns(2.0), ns(2.0))
    f.close()

    (lost,) = (a for a in replayed_alarms(path, 1.0) if a["kind"] == "link-lost" and a["providerId"] == str(VEHICLE))
    assert (lost["state"], lost["ackedAt"], lost["ackedBy"]) == ("active-acknowledged", START + 1.34, "bob")


def test_a_vehicle_disposed_in_the_last_tick_of_a_recording_is_lost_at_its_end(tmp_path: Path) -> None:
    """Live, the vehicle disposed its reports at 1.25 s and the console's ticker (of its own phase) found it lost at
    1.3 s; the recording stopped at 1.35 s. The replay's grid of ticks (1.2, then 1.4: past the end) showed it live at
    the end, where the live console had it lost."""
    sample = fix_status(True, 40.0).data
    path = tmp_path / "run.mcap"
    f = _File(path, "relief")
    for at in (0.0, 0.1, 0.2, 0.3):
        f.add_samples(Sem.GPS_FIX_STATUS_REPORT, [(sample, True, int(InstanceState.Alive), 0)], ns(at))
    disposed = _instance_event(Sem.GPS_FIX_STATUS_REPORT, sample, True, int(InstanceState.NotAliveDisposed))
    f.add(INSTANCES, json.dumps(disposed).encode(), ns(1.25), ns(1.25))
    f.add(INSTANCES, json.dumps(disposed).encode(), ns(1.35), ns(1.35))  # the file's last message
    f.close()

    # a long silence timeout: only the disposes can say it is lost
    alarms, link = replayed(path, 10.0)
    assert link == "lost"
    assert [a["kind"] for a in alarms if a["providerId"] == str(VEHICLE)] == ["link-lost"]
