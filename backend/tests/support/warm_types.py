"""Imported by the warm interpreter (`warm.py`) before it forks: each DDS topic type's XTypes type information, which
cyclonedds builds at the type's first Topic and keeps on the type (about 0.3 CPU-second of a forked console's start,
measured), built once here instead of in each forked process."""

from __future__ import annotations

from sem_console.dds.topics import Sem, Sem60

for _sem in (*Sem, *Sem60):
    for _type in (_sem.spec.type, _sem.spec.appendable):
        if _type is not None:
            _type.__idl__.fill_type_data()
