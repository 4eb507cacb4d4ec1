"""The Foxglove gateway's JSON channels as foxglove-sdk gets them: its real server in this process, read back through
foxglove-sdk's own MCAP sink (every message logged, as logged), no client process."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any, cast

import orjson
from mcap.reader import make_reader

from conftest import free_port
from sem_console.console.feed import Feed
from sem_console.core.messages import ProviderSummary, ReportEnvelope, provider_message, report_message
from sem_console.gateways.foxglove.gateway import FoxgloveGateway
from sem_console.gateways.foxglove.schemas import location_fix
from test_foxglove_messages import fix

ALPHA, BRAVO = "00000000-0000-0000-0000-00000000000a", "00000000-0000-0000-0000-00000000000b"


def provider(pid: str, name: str | None) -> ProviderSummary:
    return cast(ProviderSummary, {"id": pid, "name": name})


def test_a_turn_s_json_messages_go_out_together_each_as_it_was_encoded_alone(tmp_path: Path) -> None:
    """The reports of one turn of the loop reach foxglove-sdk at its end, all of them, in order, each with its time
    and, byte for byte, the JSON a client was sent for it alone: the vehicle, then the envelope the dashboard gets."""
    path = tmp_path / "out.mcap"
    ins: ReportEnvelope = {"report": {"heading": 1.5, "missing": None}, "invalid": [], "receivedAt": 300.5}
    fixes = [
        (ALPHA, fix(36.85, -75.98)),
        (BRAVO, fix(36.9, -76.0, ["altitudeGeodetic: 1e9 is out of range"])),
        (ALPHA, fix(1.0, 2.0)),
    ]

    async def scenario() -> int:
        import foxglove

        feed = Feed()
        gateway = FoxgloveGateway(feed, free_port())
        await gateway.start()
        assert gateway.context is not None, gateway.stats.last_error
        writer = foxglove.open_mcap(path, context=gateway.context)
        try:
            feed.publish(provider_message("new", provider(ALPHA, "Alpha")))
            feed.publish(provider_message("new", provider(BRAVO, None)))
            for pid, envelope in fixes:
                feed.publish(report_message(pid, "GPSFixReport", envelope))
            feed.publish(report_message(BRAVO, "InertialSensorReport", ins))
            during = gateway.stats.messages_out
            await asyncio.sleep(0)  # the end of the turn
            assert gateway.stats.messages_out == 7, "each report and each fix's LocationFix, once"
            return during
        finally:
            writer.close()
            await gateway.stop()

    assert asyncio.run(scenario()) == 0, "nothing handed to foxglove-sdk before the turn ended"
    got: dict[str, list[tuple[int, bytes]]] = {}
    with path.open("rb") as f:
        for _schema, channel, message in make_reader(f).iter_messages(log_time_order=False):
            got.setdefault(channel.topic, []).append((message.log_time, message.data))

    def sent(pid: str, name: str | None, envelope: ReportEnvelope) -> tuple[int, bytes]:
        body: dict[str, Any] = {"providerId": pid, "vehicle": name, **envelope}
        return round(envelope["receivedAt"] * 1e9), orjson.dumps(body)

    names = {ALPHA: "Alpha", BRAVO: None}
    assert got["/reports/GPSFixReport"] == [sent(pid, names[pid], e) for pid, e in fixes]
    assert got["/reports/InertialSensorReport"] == [sent(BRAVO, None, ins)]
    for pid, frame in ((ALPHA, "Alpha"), (BRAVO, BRAVO)):
        mine = [e for p, e in fixes if p == pid]
        expected = [(round(e["receivedAt"] * 1e9), orjson.dumps(location_fix(e, frame))) for e in mine]
        assert got[f"/vehicles/{pid}/location"] == expected
