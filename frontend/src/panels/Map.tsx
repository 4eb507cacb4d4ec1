// The map: MapLibre GL over the built-in offline basemap. Vehicles at their GPSFixReport positions
// with a course arrow (colour by fix validity, stale and lost marked), their tracks, the
// GPSFixStatusReport origins and the CoMap world model's features by coverage.
import { useEffect, useMemo, useRef, useState, useSyncExternalStore } from "react";
import { addProtocol, LngLatBounds, Map as MapLibre, NavigationControl, ScaleControl, setWorkerUrl, type ExpressionSpecification, type GeoJSONSource, type MapMouseEvent } from "maplibre-gl";
import workerUrl from "maplibre-gl/dist/maplibre-gl-worker.mjs?url";
import { FetchSource, PMTiles, Protocol } from "pmtiles";
import "maplibre-gl/dist/maplibre-gl.css";

// the worker is a file of the build, served by the console like the rest of the dashboard
setWorkerUrl(workerUrl);
const pmtiles = new Protocol();
addProtocol("pmtiles", pmtiles.tile);
import { Panel } from "../components/Panel";
import { useChartConfigured, useNow, useSelector, useStore, useTrackedProviders, useWorldModel } from "../data/hooks";
import { useToken } from "../data/auth";
import { CHART_PATH, CHART_SOURCE, chartStyle } from "../lib/chart";
import { CoMapControls, CoMapOff, type MapTool } from "./CoMap";
import type { FeatureCollection } from "geojson";
import { useCollapsed, useDmsSetting } from "../data/settings";
import { report, select, type ProviderView } from "../data/store";
import { PALETTES, loadLand, offlineStyle, setPalette } from "../lib/basemap";
import { freshness } from "../lib/freshness";
import {
  EMPTY,
  bearingDeg,
  framePoints,
  middle,
  nearestVertex,
  coverageColor,
  distanceText,
  measureGeoJson,
  moveVertex,
  pathLengthM,
  positionText,
  tracksGeoJson,
  validPosition,
  vertexHandles,
  vehiclesGeoJson,
  withLiveCoverage,
  type LonLat,
  type VehicleMark,
} from "../lib/geo";
import { VehicleOverlay } from "../lib/mapOverlay";
import { countRender } from "../lib/renders";
import { useTheme } from "../lib/theme";
import { radToDeg } from "../lib/units";
import { shortId, vehicleColor } from "../lib/vehicle";

/** The vehicles, tracks and origins are redrawn at most this often (and only when they changed): a
 * redraw of the map costs a frame or more without a GPU, and vehicles at sea move a few metres a second. */
const MAP_UPDATE_MS = 1000;
/** The first view takes in the coast when it is this near the vehicles (a sea without a coast tells the
 * operator nothing of where the vehicles are), else the vehicles alone. */
const COAST_WITHIN_M = 60_000;
/** Closest zoom of a frame of the vehicles (a lone vehicle would else fill the map with a few metres of sea). */
const FRAME_MAX_ZOOM = 14;

const FIX_COLOR = ["match", ["get", "fix"], "valid", "#4caf50", "invalid", "#e0593f", "#9fb3c8"] as const;

function vehicleMark(p: ProviderView, now: number, selected: string | null): VehicleMark | null {
  const fix = report(p, "GPSFixReport");
  const st = report(p, "GPSFixStatusReport");
  const g = fix?.position2DWithTime?.geodeticPosition;
  const position = validPosition(g?.geodeticLatitude?.latitude, g?.geodeticLongitude?.longitude);
  if (!position) return null;
  const view = p.topics.GPSFixReport;
  const f = view ? freshness(Math.max(0, now - view.at), "GPSFixReport", view.interval, p.link) : "none";
  const link = p.link === "lost" || f === "lost" ? "lost" : f === "stale" ? "stale" : p.link === "regained" ? "regained" : "live";
  const course = typeof fix?.trueCourse === "number" && Number.isFinite(fix.trueCourse) ? ((radToDeg(fix.trueCourse) % 360) + 360) % 360 : null;
  return {
    id: p.id,
    label: p.name ?? shortId(p.id), // on the map: the name, or the short id of a vehicle without one
    position,
    courseDeg: course,
    fix: st?.fixValid === true ? "valid" : st?.fixValid === false ? "invalid" : "unknown",
    gpsPosition: fix?.GPSLatLongValid ?? null,
    link,
    selected: p.id === selected,
  };
}

