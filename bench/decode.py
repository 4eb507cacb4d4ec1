"""Decode cost per SEM topic, µs per sample: the console's generated decoder (codec/fastcdr.py) beside
cyclonedds' own deserializer, in the same run, on the same bytes. Reports are the simulator's (a
GPSReport of 40 satellites, every optional member present, as sem-sim sends them); status, ack and
command samples are random (backend/tests/support/samplegen.py). Each topic in every encoding its writers may
use: XCDR2 for the types with @optional members, XCDR1 (what writers offer) and XCDR2 for the others.

Columns: cyclonedds = `T.deserialize`; cyclonedds+json = that and `convert.to_json` (the console's
path before the generated decoder); console = what the console runs now (a report straight to its
JSON, a status to its sample). The rows marked (6.0) are the same vehicle's reports as a UMAA 6.0 vehicle
writes them, the console's cost including the version's adapter to its model. The last row is the decode cost per
vehicle-second of a 3.0.1 vehicle at the ingest benchmark's rates (GPSReport at 1 Hz, the other reports at 10 Hz).
CPU time, best of several rounds. Then each 6.0 report beside the 3.0.1 report it stands for (GlobalPose for
GPSFixReport), timed in turns in the same rounds so the machine's load weighs on both alike, with the cost per value
of the model's JSON it returns (every leaf, nulls included) and per byte of the sample; and from the same rounds a
vehicle-second of each version: the 3.0.1 vehicle above, and the same vehicle as 6.0 (GPSReport at 1 Hz, GlobalPose and
InertialSensorReport at 10 Hz; no fix status).
Usage: python bench/decode.py [--rounds 5]
"""

from __future__ import annotations

import argparse
import os
import random
import sys
import time
import uuid
from collections.abc import Callable
from typing import Any

from common import ROOT, emit, table, target

sys.path.insert(0, str(ROOT / "backend" / "tests"))

from sem_console.codec import fastcdr
from sem_console.codec.convert import to_json
from sem_console.codec.decode import REPORT_TOPICS, report_json
from sem_console.dds.topics import Sem, Sem60
from sem_console.sim import umaa_6_0 as sim60
from sem_console.sim.options import SimOptions
from sem_console.sim.reports import Sensors
from support.samplegen import random_sample

RATES = {Sem.GPS_REPORT: 1, Sem.GPS_FIX_REPORT: 10, Sem.GPS_FIX_STATUS_REPORT: 10, Sem.INS_REPORT: 10}
RATES_6_0 = {Sem60.GPS_REPORT: 1, Sem60.GLOBAL_POSE_REPORT: 10, Sem60.INS_REPORT: 10}  # the same vehicle, as 6.0
COUNTERPARTS = {
    Sem60.GPS_REPORT: Sem.GPS_REPORT,
    Sem60.GLOBAL_POSE_REPORT: Sem.GPS_FIX_REPORT,
    Sem60.INS_REPORT: Sem.INS_REPORT,
}  # the 3.0.1 report each 6.0 one feeds in the model


def samples() -> dict[Sem, Any]:
    s = Sensors(SimOptions(vehicles=1, satellites=40), 1, uuid.UUID(int=1), set())
    now = time.monotonic()
    sats = s.satellites(now)
    fix, status = s.fix_reports(now, sats)
    out: dict[Sem, Any] = {
        Sem.GPS_REPORT: s.gps_report(now, sats),
        Sem.GPS_FIX_REPORT: fix,
        Sem.GPS_FIX_STATUS_REPORT: status,
        Sem.INS_REPORT: s.ins_report(now),
    }
    rng = random.Random(1)
    for sem in Sem:
        out.setdefault(sem, random_sample(sem.spec.type, rng))
    return out


def samples_6_0() -> dict[Sem60, Any]:
    """The same vehicle's reports as a UMAA 6.0 vehicle writes them (`sem-sim --umaa 6.0`)."""
    s = Sensors(SimOptions(vehicles=1, satellites=40), 1, uuid.UUID(int=1), set())
    now = time.monotonic()
    sats = s.satellites(now)
    fix, _status = s.fix_reports(now, sats)
    return {
        Sem60.GPS_REPORT: sim60.gps_report(s.gps_report(now, sats)),
        Sem60.GLOBAL_POSE_REPORT: sim60.global_pose(fix),
        Sem60.INS_REPORT: sim60.ins_report(s.ins_report(now), {}),
    }


