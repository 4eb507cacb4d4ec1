"""One settings object for the whole process; every value can come from SEM_* environment variables."""

from __future__ import annotations

from pathlib import Path

from pydantic import Field
from pydantic_settings import BaseSettings, SettingsConfigDict


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SEM_", extra="ignore")

    # DDS
    domain: int = Field(0, ge=0, le=232, description="DDS domain id (Cyclone's default port mapping allows 0..232)")
    dds_interface: str = Field("lo", description="network interface Cyclone binds to when CYCLONEDDS_URI is not set")
    dds_peers: str = Field("127.0.0.1", description="unicast discovery peers when CYCLONEDDS_URI is not set, comma separated")

    # HTTP
    host: str = "127.0.0.1"
    port: int = Field(8000, ge=0, le=65535)
    sim: int = Field(0, ge=0, le=100, description="simulated vehicles to run inside the console on the same domain")
    sim_time_scale: float = Field(1.0, gt=0, le=100)
    sim_first_vehicle: int = Field(1, ge=1, le=9_500, description="number of the embedded simulator's first vehicle")
    frontend_dir: Path | None = Field(None, description="built dashboard to serve at / (default: frontend/dist if it exists)")

    # UMAA consumer and link health
    db_path: Path = Field(Path("var/sem-console.sqlite3"), description="SQLite command history and the console's GUID")
    comms_lost_timeout: float = Field(3.0, gt=0, description="seconds without a sample before a provider is lost")
    regained_time: float = Field(3.0, ge=0, description="seconds of continuous samples before a lost provider is regained")
    unanswered_timeout: float = Field(5.0, gt=0, description="seconds without ISSUED before a command is unanswered")
    report_interval: float = Field(0.005, ge=0, le=10, description="at most one take of report topics per this many seconds (conflation window)")
    ws_max_queue: int = Field(10_000, ge=10, description="ordered messages a WebSocket client may fall behind (while it sends nothing for ws_stall_seconds) before it is dropped")
    ws_stall_seconds: float = Field(5.0, ge=0, description="seconds without a completed send that make a client over ws_max_queue stalled")

    # Operators: "name:token,name2:token2" (a bare token is operator "operator"). Empty: no sign-in.
    operator_tokens: str = ""

    def operators(self) -> dict[str, str]:
        """token -> operator name."""
        out = {}
        for item in filter(None, (x.strip() for x in self.operator_tokens.split(","))):
            name, _, token = item.rpartition(":")
            out[token] = name or "operator"
        return out
