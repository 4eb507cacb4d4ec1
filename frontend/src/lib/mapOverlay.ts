// The vehicles' names on the map, and for each vehicle outside the view an arrow at the map's edge that
// points to it: HTML over the map's canvas. MapLibre draws text only from glyph files, which the offline
// basemap does not have (it requests nothing from anywhere); a few HTML labels need none. They are placed
// when the camera moves (MapLibre's "move": only while it moves, never while the map is still) and when the
// vehicles' data changes (at the map's bounded update rate); the selected vehicle's ring and name on the frame
// after each of its fixes. No React render at all.
import type { Map as MapLibre } from "maplibre-gl";
import { distanceM, distanceText, edgeMark, type EdgeMark, type VehicleMark } from "./geo";
import { inline, lastHeardText, linkOrPlanned } from "./labels";
import { projectionText, type Projection } from "./projection";
import { vehicleColor } from "./vehicle";

/** How far inside the map's border the edge arrows sit (px): clear of the border, under the controls. */
const EDGE_INSET = 22;
/** How many places an edge arrow may be moved along its side to clear the others (place). */
const MAX_STACK = 3;
/** The "+N more" note's place (styles.css .map-edge-more), kept clear of the arrows. */
const NOTE_BOX: Box = { x: 0, y: 0, w: 190, h: 26 };

interface Marker {
  mark: VehicleMark;
  label: HTMLDivElement;
  projected: HTMLDivElement; // a lost vehicle's "projected" label at its dead-reckoned position (or why there is none)
  edge: HTMLButtonElement;
  edgeName: HTMLSpanElement;
  arrow: SVGSVGElement;
  size: { w: number; h: number } | null; // the edge arrow's box, measured once per text
  labelSize: { w: number; h: number } | null; // the name's box likewise
  side: Side; // which side of its dot the name is on (kept there while that side is clear)
  projectedSize: { w: number; h: number } | null; // the projection label's box likewise
}

export interface Box {
  x: number;
  y: number;
  w: number;
  h: number;
}

const SVG = "http://www.w3.org/2000/svg";
const clamp = (v: number, lo: number, hi: number) => Math.max(lo, Math.min(hi, v));
/** The side of its vehicle's dot a name is on: right, or left where the right would cover another name. */
export type Side = "right" | "left";
/** Where a name `w` px wide starts: on `side` of its vehicle at screen point `p`, centred on it vertically. */
export const labelOrigin = (p: { x: number; y: number }, side: Side, w: number) => ({
  x: side === "right" ? p.x + 14 : p.x - 14 - w,
  y: p.y - 9,
});
/** A name's transform, to its box's start. */
const labelAt = (p: { x: number; y: number }, side: Side, w: number) => {
  const o = labelOrigin(p, side, w);
  return `translate(${Math.round(o.x)}px, ${Math.round(o.y)}px)`;
};
/** Where `map` draws a position: at its copy of the world nearest the map's centre, as the fleet's dots are
 * (FleetCanvas), not a world away when the view is over the antimeridian. */
const projectNear = (map: MapLibre, { lon, lat }: { lon: number; lat: number }) =>
  map.project([lon + 360 * Math.round((map.getCenter().lng - lon) / 360), lat]);
const overlaps = (a: Box, b: Box) => a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;

/** Where each name goes (the overlay's `place`), in order: the first of its places (`candidates`: its sides of the
 * dot) that covers no name placed before it nor one of `taken` (the "+N more" note, which a name drawn over it hid),
 * and none of `avoid` (the lost vehicles' "projected" labels) when one of its places can; -1 for a name with no such
 * place, left to its dot. The first `keep` (the selected vehicle's name) are never left out: at their first place
 * clear of `taken`, else their first. */
export function firstClear(candidates: readonly Box[][], taken: Box[] = [], keep = 0, avoid: Box[] = []): number[] {
  const shown: Box[] = [];
  return candidates.map((boxes, i) => {
    const free = (box: Box) => !taken.some((b) => overlaps(b, box));
    const clear = (box: Box) => !shown.some((b) => overlaps(b, box)) && free(box);
    let k = avoid.length ? boxes.findIndex((box) => clear(box) && !avoid.some((b) => overlaps(b, box))) : -1;
    if (k < 0) k = boxes.findIndex(clear);
    if (k < 0 && i < keep) k = Math.max(0, boxes.findIndex(free));
    if (k >= 0) shown.push(boxes[k]);
    return k;
  });
}

