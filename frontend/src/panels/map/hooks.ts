// The map panel's parts, each a hook over the one MapLibre map: the map itself, the pointer and its tools, and
// one hook per layer. Each reads the map from `mapRef` once it is `ready` (loaded, layers added).
import { Map as MapLibre, NavigationControl, ScaleControl, addProtocol, type MapMouseEvent } from "maplibre-gl";
import { FetchSource, PMTiles, Protocol } from "pmtiles";
import { useEffect, useRef, useState, type Dispatch, type RefObject, type SetStateAction } from "react";
import type { FeatureCollection } from "geojson";
import type { Store } from "../../data/connection";
import { cancelFrame, onFrame } from "../../data/frame";
import { select, type ProviderView } from "../../data/store";
import { PALETTES, loadLand, offlineStyle, setPalette } from "../../lib/basemap";
import { CHART_PATH, CHART_SOURCE, chartStyle } from "../../lib/chart";
import {
  EMPTY,
  coverageColor,
  framePoints,
  measureGeoJson,
  middle,
  moveVertex,
  nearestVertex,
  tracksGeoJson,
  vehiclesGeoJson,
  vertexHandles,
  type LonLat,
  type VehicleMark,
} from "../../lib/geo";
import "../../lib/mapWorker"; // its worker started (boot.ts started it already)
import { VehicleOverlay } from "../../lib/mapOverlay";
import { countRender } from "../../lib/renders";
import type { Theme } from "../../lib/theme";
import { vehicleColor } from "../../lib/vehicle";
import type { MapTool } from "../CoMap";
import type { CursorStore } from "./MapCursor";
import { VEHICLE_DOTS, VEHICLE_HITS, addLayers, fitAll, originOf, source } from "./layers";
import { setBatched } from "./repaints";
import "maplibre-gl/dist/maplibre-gl.css";

const pmtiles = new Protocol();
addProtocol("pmtiles", pmtiles.tile);

/** The first view takes in the coast when it is this near the vehicles (a sea without a coast tells the
 * operator nothing of where the vehicles are), else the vehicles alone. */
const COAST_WITHIN_M = 60_000;

declare global {
  interface Window {
    __semMap?: MapLibre; // test hook: Playwright reads rendered features and projects positions
  }
}

export type MapRef = RefObject<MapLibre | null>;

/** The map itself, while the panel is open (a collapsed panel has no container, and a map kept without one would
 * still draw every update), in the theme's basemap colours; `ready` once loaded with the layers added. */
export function useMapInstance(container: RefObject<HTMLDivElement | null>, collapsed: boolean, theme: Theme): { mapRef: MapRef; ready: boolean } {
  const mapRef = useRef<MapLibre | null>(null);
  const [ready, setReady] = useState(false);
  const themeRef = useRef(theme); // the theme a new map starts in
  useEffect(() => {
    if (collapsed || !container.current) return;
    const map = new MapLibre({
      container: container.current,
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
    map.on("load", () => {
      addLayers(map);
      setReady(true);
    });
    map.on("render", () => countRender("map:frame")); // the map's redraws (?renders only)
    return () => {
      if (window.__semMap === map) delete window.__semMap;
      map.remove();
      mapRef.current = null;
      setReady(false);
    };
  }, [collapsed, container]);
  // a change of theme recolours the basemap (three paint properties)
  useEffect(() => {
    themeRef.current = theme;
    const map = mapRef.current;
    if (ready && map) setPalette(map, PALETTES[theme]);
  }, [ready, theme]);
  return { mapRef, ready };
}

/** The basemap's land, for the first view's coast: loaded into each new map; `landLoaded` once loaded or failed
 * (the first view waits for it). */
export function useLand(mapRef: MapRef, ready: boolean): { land: RefObject<FeatureCollection | null>; landLoaded: boolean } {
  const land = useRef<FeatureCollection | null>(null);
  const [landLoaded, setLandLoaded] = useState(false);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    let alive = true;
    loadLand()
      .then((fc) => {
        if (!alive) return;
        land.current = fc;
        source(map, "land")?.setData(fc);
      })
      .catch(() => undefined)
      .finally(() => alive && setLandLoaded(true));
    return () => {
      alive = false;
    };
  }, [mapRef, ready]);
  return { land, landLoaded };
}

