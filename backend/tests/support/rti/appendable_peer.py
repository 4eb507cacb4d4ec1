"""Child process of test_interop_rti's recipe tests: GPSReport and GPSFixReport between Cyclone
endpoints whose types are appendable (the `UMAA` package first on sys.path, generated with
idlgen's extensibility "appendable") and an RTI participant on the repository's drop-in QoS
profile. Prints one JSON line: per topic, whether each side matched the other and how many of 20
random samples arrived right each way.

Usage: python -m support.rti.appendable_peer DOMAIN VERSION(6|7) MASK(mask|nomask) [force] [-v]
       python -m support.rti.appendable_peer DOMAIN cyclone   (no RTI: what Cyclone endpoints of other types match)
(`force`: Cyclone's reader sets force_type_validation, i.e. refuses writers without type information.)
"""

from __future__ import annotations

import json
import random
import sys
import time
from typing import Any

from cyclonedds.core import Policy, Qos

from sem_console.dds.bus import Bus, all_samples
from sem_console.dds.qos import reader_qos
from sem_console.dds.topics import Sem
from support.rti.connector import RECIPE_ENV, RtiParticipant
from support.rti.connext7 import RemoteParticipant
from support.samplegen import random_sample, to_plain
from test_interop_rti import same

TOPICS = [Sem.GPS_REPORT, Sem.GPS_FIX_REPORT]


def cyclone_only(domain: int) -> None:
    """Appendable Cyclone endpoints only: after discovery, how many writers each reader matched and
    readers each writer matched (our own reader and writer are in participants of their own)."""
    readers = {s: Bus(domain).reader(s) for s in TOPICS}
    writers = {s: Bus(domain).writer(s) for s in TOPICS}
    time.sleep(3)
    print(
        json.dumps(
            {
                s.name: [len(readers[s].get_matched_publications()) - 1, len(writers[s].get_matched_subscriptions()) - 1]
                for s in TOPICS
            }
        ),
        flush=True,
    )


def main() -> None:
    if sys.argv[2] == "cyclone":
        return cyclone_only(int(sys.argv[1]))
    domain, version, mask = int(sys.argv[1]), sys.argv[2], sys.argv[3] == "mask"
    force = "force" in sys.argv[4:]
    extra = Qos(Policy.TypeConsistency.AllowTypeCoercion(force_type_validation=True)) if force else Qos()
    readers = {s: Bus(domain).reader(s, qos=reader_qos(s.spec.cls) + extra) for s in TOPICS}
    writers = {s: Bus(domain).writer(s) for s in TOPICS}
    kw: dict[str, Any] = {"writers": TOPICS, "readers": TOPICS, "recipe": "AppendableGps"}
    p = RemoteParticipant(domain, env=RECIPE_ENV if mask else {}, **kw) if version == "7" else RtiParticipant(domain, **kw)
    try:
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and not all(
            len(p.matched(s, True)) == 2 and len(p.matched(s, False)) == 2 for s in TOPICS
        ):
            time.sleep(0.1)
        time.sleep(0.5)
        result: dict[str, dict[str, int]] = {}
        rng = random.Random(23)
        theirs = {s: [random_sample(s.spec.type, rng) for _ in range(20)] for s in TOPICS}
        ours = {s: [random_sample(s.spec.type, rng) for _ in range(20)] for s in TOPICS}
        for s in TOPICS:
            result[s.name] = {
                "cyclone_matched_rti": len(readers[s].get_matched_publications()) - 1,
                "rti_matched_cyclone": len(p.matched(s, False)) - 1,
            }
            for x in theirs[s]:
                p.write(s, to_plain(x))
            for x in ours[s]:
                writers[s].write(x)
        time.sleep(2)
        for s in TOPICS:
            got = [to_plain(g) for g in readers[s].take(N=200, condition=all_samples(readers[s]))]
            rti_got = [x for x, _ in p.take(s) if x]
            result[s.name]["received"] = len(got)
            result[s.name]["rti_received"] = len(rti_got)
            result[s.name]["rti_to_cyclone_right"] = sum(any(same(to_plain(x), g) for g in got) for x in theirs[s])
            result[s.name]["cyclone_to_rti_right"] = sum(any(same(to_plain(x), g) for g in rti_got) for x in ours[s])
            if "-v" in sys.argv:
                for x in ours[s]:
                    if not any(same(to_plain(x), g) for g in rti_got):
                        print("MISS", s.name, json.dumps(to_plain(x)), file=sys.stderr)
                        print("GOT", json.dumps([g for g in rti_got if g["source"] == to_plain(x)["source"]]), file=sys.stderr)
        print(json.dumps(result), flush=True)
    finally:
        p.close()


if __name__ == "__main__":
    main()