def console_6_0(sem: Sem60) -> Callable[[bytes], Any]:
    """What the console runs for a 6.0 report: its JSON as the version's model (codec/decode.py)."""
    return report_json(sem)


def values(json: Any) -> int:
    """The leaf values of a JSON value (nulls included)."""
    if isinstance(json, dict):
        return sum(values(v) for v in json.values())
    if isinstance(json, list):
        return sum(values(v) for v in json)
    return 1


def in_turns(runs: list[tuple[Callable[[bytes], Any], bytes]], rounds: int) -> list[float]:
    """CPU µs per call of each run, the best of `rounds` rounds that time every run in turn (about 50 ms each)."""
    ns = []
    for fn, data in runs:
        t0 = time.process_time()
        fn(data)
        ns.append(max(1, int(0.05 / max(time.process_time() - t0, 1e-6))))
    best = [float("inf")] * len(runs)
    for _ in range(rounds):
        for k, ((fn, data), n) in enumerate(zip(runs, ns, strict=True)):
            t0 = time.process_time()
            for _ in range(n):
                fn(data)
            best[k] = min(best[k], (time.process_time() - t0) / n)
    return [b * 1e6 for b in best]


def cpu_us(fn: Callable[[bytes], Any], data: bytes, rounds: int) -> float:
    """CPU µs per call, the best of `rounds` rounds of about 50 ms each."""
    return in_turns([(fn, data)], rounds)[0]


