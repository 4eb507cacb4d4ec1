// The map: MapLibre GL over the built-in offline basemap. Vehicles at their GPSFixReport positions
// with a course arrow (colour by fix validity, stale and lost marked; a lost one's projection dashed), their tracks, the
// GPSFixStatusReport origins and the CoMap world model's features by coverage. The map's parts are hooks
// and components in ./map (the map itself, the pointer and its tools, one hook per layer, the toolbar).
import { memo, useCallback, useMemo, useRef, useState } from "react";
import type { Map as MapLibre } from "maplibre-gl";
import type { FeatureCollection } from "geojson";
import { Panel } from "../../components/Panel";
import { useToken } from "../../data/auth";
import {
  useAlarmed,
  useNow,
  usePaceOf,
  useProvidersOnFrame,
  useReceiving,
  useSelectedTopic,
  useSelector,
  useSilences,
  useSelectVehicle,
} from "../../data/hooks";
import type { ProviderView } from "../../data/slices/vehicles";
import { useChartConfigured, useStoredTracks, useWorldModel } from "../../data/loaders";
import { useCollapsed, useDmsSetting } from "../../data/settings";
import type { VehicleOverlay } from "../../lib/mapOverlay";
import {
  bearingDeg,
  distanceText,
  pathLengthM,
  vertexHandles,
  withLiveCoverage,
  type LonLat,
  type VehicleMark,
} from "../../lib/geo";
import { useTheme } from "../../lib/theme";
import { CoMapControls, CoMapOff, type MapTool } from "../CoMap/CoMap";
import { CursorStore, MapCursor } from "./MapCursor";
import { MapLegend } from "./MapLegend";
import { MapPace } from "./MapPace";
import { MapToolbar } from "./MapToolbar";
import type { FleetCanvas, FleetData, ToolMarks } from "./FleetCanvas";
import {
  useChart,
  useFitAll,
  useLand,
  useLandSource,
  useMapInstance,
  useMeasureLayer,
  usePointer,
  useSelectedRing,
  useSettled,
  useVehicleLayer,
  useWorldModelLayer,
} from "./hooks";
import { fitAll, originOf, vehicleMark } from "./layers";

/** The fleet (every vehicle's mark, tracks and origins, on a canvas over the map) is redrawn on the first frame at
 * least this long after the last (and only when it changed), so at least twice a second while vehicles move: with
 * 250 vehicles a redraw of the canvas and the names is a few milliseconds, and vehicles at sea move a few metres a
 * second. The selected vehicle's ring (HTML over the map) moves on the frame after each of its fixes. */
const FLEET_EVERY_MS = 450;

/** The vehicles' stored tracks loaded into the store once the map has drawn its first screen (`ready`: settled):
 * rendered only when the vehicles or the map's readiness change, not on each fix of the selected vehicle as the map
 * panel is. */
const StoredTracks = memo(function StoredTracks({ ready }: { ready: boolean }) {
  useStoredTracks(ready);
  return null;
});

/** The selected vehicle's ring (HTML over the map) at its newest fix: the one part of the map that subscribes to the
 * selected vehicle's fix, so each fix renders this (nothing of its own to draw) and not the map panel's tree (the
 * CoMap controls, toolbar, status and legend), which renders at the fleet's rate. */
const SelectedRing = memo(function SelectedRing({
  overlay,
  vehicle,
  now,
  selected,
}: {
  overlay: VehicleOverlay | null;
  vehicle: ProviderView | undefined;
  now: number;
  selected: string | null;
}) {
  const fix = useSelectedTopic("GPSFixReport");
  const alarmed = useAlarmed();
  const receiving = useReceiving();
  const silences = useSilences();
  const paceOf = usePaceOf();
  const mark = useMemo(
    () =>
      vehicle
        ? vehicleMark(
            fix ? { ...vehicle, topics: { ...vehicle.topics, GPSFixReport: fix } } : vehicle,
            now,
            selected,
            alarmed,
            receiving,
            silences,
            paceOf(vehicle.id),
          )
        : null,
    [vehicle, fix, now, selected, alarmed, receiving, silences, paceOf],
  );
  useSelectedRing(overlay, mark);
  return null;
});

