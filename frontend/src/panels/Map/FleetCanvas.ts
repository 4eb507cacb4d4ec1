// The fleet (every vehicle's dot, course arrow and link ring, the tracks, the origins) on a 2D canvas over the map, not
// in MapLibre: MapLibre redraws the whole map, basemap and all, for any change of a source, and a software-rendered
// (no GPU) map's redraw is 35-70 ms, 33 of it the basemap, so the fleet's updates at two a second and more were most
// of the page's long tasks. Here a fleet update redraws this canvas alone; the map redraws only when its camera moves
// (or its tiles, the world model, the tools change). The canvas is redrawn on the map's own `render` (in the same
// frame as the map, so it stays on the map while it pans and zooms) and on the frame after the fleet changed.
// A click and the pointer's cursor find their vehicle in what was drawn (`hit`), not in MapLibre's features.
// A lost vehicle's projection, a guess, is drawn dashed and faint under every vehicle (drawProjection).
import type { Map as MapLibre } from "maplibre-gl";
import { cancelFrame, onFrame } from "../../data/frame";
import type { LonLat, VehicleMark } from "../../lib/geo";
import { vehicleColor } from "../../lib/vehicle";
import {
  PROJECTED_R,
  clustered,
  countInView,
  hitCluster,
  hitVehicle,
  mercator,
  nearestCopy,
  place,
  placeProjection,
  similarity,
  thinned,
  unwrapped,
  type Cluster,
  type Placed,
  type Point,
  type Projected,
  type ToScreen,
} from "./fleet";

export const FIX_COLORS: Record<VehicleMark["fix"], string> = { valid: "#4caf50", invalid: "#e0593f", unknown: "#9fb3c8" };
const LINK_COLORS: Partial<Record<VehicleMark["link"], string>> = { lost: "#e0593f", stale: "#f5a623" };

export interface FleetTrack {
  id: string;
  selected: boolean;
  points: LonLat[];
}

/** What the canvas draws: the vehicles (the selected one on top), their tracks and their origins. */
export interface FleetData {
  marks: VehicleMark[];
  tracks: FleetTrack[];
  origins: { id: string; at: LonLat }[];
}

/** The tools' points, drawn again over the fleet (MapLibre draws them too, under this canvas, where a vehicle's dot
 * hid a measured point or a vertex handle the operator drags): the measured path, the area being drawn or the Move-to
 * destination (`path`), and the edit tool's vertex handles. */
export interface ToolMarks {
  path: LonLat[];
  handles: LonLat[];
}

declare global {
  interface Window {
    __semFleet?: FleetCanvas; // test hook: Playwright reads the tracks drawn
  }
}

/** A course arrow pointing up, its middle at 0,0 (MapLibre's 32 px icon at 0.7). */
const ARROW: [number, number][] = [
  [0, -10.5],
  [7.7, 9.1],
  [0, 4.5],
  [-7.7, 9.1],
];

export class FleetCanvas {
  private readonly canvas: HTMLCanvasElement;
  private readonly ctx: CanvasRenderingContext2D;
  private readonly resized: ResizeObserver;
  private width = 0;
  private height = 0;
  private data: FleetData = { marks: [], tracks: [], origins: [] };
  private tools: ToolMarks = { path: [], handles: [] };
  private placed: Placed[] = []; // the vehicles drawn on their own
  private clusters: Cluster[] = [];
  private clusteredIds: ReadonlySet<string> = new Set();
  private drawnCount = -1;
  private lastView: { toScreen: (m: Point) => Point; cx: number } | null = null; // the transform of the last drawing
  // a track's Mercator points, kept while the store keeps its array (a track changes once a second at most)
  private readonly mercs = new WeakMap<LonLat[], Point[]>();

