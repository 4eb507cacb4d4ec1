"""The provider's journal: the last status of each command it answered, in a small JSON file.

Status and ack samples live in the provider's own transient-local writers, so they die with
the process; this file is what lets a restarted provider tell a command it never saw (start
it) from one it was running (resume or fail it) or had finished (leave it for the consumer's
cleanup). Entries go when a command is cleaned up.

One process owns a journal at a time: it holds an exclusive lock on `<file>.lock` (released by
the kernel when the process ends, however it ends), so a second simulator never writes over
the first one's file.
"""

from __future__ import annotations

import fcntl
import json
import logging
import os
import uuid
from pathlib import Path

from UMAA.Common.MaritimeEnumeration.CommandStatusEnumType import CommandStatusEnumType as Status

from sem_console.dds.topics import Service

log = logging.getLogger("sem-sim")


class InUse(Exception):
    """Another process already is this provider (its vehicles are on the bus, or its journal is locked).

    `free`: the first vehicle number after every simulated vehicle seen on the bus, when that is the conflict.
    """

    def __init__(self, message: str, free: int | None = None) -> None:
        super().__init__(message)
        self.free = free


def default_state_file(domain: int, first_vehicle: int = 1) -> Path:
    base = Path(os.environ.get("XDG_STATE_HOME") or Path.home() / ".local" / "state")
    name = f"domain-{domain}.json" if first_vehicle == 1 else f"domain-{domain}-from-{first_vehicle}.json"
    return base / "sem-sim" / name


class Journal:
    def __init__(self, path: Path) -> None:
        self.path = path
        self._lock = self._take_lock(path)
        try:
            self.entries: dict[str, str] = json.loads(path.read_text())
        except (OSError, ValueError):
            self.entries = {}

    @staticmethod
    def _take_lock(path: Path) -> int | None:
        lock = path.with_name(path.name + ".lock")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as e:  # a read-only disk must not stop the vehicle (nor can anyone else write there)
            log.warning("cannot lock %s: %s", lock, e)
            return None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            owner = os.pread(fd, 32, 0).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise InUse(
                f"state file {path} is in use by another simulator (pid {owner}); give this one its own --state-file"
            ) from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, str(os.getpid()).encode(), 0)
        return fd

    def close(self) -> None:
        if self._lock is not None:
            os.close(self._lock)  # releases the lock
            self._lock = None

    @staticmethod
    def _key(vehicle: uuid.UUID, service: Service, session: uuid.UUID) -> str:
        return f"{vehicle}/{service.value}/{session}"

    def get(self, vehicle: uuid.UUID, service: Service, session: uuid.UUID) -> Status | None:
        name = self.entries.get(self._key(vehicle, service, session))
        return Status[name] if name is not None and name in Status.__members__ else None

    def set(self, vehicle: uuid.UUID, service: Service, session: uuid.UUID, status: Status) -> None:
        self.entries[self._key(vehicle, service, session)] = status.name
        self._save()

    def drop(self, vehicle: uuid.UUID, service: Service, session: uuid.UUID) -> None:
        if self.entries.pop(self._key(vehicle, service, session), None) is not None:
            self._save()

    def _save(self) -> None:
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            tmp = self.path.with_suffix(".tmp")
            tmp.write_text(json.dumps(self.entries))
            tmp.replace(self.path)
        except OSError as e:  # a read-only disk must not stop the vehicle
            log.warning("cannot write %s: %s", self.path, e)
