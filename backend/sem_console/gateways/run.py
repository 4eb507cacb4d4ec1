"""Starts and stops the gateways the settings ask for, and tells WebSocket clients how they fare."""

from __future__ import annotations

import asyncio
import contextlib
import time
from collections.abc import Callable
from typing import Any

from sem_console.console.feed import Feed
from sem_console.core.config import Settings
from sem_console.core.messages import GatewayState, ServerMessage, gateways_message
from sem_console.gateways.aspn.gateway import AspnGateway
from sem_console.gateways.foxglove.gateway import FoxgloveGateway, Playback
from sem_console.gateways.jaus.gateway import JausGateway

STATE_PERIOD = 1.0  # seconds between `gateways` WebSocket messages (sent only when something changed)


class Gateways:
    def __init__(
        self,
        settings: Settings,
        feed: Feed,
        now: Callable[[], float] = time.time,
        world: Callable[[], dict[str, Any]] | None = None,
        replay: tuple[tuple[int, int], Callable[[], Playback | None]] | None = None,
    ) -> None:
        """`now`: the console's clock (UTC seconds), the recording's time in a replay; `world`: CoMap's world model
        now; `replay`: a replay's span (first and last log times, ns) and the console's replay, once it runs."""
        self.aspn = AspnGateway(feed, settings.aspn_lcm, settings.aspn_prefix, settings.aspn_log_seconds)
        self.jaus = JausGateway(feed, settings.jaus_port, settings.jaus_subsystem, settings.jaus_host or settings.host)
        self.foxglove = FoxgloveGateway(feed, settings.foxglove_port, settings.foxglove_host, now, world, replay)
        self._task: asyncio.Task[None] | None = None

    def states(self) -> list[GatewayState]:
        return [self.aspn.state(), self.jaus.state(), self.foxglove.state()]

    async def start(self, publish: Callable[[ServerMessage], None]) -> None:
        await self.jaus.start()
        await self.foxglove.start()
        if self.aspn.enabled or self.jaus.stats.enabled or self.foxglove.stats.enabled:
            self._task = asyncio.get_running_loop().create_task(self._report(publish))

    async def _report(self, publish: Callable[[ServerMessage], None]) -> None:
        last: list[GatewayState] | None = None
        while True:
            await asyncio.sleep(STATE_PERIOD)
            states = self.states()
            if states != last:
                publish(gateways_message(states))
                last = states

    async def stop(self) -> None:
        if self._task:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
        self.aspn.close()
        self.jaus.close()
        await self.foxglove.stop()