export function MapPanel() {
  const theme = useTheme();
  const container = useRef<HTMLDivElement>(null);
  const [collapsed] = useCollapsed("map-panel");
  const { mapRef, ready } = useMapInstance(container, collapsed, theme);
  const settled = useSettled(mapRef, ready);
  const fleet = useProvidersOnFrame(undefined, FLEET_EVERY_MS);
  const selected = useSelector((s) => s.selected);

  const selectVehicle = useSelectVehicle();
  const now = useNow(1000);
  const worldModel = useWorldModel();
  const [useDms, setDms] = useDmsSetting();
  const chartConfigured = useChartConfigured();
  const token = useToken();
  const [follow, setFollow] = useState(true);
  const [cursor] = useState(() => new CursorStore());
  const [tool, setTool] = useState<MapTool>("select");
  const measuring = tool === "measure";
  const [measure, setMeasure] = useState<LonLat[]>([]);
  const [drawn, setDrawn] = useState<LonLat[]>([]);
  const [moveTarget, setMoveTarget] = useState<LonLat | null>(null);
  const [picked, setPicked] = useState<unknown>(null); // the featureId clicked in the edit tool (to delete)
  // the world model being edited: its geometry only; coverage is always the console's (withLiveCoverage)
  const [draft, setDraft] = useState<FeatureCollection | null>(null);
  const shownModel = useMemo(() => (draft ? withLiveCoverage(draft, worldModel) : worldModel), [draft, worldModel]);
  const modelRef = useRef<FeatureCollection | null>(null); // what the edit tool moves vertices of
  // the fleet's marks (drawn by the map, named by the overlay, fitted and followed) change at the fleet's rate; the
  // selected vehicle's ring with its newest fix on every frame after one (SelectedRing)
  const alarmed = useAlarmed();
  const receiving = useReceiving();
  const silences = useSilences();
  const paceOf = usePaceOf();
  const fleetAll = useMemo(
    () =>
      fleet
        .map((p) => vehicleMark(p, now, selected, alarmed, receiving, silences, paceOf(p.id)))
        .filter((v): v is VehicleMark => v !== null),
    [fleet, now, selected, alarmed, receiving, silences, paceOf],
  );
  const selectedVehicle = useMemo(() => fleet.find((v) => v.id === selected), [fleet, selected]);
  const fleetData = useMemo<FleetData>(
    () => ({
      marks: fleetAll,
      tracks: fleet.map((p) => ({ id: p.id, selected: p.id === selected, points: p.track })),
      origins: fleet.flatMap((p) => {
        const at = originOf(p);
        return at ? [{ id: p.id, at }] : [];
      }),
    }),
    [fleet, fleetAll, selected],
  );
  const fleetCanvas = useRef<FleetCanvas | null>(null);
  const [vehiclesDrawn, setVehiclesDrawn] = useState(0);
  const toolPoints = useMemo(
    () => (tool === "measure" ? measure : tool === "draw" ? drawn : tool === "move-target" && moveTarget ? [moveTarget] : []),
    [tool, measure, drawn, moveTarget],
  );

  const chart = useChart(mapRef, ready, chartConfigured, token);
  const { land, landLoaded, landDrawn } = useLand(mapRef, ready);
  usePointer(mapRef, ready, tool, modelRef, fleetCanvas, {
    selectVehicle,
    cursor,
    setFollow,
    setMeasure,
    setDrawn,
    setMoveTarget,
    setPicked,
    setDraft,
  });
  // an edge arrow: that vehicle selected, in the middle of the map, and followed
  const pickEdge = useCallback(
    (map: MapLibre, m: VehicleMark) => {
      selectVehicle(m.id);
      map.jumpTo({ center: [m.position.lon, m.position.lat] });
      setFollow(true);
    },
    [selectVehicle],
  );
  useWorldModelLayer(mapRef, ready, shownModel, tool, picked, modelRef);
  useMeasureLayer(mapRef, ready, toolPoints);
  // followed at the fleet's rate, a jump (a redraw of the map) only when it leaves the middle: between jumps the ring
  // moves from the middle
  const framed = useFitAll(mapRef, ready, fleetAll, follow, land, landLoaded);
  useLandSource(mapRef, ready, land, landLoaded, framed || fleetAll.length === 0);
  // the fleet drawn from the first view on (the vehicles, with the coast): not for a moment over the whole world at
  // zoom 1, where they are one pixel and a click or a count there means nothing
  // the tools' points drawn again over the fleet's canvas (the map's own layers are under it)
  const toolMarks = useMemo<ToolMarks>(
    () => ({
      path: toolPoints,
      handles:
        tool === "edit"
          ? vertexHandles(shownModel).features.map((f) => ({ lon: f.geometry.coordinates[0], lat: f.geometry.coordinates[1] }))
          : [],
    }),
    [toolPoints, tool, shownModel],
  );
  const overlay = useVehicleLayer(mapRef, framed, fleetCanvas, fleetData, pickEdge, setVehiclesDrawn, toolMarks);

  const measured = pathLengthM(measure);
  const lastLeg = measure.length >= 2 ? bearingDeg(measure[measure.length - 2], measure[measure.length - 1]) : null;
  return (
    <Panel
      title="Map"
      testId="map-panel"
      className="map-panel"
      actions={
        <MapToolbar
          follow={follow}
          setFollow={setFollow}
          canFit={fleetAll.length > 0}
          fitAll={() => {
            const map = mapRef.current;
            if (!map) return;
            setFollow(false); // following would take the view back to one vehicle
            fitAll(
              map,
              fleetAll.map((m) => m.position),
            );
          }}
          measuring={measuring}
          toggleMeasure={() => {
            setTool(measuring ? "select" : "measure");
            setMeasure([]);
          }}
          useDms={useDms}
          setDms={setDms}
        />
      }
    >
      {settled && <StoredTracks ready />}
      <SelectedRing overlay={overlay} vehicle={selectedVehicle} now={now} selected={selected} />
      <div className="map-wrap">
        <div
          ref={container}
          className="map"
          data-testid="map"
          data-ready={ready}
          data-land={landDrawn}
          data-vehicles={vehiclesDrawn}
        />
        <div className="map-status">
          <MapCursor cursor={cursor} useDms={useDms} />
          {chart !== "none" && (
            <span data-testid="map-chart" className={chart === "failed" ? "error" : undefined}>
              chart: {chart === "failed" ? "cannot be read" : chart}
            </span>
          )}
          <span data-testid="map-vehicle-count">
            {vehiclesDrawn} of {fleet.length} vehicles drawn
          </span>
          <MapPace />
          {measuring && (
            <span data-testid="map-distance">
              {measure.length < 2 ? "click points to measure" : `${distanceText(measured)} · last leg ${lastLeg!.toFixed(0)}°`}
            </span>
          )}
        </div>
      </div>
      {worldModel ? (
        <CoMapControls
          model={shownModel ?? worldModel}
          consoleModel={worldModel}
          dirty={draft !== null}
          setDraft={setDraft}
          tool={tool}
          setTool={(t) => {
            setTool(t);
            setMoveTarget(null);
          }}
          drawn={drawn}
          clearDrawn={() => setDrawn([])}
          moveTarget={moveTarget}
          picked={tool === "edit" ? picked : null}
          unpick={() => setPicked(null)}
        />
      ) : (
        <CoMapOff />
      )}
      <MapLegend model={shownModel} />
    </Panel>
  );
}