/** Which of `items` (each a vehicle's label and its box) are shown where they would cover one another: placed in the
 * order of `labelRank` (the selected vehicle's first, never left out; then those in alarm; then the lost; then the
 * others, each in the fleet's order), each unless it covers one placed before it or one of `taken` (firstClear). The one
 * rule of the vehicles' names and of the lost vehicles' projection labels. */
export function shownByRank(items: readonly { mark: VehicleMark; box: Box }[], taken: Box[] = []): boolean[] {
  return placedByRank(
    items.map(({ mark, box }) => ({ mark, boxes: [box] })),
    taken,
  ).map((k) => k >= 0);
}

/** shownByRank for names with several places each (`boxes`, in the order tried): which place each takes, -1 none;
 * a place clear of `avoid` first (firstClear). */
export function placedByRank(
  items: readonly { mark: VehicleMark; boxes: Box[] }[],
  taken: Box[] = [],
  avoid: Box[] = [],
): number[] {
  const order = items.map((_, i) => i).sort((a, b) => labelRank(items[a].mark) - labelRank(items[b].mark)); // stable
  const keep = order.length > 0 && labelRank(items[order[0]].mark) === 0 ? 1 : 0;
  const placed = firstClear(
    order.map((i) => items[i].boxes),
    taken,
    keep,
    avoid,
  );
  const out: number[] = new Array<number>(items.length);
  for (const [k, i] of order.entries()) out[i] = placed[k];
  return out;
}

/** The box of a lost vehicle's projection label of size `size` (placeProjection): left of its dead-reckoned position
 * `p` ("projected · within 127 m"), or under the vehicle's name at `p`, its position (on the name's `side`), the
 * reason it has none. */
export function projectionBox(
  kind: Projection["kind"],
  p: { x: number; y: number },
  size: { w: number; h: number },
  side: Side = "right",
): Box {
  if (kind === "projected") return { x: p.x - 12 - size.w, y: p.y - 8, ...size };
  const o = labelOrigin(p, side, size.w);
  return { x: o.x, y: o.y + 20, ...size };
}

/** The sides a name may take, its own first (a name does not jump from side to side while its side is clear): a lost
 * vehicle's name whose "projected" label is left of its ghost (on its dot at first) stays right of its dot. */
function sidesOf(mark: VehicleMark, side: Side): Side[] {
  if (mark.projection?.kind === "projected") return ["right"];
  return side === "right" ? ["right", "left"] : ["left", "right"];
}

/** A vehicle's name on the map (`atEdge`: on its edge arrow, kept short): a lost one's says so by the page's one rule
 * (`plannedUntil`: "out of comms (planned) until 14:20 UTC" in its planned silence, else "lost"), and, on the map,
 * when it was last heard. */
export function markName(mark: VehicleMark, atEdge = false): string {
  if (mark.link !== "lost") return mark.label;
  const text = `${mark.label} · ${inline(linkOrPlanned("lost", mark.plannedUntil))}`;
  return atEdge || mark.heardS === null ? text : `${text} · ${inline(lastHeardText(mark.heardS))}`;
}

/** Where the edge arrows go (the overlay's `place`), in order: each at its edge point, or moved along its side towards
 * the middle by at most MAX_STACK places to clear those before it and the "+N more" note; null for one that finds no
 * place within the map (counted in the note). `w`, `h`: each arrow's size. */
export function edgeBoxes(arrows: { edge: EdgeMark; w: number; h: number }[], width: number, height: number): (Box | null)[] {
  const placed: Box[] = [NOTE_BOX];
  return arrows.map(({ edge, w, h }) => {
    const right = edge.x > width / 2;
    const box = { x: clamp(right ? edge.x - w : edge.x, 2, width - w - 2), y: clamp(edge.y - h / 2, 2, height - h - 2), w, h };
    const step = box.y + h / 2 < height / 2 ? h + 2 : -(h + 2);
    for (let i = 0; i < MAX_STACK && placed.some((b) => overlaps(b, box)); i++) box.y += step;
    if (placed.some((b) => overlaps(b, box)) || box.y < 2 || box.y + h > height - 2) return null;
    placed.push(box);
    return box;
  });
}