export type ChartState = "none" | "loading" | "shown" | "failed";

/** The console's PMTiles chart (when it serves one), over the built-in land and under everything else. */
export function useChart(mapRef: MapRef, ready: boolean, chartConfigured: boolean, token: string | null): ChartState {
  const [chart, setChart] = useState<ChartState>("none");
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
  }, [mapRef, ready, chartConfigured, token]);
  return chart;
}

/** What a click, a drag and the pointer do on the map, by tool. */
export interface PointerActions {
  store: Store;
  cursor: CursorStore;
  setFollow: Dispatch<SetStateAction<boolean>>;
  setMeasure: Dispatch<SetStateAction<LonLat[]>>;
  setDrawn: Dispatch<SetStateAction<LonLat[]>>;
  setMoveTarget: Dispatch<SetStateAction<LonLat | null>>;
  setPicked: Dispatch<SetStateAction<unknown>>;
  setDraft: Dispatch<SetStateAction<FeatureCollection | null>>;
}

/** The pointer on the map: its position (the cursor readout), a click by tool (measure, draw, move-target, edit's
 * pick, else select a vehicle), the edit tool's vertex drag over `modelRef`'s model, and the canvas's cursor. */
export function usePointer(mapRef: MapRef, ready: boolean, tool: MapTool, modelRef: RefObject<FeatureCollection | null>, actions: PointerActions): void {
  const toolRef = useRef<MapTool>(tool);
  const { store, cursor, setFollow, setMeasure, setDrawn, setMoveTarget, setPicked, setDraft } = actions;
  useEffect(() => {
    toolRef.current = tool;
    const map = mapRef.current;
    if (map) map.getCanvas().style.cursor = tool === "select" ? "" : "crosshair";
  }, [mapRef, ready, tool]);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const canvas = map.getCanvas();
    // the edit tool: press on a vertex handle and drag it (the map does not pan meanwhile)
    let dragging: { featureId: unknown; index: number } | null = null;
    const startDrag = (e: MapMouseEvent & { features?: { properties: Record<string, unknown> }[] }) => {
      const h = e.features?.[0]?.properties;
      if (toolRef.current !== "edit" || !h) return;
      e.preventDefault();
      dragging = { featureId: h.featureId, index: Number(h.index) };
    };
    // the drag ends when the button is released, over the map or anywhere else
    const endDrag = () => (dragging = null);
    const move = (e: MapMouseEvent) => {
      cursor.set({ lon: e.lngLat.lng, lat: e.lngLat.lat });
      if (dragging && (e.originalEvent.buttons & 1) === 0) dragging = null; // released outside the window
      const model = modelRef.current;
      if (dragging && model) setDraft(moveVertex(model, dragging.featureId, dragging.index, { lon: e.lngLat.lng, lat: e.lngLat.lat }));
    };
    const overHandle = () => toolRef.current === "edit" && (canvas.style.cursor = "move");
    const offHandle = () => toolRef.current === "edit" && (canvas.style.cursor = "crosshair");
    const out = () => cursor.set(null);
    const panned = () => setFollow(false); // the operator pans away: stop following
    const click = (e: MapMouseEvent) => {
      const at = { lon: e.lngLat.lng, lat: e.lngLat.lat };
      if (toolRef.current === "measure") return setMeasure((m) => [...m, at]);
      if (toolRef.current === "draw") return setDrawn((d) => [...d, at]);
      if (toolRef.current === "move-target") return setMoveTarget(at);
      if (toolRef.current === "edit") {
        const f = map.queryRenderedFeatures(e.point, { layers: ["edit-handle", "wm-point", "wm-line", "wm-fill"] })[0];
        return setPicked(f?.properties?.featureId ?? null);
      }
      const hit = map.queryRenderedFeatures(e.point, { layers: VEHICLE_HITS })[0];
      const id = hit?.properties?.id as string | undefined;
      if (id) {
        store.update((s) => select(s, id));
        setFollow(true);
      }
    };
    const overVehicle = () => (canvas.style.cursor = "pointer");
    const offVehicle = () => (canvas.style.cursor = "");
    map.on("mousedown", "edit-handle", startDrag);
    map.on("mouseup", endDrag);
    window.addEventListener("mouseup", endDrag);
    map.on("mousemove", move);
    map.on("mouseenter", "edit-handle", overHandle);
    map.on("mouseleave", "edit-handle", offHandle);
    map.on("mouseout", out);
    map.on("dragstart", panned);
    map.on("click", click);
    map.on("mouseenter", "vehicle-dot", overVehicle);
    map.on("mouseleave", "vehicle-dot", offVehicle);
    return () => {
      map.off("mousedown", "edit-handle", startDrag);
      map.off("mouseup", endDrag);
      window.removeEventListener("mouseup", endDrag);
      map.off("mousemove", move);
      map.off("mouseenter", "edit-handle", overHandle);
      map.off("mouseleave", "edit-handle", offHandle);
      map.off("mouseout", out);
      map.off("dragstart", panned);
      map.off("click", click);
      map.off("mouseenter", "vehicle-dot", overVehicle);
      map.off("mouseleave", "vehicle-dot", offVehicle);
      cursor.set(null);
    };
  }, [mapRef, ready, modelRef, store, cursor, setFollow, setMeasure, setDrawn, setMoveTarget, setPicked, setDraft]);
}

