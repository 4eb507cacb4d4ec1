// The map panel's parts, each a hook over the one MapLibre map: the map itself, the pointer and its tools, and
// one hook per layer. Each reads the map from `mapRef` once it is `ready` (loaded, layers added).
import { Map as MapLibre, NavigationControl, ScaleControl, addProtocol, type MapMouseEvent } from "maplibre-gl";
import { FetchSource, PMTiles, Protocol } from "pmtiles";
import { useEffect, useRef, useState, type Dispatch, type RefObject, type SetStateAction } from "react";
import type { FeatureCollection } from "geojson";
import { PALETTES, addLand, loadLand, offlineStyle, setPalette } from "../../lib/basemap";
import { CHART_PATH, CHART_SOURCE, chartStyle } from "../../lib/chart";
import {
  EMPTY,
  coverageColor,
  framePoints,
  measureGeoJson,
  middle,
  moveVertex,
  nearestVertex,
  vertexHandles,
  type LonLat,
  type VehicleMark,
} from "../../lib/geo";
import "../../lib/mapWorker"; // its worker started (boot.ts started it already)
import { VehicleOverlay } from "../../lib/mapOverlay";
import { countRender } from "../../lib/renders";
import type { Theme } from "../../lib/theme";
import type { MapTool } from "../CoMap/CoMap";
import { FleetCanvas, type FleetData, type ToolMarks } from "./FleetCanvas";
import type { CursorStore } from "./MapCursor";
import { outsideMiddle } from "./fleet";
import { addLayers, countLandInView, fitAll, landRings, source } from "./layers";
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
export function useMapInstance(
  container: RefObject<HTMLDivElement | null>,
  collapsed: boolean,
  theme: Theme,
): { mapRef: MapRef; ready: boolean } {
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
      addLand(map, PALETTES[themeRef.current]);
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

/** True once the map, `ready`, has drawn and settled (its first `idle`, or a second at most): for what the first
 * screen can do without (the vehicles' stored tracks, 50 requests and their answers with 50 vehicles), so it waits
 * for the map's first frames instead of the other way round. */
export function useSettled(mapRef: MapRef, ready: boolean): boolean {
  const [settled, setSettled] = useState(false);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return setSettled(false);
    const settle = () => setSettled(true);
    const timer = setTimeout(settle, 1000);
    map.once("idle", settle);
    return () => {
      clearTimeout(timer);
      map.off("idle", settle);
    };
  }, [mapRef, ready]);
  return settled;
}

/** The basemap's land, for the first view's coast: loaded for each new map; `landLoaded` once loaded or failed
 * (the first view waits for it; useLandSource draws it). `landDrawn`: how many of its polygons are in view, for the
 * operator's status line and the tests, counted from the land's own polygons when the camera stops (a search of the
 * map's rendered features, once a second, was a task of its own). */
export function useLand(
  mapRef: MapRef,
  ready: boolean,
): { land: RefObject<FeatureCollection | null>; landLoaded: boolean; landDrawn: number } {
  const land = useRef<FeatureCollection | null>(null);
  const [landLoaded, setLandLoaded] = useState(false);
  const [landDrawn, setLandDrawn] = useState(0);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    let alive = true;
    let rings: ReturnType<typeof landRings> = [];
    const count = () => {
      const b = map.getBounds();
      setLandDrawn(countLandInView(rings, { west: b.getWest(), south: b.getSouth(), east: b.getEast(), north: b.getNorth() }));
    };
    map.on("moveend", count);
    loadLand()
      .then((fc) => {
        if (!alive) return;
        land.current = fc;
        rings = landRings(fc);
        count();
      })
      .catch(() => undefined)
      .finally(() => alive && setLandLoaded(true));
    return () => {
      alive = false;
      map.off("moveend", count);
    };
  }, [mapRef, ready]);
  return { land, landLoaded, landDrawn };
}

/** The land drawn into each map once, when `show`: from the first view of the fleet on (or at once, with no fleet to
 * frame). Drawn at the map's load, the whole world's coast was tiled and drawn at zoom 1 for the frames before the
 * jump to the fleet: 3 of a page load's 8 map frames, each a WebGL frame read back for the page's compositing. */
