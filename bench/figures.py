"""The docs' benchmark figures, read from the JSON the benchmarks leave in bench/results/ (bench/common.py `emit`).

An MkDocs hook (mkdocs.yml `hooks:`): in docs/benchmarks.md the marker `<!-- bench-figures -->` becomes one section
per benchmark with the date, the machine and every figure beside its target, so the page cannot drift from what
was measured. `python bench/figures.py` prints the same Markdown.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

RESULTS = Path(__file__).resolve().parent / "results"
MARKER = "<!-- bench-figures -->"
ORDER = (
    "scale",
    "storage",
    "latency",
    "fanout",
    "browser",
    "paint",
    "snapshot",
    "ingest",
    "decode",
    "roundtrip",
    "recording",
    "foxglove",
    "mcap_write",
    "opscentre",
    "soak",
)  # the rest follow by name


def _value(v: Any) -> str:
    if v is None:
        return "-"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return "n/a" if math.isnan(v) else f"{v:,.3g}" if abs(v) < 1000 else f"{v:,.0f}"
    if isinstance(v, int):
        return f"{v:,}"
    return str(v)


def _machine(m: dict[str, Any] | None, cores: Any) -> str:
    if not m:  # a result from before the machine was recorded
        return f"{cores} cores"
    return (
        f"{m.get('cpu')}, {m.get('cores')} cores, {m.get('memoryGiB')} GiB, {m.get('os')}, Python {m.get('python')}, "
        f"Cyclone DDS {m.get('cyclonedds')}; load average {m.get('loadAverage1m')} at the end"
    )


def section(result: dict[str, Any]) -> str:
    name = result.get("bench", "?")
    lines = [
        f"### {name} {{#bench-{name.replace('_', '-')}}}",
        "",
        f"`bench/{name}.py`, measured {result.get('date', 'undated')} on {_machine(result.get('machine'), result.get('cores'))}.",
        "",
    ]
    targets = result.get("targets") or []
    if targets:
        lines += ["| figure | measured | target | |", "|---|---|---|---|"]
        for t in targets:
            verdict = "holds" if t.get("holds") else "**missed**"
            unit = t.get("unit", "")
            lines.append(f"| {t.get('name')} | {_value(t.get('value'))} {unit} | {t.get('target')} {unit} | {verdict} |")
    scalars = {
        k: v
        for k, v in result.items()
        if k not in {"bench", "cores", "date", "machine", "command", "targets"} and isinstance(v, (int, float, str, bool))
    }
    if scalars:
        lines += ["", "| figure | measured |", "|---|---|"] + [f"| {k} | {_value(v)} |" for k, v in scalars.items()]
    skip = {"bench", "cores", "date", "machine", "command", "targets"}
    for key, v in result.items():
        if key in skip:
            continue
        if isinstance(v, dict) and v and all(isinstance(x, (int, float, str, bool)) or x is None for x in v.values()):
            lines += ["", f"**{key}**", "", "| | |", "|---|---|"] + [f"| {k} | {_value(x)} |" for k, x in v.items()]
        elif isinstance(v, list) and v and all(isinstance(row, dict) for row in v):
            columns = [c for c in v[0] if all(not isinstance(row.get(c), (dict, list)) for row in v)]
            lines += ["", f"**{key}**", "", "| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
            lines += ["| " + " | ".join(_value(row.get(c, "")) for c in columns) + " |" for row in v]
    lines += ["", f"The whole output: `bench/results/{name}.json`.", ""]
    return "\n".join(lines)


def render(results: Path = RESULTS) -> str:
    found: dict[str, dict[str, Any]] = {}
    for f in sorted(results.glob("*.json")):
        try:
            data = json.loads(f.read_text())
        except ValueError as e:  # a half-written file must not break the docs build silently
            raise SystemExit(f"bench/figures.py: {f} is not JSON ({e}); run its benchmark again") from None
        found[data.get("bench", f.stem)] = data
    if not found:
        return "No benchmark has been run on this checkout yet: `./scripts/bench` writes `bench/results/`.\n"
    names = [n for n in ORDER if n in found] + sorted(set(found) - set(ORDER))
    return "\n".join(section(found[n]) for n in names)


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:  # the MkDocs hook
    return markdown.replace(MARKER, render()) if MARKER in markdown else markdown


if __name__ == "__main__":
    print(render())