/** The marks of the vehicle layer: the fleet's at its rate (`fleet` without the selected vehicle, `selected`, `all`),
 * and the selected vehicle's newest (on every frame after its fix). */
export interface VehicleMarks {
  fleet: VehicleMark[];
  selected: VehicleMark | null;
  all: VehicleMark[];
  newest: VehicleMark | null;
}

/** The vehicles: the map's dots and course arrows at the fleet's rate, the fleet's and the selected vehicle's each in
 * a source of its own, updated only when its marks changed; every vehicle's name and edge arrow (an edge arrow's
 * click: `onPick`); and the selected vehicle's ring at its newest position, moved without redrawing the map. */
export function useVehicleLayer(mapRef: MapRef, ready: boolean, marks: VehicleMarks, onPick: (map: MapLibre, m: VehicleMark) => void): void {
  const { fleet, selected, all, newest } = marks;
  const overlay = useRef<VehicleOverlay | null>(null);
  const drawn = useRef<Drawn>({ map: null, vehicles: "", selected: "" });
  const pick = useRef(onPick);
  useEffect(() => {
    pick.current = onPick;
  }, [onPick]);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const o = new VehicleOverlay(map, (m) => pick.current(map, m));
    overlay.current = o;
    return () => {
      o.destroy();
      if (overlay.current === o) overlay.current = null;
    };
  }, [mapRef, ready]);
  useEffect(() => {
    const map = mapRef.current;
    if (ready && map) setVehicles(drawn, map, "vehicles", fleet);
  }, [mapRef, ready, fleet]);
  useEffect(() => {
    const map = mapRef.current;
    if (ready && map) setVehicles(drawn, map, "selected", selected ? [selected] : []);
  }, [mapRef, ready, selected]);
  // the names and edge arrows, at the same bounded rate as the vehicles' data
  useEffect(() => {
    if (ready) overlay.current?.set(all);
  }, [ready, all]);
  useEffect(() => {
    if (ready) overlay.current?.setSelected(newest);
  }, [ready, newest]);
}

type Drawn = { map: MapLibre | null; vehicles: string; selected: string }; // what the vehicle sources hold now

/** Vehicle source `id` of `map` set to `marks`, only when they moved or changed (no redraw else). */
function setVehicles(drawn: RefObject<Drawn>, map: MapLibre, id: "vehicles" | "selected", marks: VehicleMark[]): void {
  const fc = vehiclesGeoJson(marks);
  for (const f of fc.features) f.properties = { ...f.properties, color: vehicleColor(String(f.properties?.id)) };
  const json = JSON.stringify(fc);
  if (drawn.current.map === map && json === drawn.current[id]) return;
  drawn.current = drawn.current.map === map ? { ...drawn.current, [id]: json } : { map, vehicles: "", selected: "", [id]: json };
  setBatched(map, id, fc);
  countRender(`map:${id}-data`);
}