/** Whose label is placed first where labels would cover one another (a name, a projection), and whose edge arrow: the
 * selected vehicle's (0), then those of vehicles in alarm (1), then those lost (2: in their planned silence, or their
 * alarm acknowledged), then the others (3). */
export function labelRank(mark: VehicleMark): number {
  return mark.selected ? 0 : mark.alarmed ? 1 : mark.link === "lost" ? 2 : 3;
}

export class VehicleOverlay {
  private readonly root: HTMLDivElement;
  private readonly markers = new Map<string, Marker>();
  private clustered: ReadonlySet<string> = new Set(); // drawn in a cluster: no name
  // the selected vehicle at its newest position: a ring over its dot, moved on every frame after its fix by a CSS
  // transform, which redraws no map (a software-rendered map redrawn ten times a second takes most of a core)
  private readonly ring: HTMLDivElement;
  private selected: VehicleMark | null = null;
  // the count of the arrows that found no place (place), at the map's top left corner
  private readonly more: HTMLDivElement;
  // the overlay's size, from a ResizeObserver: reading clientWidth where the ring is placed (in React's effects,
  // after the DOM changed) forced a layout of the page on every fix of the selected vehicle
  private width = 0;
  private height = 0;
  private readonly resized: ResizeObserver;

  /** `pick`: the operator clicked the edge arrow of vehicle `id` (select it and bring it into view). */
  constructor(
    private readonly map: MapLibre,
    private readonly pick: (mark: VehicleMark) => void,
  ) {
    this.root = document.createElement("div");
    this.root.className = "map-overlay";
    this.root.dataset.testid = "map-overlay";
    // between the canvas and the controls: above the vehicles, under the zoom buttons; outside the
    // canvas container, so a click on an arrow is not also a click on the map
    const container = map.getContainer();
    container.insertBefore(this.root, container.querySelector(".maplibregl-control-container"));
    this.ring = document.createElement("div");
    this.ring.className = "map-selected";
    this.ring.dataset.testid = "map-selected";
    this.ring.hidden = true;
    this.root.append(this.ring);
    this.more = document.createElement("div");
    this.more.className = "map-edge-more";
    this.more.dataset.testid = "map-edge-more";
    this.more.hidden = true;
    this.root.append(this.more);
    map.on("move", this.place);
    this.resized = new ResizeObserver(([entry]) => {
      this.width = entry.contentRect.width;
      this.height = entry.contentRect.height;
      this.place();
    });
    this.resized.observe(this.root);
  }

  /** The vehicles the fleet's canvas draws in a cluster: their names hidden, placed again. */
  setClustered(ids: ReadonlySet<string>): void {
    this.clustered = ids;
    this.place();
  }

  /** The vehicles to label (at the map's update rate): elements made, updated or removed, then placed. */
  set(marks: VehicleMark[]): void {
    const seen = new Set<string>();
    for (const mark of marks) {
      seen.add(mark.id);
      const m = this.markers.get(mark.id) ?? this.add(mark);
      m.mark = mark;
      const planned = mark.plannedUntil !== null; // lost in its planned silence: named so, as everywhere
      const lost = mark.link === "lost" && !planned;
      const text = markName(mark, true);
      const named = markName(mark);
      if (m.label.textContent !== named) {
        m.label.textContent = named;
        m.labelSize = null;
      }
      m.label.classList.toggle("selected", mark.selected);
      m.label.classList.toggle("lost", lost);
      m.label.classList.toggle("planned", planned);
      m.edge.classList.toggle("selected", mark.selected);
      m.edge.classList.toggle("lost", lost);
      m.edge.classList.toggle("planned", planned);
      if (m.edgeName.textContent !== text) {
        m.edgeName.textContent = text;
        m.size = null;
      }
      this.describeProjection(m);
    }
    for (const [id, m] of this.markers) {
      if (seen.has(id)) continue;
      m.label.remove();
      m.edge.remove();
      m.projected.remove();
      this.markers.delete(id);
    }
    this.place();
  }

