import type { Map as MapLibre } from "maplibre-gl";
import { afterEach, describe, expect, it, vi } from "vitest";
import { setBatched } from "./repaints";

const EMPTY: GeoJSON.FeatureCollection = { type: "FeatureCollection", features: [] };

/** The part of a MapLibre map the batch uses: redraw requests counted, sources loaded when the test says. */
class FakeMap {
  repaints = 0;
  moving = false;
  readonly loaded = new Set<string>();
  readonly sources = new Map<string, { setData: () => Promise<void> }>();
  readonly listeners = new Set<() => void>();
  constructor(ids: string[]) {
    for (const id of ids) this.sources.set(id, { setData: () => Promise.resolve() });
  }
  triggerRepaint(): void {
    this.repaints++;
  }
  isMoving = () => this.moving;
  getSource = (id: string) => this.sources.get(id);
  isSourceLoaded = (id: string) => this.loaded.has(id);
  on = (_: string, l: () => void) => this.listeners.add(l);
  off = (_: string, l: () => void) => this.listeners.delete(l);
  /** Source `id`'s tiles have all arrived: its last `sourcedata` event. */
  load(id: string): void {
    this.loaded.add(id);
    for (const l of [...this.listeners]) l();
  }
  get map(): MapLibre {
    return this as unknown as MapLibre;
  }
}

const settled = () => new Promise<void>((r) => setTimeout(r, 0));

afterEach(() => {
  vi.useRealTimers();
});

describe("the map's batch of source updates", () => {
  it("holds the redraws asked for while its sources load, then redraws once, and listens no longer", async () => {
    const m = new FakeMap(["vehicles", "tracks"]);
    setBatched(m.map, "vehicles", EMPTY);
    setBatched(m.map, "tracks", EMPTY);
    m.map.triggerRepaint(); // the worker's answer, a tile, the follow jump ...
    m.map.triggerRepaint();
    await settled();
    expect(m.repaints).toBe(0);
    m.load("vehicles");
    expect(m.repaints).toBe(0); // tracks still loading
    m.load("tracks");
    expect(m.repaints).toBe(1);
    expect(m.listeners.size).toBe(0);
    m.map.triggerRepaint(); // no batch: at once
    expect(m.repaints).toBe(2);
  });

  it("never holds a moving camera, and a batch with nothing asked meanwhile draws nothing more", async () => {
    const m = new FakeMap(["vehicles"]);
    setBatched(m.map, "vehicles", EMPTY);
    m.moving = true;
    m.map.triggerRepaint();
    expect(m.repaints).toBe(1);
    await settled();
    m.load("vehicles");
    expect(m.repaints).toBe(1);
  });

  it("redraws at the hold's end when a source never loads, and holds the next batch again", async () => {
    vi.useFakeTimers();
    const m = new FakeMap(["selected"]);
    setBatched(m.map, "selected", EMPTY);
    m.map.triggerRepaint();
    await vi.advanceTimersByTimeAsync(249);
    expect(m.repaints).toBe(0);
    await vi.advanceTimersByTimeAsync(1);
    expect(m.repaints).toBe(1);
    m.map.triggerRepaint(); // the hold is over: at once
    expect(m.repaints).toBe(2);
    setBatched(m.map, "selected", EMPTY); // the earlier update still loading: this one's deadline is its own
    m.map.triggerRepaint();
    expect(m.repaints).toBe(2);
    await vi.advanceTimersByTimeAsync(250);
    expect(m.repaints).toBe(3);
    m.load("selected"); // both loaded at last: nothing left to hold or to listen to
    expect(m.listeners.size).toBe(0);
    expect(m.repaints).toBe(3);
  });

  it("waits for nothing on a source gone with its map (a collapsed panel)", async () => {
    const m = new FakeMap(["vehicles"]);
    setBatched(m.map, "vehicles", EMPTY);
    m.map.triggerRepaint();
    m.sources.delete("vehicles");
    await settled();
    expect(m.repaints).toBe(1);
    expect(m.listeners.size).toBe(0);
  });
});
