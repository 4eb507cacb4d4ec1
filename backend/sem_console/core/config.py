"""One settings object for the whole process; every value can come from SEM_* environment variables."""

from __future__ import annotations

from pydantic_settings import BaseSettings, SettingsConfigDict


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="SEM_", extra="ignore")

    # DDS domain id (0..232: Cyclone's default port mapping).
    domain: int = 0
    # Network interface Cyclone binds to when CYCLONEDDS_URI is not set.
    dds_interface: str = "lo"
    # Unicast discovery peers when CYCLONEDDS_URI is not set (comma separated).
    dds_peers: str = "127.0.0.1"


def get_settings() -> Settings:
    return Settings()