export function useLandSource(
  mapRef: MapRef,
  ready: boolean,
  land: RefObject<FeatureCollection | null>,
  landLoaded: boolean,
  show: boolean,
): void {
  const drawnInto = useRef<MapLibre | null>(null);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map || !landLoaded || !show || !land.current || drawnInto.current === map) return;
    drawnInto.current = map;
    source(map, "land")?.setData(land.current);
  }, [mapRef, ready, land, landLoaded, show]);
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
  selectVehicle: (providerId: string) => void;
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
export function usePointer(
  mapRef: MapRef,
  ready: boolean,
  tool: MapTool,
  modelRef: RefObject<FeatureCollection | null>,
  fleetRef: RefObject<FleetCanvas | null>,
  actions: PointerActions,
): void {
  const toolRef = useRef<MapTool>(tool);
  const { selectVehicle, cursor, setFollow, setMeasure, setDrawn, setMoveTarget, setPicked, setDraft } = actions;
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
    let overVehicle = false;
    const move = (e: MapMouseEvent) => {
      cursor.set({ lon: e.lngLat.lng, lat: e.lngLat.lat });
      if (dragging && (e.originalEvent.buttons & 1) === 0) dragging = null; // released outside the window
      const model = modelRef.current;
      if (dragging && model)
        setDraft(moveVertex(model, dragging.featureId, dragging.index, { lon: e.lngLat.lng, lat: e.lngLat.lat }));
      // the pointer over a vehicle (the fleet is drawn on a canvas of our own: hit in what it drew)
      const fleet = fleetRef.current;
      const over = toolRef.current === "select" && fleet !== null && (fleet.hit(e.point) ?? fleet.cluster(e.point)) !== null;
      if (over !== overVehicle) {
        overVehicle = over;
        // off it: the tool's cursor (a tool chosen while over a vehicle: its crosshair, not the select tool's)
        canvas.style.cursor = over ? "pointer" : toolRef.current === "select" ? "" : "crosshair";
      }
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
      const id = fleetRef.current?.hit(e.point);
      if (id) {
        selectVehicle(id);
        setFollow(true);
        return;
      }
      // a cluster: zoomed in on it, until its vehicles are drawn apart
      const cluster = fleetRef.current?.cluster(e.point);
      if (cluster) map.easeTo({ center: map.unproject([cluster.x, cluster.y]), zoom: map.getZoom() + 2 });
    };
    map.on("mousedown", "edit-handle", startDrag);
    map.on("mouseup", endDrag);
    window.addEventListener("mouseup", endDrag);
    map.on("mousemove", move);
    map.on("mouseenter", "edit-handle", overHandle);
    map.on("mouseleave", "edit-handle", offHandle);
    map.on("mouseout", out);
    map.on("dragstart", panned);
    map.on("click", click);
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
      cursor.set(null);
    };
  }, [
    mapRef,
    ready,
    modelRef,
    fleetRef,
    selectVehicle,
    cursor,
    setFollow,
    setMeasure,
    setDrawn,
    setMoveTarget,
    setPicked,
    setDraft,
  ]);
}

/** The vehicles: every vehicle's dot, course arrow, track and origin on the fleet's canvas (`data`, at the fleet's
 * rate; no map redraw) and its name and edge arrow (an edge arrow's click: `onPick`). `fleetRef` holds the canvas (what
 * a click hits); `onCount`: the number of vehicles in view; `tools`: the tools' points, drawn over the fleet. Returns the overlay (null until the map is ready), whose
 * selected vehicle's ring `useSelectedRing` moves: a component of its own, so that a fix of the selected vehicle
 * renders that component only, not the map panel. */
export function useVehicleLayer(
  mapRef: MapRef,
  ready: boolean,
  fleetRef: RefObject<FleetCanvas | null>,
  data: FleetData,
  onPick: (map: MapLibre, m: VehicleMark) => void,
  onCount: (n: number) => void,
  tools: ToolMarks,
): VehicleOverlay | null {
  // state, not a ref: the ring's component (a child, whose effects run before these) is given it once it exists
  const [overlay, setOverlay] = useState<VehicleOverlay | null>(null);
  const pick = useRef(onPick);
  const count = useRef(onCount);
  useEffect(() => {
    pick.current = onPick;
    count.current = onCount;
  }, [onPick, onCount]);
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    const o = new VehicleOverlay(map, (m) => pick.current(map, m));
    const c = new FleetCanvas(
      map,
      (n) => count.current(n),
      (ids) => o.setClustered(ids), // a vehicle in a cluster: its name not shown
    );
    fleetRef.current = c;
    setOverlay(o);
    return () => {
      o.destroy();
      c.destroy();
      count.current(0); // nothing drawn until the next map's first view
      setOverlay((now) => (now === o ? null : now));
      if (fleetRef.current === c) fleetRef.current = null;
    };
  }, [mapRef, ready, fleetRef]);
  useEffect(() => {
    if (!ready) return;
    fleetRef.current?.set(data);
    countRender("map:fleet-data");
    // the names and edge arrows, at the same rate
    overlay?.set(data.marks);
  }, [ready, fleetRef, data, overlay]);
  // the tools' points over the fleet (a vehicle's dot no longer hides them); again on a new map's canvas (`overlay`
  // is made with it)
  useEffect(() => {
    if (ready) fleetRef.current?.setTools(tools);
  }, [ready, fleetRef, tools, overlay]);
  return overlay;
}