  /** The selected vehicle's newest mark (null: none, or no position): its ring placed at once. */
  setSelected(mark: VehicleMark | null): void {
    this.selected = mark;
    this.placeRing();
    // its name goes with the ring, not with the map's dot (drawn at the fleet's rate): only its label is moved,
    // unless it crossed the map's edge (then every label and edge arrow is placed again)
    const m = mark && this.markers.get(mark.id);
    if (!mark || !m || !this.width) return;
    const p = projectNear(this.map, mark.position);
    const inView = edgeMark(p.x, p.y, this.width, this.height, EDGE_INSET) === null;
    if (inView && !m.label.hidden) m.label.style.transform = labelAt(p, m.side, m.labelSize?.w ?? 0);
    else if (inView || m.edge.hidden) this.place();
  }

  /** A name to `side` of its dot, its colour bar towards the dot (styles.css .map-label.left), written only when
   * changed. */
  private setSide(m: Marker, side: Side): void {
    if (m.side === side) return;
    m.side = side;
    const colour = vehicleColor(m.mark.id);
    m.label.classList.toggle("left", side === "left");
    m.label.style.borderLeftColor = side === "right" ? colour : "";
    m.label.style.borderRightColor = side === "left" ? colour : "";
  }

  /** Where a vehicle's name goes: the selected vehicle's newest position (its ring), another's mark. */
  private positionOf(m: Marker): VehicleMark["position"] {
    return this.selected?.id === m.mark.id ? this.selected.position : m.mark.position;
  }

  private placeRing(): void {
    const mark = this.selected;
    const p = mark ? projectNear(this.map, mark.position) : null;
    const inView = p !== null && p.x >= 0 && p.y >= 0 && p.x <= this.width && p.y <= this.height;
    if (this.ring.hidden === inView) this.ring.hidden = !inView;
    if (!mark || !p || !inView) return;
    this.ring.style.transform = `translate(${p.x.toFixed(1)}px, ${p.y.toFixed(1)}px)`;
    // the latitude it shows, for the probe benchmark: only a ring on screen, once per position
    const lat = mark.position.lat.toFixed(6);
    if (this.ring.dataset.lat !== lat) this.ring.dataset.lat = lat;
  }

  private add(mark: VehicleMark): Marker {
    const colour = vehicleColor(mark.id);
    const label = document.createElement("div");
    label.className = "map-label";
    label.dataset.testid = "map-label";
    label.dataset.vehicle = mark.id;
    label.style.borderLeftColor = colour;
    const edge = document.createElement("button");
    edge.type = "button";
    edge.className = "map-edge";
    edge.dataset.testid = "map-edge";
    edge.dataset.vehicle = mark.id;
    edge.style.borderColor = colour;
    // an arrowhead pointing up (north on a map not turned), turned by the edge mark's angle
    const arrow = document.createElementNS(SVG, "svg");
    arrow.setAttribute("class", "map-edge-arrow");
    arrow.setAttribute("viewBox", "-5 -5 10 10");
    arrow.setAttribute("aria-hidden", "true");
    const head = document.createElementNS(SVG, "path");
    head.setAttribute("d", "M0 -5 L4.5 4.5 L0 2 L-4.5 4.5 Z");
    head.setAttribute("fill", "currentColor");
    arrow.append(head);
    const edgeName = document.createElement("span");
    edge.append(arrow, edgeName);
    const projected = document.createElement("div");
    projected.className = "map-projection";
    projected.dataset.testid = "map-projection";
    projected.dataset.vehicle = mark.id;
    projected.hidden = true;
    const m: Marker = {
      mark,
      label,
      projected,
      edge,
      edgeName,
      arrow,
      size: null,
      labelSize: null,
      projectedSize: null,
      side: "right",
    };
    edge.addEventListener("click", () => this.pick(m.mark));
    // read after its vehicle's name (a screen reader goes in the page's order; drawn under the names: styles.css)
    this.root.append(label, projected, edge);
    this.markers.set(mark.id, m);
    return m;
  }

