"""The Foxglove gateway: the console's feed served, read-only, over the Foxglove WebSocket protocol by foxglove-sdk.

Channels: JSON, each with its JSON Schema: a `foxglove.LocationFix` per vehicle (`/vehicles/<id>/location`), the
fleet's `foxglove.LocationFixes` once a second (`/fleet/locations`), a `foxglove.Log` of alarms and command transitions
(`/console/log`), CoMap's world model as `foxglove.GeoJSON` once a second (`/comap/world`), and each report topic's
decoded reports as the dashboard gets them (`/reports/<topic>`); and raw, each SEM topic of either UMAA version by its
DDS name, every sample's CDR as it came off the wire (`cdr`), with the `omgidl` schema the recorder writes
(`recording/schema.py`); an appendable writer's samples (delimited XCDR2) on a topic of their own, `<DDS name>/appendable`.
The raw samples come from the feed's tap, on the ingest threads (a replay's, on its reading thread, as they are played).

Nothing is encoded for a channel no client subscribes to (foxglove-sdk's `has_sinks`): such a message is only counted
(`left out: no subscriber`; a raw take is not counted). The JSON messages of one turn of the event loop are handed to
foxglove-sdk together at its end (`_flush`): its sending thread is then woken once for them all, not once each.
The server offers no capability but, in a replay, playback control: a client's publish, service call or parameter
request is refused by foxglove-sdk itself, so nothing a Foxglove client sends reaches the console. Playback control
(play, pause, seek, speed) drives the console's own replay, the one the dashboard's controls drive, and the replay's
position goes back to every client as Foxglove's playback state, whoever moved it.
"""

from __future__ import annotations

import asyncio
import contextlib
import threading
import time
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any, Protocol, cast

import orjson

from sem_console.console.feed import Feed
from sem_console.core.messages import Alarm, GatewayState, ReplayStatus, ReportEnvelope, TransitionMessage
from sem_console.dds.topics import AnySem, delimited
from sem_console.gateways import Stats, log
from sem_console.gateways.foxglove import schemas
from sem_console.recording.recorder import SEM_TOPICS  # a raw channel each, as in a recording
from sem_console.recording.schema import MESSAGE_ENCODING, SCHEMA_ENCODING, topic_idl, type_name, version_of

if TYPE_CHECKING:  # foxglove-sdk (its native library) is loaded only by a gateway that runs
    import foxglove
    from foxglove.websocket import PlaybackControlRequest, ServerListener, WebSocketServer

FLEET_PERIOD = 1.0  # seconds between two LocationFixes of the fleet
FLEET_TOPIC = "/fleet/locations"
LOG_TOPIC = "/console/log"
WORLD_TOPIC = "/comap/world"
STOP_SECONDS = 3.0  # the longest the console's shutdown waits for foxglove-sdk's server to stop
PLAYBACK_PERIOD = 0.2  # seconds between two looks at the replay's position (sent to clients when it moved)
APPENDABLE = "appendable"
# after the DDS name, the topic of an appendable writer's raw channel: Foxglove's and Lichtblick's players take one
# channel per topic (a second channel of a topic is an error there, and none of its messages is shown)
APPENDABLE_TOPIC = "/appendable"


class Playback(Protocol):
    """The console's replay (`console.replay_source.Replay`): what Foxglove's playback control drives."""

    start: float
    end: float
    seeks: int  # seeks done, whoever asked

    def status(self) -> ReplayStatus: ...
    async def play(self) -> None: ...
    def pause(self) -> None: ...
    def set_speed(self, speed: float) -> None: ...
    async def seek(self, position: float) -> None: ...


def vehicle_topic(provider_id: str) -> str:
    return f"/vehicles/{provider_id}/location"


def report_topic(topic: str) -> str:
    return f"/reports/{topic}"


