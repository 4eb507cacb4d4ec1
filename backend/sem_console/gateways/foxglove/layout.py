"""The Foxglove layout shipped as docs/foxglove-layout.json (written by `python -m sem_console.docs_gen`), built with
foxglove-sdk's own layout classes (`foxglove.layouts`): the fleet on a Map, one vehicle's speed on a Plot and its fix
and INS states on State Transitions (the vehicle is the layout variable `vehicle`, its id), and the console's Log."""

from __future__ import annotations

import json

import foxglove.layouts as fl

from sem_console.gateways.foxglove.gateway import FLEET_TOPIC, LOG_TOPIC, report_topic
from sem_console.sim.options import vehicle_guid


def of_vehicle(topic: str, member: str) -> str:
    """A message path to a member of the chosen vehicle's reports (the one report channel holds the whole fleet)."""
    return f"{report_topic(topic)}{{providerId==$vehicle}}.report.{member}"


def layout() -> str:
    fleet_map = fl.MapPanel(
        title="Fleet",
        # each vehicle's own LocationFix topic gives it a colour and a track; the fleet's topic would draw them twice
        config=fl.MapConfig(layer="map", zoom_level=13, disabled_topics=[FLEET_TOPIC]),
    )
    speed = fl.PlotPanel(
        title="Speed over ground (m/s)",
        config=fl.PlotConfig(paths=[fl.PlotSeries(value=of_vehicle("GPSFixReport", "SOG"), label="SOG")]),
    )
    states = fl.StateTransitionsPanel(
        title="GPS fix and INS",
        config=fl.StateTransitionsConfig(
            paths=[
                fl.StateTransitionsSeries(value=of_vehicle("GPSFixStatusReport", "fixValid"), label="Fix valid"),
                fl.StateTransitionsSeries(value=of_vehicle("GPSFixReport", "GPSLatLongValid"), label="GPS position"),
                fl.StateTransitionsSeries(value=of_vehicle("InertialSensorReport", "status"), label="INS status"),
            ]
        ),
    )
    log = fl.LogPanel(title="Alarms and commands", config=fl.LogConfig(topic_to_render=LOG_TOPIC))
    right = fl.SplitContainer(
        direction="column", items=[fl.SplitItem(content=speed), fl.SplitItem(content=states), fl.SplitItem(content=log)]
    )
    whole = fl.Layout(
        content=fl.SplitContainer(
            direction="row", items=[fl.SplitItem(proportion=3, content=fleet_map), fl.SplitItem(proportion=2, content=right)]
        ),
        variables={"vehicle": str(vehicle_guid(1))},  # sem-sim's first vehicle; set it to the id of the vehicle to watch
    )
    return json.dumps(json.loads(whole.to_json()), indent=2) + "\n"