def compare_6_0(rounds: int) -> tuple[list[dict[str, Any]], dict[str, float]]:
    """Each 6.0 report beside its 3.0.1 counterpart, and a vehicle-second of each version at the simulator's rates
    (RATES, RATES_6_0), as the simulator sends them: every report of both versions timed in turns in the same rounds."""
    old, new = samples(), samples_6_0()
    topics: list[Any] = [*RATES, *RATES_6_0]
    runs = []
    for s in topics:
        sample = old[s] if isinstance(s, Sem) else new[s]
        data = s.spec.type.serialize(sample, use_version_2=s.spec.xcdr2_only)
        fn = report_json(s)
        fn(data)  # a presence pattern is learned on the first sample
        runs.append((fn, data))
    us = dict(zip(topics, in_turns(runs, rounds), strict=True))
    by_topic = dict(zip(topics, runs, strict=True))
    per_vehicle = {
        "3.0.1": sum(rate * us[s] for s, rate in RATES.items()) / 1000,
        "6.0": sum(rate * us[s] for s, rate in RATES_6_0.items()) / 1000,
    }
    out = []
    for sem60, sem in COUNTERPARTS.items():
        row: dict[str, Any] = {"topic_6_0": sem60.spec.name.rsplit("::", 1)[1], "topic_3_0_1": sem.spec.name.rsplit("::", 1)[1]}
        for key, s in (("3_0_1", sem), ("6_0", sem60)):
            fn, data = by_topic[s]
            n = values(fn(data)[0])
            row |= {
                f"bytes_{key}": len(data),
                f"values_{key}": n,
                f"us_{key}": round(us[s], 2),
                f"ns_per_value_{key}": round(us[s] * 1000 / n, 1),
                f"ns_per_byte_{key}": round(us[s] * 1000 / len(data), 1),
            }
        row["ratio"] = round(us[sem60] / us[sem], 2)
        out.append(row)
    return out, per_vehicle


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    rows, figures = [], []
    per_vehicle = {"cyclonedds_json": 0.0, "console": 0.0}
    for sem, sample in samples().items():
        t = sem.spec.type
        dec = fastcdr.decoder(t)
        report = sem in REPORT_TOPICS
        ours = dec.json if report else dec.sample
        for v2 in [True] if sem.spec.xcdr2_only else [False, True]:
            data = t.serialize(sample, use_version_2=v2)
            cdds = cpu_us(t.deserialize, data, args.rounds)
            cdds_json = cpu_us(lambda d, t=t: to_json(t.deserialize(d)), data, args.rounds) if report else None
            console = cpu_us(ours, data, args.rounds)
            before = cdds_json if cdds_json is not None else cdds
            r = {
                "topic": sem.spec.name.rsplit("::", 1)[1],
                "encoding": "XCDR2" if v2 else "XCDR1",
                "bytes": len(data),
                "cyclonedds_us": round(cdds, 1),
                "cyclonedds_json_us": None if cdds_json is None else round(cdds_json, 1),
                "console_us": round(console, 1),
                "console_mode": "json" if report else "sample",
                "speedup_vs_cyclonedds": round(cdds / console, 1),
                "speedup_vs_before": round(before / console, 1),
            }
            figures.append(r)
            rows.append(list(r.values()))
            # the encoding the simulator's writers use: XCDR2 for types with optionals, else XCDR1
            if sem in RATES and v2 == sem.spec.xcdr2_only:
                per_vehicle["cyclonedds_json"] += RATES[sem] * before
                per_vehicle["console"] += RATES[sem] * console
    for sem, sample in samples_6_0().items():
        t, v2 = sem.spec.type, sem.spec.xcdr2_only  # as the simulator's 6.0 writers send them
        data = t.serialize(sample, use_version_2=v2)
        cdds, console = cpu_us(t.deserialize, data, args.rounds), cpu_us(console_6_0(sem), data, args.rounds)
        cdds_json = cpu_us(lambda d, t=t: to_json(t.deserialize(d)), data, args.rounds)
        r = {
            "topic": f"{sem.spec.name.rsplit('::', 1)[1]} (6.0)",
            "encoding": "XCDR2" if v2 else "XCDR1",
            "bytes": len(data),
            "cyclonedds_us": round(cdds, 1),
            "cyclonedds_json_us": round(cdds_json, 1),
            "console_us": round(console, 1),
            "console_mode": "json+model",
            "speedup_vs_cyclonedds": round(cdds / console, 1),
            "speedup_vs_before": round(cdds_json / console, 1),
        }
        figures.append(r)
        rows.append(list(r.values()))
    keys = list(figures[0])
    rows.append(
        [
            "per vehicle-second (ms)",
            "as sent",
            "",
            "",
            round(per_vehicle["cyclonedds_json"] / 1000, 3),
            round(per_vehicle["console"] / 1000, 3),
            "",
            "",
            round(per_vehicle["cyclonedds_json"] / max(per_vehicle["console"], 1e-9), 1),
        ]
    )
    table("Decode cost per sample, µs of CPU (console: generated decoder; cyclonedds: its deserializer)", keys, rows)
    pairs, versions = compare_6_0(args.rounds * 2)
    table(
        "6.0 beside 3.0.1, timed in turns: console µs per sample, ns per value of the model's JSON and per byte",
        list(pairs[0]),
        [list(r.values()) for r in pairs],
    )
    print(
        f"per vehicle-second, the same rounds: 3.0.1 {versions['3.0.1']:.3f} ms, 6.0 {versions['6.0']:.3f} ms "
        f"(ratio {versions['6.0'] / versions['3.0.1']:.2f})"
    )
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    targets = []
    for r in pairs:
        new, old = r["topic_6_0"].removesuffix("Type"), r["topic_3_0_1"]
        print(f"ratio   {new} (6.0) / {old} (3.0.1) per sample: {r['ratio']}")
        targets.append(
            target(f"{new} per sample <= {old} per sample", r["us_6_0"], "µs", "<=", r["us_3_0_1"], f"{old}'s in the same rounds")
        )
    targets.append(
        target(
            "a 6.0 vehicle-second <= a 3.0.1 vehicle-second",
            round(versions["6.0"], 3),
            "ms",
            "<=",
            round(versions["3.0.1"], 3),
            "the 3.0.1 vehicle's in the same rounds",
        )
    )
    emit(
        "decode",
        {
            "topics": figures,
            "per_vehicle_second_ms": {k: round(v / 1000, 3) for k, v in per_vehicle.items()},
            "versions_in_turns": pairs,
            "per_vehicle_second_in_turns_ms": {k: round(v, 3) for k, v in versions.items()},
            "targets": targets,
            "load_average": round(os.getloadavg()[0], 2),
        },
    )


if __name__ == "__main__":
    main()