  /** `onCount`: the number of vehicles in view changed (the status line's "n of m vehicles drawn"); `onClustered`: the
   * vehicles drawn in a cluster changed (their names are not shown). */
  constructor(
    private readonly map: MapLibre,
    private readonly onCount: (n: number) => void,
    private readonly onClustered: (ids: ReadonlySet<string>) => void = () => undefined,
  ) {
    this.canvas = document.createElement("canvas");
    this.canvas.className = "map-fleet";
    this.canvas.dataset.testid = "map-fleet";
    // over the map's canvas, under the names and edge arrows (VehicleOverlay) and the controls
    const container = map.getContainer();
    container.insertBefore(this.canvas, map.getCanvasContainer().nextSibling);
    this.ctx = this.canvas.getContext("2d")!;
    map.on("render", this.draw);
    this.resized = new ResizeObserver(([entry]) => {
      this.width = entry.contentRect.width;
      this.height = entry.contentRect.height;
      this.draw();
    });
    this.resized.observe(this.canvas);
    window.__semFleet = this;
  }

  /** The fleet to draw, on the next frame. */
  set(data: FleetData): void {
    this.data = data;
    onFrame(this.draw);
  }

  /** The tools' points to draw over the fleet, on the next frame. */
  setTools(tools: ToolMarks): void {
    this.tools = tools;
    onFrame(this.draw);
  }

  /** The vehicle drawn under point `p` of the map (px from its top left), or null. */
  hit(p: Point): string | null {
    return hitVehicle(this.placed, p);
  }

  /** The cluster drawn under point `p` of the map: its middle on the screen, or null. */
  cluster(p: Point): Point | null {
    return hitCluster(this.clusters, p)?.at ?? null;
  }

  /** The clusters drawn (for the tests): each one's vehicles. */
  drawnClusters(): string[][] {
    return this.clusters.map((c) => c.ids);
  }

  /** The tracks drawn (for the tests: where a vehicle went): of each, the points the last drawing put on the canvas,
   * so a track given to the canvas but drawn off it, or not drawn at all, shows nothing. */
  tracks(): FleetTrack[] {
    const view = this.lastView;
    if (!view) return [];
    const { toScreen, cx } = view;
    return this.data.tracks.flatMap((t) => {
      if (t.points.length < 2) return [];
      const merc = this.merc(t.points);
      const k = nearestCopy(merc[merc.length - 1], cx).x - merc[merc.length - 1].x;
      const points = t.points.filter((_, i) => {
        const p = toScreen({ x: merc[i].x + k, y: merc[i].y });
        return p.x >= 0 && p.y >= 0 && p.x <= this.width && p.y <= this.height;
      });
      return points.length ? [{ ...t, points }] : [];
    });
  }

  /** Mercator to the map's pixels, fixed by where the map itself puts its centre and a point ~128 px east of it:
   * both inside the world (a screen corner may be past a pole on a turned map, where Mercator is clamped) and
   * independent of this canvas's size (the map's may change a frame before or after it). */
  private toScreen(c: LonLat) {
    const b = { lon: c.lon + 90 / 2 ** this.map.getZoom(), lat: c.lat };
    return similarity(mercator(c), this.map.project([c.lon, c.lat]), mercator(b), this.map.project([b.lon, b.lat]));
  }

  private merc(points: LonLat[]): Point[] {
    let m = this.mercs.get(points);
    if (!m) {
      m = unwrapped(points.map(mercator));
      this.mercs.set(points, m);
    }
    return m;
  }

