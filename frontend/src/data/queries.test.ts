import { QueryObserver } from "@tanstack/react-query";
import { afterEach, describe, expect, it, vi } from "vitest";
import { capabilitiesQuery, comapStatusQuery, healthQuery, makeQueryClient, seriesQuery, tasksQuery, trackQuery, worldModelQuery } from "./queries";
import { HISTORY_SECONDS, TRACK_SECONDS } from "./store";

interface Asked {
  url: string;
  auth: string | null;
}

/** fetch answering each path with `answer(path)` (a body, or a status for an error), recording what was asked. */
function fakeFetch(answer: (url: string) => unknown): Asked[] {
  const asked: Asked[] = [];
  vi.stubGlobal("fetch", async (url: string, init: RequestInit = {}) => {
    const headers = (init.headers ?? {}) as Record<string, string>;
    asked.push({ url, auth: headers.Authorization ?? null });
    const body = answer(url);
    if (typeof body === "number") return new Response(JSON.stringify({ detail: "no" }), { status: body });
    return new Response(JSON.stringify(body), { status: 200, headers: { "Content-Type": "application/json" } });
  });
  return asked;
}

const NOW = 1_800_000_000;
const now = () => NOW;

describe("REST queries (TanStack Query)", () => {
  afterEach(() => vi.unstubAllGlobals());

  it("asks /api/health once for every reader; a seeded answer is not asked again", async () => {
    const asked = fakeFetch(() => ({ basemap: true }));
    const client = makeQueryClient();
    await client.fetchQuery(healthQuery());
    await client.fetchQuery(healthQuery());
    expect(asked).toHaveLength(1);
    const seeded = makeQueryClient();
    seeded.setQueryData(healthQuery().queryKey, { basemap: false } as never);
    expect((await seeded.fetchQuery(healthQuery())).basemap).toBe(false);
    expect(asked).toHaveLength(1);
  });

  it("loads a vehicle's series and track from the instant's window, with the token, as chart and track points", async () => {
    const asked = fakeFetch((url) =>
      url.includes("/series")
        ? [{ time: NOW - 1, cn0Mean: 41.5, satellitesUsed: 7, satellitesInView: 9 }]
        : [{ time: NOW - 2, latitude: 1.5, longitude: 2.5 }],
    );
    const client = makeQueryClient();
    expect(await client.fetchQuery(seriesQuery("v/1", "tok", 0, now))).toEqual([{ t: NOW - 1, cn0: 41.5, used: 7, inView: 9 }]);
    expect(await client.fetchQuery(trackQuery("v/1", null, 0, now))).toEqual([{ t: NOW - 2, lat: 1.5, lon: 2.5 }]);
    const since = (s: number) => encodeURIComponent(new Date((NOW - s) * 1000).toISOString());
    expect(asked).toEqual([
      { url: `/api/providers/v%2F1/series?since=${since(HISTORY_SECONDS)}`, auth: "Bearer tok" },
      { url: `/api/providers/v%2F1/track?since=${since(TRACK_SECONDS)}`, auth: null },
    ]);
  });

  it("keys every loader by the token, and the history and track by the replay's instant too", () => {
    expect(seriesQuery("a", "t", 3, now).queryKey).toEqual(["series", "a", "t", 3]);
    expect(trackQuery("a", "t", 3, now).queryKey).toEqual(["track", "a", "t", 3]);
    expect(seriesQuery("a", "t", 3, now).queryKey).not.toEqual(seriesQuery("a", "t", 4, now).queryKey); // a seek: another query
    expect(worldModelQuery("t", () => 0).queryKey).toContain("t");
    expect(tasksQuery(null, () => 0).queryKey).toContain(null);
    expect(capabilitiesQuery("a", "t", 5000).queryKey).toEqual(["capabilities", "a", "t"]);
    expect(comapStatusQuery("t").queryKey).toContain("t");
  });

  it("gives the world model and tasks with the message count when asked, and a console without CoMap as absent", async () => {
    let seq = 4;
    fakeFetch((url) => (url === "/api/worldmodel" ? 404 : url === "/api/comap" ? 404 : []));
    const client = makeQueryClient();
    const model = client.fetchQuery(worldModelQuery(null, () => seq));
    seq = 5; // a message came while the request was out: the store will drop the answer
    expect(await model).toEqual({ value: null, seq: 4 });
    expect(await client.fetchQuery(tasksQuery(null, () => seq))).toEqual({ value: [], seq: 5 });
    expect(await client.fetchQuery(comapStatusQuery(null))).toBe("absent");
  });

  it("asks again when the connection is live again (a reconnect), and not while it is down", async () => {
    const asked = fakeFetch(() => []);
    const client = makeQueryClient();
    const observer = new QueryObserver(client, { ...tasksQuery(null, () => 0), enabled: true });
    const off = observer.subscribe(() => undefined);
    await vi.waitFor(() => expect(asked).toHaveLength(1));
    observer.setOptions({ ...tasksQuery(null, () => 0), enabled: false }); // the connection drops
    await new Promise((r) => setTimeout(r, 10));
    expect(asked).toHaveLength(1);
    observer.setOptions({ ...tasksQuery(null, () => 0), enabled: true }); // live again
    await vi.waitFor(() => expect(asked).toHaveLength(2));
    off();
  });
});