  /** A lost vehicle's projection in words ("projected · within 127 m", or why there is none), with where it is (the
   * tests read it), written only when changed. */
  private describeProjection(m: Marker): void {
    const pr = m.mark.projection;
    const text = pr ? projectionText(pr) : "";
    if (m.projected.textContent !== text) {
      m.projected.textContent = text;
      m.projectedSize = null;
    }
    const d = m.projected.dataset;
    const kind = pr?.kind ?? "";
    if (d.kind !== kind) d.kind = kind;
    const lat = pr?.kind === "projected" ? pr.at.lat.toFixed(6) : "";
    const lon = pr?.kind === "projected" ? pr.at.lon.toFixed(6) : "";
    const radius = pr?.kind === "projected" ? pr.radiusM.toFixed(0) : "";
    if (d.lat !== lat) d.lat = lat;
    if (d.lon !== lon) d.lon = lon;
    if (d.radius !== radius) d.radius = radius;
  }

  /** Where a lost vehicle's projection label would go (its dead-reckoned position, or its own when it has none), when
   * that is in view; null for a vehicle not lost, or out of view (its label hidden). */
  private projectionAt(m: Marker): { x: number; y: number } | null {
    const pr = m.mark.projection;
    const p = pr ? projectNear(this.map, pr.kind === "projected" ? pr.at : this.positionOf(m)) : null;
    return p !== null && edgeMark(p.x, p.y, this.width, this.height, 0) === null ? p : null;
  }

  /** A lost vehicle's projection label: "projected" left of its dead-reckoned position `p` (the vehicle's name is right
   * of its dot, which the ghost starts on), or under the vehicle's own name the reason it has none. */
  private placeProjection(m: Marker, p: { x: number; y: number }): void {
    const b = projectionBox(m.mark.projection?.kind ?? "projected", p, m.projectedSize!, m.side);
    m.projected.style.transform =
      m.mark.projection?.kind === "projected"
        ? `translate(${Math.round(p.x - 12)}px, ${Math.round(p.y - 8)}px) translate(-100%, 0)`
        : `translate(${Math.round(b.x)}px, ${Math.round(b.y)}px)`;
  }

