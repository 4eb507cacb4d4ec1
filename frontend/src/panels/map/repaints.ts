// The map's redraws of a batch of source updates, made one. MapLibre redraws when a GeoJSON source's new data comes back
// from its worker, and again as each of the source's tiles does: the fleet's sources (vehicles, selected, tracks,
// origins) updated together, and the follow jump with them, were three or more redraws (6.4 a second with 50
// vehicles), each a frame or more of a software-rendered map, and most of the page's long tasks. While a batch loads,
// the map's redraw requests wait; one redraw follows when the last of its sources has loaded, or HOLD_MAX_MS after
// the batch began (a source that never loads cannot freeze the map). The camera moving (a pan, a zoom) is never held.
import type { Map as MapLibre } from "maplibre-gl";
import { source } from "./layers";

const HOLD_MAX_MS = 250;

class RepaintBatch {
  private readonly repaint: () => void;
  private pending = 0; // source updates not loaded yet
  private asked = false; // a redraw was asked for meanwhile
  private timer: ReturnType<typeof setTimeout> | undefined; // the end of the hold, HOLD_MAX_MS after it began

  constructor(private readonly map: MapLibre) {
    this.repaint = map.triggerRepaint.bind(map);
    // MapLibre asks for every redraw through triggerRepaint (its updates, its sources' and tiles' arrivals)
    map.triggerRepaint = () => {
      if (this.timer !== undefined && !map.isMoving()) this.asked = true;
      else this.repaint();
    };
  }

  /** Source `id` getting new data (`update`: its setData): the map's redraws wait until it has loaded. */
  hold(id: string, update: Promise<void>): void {
    this.pending++;
    // one deadline for the hold, however many updates join it (batches that overlap cannot hold the map for long)
    this.timer ??= setTimeout(() => this.release(), HOLD_MAX_MS);
    let done = false;
    const loaded = () => {
      // a source gone (the map removed meanwhile: a collapsed panel) waits for nothing
      if (!this.map.getSource(id) || this.map.isSourceLoaded(id)) finish();
    };
    const finish = () => {
      if (done) return;
      done = true;
      this.map.off("sourcedata", loaded);
      if (--this.pending === 0) this.release();
    };
    // the promise settles once the worker has the data and the source's tiles are reloading: then each tile's arrival
    // is a `sourcedata` event, and the source is loaded with the last
    update.then(() => {
      loaded();
      if (!done) this.map.on("sourcedata", loaded);
    }, finish);
  }

  /** The hold's end (its updates loaded, or its time up): the redraw asked for meanwhile, once. */
  private release(): void {
    clearTimeout(this.timer);
    this.timer = undefined;
    if (!this.asked) return;
    this.asked = false;
    this.repaint();
  }
}

const batches = new WeakMap<MapLibre, RepaintBatch>();

/** Set GeoJSON source `id` of `map` to `data`, its redraw one with the other sources set in the same task (and any
 * camera jump then). */
export function setBatched(map: MapLibre, id: string, data: GeoJSON.GeoJSON): void {
  const src = source(map, id);
  if (!src) return;
  let batch = batches.get(map);
  if (!batch) {
    batch = new RepaintBatch(map);
    batches.set(map, batch);
  }
  batch.hold(id, src.setData(data));
}