function originOf(p: ProviderView): LonLat | null {
  const o = report(p, "GPSFixStatusReport")?.originPosition?.geodeticPosition;
  return validPosition(o?.geodeticLatitude?.latitude, o?.geodeticLongitude?.longitude);
}

/** A course arrow as an SDF image (coloured by the layer), pointing up (north) at rotation 0. */
function arrowImage(size = 32): ImageData {
  const c = document.createElement("canvas");
  c.width = c.height = size;
  const g = c.getContext("2d")!;
  g.fillStyle = "#fff";
  g.beginPath();
  g.moveTo(size / 2, 1);
  g.lineTo(size - 5, size - 3);
  g.lineTo(size / 2, size * 0.7);
  g.lineTo(5, size - 3);
  g.closePath();
  g.fill();
  return g.getImageData(0, 0, size, size);
}

function source(map: MapLibre, id: string): GeoJSONSource | undefined {
  return map.getSource(id) as GeoJSONSource | undefined;
}

function addLayers(map: MapLibre): void {
  for (const id of ["worldmodel", "tracks", "origins", "vehicles", "measure", "handles"]) map.addSource(id, { type: "geojson", data: EMPTY });
  map.addImage("course-arrow", arrowImage(), { sdf: true });
  map.addLayer({ id: "wm-fill", type: "fill", source: "worldmodel", filter: ["==", ["geometry-type"], "Polygon"], paint: { "fill-color": ["get", "color"], "fill-opacity": 0.25 } });
  map.addLayer({ id: "wm-line", type: "line", source: "worldmodel", paint: { "line-color": ["get", "color"], "line-width": ["case", ["get", "picked"], 5, 2] } });
  map.addLayer({ id: "wm-point", type: "circle", source: "worldmodel", filter: ["==", ["geometry-type"], "Point"], paint: { "circle-color": ["get", "color"], "circle-radius": 5 } });
  map.addLayer({
    id: "tracks",
    type: "line",
    source: "tracks",
    paint: { "line-color": ["get", "color"], "line-width": ["case", ["get", "selected"], 2.5, 1.5], "line-opacity": 0.8 },
  });
  map.addLayer({
    id: "origins",
    type: "circle",
    source: "origins",
    paint: { "circle-radius": 4, "circle-color": "#0000", "circle-stroke-color": ["get", "color"], "circle-stroke-width": 2 },
  });
  map.addLayer({
    id: "vehicle-link",
    type: "circle",
    source: "vehicles",
    filter: ["in", ["get", "link"], ["literal", ["stale", "lost"]]],
    paint: {
      "circle-radius": 15,
      "circle-color": "#0000",
      "circle-stroke-width": 2,
      "circle-stroke-color": ["match", ["get", "link"], "lost", "#e0593f", "#f5a623"],
    },
  });
  map.addLayer({
    id: "vehicle-dot",
    type: "circle",
    source: "vehicles",
    paint: {
      "circle-radius": ["case", ["get", "selected"], 9, 7],
      "circle-color": FIX_COLOR as unknown as ExpressionSpecification,
      "circle-opacity": ["case", ["==", ["get", "link"], "lost"], 0.4, 1],
      "circle-stroke-color": ["case", ["get", "selected"], "#ffffff", ["get", "color"]],
      "circle-stroke-width": ["case", ["get", "selected"], 3, 2],
    },
  });
  map.addLayer({
    id: "vehicle-arrow",
    type: "symbol",
    source: "vehicles",
    filter: ["get", "hasCourse"],
    layout: {
      "icon-image": "course-arrow",
      "icon-rotate": ["get", "course"],
      "icon-rotation-alignment": "map",
      "icon-allow-overlap": true,
      "icon-ignore-placement": true,
      "icon-offset": [0, -20],
      "icon-size": 0.7,
    },
    paint: { "icon-color": FIX_COLOR as unknown as ExpressionSpecification, "icon-halo-color": "#000", "icon-halo-width": 1 },
  });
  map.addLayer({ id: "measure-line", type: "line", source: "measure", paint: { "line-color": "#fff", "line-width": 2, "line-dasharray": [2, 2] } });
  map.addLayer({ id: "measure-point", type: "circle", source: "measure", filter: ["==", ["geometry-type"], "Point"], paint: { "circle-radius": 4, "circle-color": "#fff" } });
  // the edit tool's vertex handles, dragged to move a vertex
  map.addLayer({ id: "edit-handle", type: "circle", source: "handles", paint: { "circle-radius": 6, "circle-color": "#fff", "circle-stroke-color": "#1e88e5", "circle-stroke-width": 2 } });
}

