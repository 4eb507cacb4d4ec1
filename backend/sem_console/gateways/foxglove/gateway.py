"""The Foxglove gateway: the console's feed served, read-only, over the Foxglove WebSocket protocol by foxglove-sdk.

Channels (JSON, each with its JSON Schema): a `foxglove.LocationFix` per vehicle (`/vehicles/<id>/location`), the
fleet's `foxglove.LocationFixes` once a second (`/fleet/locations`), a `foxglove.Log` of alarms and command transitions
(`/console/log`), and each report topic's decoded reports as the dashboard gets them (`/reports/<topic>`).

Nothing is encoded for a channel no client subscribes to (foxglove-sdk's `has_sinks`): such a message is only counted
(`left out: no subscriber`). The server offers no capability: a client's publish, service call or parameter request is
refused by foxglove-sdk itself, so nothing a Foxglove client sends reaches the console.
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
import time
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, cast

import orjson

from sem_console.console.feed import Feed
from sem_console.core.messages import Alarm, GatewayState, ReportEnvelope, TransitionMessage
from sem_console.gateways import Stats, log
from sem_console.gateways.foxglove import schemas

if TYPE_CHECKING:  # foxglove-sdk (its native library) is loaded only by a gateway that runs
    import foxglove
    from foxglove.websocket import WebSocketServer

FLEET_PERIOD = 1.0  # seconds between two LocationFixes of the fleet
FLEET_TOPIC = "/fleet/locations"
LOG_TOPIC = "/console/log"
STOP_SECONDS = 3.0  # the longest the console's shutdown waits for foxglove-sdk's server to stop


def vehicle_topic(provider_id: str) -> str:
    return f"/vehicles/{provider_id}/location"


def report_topic(topic: str) -> str:
    return f"/reports/{topic}"


class FoxgloveGateway:
    def __init__(self, feed: Feed, port: int, host: str = "127.0.0.1", now: Callable[[], float] = time.time) -> None:
        """`now`: the console's clock (UTC seconds), the recording's time in a replay."""
        self.port, self.host, self.now = port, host, now
        self.stats = Stats("foxglove", port != 0)
        self.context: foxglove.Context | None = None  # this gateway's channels only (not foxglove-sdk's global ones)
        self.server: WebSocketServer | None = None
        self.channels: dict[str, foxglove.Channel] = {}
        self.fixes: dict[str, ReportEnvelope] = {}  # provider id -> its latest GPSFixReport
        self.names: dict[str, str | None] = {}  # provider id -> its name in the console
        self.alarms: dict[int, Alarm] = {}  # the active alarms, by id
        self._task: asyncio.Task[None] | None = None
        self._unsubscribe = feed.subscribe("foxglove", self.on_message) if port else None

    async def start(self) -> None:
        if not self.port:
            return
        import foxglove

        self.stats.endpoint = f"ws://{self._where(self.port)}"
        self.context = foxglove.Context()
        try:  # sem-console checked the port at start (cli.py); it can still be taken since
            server = await asyncio.to_thread(
                foxglove.start_server,
                name="sem-console",
                host=self.host,
                port=self.port,
                capabilities=[],  # read-only: no client publish, services, parameters (nor playback control yet)
                context=self.context,
            )
        except Exception as e:  # shown as the gateway's last error; the console runs on without it
            self.stats.error(f"cannot listen on TCP {self._where(self.port)}: {e}")
            return
        self.server = server
        self.stats.endpoint = f"ws://{self._where(server.port)}"
        self._channel(LOG_TOPIC, "foxglove.Log", schemas.LOG)
        self._channel(FLEET_TOPIC, "foxglove.LocationFixes", schemas.LOCATION_FIXES)
        self._task = asyncio.get_running_loop().create_task(self._fleet())

    def _where(self, port: int) -> str:
        return f"[{self.host}]:{port}" if ":" in self.host else f"{self.host}:{port}"

    async def stop(self) -> None:
        if self._unsubscribe:
            self._unsubscribe()
        if self._task:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
        if self.server is not None:
            # foxglove-sdk's stop waits until every client took what was queued for it: a client that stopped reading
            # (asleep at the end of an SSH tunnel) would hold it, and the console's shutdown, for ever
            stopping = threading.Thread(target=self.server.stop, name="foxglove-stop", daemon=True)
            stopping.start()
            await asyncio.to_thread(stopping.join, STOP_SECONDS)
            if stopping.is_alive():
                log.warning("foxglove gateway: its server did not stop within %.0f s (a client stopped reading)", STOP_SECONDS)
            self.server = None

    def state(self) -> GatewayState:
        return self.stats.state()

    # ---- channels ------------------------------------------------------------------------
    def _channel(self, topic: str, schema_name: str, schema: dict[str, Any]) -> foxglove.Channel:
        ch = self.channels.get(topic)
        if ch is None:
            import foxglove

            described = foxglove.Schema(name=schema_name, encoding="jsonschema", data=orjson.dumps(schema))
            ch = foxglove.Channel(topic, schema=described, message_encoding="json", context=self.context)
            self.channels[topic] = ch
        return ch

    def _log(self, ch: foxglove.Channel, message: Any, at: float) -> None:
        """Encode and send `message` if a client subscribes to `ch`; else only count it."""
        if not ch.has_sinks():
            self.stats.count("left out: no subscriber")
            return
        ch.log(orjson.dumps(message), log_time=max(0, round(at * 1e9)))
        self.stats.sent()

    def _vehicle(self, provider_id: str) -> str:
        return self.names.get(provider_id) or provider_id

    # ---- the console's feed --------------------------------------------------------------
    def on_message(self, message: Mapping[str, Any]) -> None:
        if self.server is None:
            return
        kind = message.get("type")
        if kind == "report":
            self._report(message["providerId"], message["topic"], message["report"])
        elif kind == "provider":
            p = message["provider"]
            self.names[p["id"]] = p["name"]
            self._channel(vehicle_topic(p["id"]), "foxglove.LocationFix", schemas.LOCATION_FIX)
        elif kind == "transition":
            m = cast(TransitionMessage, message)
            entry = schemas.transition_log(m, self._vehicle(m["command"]["providerId"]))
            self._log(self.channels[LOG_TOPIC], entry, m["transition"]["receivedAt"])
        elif kind == "alarms":
            now = self.now()
            for entry in schemas.alarm_logs(self.alarms, message["alarms"], now):
                self._log(self.channels[LOG_TOPIC], entry, now)
            self.alarms = {a["id"]: a for a in message["alarms"]}

    def _report(self, provider_id: str, topic: str, envelope: ReportEnvelope) -> None:
        at = envelope["receivedAt"]
        ch = self.channels.get(report_topic(topic))
        if ch is None:
            type_name = f"{topic}Type"
            ch = self._channel(report_topic(topic), f"sem_console.{type_name}", schemas.report_schema(type_name))
        if ch.has_sinks():
            self._log(ch, {"providerId": provider_id, "vehicle": self.names.get(provider_id), **envelope}, at)
        else:
            self.stats.count("left out: no subscriber")
        if topic == "GPSFixReport":
            self.fixes[provider_id] = envelope
            fix_channel = self._channel(vehicle_topic(provider_id), "foxglove.LocationFix", schemas.LOCATION_FIX)
            if not fix_channel.has_sinks():
                self.stats.count("left out: no subscriber")
            elif (fix := schemas.location_fix(envelope, self._vehicle(provider_id))) is not None:
                self._log(fix_channel, fix, at)
            else:
                self.stats.count("left out: no valid position")

    async def _fleet(self) -> None:
        ch = self.channels[FLEET_TOPIC]
        while True:
            await asyncio.sleep(FLEET_PERIOD)
            if not ch.has_sinks():
                self.stats.count("left out: no subscriber")
                continue
            fixes = [f for pid, e in self.fixes.items() if (f := schemas.location_fix(e, self._vehicle(pid))) is not None]
            self._log(ch, {"fixes": fixes}, self.now())
