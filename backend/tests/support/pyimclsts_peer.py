"""Run by tests/test_comap_pyimclsts.py in a folder where pyimclsts generated its classes from
tests/data/comap-imc.xml (pyimclsts imports them from the working directory).

stdin: {"decode": [hex packets]}; stdout: {"decoded": [plain dicts], "crc": [pyimclsts' CRC of each
packet's header and payload], "encoded": {name: hex}}.
Fields are read from the instances' stored values: pyimclsts' getters deep-copy, which fails for
its message objects under Python 3.11 (a bug of pyimclsts 0.1.2.1, not of the packets)."""

from __future__ import annotations

import json
import sys
from typing import Any

import pyimc_generated as pg  # type: ignore[import-not-found]
import pyimclsts.core as core  # type: ignore[import-untyped]
import pyimclsts.network as n  # type: ignore[import-untyped]


def plain(x: Any) -> Any:
    if isinstance(x, list):
        return [plain(i) for i in x]
    if hasattr(x, "Attributes"):
        out = {"_name": x.Attributes.abbrev}
        for f in x.Attributes.fields:
            out[f] = plain(getattr(x, "_" + f))
        if getattr(x, "_header", None) is not None:
            out["_header"] = list(x._header)
        return out
    if hasattr(x, "value"):  # a local enumeration
        return int(x.value)
    return x


def main() -> None:
    request = json.load(sys.stdin)
    packets = [bytes.fromhex(h) for h in request["decode"]]
    decoded = [plain(n.unpack(p)) for p in packets]
    crc = [core.CRC16IMB(p[:-2]) for p in packets]
    m = pg.messages
    wm = m.WorldModel(
        geo_features=[
            m.GeoFeature(
                feature_id=42,
                points=[
                    m.MapPoint(lat=0.6422, lon=-1.3212, alt=0.0),
                    m.MapPoint(lat=0.6422, lon=-1.3210, alt=0.0),
                    m.MapPoint(lat=0.6424, lon=-1.3210, alt=0.0),
                ],
            )
        ],
        cov_states=[m.CoverageState(feature_id=42, state=2)],
    )
    head = {"src": 0x2001, "src_ent": 0, "dst": 0xFFFF, "dst_ent": 0xFF}
    encoded = {
        "WorldModel-le": wm.pack(is_big_endian=False, **head).hex(),
        "WorldModel-be": wm.pack(is_big_endian=True, **head).hex(),
        "TaskStatus": m.TaskStatus(task_id=3, status=2, progress=40, quality=80).pack(is_big_endian=False, **head).hex(),
        "TaskAdmin": m.TaskAdmin(tid=3, op=1).pack(is_big_endian=False, **head).hex(),
        "VehicleCapabilities": m.VehicleCapabilities(
            capabilities=[
                m.CapabilityAreaSurvey(sensor=1, resolution=10.0, res_bathym_factor=1.0, cov_rate=60.0, cov_bathym_factor=1.0),
                m.CapabilityMove(speed=2.0),
            ]
        )
        .pack(is_big_endian=False, **head)
        .hex(),
    }
    json.dump({"decoded": decoded, "crc": crc, "encoded": encoded}, sys.stdout)


if __name__ == "__main__":
    main()
