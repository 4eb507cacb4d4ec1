"""The Foxglove layout shipped in docs/ (docs/foxglove-layout.json): its format against the published TypeScript type of
Foxglove's layouts (@foxglove/embed's `Layout`, checked by tests/support/foxglove_layout.cjs), and what it reads
against what a real console advertises and sends over the Foxglove WebSocket protocol (tests/support/foxglove.py)."""

from __future__ import annotations

import asyncio
import json
import math
import re
import subprocess
from pathlib import Path
from typing import Any

import pytest

from conftest import free_port
from support.foxglove import connect
from test_console import V1, V2, provider_ready
from test_foxglove import gateway, until

ROOT = Path(__file__).resolve().parents[3]
LAYOUT = ROOT / "docs" / "foxglove-layout.json"
DOCS = ROOT / "docs" / "foxglove.md"
CHECKER = Path(__file__).resolve().parents[1] / "support" / "foxglove_layout.cjs"
PATH = re.compile(r"^(?P<topic>/[^{.]+)(?:\{(?P<key>\w+)==(?P<value>[^}]+)\})?(?P<members>(?:\.\w+)*)$")
SCALARS = {"number", "integer", "boolean", "string"}


def check(layout: dict[str, Any], tmp_path: Path) -> dict[str, Any]:
    """The layout checked against @foxglove/embed's `Layout` type, by Node."""
    file = tmp_path / "layout.json"
    file.write_text(json.dumps(layout))
    run = subprocess.run(["node", str(CHECKER), str(file)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return dict(json.loads(run.stdout))


def documented_differences() -> set[tuple[str, str]]:
    """The table of docs/foxglove.md's layout section: (type, key) where the file departs from the published type."""
    rows = set()
    for line in DOCS.read_text().split("## A layout", 1)[1].split("\n## ", 1)[0].splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) >= 3 and re.fullmatch(r"`\w+`", cells[0]) and re.fullmatch(r"`\w+`", cells[1]):
            rows.add((cells[0].strip("`"), cells[1].strip("`")))
    return rows


@pytest.mark.process
def test_the_layout_has_the_published_layout_types_keys_and_values_but_where_the_docs_say(tmp_path: Path) -> None:
    """Every panel's type, keys and config values are those of Foxglove's published `Layout` type; a split container
    is written as foxglove-sdk's layout classes write it, which that type, older, names otherwise: docs/foxglove.md
    lists where, and this fails when the list is not what the check finds."""
    layout = json.loads(LAYOUT.read_text())
    got = check(layout, tmp_path)
    found = {(e["type"], e["key"]) for e in got["errors"]}
    assert found == documented_differences(), f"{got['versions']}: {got['errors']}"
    assert all(e["type"] == "Split" for e in got["errors"]), got["errors"]  # the panels have no error at all
    # the check can fail: a misspelt config key, a value the type does not have, a panel without its version
    log = layout["content"]["items"][1]["content"]["items"][2]["content"]
    log["config"]["topicToRendr"] = log["config"].pop("topicToRender")
    layout["content"]["items"][0]["content"]["config"]["layer"] = "satelite"
    del layout["content"]["items"][1]["content"]["items"][0]["content"]["version"]
    broken = {(e["type"], e["key"]) for e in check(layout, tmp_path)["errors"]} - found
    assert broken == {("LogPanel.config", "topicToRendr"), ("MapPanel.config", "layer"), ("PlotPanel", "version")}


def panels(content: dict[str, Any]) -> list[dict[str, Any]]:
    if content["type"] == "panel":
        return [content]
    children = [i["content"] for i in content.get("items", []) + content.get("tabs", [])]
    children += [i["panel"] for i in content.get("panels", [])]
    return [p for c in children for p in panels(c)]


def strings(value: Any) -> list[str]:
    if isinstance(value, str):
        return [value]
    if isinstance(value, dict):
        value = list(value.values())
    return [s for v in value for s in strings(v)] if isinstance(value, list) else []


def member(schema: dict[str, Any], members: list[str]) -> dict[str, Any]:
    """The JSON Schema of a member path in a channel's schema (its `$ref`s inlined, as the gateway advertises it)."""
    for name in members:
        assert name in schema.get("properties", {}), f"no member {name!r} of {members} in {sorted(schema['properties'])}"
        schema = schema["properties"][name]
    return schema


def test_the_layouts_topics_and_message_paths_are_the_consoles_and_its_map_shows_the_fleet(sim, console) -> None:
    """Every topic and message path the layout names is a channel the console advertises, with a member of a plotted
    type, and live: each path gives its value for the layout's vehicle. The Map panel subscribes to every
    foxglove.LocationFix topic the layout does not disable and draws a fix whose latitude and longitude are finite (the
    open-source Map panel's rule, Lichtblick's): one topic a vehicle, each with its position."""
    layout = json.loads(LAYOUT.read_text())
    variables = {f"${k}": v for k, v in layout["variables"].items()}
    named = [s for p in panels(layout["content"]) for s in strings(p.get("config", {})) if s.startswith("/")]
    paths = [m for s in named if (m := PATH.match(s))]
    assert [m.string for m in paths] == named, "a topic or message path the pattern does not read"
    (disabled,) = [p["config"].get("disabledTopics", []) for p in panels(layout["content"]) if p["panelType"] == "Map"]
    (log,) = [p["config"]["topicToRender"] for p in panels(layout["content"]) if p["panelType"] == "Log"]
    assert variables == {"$vehicle": V1}  # sem-sim's first vehicle, as the docs say
    sim("--vehicles", "2")
    c = console("--foxglove-port", str(free_port()))
    provider_ready(c.url, V1, {"GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"})
    provider_ready(c.url, V2, {"GPSFixReport"})
    fleet = {f"/vehicles/{v}/location" for v in (V1, V2)}
    wanted = {m["topic"] for m in paths} | fleet
    values: dict[str, Any] = {}  # a message path -> a value it had in a message of the layout's vehicle
    fixes: dict[str, dict[str, Any]] = {}  # a LocationFix topic -> its last message

    async def session() -> dict[str, dict[str, Any]]:
        async with connect(gateway(c.url)["endpoint"]) as client:
            await until(client, lambda _m: wanted <= set(client.topics()), 15, f"advertisement of {wanted}")
            topics = client.topics()
            on_map = {t for t, ch in topics.items() if ch["schemaName"] == "foxglove.LocationFix"} - set(disabled)
            assert fleet <= on_map, on_map
            readable(topics, paths)
            await client.subscribe(sorted({m["topic"] for m in paths if m["members"]} | on_map))

            def take(m: Any) -> bool:
                if m is not None and m.topic in on_map:
                    fixes[m.topic] = m.json()
                elif m is not None:
                    body = m.json()
                    for p in (p for p in paths if p["topic"] == m.topic and p["members"]):
                        mine = p["key"] is None or str(body.get(p["key"])) == variables.get(p["value"], p["value"])
                        if mine and (value := member_value(body, p["members"])) is not None:
                            values[p.string] = value
                return fleet <= set(fixes) and len(values) == len({p.string for p in paths if p["members"]})

            await until(client, take, 30, "a value of every message path and a fix of every vehicle")
            return topics

    topics = asyncio.run(session())
    assert topics[log]["schemaName"] == "foxglove.Log"
    assert all(topics[t]["schemaName"] == "foxglove.LocationFixes" for t in disabled)  # the fleet's, drawn once
    for topic, fix in fixes.items():
        assert math.isfinite(fix["latitude"]) and math.isfinite(fix["longitude"]), (topic, fix)  # drawn


def readable(topics: dict[str, dict[str, Any]], paths: list[re.Match[str]]) -> None:
    """Each message path's member, and its filter's, is in its channel's advertised schema, of a type Plot takes."""
    for p in (p for p in paths if p["members"]):
        schema = json.loads(topics[p["topic"]]["schema"])
        if p["key"]:
            member(schema, [p["key"]])
        kind = member(schema, p["members"].strip(".").split("."))["type"]
        kinds = ({kind} if isinstance(kind, str) else set(kind)) - {"null"}
        assert kinds and kinds <= SCALARS, (p.string, kind)


def member_value(body: dict[str, Any], members: str) -> Any:
    for name in members.strip(".").split("."):
        body = body[name]
    return body
