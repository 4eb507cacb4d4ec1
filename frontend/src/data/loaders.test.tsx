// @vitest-environment jsdom
// The REST loads merged into the store: asked on each connection (not while it is down), each answer merged once, and
// an answer older than a WebSocket message of the same kind dropped.
import { QueryClientProvider } from "@tanstack/react-query";
import { act, cleanup, renderHook, waitFor } from "@testing-library/react";
import type { ReactNode } from "react";
import { afterEach, describe, expect, it, vi } from "vitest";
import type { Task } from "../api/rest";
import { DataContext } from "./hooks";
import { useStoredTracks, useTasks, useVehicleCapabilities, useWorldModel } from "./loaders";
import { makeQueryClient } from "./queries";
import { TRACK_SECONDS } from "./slices/vehicles";
import { TestSource, snapshotMessage, vehicle } from "./testing";

const task = (taskId: number, state: Task["state"], stateAt: number): Task => ({
  taskId,
  createdAt: 1,
  deadline: null,
  featureId: null,
  imcId: 7,
  kind: "move",
  operator: null,
  point: null,
  progress: 0,
  quality: null,
  resolution: null,
  sensor: null,
  state,
  stateAt,
  station: null,
  synch: null,
  vehicle: "v",
  updatedAt: stateAt,
});

/** fetch answering `answer(path)` after `delay` resolves, counting the requests of each path. */
function fakeConsole(answer: (path: string) => unknown, delay: () => Promise<void> = async () => undefined): Map<string, number> {
  const asked = new Map<string, number>();
  vi.stubGlobal("fetch", async (request: Request) => {
    const path = new URL(request.url).pathname;
    asked.set(path, (asked.get(path) ?? 0) + 1);
    await delay();
    return Response.json(answer(path));
  });
  return asked;
}

function wrapper(source: TestSource) {
  const queries = makeQueryClient();
  return ({ children }: { children: ReactNode }) => (
    <QueryClientProvider client={queries}>
      <DataContext.Provider value={{ store: source.store, source }}>{children}</DataContext.Provider>
    </QueryClientProvider>
  );
}

describe("REST loads merged into the store", () => {
  afterEach(() => {
    cleanup();
    vi.unstubAllGlobals();
  });

  it("asks for the tasks on each connection, not while it is down, and merges the answer into the store", async () => {
    const asked = fakeConsole(() => [task(1, "IN_PROGRESS", 10)]);
    const source = new TestSource();
    act(() => source.send(snapshotMessage()));
    const { result } = renderHook(() => useTasks(), { wrapper: wrapper(source) });
    await waitFor(() => expect(result.current.map((t) => t.state)).toEqual(["IN_PROGRESS"]));
    expect(source.store.getState().tasks[1].state).toBe("IN_PROGRESS");
    act(() => source.setState("reconnecting"));
    await new Promise((r) => setTimeout(r, 20));
    expect(asked.get("/api/tasks")).toBe(1);
    act(() => source.setState("live"));
    await waitFor(() => expect(asked.get("/api/tasks")).toBe(2));
  });

  it("drops a world model answered before a newer `worldmodel` message came", async () => {
    let answer: () => void = () => undefined;
    const asked = fakeConsole(
      () => ({
        type: "FeatureCollection",
        features: [{ type: "Feature", id: 1, properties: { name: "old" }, geometry: { type: "Point", coordinates: [0, 0] } }],
      }),
      () => new Promise((r) => (answer = r)),
    );
    const source = new TestSource();
    const { result } = renderHook(() => useWorldModel(), { wrapper: wrapper(source) });
    await waitFor(() => expect(asked.get("/api/worldmodel")).toBe(1));
    act(() =>
      source.send({ type: "worldmodel", worldModel: { type: "FeatureCollection", features: [], source: null, updatedAt: 2 } }),
    );
    act(() => answer());
    await new Promise((r) => setTimeout(r, 20));
    expect(result.current?.features).toEqual([]); // the message's, not the older answer's
  });

  it("asks each vehicle's stored track once, a vehicle that appears its own only, and merges it into the store", async () => {
    const asked = fakeConsole((path) => [{ time: 990, latitude: path.includes("/a/") ? 1 : 2, longitude: 3 }]);
    const source = new TestSource();
    act(() => source.send(snapshotMessage({ providers: [vehicle("a")] })));
    renderHook(() => useStoredTracks(true), { wrapper: wrapper(source) });
    await waitFor(() => expect(source.store.getState().providers.a.track).toEqual([{ t: 990, lat: 1, lon: 3 }]));
    act(() => source.send({ type: "provider", event: "appeared", provider: vehicle("b") }));
    await waitFor(() => expect(source.store.getState().providers.b.track).toEqual([{ t: 990, lat: 2, lon: 3 }]));
    expect(Object.fromEntries(asked)).toEqual({ "/api/providers/a/track": 1, "/api/providers/b/track": 1 });
  });

  it("asks for the stored track since TRACK_SECONDS before now on the console's clock, whatever the page's says", async () => {
    const since: (string | null)[] = [];
    vi.stubGlobal("fetch", async (request: Request) => {
      since.push(new URL(request.url).searchParams.get("since"));
      return Response.json([]);
    });
    const source = new TestSource();
    source.clock = 1_700_000_000 + 300; // the page's clock 5 minutes ahead of the console's
    act(() => source.send(snapshotMessage({ serverTime: 1_700_000_000, providers: [vehicle("a")] })));
    renderHook(() => useStoredTracks(true), { wrapper: wrapper(source) });
    await waitFor(() => expect(since).toHaveLength(1));
    expect(since[0]).toBe(new Date((1_700_000_000 - TRACK_SECONDS) * 1000).toISOString());
  });
});

describe("REST reads shown as the console answers them", () => {
  afterEach(() => {
    cleanup();
    vi.unstubAllGlobals();
  });

  it("shows a vehicle's CoMap capabilities only as the console answers them now: one selected again while the console is out of reach has none", async () => {
    let imcId = 7;
    const asked = fakeConsole((path) => ({ imcId: path.includes("/a/") ? imcId : 9, capabilities: [], lastHeard: 1000 }));
    const source = new TestSource();
    act(() => source.send(snapshotMessage({ providers: [vehicle("a"), vehicle("b")] })));
    const { result, rerender } = renderHook(({ id }: { id: string }) => useVehicleCapabilities(id), {
      wrapper: wrapper(source),
      initialProps: { id: "a" },
    });
    await waitFor(() => expect(result.current?.imcId).toBe(7));
    rerender({ id: "b" }); // the operator selects another vehicle
    await waitFor(() => expect(result.current?.imcId).toBe(9));
    imcId = 8; // meanwhile a's capabilities change on the console
    act(() => source.setState("reconnecting")); // and the console goes out of reach
    rerender({ id: "a" }); // a selected again: nothing to ask, and what was answered before is not what it is now
    await new Promise((r) => setTimeout(r, 20));
    expect(result.current).toBeNull();
    act(() => source.setState("live"));
    await waitFor(() => expect(result.current?.imcId).toBe(8));
    expect(asked.get("/api/providers/a/capabilities")).toBe(2);
  });
});