  readonly draw = (): void => {
    cancelFrame(this.draw);
    const { width: w, height: h, ctx } = this;
    this.lastView = null;
    if (!w || !h) return;
    // the backing store sized on each drawing, not only on a resize: the device pixel ratio changes without one (the
    // window moved to another screen), and a canvas left at the old ratio is drawn blurred or too coarse
    const dpr = window.devicePixelRatio || 1;
    const cw = Math.round(w * dpr);
    const ch = Math.round(h * dpr);
    if (this.canvas.width !== cw) this.canvas.width = cw;
    if (this.canvas.height !== ch) this.canvas.height = ch;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    const centre = this.map.getCenter();
    const c = { lon: centre.lng, lat: centre.lat };
    const toScreen = this.toScreen(c);
    const cx = mercator(c).x; // each vehicle, track and origin drawn at its copy of the world nearest the centre
    this.lastView = { toScreen, cx };
    const { marks, tracks, origins } = this.data;
    ctx.lineJoin = ctx.lineCap = "round";
    ctx.globalAlpha = 0.8;
    for (const t of tracks) {
      if (t.points.length < 2) continue;
      const merc = this.merc(t.points);
      const k = nearestCopy(merc[merc.length - 1], cx).x - merc[merc.length - 1].x; // the track goes with its vehicle
      const pts = thinned(
        merc.map((m) => toScreen(k ? { x: m.x + k, y: m.y } : m)),
        1,
      );
      ctx.beginPath();
      ctx.moveTo(pts[0].x, pts[0].y);
      for (let i = 1; i < pts.length; i++) ctx.lineTo(pts[i].x, pts[i].y);
      ctx.lineWidth = t.selected ? 2.5 : 1.5;
      ctx.strokeStyle = vehicleColor(t.id);
      ctx.stroke();
    }
    ctx.globalAlpha = 1;
    ctx.lineWidth = 2;
    for (const o of origins) {
      const p = toScreen(nearestCopy(mercator(o.at), cx));
      ctx.beginPath();
      ctx.arc(p.x, p.y, 4, 0, 2 * Math.PI);
      ctx.strokeStyle = vehicleColor(o.id);
      ctx.stroke();
    }
    // lost vehicles' projections under every vehicle: a guess never hides a report
    for (const m of marks) if (m.projection?.kind === "projected") this.drawProjection(m.id, m.projection, toScreen, cx);
    // the selected vehicle last: on top
    const ordered = [...marks.filter((m) => !m.selected), ...marks.filter((m) => m.selected)];
    const all = place(ordered, toScreen, this.map.getBearing(), cx);
    // zoomed out, the vehicles close together on the screen are one mark with their count; the selected one, those
    // in alarm and the lost are always drawn on their own, over the clusters; at the closest zoom, every one
    const { singles, clusters } = clustered(all, this.map.getZoom() < this.map.getMaxZoom());
    this.placed = singles;
    this.clusters = clusters;
    const near = (p: Point) => p.x > -30 && p.y > -30 && p.x < w + 30 && p.y < h + 30;
    for (const c of clusters) if (near(c.at)) this.drawCluster(c);
    // those off the screen (by more than a link ring and an arrow) drawn not at all: zoomed in on one of 250
    for (const v of singles) if (near(v.at)) this.drawVehicle(v);
    this.drawTools(toScreen, cx);
    const ids = new Set(clusters.flatMap((c) => c.ids));
    if (ids.size !== this.clusteredIds.size || [...ids].some((id) => !this.clusteredIds.has(id))) {
      this.clusteredIds = ids;
      this.onClustered(ids);
    }
    const n = countInView(all, w, h);
    if (n !== this.drawnCount) {
      this.drawnCount = n;
      this.onCount(n);
    }
  };