/** The selected vehicle's ring on `overlay` at its `newest` mark (on every frame after its fix). */
export function useSelectedRing(overlay: VehicleOverlay | null, newest: VehicleMark | null): void {
  useEffect(() => {
    overlay?.setSelected(newest);
  }, [overlay, newest]);
}

/** The CoMap world model's features by coverage (the picked one wider) and, in the edit tool, its vertex handles;
 * `modelRef` holds the model shown (what a vertex drag moves). */
export function useWorldModelLayer(
  mapRef: MapRef,
  ready: boolean,
  model: FeatureCollection | null,
  tool: MapTool,
  picked: unknown,
  modelRef: RefObject<FeatureCollection | null>,
): void {
  useEffect(() => {
    const map = mapRef.current;
    if (!ready || !map) return;
    modelRef.current = model;
    const features = (model?.features ?? []).map((f) => ({
      ...f,
      properties: {
        ...f.properties,
        color: coverageColor(f.properties?.coverage ?? null),
        picked: tool === "edit" && picked !== null && f.properties?.featureId === picked,
      },
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
 * followed (unless the operator panned away): centred when following starts or another vehicle is selected, then
 * centred again only when it leaves the middle of the map (a jump redraws the basemap: jumping after every metre
 * redrew it at the fleet's rate). */
export function useFitAll(
  mapRef: MapRef,
  ready: boolean,
  marks: VehicleMark[],
  follow: boolean,
  land: RefObject<FeatureCollection | null>,
  landLoaded: boolean,
): boolean {
  const framed = useRef<MapLibre | null>(null); // the map that had its first frame: a reopened panel's is framed again
  const [isFramed, setFramed] = useState(false); // the same, for the render
  const centred = useRef<string | null>(null); // the vehicle centred since following started
  useEffect(() => {
    if (!follow) centred.current = null;
    const map = mapRef.current;
    if (!ready || !map) {
      framed.current = null;
      setFramed(false);
      return;
    }
    if (!marks.length) return;
    const sel = marks.find((m) => m.selected);
    if (framed.current !== map) {
      if (!landLoaded) return; // a moment: the coast is part of the first view
      framed.current = map;
      centred.current = follow && sel ? sel.id : null;
      const positions = marks.map((m) => m.position);
      const centre = (follow && sel ? sel.position : middle(positions))!;
      const coast = land.current ? nearestVertex(land.current, centre, COAST_WITHIN_M) : null;
      fitAll(map, framePoints(positions, coast, centre));
      // framed now, whether or not the map moved: fitAll jumps at once, and moves nothing when the frame cannot fit
      // (a map under 120 px either way, its padding): waiting for a moveend there left the fleet undrawn for good
      queueMicrotask(() => framed.current === map && setFramed(true));
      return;
    }
    if (!follow || !sel) return;
    // a jump, not an animation (an animation redraws the map every frame)
    const at = map.project([sel.position.lon, sel.position.lat]);
    // the map's size from its canvas's pixels: reading the container's (a layout) after React's commit forced one
    const w = map.getCanvas().width / map.getPixelRatio();
    const h = map.getCanvas().height / map.getPixelRatio();
    if (centred.current === sel.id && !outsideMiddle(at, w, h)) return;
    centred.current = sel.id;
    map.jumpTo({ center: [sel.position.lon, sel.position.lat] });
  }, [mapRef, ready, marks, follow, land, landLoaded]);
  // a map removed (a collapsed panel) and made again is framed again: the effect runs with ready false between
  return ready && isFramed;
}