class FoxgloveGateway:
    def __init__(
        self,
        feed: Feed,
        port: int,
        host: str = "127.0.0.1",
        now: Callable[[], float] = time.time,
        world: Callable[[], dict[str, Any]] | None = None,
        replay: tuple[tuple[int, int], Callable[[], Playback | None]] | None = None,
    ) -> None:
        """`now`: the console's clock (UTC seconds), the recording's time in a replay. `world`: CoMap's world model now
        (a GeoJSON FeatureCollection). `replay`: the recording's first and last log times (ns) and the console's
        replay (None until the console started it), for playback control."""
        self.port, self.host, self.now, self.world, self.replay = port, host, now, world, replay
        self.stats = Stats("foxglove", port != 0)
        self.context: foxglove.Context | None = None  # this gateway's channels only (not foxglove-sdk's global ones)
        self.server: WebSocketServer | None = None
        self.channels: dict[str, foxglove.Channel] = {}
        self.fixes: dict[str, ReportEnvelope] = {}  # provider id -> its latest GPSFixReport
        self.names: dict[str, str | None] = {}  # provider id -> its name in the console
        self.alarms: dict[int, Alarm] = {}  # the active alarms, by id
        self.raw: dict[Any, foxglove.Channel] = {}  # SEM topic (and (topic, APPENDABLE)) -> its raw channel
        self._raw_lock = threading.Lock()  # the ingest threads open an appendable writer's channel at its first sample
        self._tasks: list[asyncio.Task[None]] = []
        self._requests: set[asyncio.Task[None]] = set()  # playback control requests being carried out
        self._pending: list[tuple[foxglove.Channel, bytes, int]] = []  # this turn's JSON messages (`_flush`)
        self._loop: asyncio.AbstractEventLoop | None = None
        self._shown: tuple[Any, ...] | None = None  # the playback state clients were last sent
        self._seeks = 0  # the replay's seeks clients were told of
        self._unsubscribe = feed.subscribe("foxglove", self.on_message) if port else None
        self._untap = feed.tap("foxglove", self) if port else None

    @property
    def active(self) -> bool:
        """Whether the raw samples are wanted (the feed's tap): the server runs."""
        return self.server is not None

    async def start(self) -> None:
        if not self.port:
            return
        import foxglove

        self.stats.endpoint = f"ws://{self._where(self.port)}"
        self.context = foxglove.Context()
        self._loop = asyncio.get_running_loop()
        for sem in SEM_TOPICS:
            self.raw[sem] = self._raw_channel(sem, "final")
        try:  # sem-console checked the port at start (cli.py); it can still be taken since
            server = await asyncio.to_thread(
                foxglove.start_server,
                name="sem-console",
                host=self.host,
                port=self.port,
                # read-only: no client publish, services, parameters; a replay's playback control only
                capabilities=[],
                server_listener=listener(self) if self.replay else None,
                playback_time_range=self.replay[0] if self.replay else None,
                context=self.context,
            )
        except Exception as e:  # shown as the gateway's last error; the console runs on without it
            self.stats.error(f"cannot listen on TCP {self._where(self.port)}: {e}")
            return
        self.server = server
        self.stats.endpoint = f"ws://{self._where(server.port)}"
        self._channel(LOG_TOPIC, "foxglove.Log", schemas.LOG)
        self._channel(FLEET_TOPIC, "foxglove.LocationFixes", schemas.LOCATION_FIXES)
        if self.world is not None:
            self._channel(WORLD_TOPIC, "foxglove.GeoJSON", schemas.GEOJSON)
        self._tasks.append(self._loop.create_task(self._fleet()))
        if self.replay is not None:
            self._tasks.append(self._loop.create_task(self._playback()))

    def _where(self, port: int) -> str:
        return f"[{self.host}]:{port}" if ":" in self.host else f"{self.host}:{port}"

    async def stop(self) -> None:
        if self._unsubscribe:
            self._unsubscribe()
        if self._untap:
            self._untap()
        for task in [*self._tasks, *self._requests]:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
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

    def _raw_channel(self, sem: AnySem, extensibility: str) -> foxglove.Channel:
        """A SEM topic's raw channel: its DDS name, its type's OMG IDL as the recorder writes it, CDR messages."""
        import foxglove

        idl = topic_idl(sem, extensibility="appendable" if extensibility == APPENDABLE else "final")
        schema = foxglove.Schema(name=type_name(sem.spec.type), encoding=SCHEMA_ENCODING, data=idl.encode())
        metadata = {"umaaVersion": version_of(sem)} | ({"extensibility": APPENDABLE} if extensibility == APPENDABLE else {})
        topic = sem.spec.name + (APPENDABLE_TOPIC if extensibility == APPENDABLE else "")
        return foxglove.Channel(topic, schema=schema, message_encoding=MESSAGE_ENCODING, context=self.context, metadata=metadata)

    def on_samples(self, sem: AnySem, samples: list[tuple[bytes, bool, int, int]], received_ns: int) -> None:
        """One take of a topic (the feed's tap, on an ingest thread): each valid sample's CDR to the topic's raw
        channel, if a client subscribes to it; an appendable writer's to its own channel."""
        final = self.raw.get(sem)
        if final is None:
            return
        sent = 0
        for data, valid, _state, _source_ns in samples:
            if not valid:
                continue
            ch = self._appendable(sem) if sem.spec.appendable is not None and delimited(data) else final
            if ch.has_sinks():
                ch.log(data, log_time=received_ns)
                sent += 1
        if sent:
            self.stats.sent(sent)

    def _appendable(self, sem: AnySem) -> foxglove.Channel:
        key = (sem, APPENDABLE)
        ch = self.raw.get(key)
        if ch is None:
            with self._raw_lock:
                ch = self.raw.get(key)
                if ch is None:
                    ch = self.raw[key] = self._raw_channel(sem, APPENDABLE)
        return ch

    def _log(self, ch: foxglove.Channel, message: Any, at: float) -> None:
        """Encode and send `message` if a client subscribes to `ch`; else only count it."""
        if not ch.has_sinks():
            self.stats.count("left out: no subscriber")
            return
        self._send(ch, orjson.dumps(message), at)

    def _send(self, ch: foxglove.Channel, data: bytes, at: float) -> None:
        """`data` to `ch` at the end of this turn of the loop (`_flush`), with its time."""
        if not self._pending:
            assert self._loop is not None  # the server runs
            self._loop.call_soon(self._flush)
        self._pending.append((ch, data, max(0, round(at * 1e9))))

    def _flush(self) -> None:
        """This turn's JSON messages to foxglove-sdk, in their order, one after the other."""
        pending, self._pending = self._pending, []
        for ch, data, log_time in pending:
            ch.log(data, log_time=log_time)
        self.stats.sent(len(pending))

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
            self._send(ch, orjson.dumps({"providerId": provider_id, "vehicle": self.names.get(provider_id), **envelope}), at)
        else:
            self.stats.count("left out: no subscriber")
        if topic == "GPSFixReport":
            self.fixes[provider_id] = envelope
            fix_channel = self._channel(vehicle_topic(provider_id), "foxglove.LocationFix", schemas.LOCATION_FIX)
            if not fix_channel.has_sinks():
                self.stats.count("left out: no subscriber")
            elif (fix := schemas.location_fix(envelope, self._vehicle(provider_id))) is not None:
                self._send(fix_channel, orjson.dumps(fix), at)
            else:
                self.stats.count("left out: no valid position")

    async def _fleet(self) -> None:
        """The fleet's LocationFixes and CoMap's world model, once a second (a client that subscribes gets them at
        once, whenever they last changed)."""
        ch, world = self.channels[FLEET_TOPIC], self.channels.get(WORLD_TOPIC)
        while True:
            await asyncio.sleep(FLEET_PERIOD)
            if not ch.has_sinks():
                self.stats.count("left out: no subscriber")
            else:
                fixes = [f for pid, e in self.fixes.items() if (f := schemas.location_fix(e, self._vehicle(pid))) is not None]
                self._log(ch, {"fixes": fixes}, self.now())
            if world is not None and self.world is not None:
                if not world.has_sinks():
                    self.stats.count("left out: no subscriber")
                else:
                    self._log(world, schemas.geojson(self.world()), self.now())

    # ---- playback control (a replay) --------------------------------------------------------
    def on_playback_request(self, request: PlaybackControlRequest) -> None:
        """A client's playback control request (on one of foxglove-sdk's threads): carried out on the loop."""
        if self._loop is not None:
            self._loop.call_soon_threadsafe(self._carry_out, request)

    def _carry_out(self, request: PlaybackControlRequest) -> None:
        task = asyncio.get_running_loop().create_task(self._control(request))
        self._requests.add(task)
        task.add_done_callback(self._requests.discard)

    async def _control(self, request: PlaybackControlRequest) -> None:
        from foxglove.websocket import PlaybackCommand

        replay = self.replay[1]() if self.replay else None
        if replay is None or self.server is None:
            return
        try:
            from sem_console.console.replay_source import MAX_SPEED, MIN_SPEED

            replay.set_speed(min(MAX_SPEED, max(MIN_SPEED, request.playback_speed)))
            if request.seek_time is not None:
                await replay.seek(min(replay.end, max(replay.start, request.seek_time / 1e9)))
            if request.playback_command == PlaybackCommand.Play:
                await replay.play()
            else:
                replay.pause()
        except Exception as e:  # shown as the gateway's last error; the replay goes on
            self.stats.error(f"playback control: {e}")
        self._show(replay, request.request_id)

    async def _playback(self) -> None:
        """The replay's position to every client whenever it moved, whoever moved it (Foxglove, the dashboard)."""
        while True:
            await asyncio.sleep(PLAYBACK_PERIOD)
            replay = self.replay[1]() if self.replay else None
            if replay is not None:
                self._show(replay, None)

    def _show(self, replay: Playback, request_id: str | None) -> None:
        """The replay's state to every client if it changed, or in answer to a request; `did_seek` when the replay
        sought since the last one sent, whoever asked (Foxglove, the dashboard, REST), as the protocol asks."""
        from foxglove.websocket import PlaybackState, PlaybackStatus

        if self.server is None:
            return
        status, did_seek = replay.status(), replay.seeks != self._seeks
        self._seeks = replay.seeks
        if status["state"] == "playing":
            state = PlaybackStatus.Playing
        else:
            state = PlaybackStatus.Ended if status["position"] >= status["end"] else PlaybackStatus.Paused
        shown = (state, status["position"], status["speed"])
        if shown == self._shown and not did_seek and request_id is None:
            return
        self._shown = shown
        self.server.broadcast_playback_state(
            PlaybackState(
                status=state,
                current_time=max(0, round(status["position"] * 1e9)),
                playback_speed=status["speed"],
                did_seek=did_seek,
                request_id=request_id,
            )
        )


def listener(gateway: FoxgloveGateway) -> ServerListener:
    """foxglove-sdk's ServerListener: only playback control requests (the server refuses every other request itself)."""
    from foxglove.websocket import ServerListener

    class Listener(ServerListener):
        def on_playback_control_request(self, playback_control_request: PlaybackControlRequest) -> None:
            """Carried out on the console's loop; its outcome goes to every client as the playback state (`_show`)."""
            gateway.on_playback_request(playback_control_request)

    return Listener()