  /** The tools' points over the vehicles, as the map's layers draw them (layers.ts: measure-*, edit-handle). */
  private drawTools(toScreen: (m: Point) => Point, cx: number): void {
    const { ctx } = this;
    const { path, handles } = this.tools;
    const at = (p: LonLat) => toScreen(nearestCopy(mercator(p), cx));
    const merc = unwrapped(path.map(mercator));
    const k = merc.length ? nearestCopy(merc[0], cx).x - merc[0].x : 0; // the path at its first point's copy
    const pts = merc.map((m) => toScreen({ x: m.x + k, y: m.y }));
    ctx.strokeStyle = ctx.fillStyle = "#fff";
    ctx.lineWidth = 2;
    if (pts.length >= 2) {
      ctx.setLineDash([4, 4]);
      ctx.beginPath();
      ctx.moveTo(pts[0].x, pts[0].y);
      for (const p of pts.slice(1)) ctx.lineTo(p.x, p.y);
      ctx.stroke();
      ctx.setLineDash([]);
    }
    for (const p of pts) {
      ctx.beginPath();
      ctx.arc(p.x, p.y, 4, 0, 2 * Math.PI);
      ctx.fill();
    }
    ctx.strokeStyle = "#1e88e5";
    for (const h of handles) {
      const p = at(h);
      ctx.beginPath();
      ctx.arc(p.x, p.y, 6, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
    }
  }

  /** A lost vehicle's dead-reckoned position as a guess, never as a report: a dashed line from its last report, a
   * hollow dashed ghost where it may be, and the circle it is probably within (faint fill, dashed edge). */
  private drawProjection(id: string, p: Projected, toScreen: ToScreen, cx: number): void {
    const { ctx } = this;
    const { from, at: to, r } = placeProjection(p, toScreen, cx, PROJECTED_R);
    const colour = vehicleColor(id);
    ctx.save();
    ctx.setLineDash([5, 4]);
    ctx.lineWidth = 1.5;
    ctx.strokeStyle = colour;
    ctx.fillStyle = colour;
    ctx.beginPath();
    ctx.arc(to.x, to.y, r, 0, 2 * Math.PI);
    ctx.globalAlpha = 0.12;
    ctx.fill();
    ctx.globalAlpha = 0.8;
    ctx.stroke();
    ctx.beginPath();
    ctx.moveTo(from.x, from.y);
    ctx.lineTo(to.x, to.y);
    ctx.stroke();
    ctx.setLineDash([3, 3]);
    ctx.lineWidth = 2;
    ctx.globalAlpha = 1;
    ctx.beginPath();
    ctx.arc(to.x, to.y, PROJECTED_R, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.restore();
  }

  /** A cluster: a disc with the count of its vehicles. */
  private drawCluster({ at, ids, r }: Cluster): void {
    const { ctx } = this;
    ctx.beginPath();
    ctx.arc(at.x, at.y, r, 0, 2 * Math.PI);
    ctx.globalAlpha = 0.85;
    ctx.fillStyle = "#1e88e5";
    ctx.fill();
    ctx.globalAlpha = 1;
    ctx.lineWidth = 2;
    ctx.strokeStyle = "#ffffff";
    ctx.stroke();
    ctx.fillStyle = "#ffffff";
    ctx.font = "bold 12px system-ui, sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    ctx.fillText(String(ids.length), at.x, at.y);
  }

  private drawVehicle({ mark, at, r, arrow, angle }: Placed): void {
    const { ctx } = this;
    const fill = FIX_COLORS[mark.fix];
    const ring = LINK_COLORS[mark.link];
    if (ring) {
      ctx.beginPath();
      ctx.arc(at.x, at.y, 15, 0, 2 * Math.PI);
      ctx.lineWidth = 2;
      ctx.strokeStyle = ring;
      ctx.stroke();
    }
    ctx.globalAlpha = mark.link === "lost" ? 0.4 : 1;
    ctx.beginPath();
    ctx.arc(at.x, at.y, r, 0, 2 * Math.PI);
    ctx.fillStyle = fill;
    ctx.fill();
    ctx.globalAlpha = 1;
    ctx.lineWidth = mark.selected ? 3 : 2;
    ctx.strokeStyle = mark.selected ? "#ffffff" : vehicleColor(mark.id);
    ctx.stroke();
    if (!arrow) return;
    const cos = Math.cos(angle);
    const sin = Math.sin(angle);
    ctx.beginPath();
    for (const [i, [x, y]] of ARROW.entries()) {
      const px = arrow.x + x * cos - y * sin;
      const py = arrow.y + x * sin + y * cos;
      if (i === 0) ctx.moveTo(px, py);
      else ctx.lineTo(px, py);
    }
    ctx.closePath();
    ctx.fillStyle = fill;
    ctx.fill();
    ctx.lineWidth = 1;
    ctx.strokeStyle = "#000";
    ctx.stroke();
  }

  destroy(): void {
    cancelFrame(this.draw);
    this.map.off("render", this.draw);
    this.resized.disconnect();
    this.canvas.remove();
    if (window.__semFleet === this) delete window.__semFleet;
  }
}
