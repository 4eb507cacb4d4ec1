"""A client of the Foxglove WebSocket protocol, written from its specification (foxglove/ws-protocol), not from the
console's code: the subprotocol `foxglove.sdk.v1` foxglove-sdk speaks (0.30 accepts only it), with the framing of
`foxglove.websocket.v1`. The tests of the console's Foxglove gateway and the benchmarks (bench/foxglove_peer.py) use it.
"""

from __future__ import annotations

import json
import struct
from collections.abc import AsyncIterator, Sequence
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from typing import Any

import websockets

SUBPROTOCOLS = ["foxglove.sdk.v1", "foxglove.websocket.v1"]  # foxglove-sdk 0.30 accepts only the first
MESSAGE_DATA = 0x01  # server binary opcode: u8 op, u32 subscription id, u64 log time (ns), payload
PLAYBACK_STATE = 0x05  # server binary opcode: u8 op, u8 status, u64 time (ns), f32 speed, u8 did seek, u32 id length, id
PLAYBACK_CONTROL_REQUEST = 0x03  # client binary opcode: u8 op, u8 command, f32 speed, u8 seek?, u64 seek time, u32, id
PLAY, PAUSE = 0, 1  # a playback control request's command
PLAYING, PAUSED, BUFFERING, ENDED = 0, 1, 2, 3  # a playback state's status
CLIENT_MESSAGE_DATA = 0x01  # client binary opcode: u8 op, u32 client channel id, payload
SERVICE_CALL_REQUEST = 0x02  # client binary opcode: u8 op, u32 service id, u32 call id, u32 encoding length, encoding, payload


@dataclass
class Message:
    topic: str
    log_time: int  # nanoseconds
    data: bytes

    def json(self) -> Any:
        return json.loads(self.data)


@dataclass
class PlaybackState:
    status: int
    time: int  # nanoseconds
    speed: float
    did_seek: bool
    request_id: str


@dataclass
class FoxgloveClient:
    ws: Any
    server_info: dict[str, Any] = field(default_factory=dict)
    channels: dict[int, dict[str, Any]] = field(default_factory=dict)  # channel id -> its advertisement
    statuses: list[dict[str, Any]] = field(default_factory=list)  # every text message that is not advertise/serverInfo
    topic_of: dict[int, str] = field(default_factory=dict)  # subscription id -> topic
    playback: list[PlaybackState] = field(default_factory=list)  # every playback state the server sent
    subscribed: dict[int, int] = field(default_factory=dict)  # channel id -> subscription id
    _next_subscription: int = 1

    def topics(self) -> dict[str, dict[str, Any]]:
        return {c["topic"]: c for c in self.channels.values()}

    def _text(self, msg: dict[str, Any]) -> None:
        op = msg.get("op")
        if op == "serverInfo":
            self.server_info = msg
        elif op == "advertise":
            self.channels.update({c["id"]: c for c in msg["channels"]})
        elif op == "unadvertise":
            for i in msg["channelIds"]:
                self.channels.pop(i, None)
        else:
            self.statuses.append(msg)

    async def subscribe(self, topics: Sequence[str]) -> None:
        """Subscribe to the channels of these topics (advertised already)."""
        by_topic = self.topics()
        await self.subscribe_channels({by_topic[t]["id"]: t for t in topics})

    async def subscribe_channels(self, channels: dict[int, str]) -> None:
        """Subscribe to these channels (advertised already), each message of one named as given."""
        subs = []
        for channel, name in channels.items():
            subs.append({"id": self._next_subscription, "channelId": channel})
            self.topic_of[self._next_subscription] = name
            self.subscribed[channel] = self._next_subscription
            self._next_subscription += 1
        await self.ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))

    async def _subscribe_again(self, status: dict[str, Any]) -> None:
        """foxglove-sdk 0.30 can refuse a subscription sent just after the channel's advertisement, as a status
        "Unknown channel ID: N" (1 in 50 in a script of its own): a channel this client subscribed to is asked again."""
        message = str(status.get("message", ""))
        if not message.startswith("Unknown channel ID: "):
            return
        channel = int(message.removeprefix("Unknown channel ID: ").strip() or -1)
        if channel in self.subscribed and channel in self.channels:
            sub = {"id": self.subscribed[channel], "channelId": channel}
            await self.ws.send(json.dumps({"op": "subscribe", "subscriptions": [sub]}))

    async def send_json(self, msg: dict[str, Any]) -> None:
        await self.ws.send(json.dumps(msg))

    async def send_binary(self, data: bytes) -> None:
        await self.ws.send(data)

    async def publish(self, channel_id: int, payload: bytes) -> None:
        """A client's message on a channel it advertised (needs the server's clientPublish capability)."""
        await self.ws.send(struct.pack("<BI", CLIENT_MESSAGE_DATA, channel_id) + payload)

    async def call_service(self, service_id: int, call_id: int, encoding: str, payload: bytes) -> None:
        e = encoding.encode()
        await self.ws.send(struct.pack("<BIII", SERVICE_CALL_REQUEST, service_id, call_id, len(e)) + e + payload)

    async def playback_control(self, command: int, speed: float, seek_ns: int | None, request_id: str) -> None:
        """A playback control request (needs the server's playbackControl capability)."""
        rid = request_id.encode()
        head = struct.pack("<BBfBQI", PLAYBACK_CONTROL_REQUEST, command, speed, seek_ns is not None, seek_ns or 0, len(rid))
        await self.ws.send(head + rid)

    async def messages(self) -> AsyncIterator[Message | None]:
        """Every message of the subscribed channels as it comes; None for each text message (applied here first)."""
        async for data in self.ws:
            if isinstance(data, str):
                msg = json.loads(data)
                self._text(msg)
                if msg.get("op") == "status":
                    await self._subscribe_again(msg)
                yield None
            elif data and data[0] == MESSAGE_DATA:
                sub, log_time = struct.unpack_from("<IQ", data, 1)
                yield Message(self.topic_of.get(sub, "?"), log_time, bytes(data[13:]))
            elif data and data[0] == PLAYBACK_STATE:
                status, at, speed, did_seek, n = struct.unpack_from("<BQfBI", data, 1)
                self.playback.append(PlaybackState(status, at, speed, bool(did_seek), bytes(data[19 : 19 + n]).decode()))
                yield None


@asynccontextmanager
async def connect(url: str) -> AsyncIterator[FoxgloveClient]:
    async with websockets.connect(url, subprotocols=SUBPROTOCOLS, max_size=2**26) as ws:  # type: ignore[arg-type]
        yield FoxgloveClient(ws)