  /** Each vehicle's label at its position when in view, else its arrow at the edge towards it. Arrows that would
   * cover one another are stacked towards the middle of their side, by at most MAX_STACK places: one moved further
   * would point from nowhere near its vehicle (with 250 vehicles and the map zoomed in, 247 arrows stood in two
   * columns over the map). Those left over are counted in a "+N more" note in the map's top left corner, which no
   * arrow covers. The selected vehicle's arrow, then those of the vehicles in alarm, then the lost, are placed first (`labelRank`):
   * never the ones left out. */
  readonly place = (): void => {
    this.placeRing();
    const { width, height } = this;
    if (!width || !height) return;
    const centre = this.map.getCenter();
    const outside: [Marker, EdgeMark][] = [];
    const inside: [Marker, { x: number; y: number }][] = [];
    for (const m of this.markers.values()) {
      const p = projectNear(this.map, this.positionOf(m));
      const edge = edgeMark(p.x, p.y, width, height, EDGE_INSET);
      if (edge) {
        if (!m.label.hidden) m.label.hidden = true; // written only when changed: 250 alike would each restyle
        outside.push([m, edge]);
      } else {
        if (!m.edge.hidden) m.edge.hidden = true;
        // a vehicle drawn in a cluster (FleetCanvas): its name not shown, the cluster's count stands for it
        if (!this.clustered.has(m.mark.id)) inside.push([m, p]);
        else if (!m.label.hidden) m.label.hidden = true;
      }
    }
    const rank = ([m]: [Marker, unknown]) => labelRank(m.mark);
    // stable: the others in the fleet's order, so that the same arrows stay shown as the map moves
    outside.sort((a, b) => rank(a) - rank(b));
    const projections: [Marker, { x: number; y: number }][] = [];
    for (const m of this.markers.values()) {
      const p = this.projectionAt(m);
      if (p) projections.push([m, p]);
      else if (!m.projected.hidden) m.projected.hidden = true;
    }
    // names that would cover one another: the first shown, the others left to their dots (along a coast, most of
    // 250 names could not be read); the selected vehicle's, then those in alarm, then the lost, come first (shownByRank)
    // the names and arrows not measured yet (a new text): all shown first, then all read, so that the page is laid
    // out once, not once per element (a hidden one has no size)
    const newNames = inside.filter(([m]) => m.labelSize === null);
    const newArrows = outside.filter(([m]) => m.size === null);
    const newProjections = projections.filter(([m]) => m.projectedSize === null);
    for (const [m] of newNames) m.label.hidden = false;
    for (const [m] of newArrows) m.edge.hidden = false;
    for (const [m] of newProjections) m.projected.hidden = false;
    for (const [m] of newNames) m.labelSize = { w: m.label.offsetWidth, h: m.label.offsetHeight };
    for (const [m] of newArrows) m.size = { w: m.edge.offsetWidth, h: m.edge.offsetHeight };
    for (const [m] of newProjections) m.projectedSize = { w: m.projected.offsetWidth, h: m.projected.offsetHeight };
    const boxes = edgeBoxes(
      outside.map(([m, edge]) => {
        m.edge.classList.toggle("from-right", edge.x > width / 2); // its name on the side towards the middle
        return { edge, ...m.size! };
      }),
      width,
      height,
    );
    const note = boxes.includes(null) ? [NOTE_BOX] : []; // the "+N more" note shown: no name over it but the selected's
    // a name that would cover another tries the other side of its dot (three vehicles 2 km apart on a diagonal, seen
    // with the coast 25 km away, are 15 px apart: right of each dot, their names touch), and the side clear of the lost
    // vehicles' "projected" labels where one is (those are placed by their own rule, below)
    const sides = inside.map(([m]) => sidesOf(m.mark, m.side));
    const ghosts = projections
      .filter(([m]) => m.mark.projection?.kind === "projected")
      .map(([m, p]) => projectionBox("projected", p, m.projectedSize!));
    const placed = placedByRank(
      inside.map(([m, p], i) => ({
        mark: m.mark,
        boxes: sides[i].map((side) => ({ ...labelOrigin(p, side, m.labelSize!.w), ...m.labelSize! })),
      })),
      note,
      ghosts,
    );
    for (const [i, [m, p]] of inside.entries()) {
      const shown = placed[i] >= 0;
      if (m.label.hidden === shown) m.label.hidden = !shown;
      if (!shown) continue;
      this.setSide(m, sides[i][placed[i]]);
      m.label.style.transform = labelAt(p, m.side, m.labelSize!.w);
    }
    // the lost vehicles' projection labels, by the same rule: many lost at once do not pile up their "projected"
    const projectedShown = shownByRank(
      projections.map(([m, p]) => ({
        mark: m.mark,
        box: projectionBox(m.mark.projection?.kind ?? "projected", p, m.projectedSize!, m.side),
      })),
      note,
    );
    for (const [i, [m, p]] of projections.entries()) {
      if (m.projected.hidden === projectedShown[i]) m.projected.hidden = !projectedShown[i];
      if (projectedShown[i]) this.placeProjection(m, p);
    }
    let more = 0;
    for (const [i, [m, edge]] of outside.entries()) {
      const box = boxes[i];
      if (m.edge.hidden !== !box) m.edge.hidden = !box; // written only when changed, as the labels
      if (!box) {
        more += 1;
        continue;
      }
      m.edge.style.transform = `translate(${Math.round(box.x)}px, ${Math.round(box.y)}px)`;
      m.arrow.style.transform = `rotate(${Math.round(edge.angleDeg)}deg)`;
      const away = distanceText(distanceM({ lon: centre.lng, lat: centre.lat }, this.positionOf(m)));
      const said = `${m.mark.label}${m.mark.link === "lost" ? ` (${inline(linkOrPlanned("lost", m.mark.plannedUntil))})` : ""}: outside the map, ${away} from its middle. Show it`;
      if (m.edge.getAttribute("aria-label") !== said) {
        m.edge.setAttribute("aria-label", said);
        m.edge.title = `${said} and select it`;
      }
    }
    if (this.more.hidden !== (more === 0)) this.more.hidden = more === 0;
    const text = `+${more} more outside the map`;
    if (more > 0 && this.more.textContent !== text) {
      this.more.textContent = text;
      this.more.title = `${more} more ${more === 1 ? "vehicle" : "vehicles"} outside the map without an arrow: Fit all shows every vehicle`;
    }
  };

  destroy(): void {
    this.map.off("move", this.place);
    this.resized.disconnect();
    this.root.remove();
    this.markers.clear();
  }
}
