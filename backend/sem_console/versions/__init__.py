"""The UMAA versions the console serves, each an adapter from its wire reports to the console's one model.

The console's model is the report JSON by report topic (`core/contract.ReportTopic`: GPSReport, GPSFixReport,
GPSFixStatusReport, InertialSensorReport), whose members are UMAA 3.0.1's and those a later version adds (optional:
absent from a report of a version without them; `umaa_6_0.MODEL_MEMBERS`, `MODEL_LITERALS`). A version's adapter
(`umaa_6_0.py`) says, for each of its report topics, which model topic it feeds and how its JSON becomes the model's
(as data where it can, `shape.py`, which the generated decoder compiles); the decoder applies it (`codec/decode.py`)
and nothing after it asks which version a vehicle speaks, but for the version it shows.
"""

from __future__ import annotations

from sem_console.core.versions import UmaaVersion

__all__ = ["UMAA_3_0_1", "UMAA_6_0", "UmaaVersion"]
UMAA_3_0_1: UmaaVersion = "3.0.1"
UMAA_6_0: UmaaVersion = "6.0"