/** The view that takes in every point (a jump: an animation would redraw the map every frame). */
function fitAll(map: MapLibre, points: LonLat[]): void {
  if (!points.length) return;
  const b = new LngLatBounds();
  for (const p of points) b.extend([p.lon, p.lat]);
  map.fitBounds(b, { padding: 60, maxZoom: FRAME_MAX_ZOOM, duration: 0 });
}

/** The pointer's position over the map, outside React state: a mouse move re-renders only the readout
 * (MapCursor), not the panel with its marks and sources. */
class CursorStore {
  private at: LonLat | null = null;
  private listeners = new Set<() => void>();
  get = (): LonLat | null => this.at;
  set(at: LonLat | null): void {
    this.at = at;
    for (const l of this.listeners) l();
  }
  subscribe = (l: () => void): (() => void) => {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  };
}

function MapCursor({ cursor, useDms }: { cursor: CursorStore; useDms: boolean }) {
  const at = useSyncExternalStore(cursor.subscribe, cursor.get);
  return <span data-testid="map-cursor">{at ? positionText(at.lat, at.lon, useDms) : "—"}</span>;
}

declare global {
  interface Window {
    __semMap?: MapLibre; // test hook: Playwright reads rendered features and projects positions
  }
}

export function MapPanel() {
  const providers = useTrackedProviders(MAP_UPDATE_MS);
  const selected = useSelector((s) => s.selected);
  const store = useStore();
  const now = useNow(1000);
  const worldModel = useWorldModel();
  const [useDms, setDms] = useDmsSetting();
  const chartConfigured = useChartConfigured();
  const token = useToken();
  const [chart, setChart] = useState<"none" | "loading" | "shown" | "failed">("none");
  const container = useRef<HTMLDivElement>(null);
  const mapRef = useRef<MapLibre | null>(null);
  const [ready, setReady] = useState(false);
  const [landDrawn, setLandDrawn] = useState(0);
  const [vehiclesDrawn, setVehiclesDrawn] = useState(0);
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
  const toolRef = useRef<MapTool>("select");
  const modelRef = useRef<FeatureCollection | null>(null); // what the edit tool moves vertices of
  const framed = useRef(false);
  const theme = useTheme();
  const themeRef = useRef(theme); // the theme a new map starts in
  const overlay = useRef<VehicleOverlay | null>(null);
  const land = useRef<FeatureCollection | null>(null); // the basemap's land, for the first view's coast
  const [landLoaded, setLandLoaded] = useState(false); // loaded or failed: the first view waits for it
  // what the map's sources hold now, to skip a setData that would change nothing
  const drawnData = useRef<{ vehicles: string; tracks: unknown[]; origins: string }>({ vehicles: "", tracks: [], origins: "" });

  const marks = useMemo(() => providers.map((p) => vehicleMark(p, now, selected)).filter((v): v is VehicleMark => v !== null), [providers, now, selected]);

  // the map itself, while the panel is open: a collapsed panel has no container, and a map kept
  // without one would still draw every update
  const [collapsed] = useCollapsed("map-panel");
  useEffect(() => {
    if (collapsed || !container.current) return;
    const map = new MapLibre({
      container: container.current!,
      style: offlineStyle(PALETTES[themeRef.current]),
      center: [0, 20],
      zoom: 1,
      attributionControl: { compact: true },
      maxPitch: 0,
      fadeDuration: 0, // no symbol fade: it would redraw the map every frame for 0.3 s after each update
      locale: { "Map.Title": "Map view" }, // the canvas's name: "Map" is the panel's (landmarks need distinct names)
    });
    mapRef.current = map;
    window.__semMap = map;
    map.addControl(new NavigationControl({ showCompass: true }), "top-right");
    map.addControl(new ScaleControl({ unit: "metric", maxWidth: 120 }), "bottom-left");
    map.addControl(new ScaleControl({ unit: "nautical", maxWidth: 120 }), "bottom-left");
    map.getCanvas().style.cursor = toolRef.current === "select" ? "" : "crosshair"; // a tool chosen before a collapse
    let alive = true;
    overlay.current = new VehicleOverlay(map, (m) => {
      // an edge arrow: that vehicle selected, in the middle of the map, and followed
      store.update((s) => select(s, m.id));
      map.jumpTo({ center: [m.position.lon, m.position.lat] });
      setFollow(true);
    });
    map.on("load", () => {
      addLayers(map);
      setReady(true);
      loadLand()
        .then((fc) => {
          if (!alive) return;
          land.current = fc;
          source(map, "land")?.setData(fc);
        })
        .catch(() => undefined)
        .finally(() => alive && setLandLoaded(true));
    });
    map.on("render", () => countRender("map:frame")); // the map's redraws (?renders only)
    // the edit tool: press on a vertex handle and drag it (the map does not pan meanwhile)
    let dragging: { featureId: unknown; index: number } | null = null;
    map.on("mousedown", "edit-handle", (e) => {
      const h = e.features?.[0]?.properties;
      if (toolRef.current !== "edit" || !h) return;
      e.preventDefault();
      dragging = { featureId: h.featureId, index: Number(h.index) };
    });
    // the drag ends when the button is released, over the map or anywhere else
    const endDrag = () => (dragging = null);
    map.on("mouseup", endDrag);
    window.addEventListener("mouseup", endDrag);
    map.on("mousemove", (e) => {
      cursor.set({ lon: e.lngLat.lng, lat: e.lngLat.lat });
      if (dragging && (e.originalEvent.buttons & 1) === 0) dragging = null; // released outside the window
      const model = modelRef.current;
      if (dragging && model) setDraft(moveVertex(model, dragging.featureId, dragging.index, { lon: e.lngLat.lng, lat: e.lngLat.lat }));
    });
    map.on("mouseenter", "edit-handle", () => toolRef.current === "edit" && (map.getCanvas().style.cursor = "move"));
    map.on("mouseleave", "edit-handle", () => toolRef.current === "edit" && (map.getCanvas().style.cursor = "crosshair"));
    map.on("mouseout", () => cursor.set(null));
    map.on("dragstart", () => setFollow(false)); // the operator pans away: stop following
    map.on("click", (e: MapMouseEvent) => {
      const at = { lon: e.lngLat.lng, lat: e.lngLat.lat };
      if (toolRef.current === "measure") return setMeasure((m) => [...m, at]);
      if (toolRef.current === "draw") return setDrawn((d) => [...d, at]);
      if (toolRef.current === "move-target") return setMoveTarget(at);
      if (toolRef.current === "edit") {
        const f = map.queryRenderedFeatures(e.point, { layers: ["edit-handle", "wm-point", "wm-line", "wm-fill"] })[0];
        return setPicked(f?.properties?.featureId ?? null);
      }
      const hit = map.queryRenderedFeatures(e.point, { layers: ["vehicle-dot", "vehicle-arrow"] })[0];
      const id = hit?.properties?.id as string | undefined;
      if (id) {
        store.update((s) => select(s, id));
        setFollow(true);
      }
    });
    map.on("mouseenter", "vehicle-dot", () => (map.getCanvas().style.cursor = "pointer"));
    map.on("mouseleave", "vehicle-dot", () => (map.getCanvas().style.cursor = ""));
    // what is drawn, for the operator's status line and the tests: counted from rendered features
    const count = setInterval(() => {
      if (!map.getLayer("vehicle-dot")) return; // layers not added yet
      setLandDrawn(map.queryRenderedFeatures({ layers: ["land"] }).length);
      setVehiclesDrawn(new Set(map.queryRenderedFeatures({ layers: ["vehicle-dot"] }).map((f) => f.properties?.id)).size);
    }, 1000);
    return () => {
      alive = false;
      clearInterval(count);
      window.removeEventListener("mouseup", endDrag);
      cursor.set(null);
      framed.current = false; // reopened: frame the vehicles again
      overlay.current?.destroy();
      overlay.current = null;
      if (window.__semMap === map) delete window.__semMap;
      map.remove();
      mapRef.current = null;
      drawnData.current = { vehicles: "", tracks: [], origins: "" };
      setReady(false);
    };
  }, [store, collapsed, cursor]);

  // the console's PMTiles chart, over the built-in land and under everything else
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map || !chartConfigured || map.getSource(CHART_SOURCE)) return;
    let current = true;
    const url = `${window.location.origin}${CHART_PATH}`;
    const archive = new PMTiles(new FetchSource(url, new Headers(token ? { Authorization: `Bearer ${token}` } : {})));
    pmtiles.add(archive);
    setTimeout(() => current && setChart("loading"));
    Promise.all([archive.getHeader(), archive.getMetadata().catch(() => null)])
      .then(([header, metadata]) => {
        if (!current || map.getSource(CHART_SOURCE)) return;
        const { source: src, layers } = chartStyle(url, header, metadata);
        map.addSource(CHART_SOURCE, src);
        for (const layer of layers) map.addLayer(layer, "wm-fill");
        setChart("shown");
      })
      .catch(() => current && setChart("failed"));
    return () => {
      current = false;
    };
  }, [ready, chartConfigured, token]);

  useEffect(() => {
    toolRef.current = tool;
    const map = mapRef.current;
    if (map) map.getCanvas().style.cursor = tool === "select" ? "" : "crosshair";
  }, [tool]);

  // layers' data
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const fc = vehiclesGeoJson(marks);
    for (const f of fc.features) f.properties = { ...f.properties, color: vehicleColor(String(f.properties?.id)) };
    const json = JSON.stringify(fc);
    if (json === drawnData.current.vehicles) return; // nothing moved or changed: no redraw
    drawnData.current.vehicles = json;
    source(map, "vehicles")?.setData(fc);
    countRender("map:vehicles-data");
  }, [ready, marks]);

  // the names and edge arrows, at the same bounded rate as the vehicles' data
  useEffect(() => {
    if (ready) overlay.current?.set(marks);
  }, [ready, marks]);

  // a change of theme recolours the basemap (three paint properties)
  useEffect(() => {
    themeRef.current = theme;
    const map = mapRef.current;
    if (ready && map) setPalette(map, PALETTES[theme]);
  }, [ready, theme]);

  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    // a track changes once a second at most; the same arrays and selection need no redraw
    const tracks = [selected, ...providers.flatMap((p) => [p.id, p.track])];
    const last = drawnData.current.tracks;
    if (tracks.length !== last.length || tracks.some((t, i) => t !== last[i])) {
      drawnData.current.tracks = tracks;
      const fc = tracksGeoJson(providers.map((p) => ({ id: p.id, selected: p.id === selected, points: p.track })));
      for (const f of fc.features) f.properties = { ...f.properties, color: vehicleColor(String(f.properties?.id)) };
      source(map, "tracks")?.setData(fc);
      countRender("map:tracks-data");
    }
    const origins = providers.flatMap((p) => {
      const o = originOf(p);
      return o ? [{ type: "Feature" as const, geometry: { type: "Point" as const, coordinates: [o.lon, o.lat] }, properties: { id: p.id, color: vehicleColor(p.id) } }] : [];
    });
    const json = JSON.stringify(origins);
    if (json === drawnData.current.origins) return;
    drawnData.current.origins = json;
    source(map, "origins")?.setData({ type: "FeatureCollection", features: origins });
  }, [ready, providers, selected]);

  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const model = shownModel;
    modelRef.current = model;
    const features = (model?.features ?? []).map((f) => ({
      ...f,
      properties: { ...f.properties, color: coverageColor(f.properties?.coverage ?? null), picked: tool === "edit" && picked !== null && f.properties?.featureId === picked },
    }));
    source(map, "worldmodel")?.setData({ type: "FeatureCollection", features });
    source(map, "handles")?.setData(tool === "edit" ? vertexHandles(model) : EMPTY);
  }, [ready, shownModel, tool, picked]);

  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const shown = tool === "measure" ? measure : tool === "draw" ? drawn : tool === "move-target" && moveTarget ? [moveTarget] : [];
    source(map, "measure")?.setData(measureGeoJson(shown));
  }, [ready, measure, drawn, moveTarget, tool]);

  // first frame: every vehicle in view, and the coast when it is near; then follow the selected one unless
  // the operator panned away
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map || !marks.length) return;
    if (!framed.current) {
      if (!landLoaded) return; // a moment: the coast is part of the first view
      framed.current = true;
      const positions = marks.map((m) => m.position);
      const sel = marks.find((m) => m.selected);
      const centre = (follow && sel ? sel.position : middle(positions))!;
      const coast = land.current ? nearestVertex(land.current, centre, COAST_WITHIN_M) : null;
      fitAll(map, framePoints(positions, coast, centre));
      return;
    }
    const sel = marks.find((m) => m.selected);
    if (!follow || !sel) return;
    // a jump, not an animation (an animation redraws the map every frame); none when it has not moved a pixel
    const at = map.project([sel.position.lon, sel.position.lat]);
    const mid = map.project(map.getCenter());
    if (Math.hypot(at.x - mid.x, at.y - mid.y) >= 1) map.jumpTo({ center: [sel.position.lon, sel.position.lat] });
  }, [ready, marks, follow, landLoaded]);

  const measured = pathLengthM(measure);
  const lastLeg = measure.length >= 2 ? bearingDeg(measure[measure.length - 2], measure[measure.length - 1]) : null;
  return (
    <Panel
      title="Map"
      testId="map-panel"
      className="map-panel"
      actions={
        <div className="map-tools">
          <button className="small" aria-pressed={follow} onClick={() => setFollow(!follow)} data-testid="map-follow" title="keep the selected vehicle in view">
            Follow
          </button>
          <button
            className="small"
            data-testid="map-fit-all"
            disabled={!marks.length}
            title="every vehicle with a position in view (stops following)"
            onClick={() => {
              const map = mapRef.current;
              if (!map) return;
              setFollow(false); // following would take the view back to one vehicle
              fitAll(map, marks.map((m) => m.position));
            }}
          >
            Fit all
          </button>
          <button
            className="small"
            aria-pressed={measuring}
            data-testid="map-measure"
            onClick={() => {
              setTool(measuring ? "select" : "measure");
              setMeasure([]);
            }}
            title="click points on the map to measure the distance along them"
          >
            Measure
          </button>
          <button className="small" onClick={() => setDms(!useDms)} aria-pressed={useDms} title="coordinates in degrees-minutes-seconds or decimal degrees">
            {useDms ? "DMS" : "Decimal"}
          </button>
        </div>
      }
    >
      <div className="map-wrap">
        <div ref={container} className="map" data-testid="map" data-ready={ready} data-land={landDrawn} data-vehicles={vehiclesDrawn} />
        <div className="map-status">
          <MapCursor cursor={cursor} useDms={useDms} />
          {chart !== "none" && <span data-testid="map-chart" className={chart === "failed" ? "error" : undefined}>chart: {chart === "failed" ? "cannot be read" : chart}</span>}
          <span data-testid="map-vehicle-count">{vehiclesDrawn} of {providers.length} vehicles drawn</span>
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
      <p className="map-legend muted">
        <span className="lg lg-valid">fix valid</span> <span className="lg lg-invalid">no fix</span> <span className="lg lg-unknown">unknown</span> · ring: stale (amber) or lost (red) · ○ origin
        {worldModel ? " · areas: covered (green), partial (amber), not (red)" : ""}
      </p>
    </Panel>
  );
}
