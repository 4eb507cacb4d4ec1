"""`sem-check`: a headless UMAA SEM conformance runner.

It tests one Service Provider on a DDS domain against ICD 3.0.1 as a Service Consumer would
see it: which SEM topics it serves with which types, keys and QoS (`discovery`), what its
reports carry (`reports`) and, only with `--commands`, how it runs commands through the
section 4.1 flow and Figure 4 (`commands`). It reuses the console's DDS layer (`dds/`), its
Figure 4 monitor (`umaa/flow.py`), its sample decoder (`codec/decode.py`) and its recorder,
and none of its HTTP layer. `runner.run` ties the parts together; `cli.main` is the command.
"""
