// @vitest-environment jsdom
import { afterEach, describe, expect, it, vi } from "vitest";
import { UNREACHABLE, requestGpsFix, worldModel } from "../api/rest";
import { loadSeries, loadTrack } from "./loaders";
import { capabilitiesQuery, comapStatusQuery, healthQuery, makeQueryClient, operatorQuery } from "./queries";
import { HISTORY_SECONDS, TRACK_SECONDS } from "./slices/vehicles";

interface Asked {
  url: string;
  auth: string | null;
}

/** fetch answering each path with `answer(path)` (a body, or a status for an error), recording what was asked. */
function fakeFetch(answer: (url: string) => unknown): Asked[] {
  const asked: Asked[] = [];
  vi.stubGlobal("fetch", async (request: Request) => {
    const url = request.url.slice(location.origin.length);
    asked.push({ url, auth: request.headers.get("Authorization") });
    const body = answer(url);
    if (typeof body === "number") return new Response(JSON.stringify({ detail: "no" }), { status: body });
    return new Response(JSON.stringify(body), { status: 200, headers: { "Content-Type": "application/json" } });
  });
  return asked;
}

const NOW = 1_800_000_000;

describe("REST through the generated paths", () => {
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
    expect(await loadSeries("v/1", "tok", NOW)).toEqual([{ t: NOW - 1, cn0: 41.5, used: 7, inView: 9 }]);
    expect(await loadTrack("v/1", null, NOW)).toEqual([{ t: NOW - 2, lat: 1.5, lon: 2.5 }]);
    const since = (s: number) => encodeURIComponent(new Date((NOW - s) * 1000).toISOString());
    expect(asked).toEqual([
      { url: `/api/providers/v%2F1/series?since=${since(HISTORY_SECONDS)}`, auth: "Bearer tok" },
      { url: `/api/providers/v%2F1/track?since=${since(TRACK_SECONDS)}`, auth: null },
    ]);
  });

  it("keys every cached read by the token", () => {
    expect(capabilitiesQuery("a", "t", 5000).queryKey).toEqual(["capabilities", "a", "t"]);
    expect(comapStatusQuery("t").queryKey).toContain("t");
    expect(operatorQuery("t").queryKey).toContain("t");
  });

  it("gives a console without CoMap as absent, and its world model as none", async () => {
    fakeFetch((url) => (url === "/api/worldmodel" ? 404 : url === "/api/comap" ? 404 : []));
    expect(await makeQueryClient().fetchQuery(comapStatusQuery(null))).toBe("absent");
    expect(await worldModel(null)).toBeNull();
  });

  it("turns a refusal into the console's words and no answer into 'console unreachable'", async () => {
    fakeFetch(() => 409);
    await expect(requestGpsFix("v", "tok")).rejects.toThrow("no");
    vi.stubGlobal("fetch", async () => {
      throw new TypeError("Failed to fetch");
    });
    await expect(requestGpsFix("v", "tok")).rejects.toMatchObject({ status: 0, message: UNREACHABLE });
  });
});
