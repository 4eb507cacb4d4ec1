"""The wire codec: raw SEM samples to what the console applies (`decode.py`), the decoder generated per type
(`fastcdr.py`), cyclonedds samples to JSON (`convert.py`) and the report types' JSON Schema (`jsonschema.py`).

Used alike by the console, sem-check, the API and the benchmarks; it imports only `dds/` and the versions' adapters
(`versions/`).
"""