/** The vehicles' tracks (the selected one wider) and their GPSFixStatusReport origins. */
export function useTrackLayer(mapRef: MapRef, ready: boolean, providers: ProviderView[], selected: string | null): void {
  const drawn = useRef<{ map: MapLibre | null; tracks: unknown[]; origins: string }>({ map: null, tracks: [], origins: "" });
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    if (drawn.current.map !== map) drawn.current = { map, tracks: [], origins: "" }; // a new map holds nothing
    // a track changes once a second at most; the same arrays and selection need no redraw
    const tracks = [selected, ...providers.flatMap((p) => [p.id, p.track])];
    const last = drawn.current.tracks;
    if (tracks.length !== last.length || tracks.some((t, i) => t !== last[i])) {
      drawn.current.tracks = tracks;
      const fc = tracksGeoJson(providers.map((p) => ({ id: p.id, selected: p.id === selected, points: p.track })));
      for (const f of fc.features) f.properties = { ...f.properties, color: vehicleColor(String(f.properties?.id)) };
      setBatched(map, "tracks", fc);
      countRender("map:tracks-data");
    }
    const origins = providers.flatMap((p) => {
      const o = originOf(p);
      return o ? [{ type: "Feature" as const, geometry: { type: "Point" as const, coordinates: [o.lon, o.lat] }, properties: { id: p.id, color: vehicleColor(p.id) } }] : [];
    });
    const json = JSON.stringify(origins);
    if (json === drawn.current.origins) return;
    drawn.current.origins = json;
    setBatched(map, "origins", { type: "FeatureCollection", features: origins });
  }, [mapRef, ready, providers, selected]);
}

/** The CoMap world model's features by coverage (the picked one wider) and, in the edit tool, its vertex handles;
 * `modelRef` holds the model shown (what a vertex drag moves). */
export function useWorldModelLayer(mapRef: MapRef, ready: boolean, model: FeatureCollection | null, tool: MapTool, picked: unknown, modelRef: RefObject<FeatureCollection | null>): void {
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    modelRef.current = model;
    const features = (model?.features ?? []).map((f) => ({
      ...f,
      properties: { ...f.properties, color: coverageColor(f.properties?.coverage ?? null), picked: tool === "edit" && picked !== null && f.properties?.featureId === picked },
    }));
    source(map, "worldmodel")?.setData({ type: "FeatureCollection", features });
    source(map, "handles")?.setData(tool === "edit" ? vertexHandles(model) : EMPTY);
  }, [mapRef, ready, model, tool, picked, modelRef]);
}

/** The points of the tool in use: the measured path, the area being drawn, or the Move-to destination. */
export function useMeasureLayer(mapRef: MapRef, ready: boolean, points: LonLat[]): void {
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    source(map, "measure")?.setData(measureGeoJson(points));
  }, [mapRef, ready, points]);
}

/** The first frame of each map: every vehicle in view, and the coast when it is near; then the selected vehicle
 * followed (unless the operator panned away). */
export function useFitAll(mapRef: MapRef, ready: boolean, marks: VehicleMark[], follow: boolean, land: RefObject<FeatureCollection | null>, landLoaded: boolean): void {
  const framed = useRef<MapLibre | null>(null); // the map that had its first frame: a reopened panel's is framed again
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map || !marks.length) return;
    if (framed.current !== map) {
      if (!landLoaded) return; // a moment: the coast is part of the first view
      framed.current = map;
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
  }, [mapRef, ready, marks, follow, land, landLoaded]);
}

/** What is drawn, for the operator's status line and the tests: counted from rendered features once a second, on the
 * frame (a hidden page draws nothing, so it counts nothing: a count of rendered features is a search of them). */
export function useDrawnCounts(mapRef: MapRef, ready: boolean): { landDrawn: number; vehiclesDrawn: number } {
  const [landDrawn, setLandDrawn] = useState(0);
  const [vehiclesDrawn, setVehiclesDrawn] = useState(0);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const count = () => {
      if (!map.getLayer("selected-dot")) return; // layers not added yet
      setLandDrawn(map.queryRenderedFeatures({ layers: ["land"] }).length);
      setVehiclesDrawn(new Set(map.queryRenderedFeatures({ layers: VEHICLE_DOTS }).map((f) => f.properties?.id)).size);
    };
    const every = setInterval(() => onFrame(count), 1000);
    return () => {
      clearInterval(every);
      cancelFrame(count);
    };
  }, [mapRef, ready]);
  return { landDrawn, vehiclesDrawn };
}
