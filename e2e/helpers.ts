// Locators and steps shared by the specs.
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import AxeBuilder from "@axe-core/playwright";
import { expect, type APIRequestContext, type Locator, type Page } from "@playwright/test";
import { load } from "./stack";

/** The simulator's command, for the list of a spec's own vehicles (`--list`); a spec starts them with startSpecSim. */
export const SEM_SIM = join(dirname(fileURLToPath(import.meta.url)), "..", ".venv", "bin", "sem-sim");

export function vehicle(page: Page, id: string): Locator {
  return page.getByTestId("vehicle").filter({ hasText: id.slice(0, 8) });
}

/** The map moved at once (MapLibre's jumpTo), answering nothing: jumpTo returns the map itself, and Playwright
 * serialised that whole object graph back to the test, about 2 CPU-seconds of the test's worker a call and as much of
 * the page's (measured 2026-12-01). */
export async function jumpMap(page: Page, to: { center?: [number, number]; zoom?: number }): Promise<void> {
  await page.evaluate((o) => {
    window.__semMap!.jumpTo(o);
  }, to);
}

/** Load the dashboard and select a vehicle of the stack (the dashboard selects none by itself). */
export async function open(page: Page, vehicleIndex = 0): Promise<string> {
  const stack = load();
  await page.goto(stack.url);
  await expect(page.getByTestId("connection-state")).toHaveText("Live");
  const id = stack.vehicles[vehicleIndex];
  await vehicle(page, id).click();
  await expect(vehicle(page, id)).toHaveAttribute("aria-pressed", "true");
  return id;
}

export function latestCommand(page: Page): Locator {
  return page.getByTestId("commands-panel").getByTestId("command").first();
}

export interface CommandRecord {
  sessionId: string;
  providerId: string;
  state: string | null;
}

/** Every command in the console's history (REST, newest first). */
export async function history(request: APIRequestContext, url = load().url): Promise<CommandRecord[]> {
  return (await (await request.get(`${url}/api/commands?limit=1000`)).json()) as CommandRecord[];
}

/** The stack's vehicles all live again and no link-lost alarm left (the cleared ones acknowledged, so they leave the
 * set): a spec that stops the simulator calls it before, so that an earlier spec's leftovers are not counted as its
 * own, and after, so that the next specs start without them. */
export async function settleLinkLost(request: APIRequestContext): Promise<void> {
  const stack = load();
  await expect
    .poll(
      async () => {
        const summaries = (await (await request.get(`${stack.url}/api/providers`)).json()) as { id: string; link: string }[];
        return stack.vehicles.every((id) => summaries.find((p) => p.id === id)?.link === "live");
      },
      { timeout: 30_000 },
    )
    .toBe(true);
  const linkLost = async () =>
    ((await (await request.get(`${stack.url}/api/alarms`)).json()) as { id: number; kind: string; state: string }[]).filter(
      (a) => a.kind === "link-lost",
    );
  await expect.poll(async () => (await linkLost()).every((a) => a.state === "cleared-unacknowledged")).toBe(true);
  for (const a of await linkLost()) await request.post(`${stack.url}/api/alarms/${a.id}/ack`, { data: {} });
  await expect.poll(async () => (await linkLost()).length).toBe(0);
}

/** Refuse (and record) every request that does not go to the console; the test fails on any. */
export async function consoleOnly(page: Page): Promise<string[]> {
  const origin = new URL(load().url).origin;
  const foreign: string[] = [];
  await page.route("**/*", (route) => {
    const url = route.request().url();
    if (new URL(url).origin === origin) return route.continue();
    foreign.push(url);
    return route.abort("blockedbyclient");
  });
  page.on("requestfailed", (r) => {
    const url = r.url();
    if (!url.startsWith("data:") && !url.startsWith("blob:") && new URL(url).origin !== origin) foreign.push(url);
  });
  return foreign;
}

/** What the tests use of the dashboard's MapLibre map (Map.tsx's test hook `window.__semMap`). */
export interface TestMap {
  project(lngLat: [number, number]): { x: number; y: number };
  unproject(point: [number, number]): { lng: number; lat: number };
  getZoom(): number;
  getCenter(): { lng: number; lat: number };
  jumpTo(options: { center?: [number, number]; zoom?: number }): void;
  queryRenderedFeatures(options: { layers: string[] }): {
    properties: Record<string, unknown> | null;
    geometry: { type: string; coordinates?: unknown };
  }[];
  getCanvas(): HTMLCanvasElement;
}

/** The fleet's canvas over the map (FleetCanvas.ts's test hook `window.__semFleet`): the tracks and clusters it draws. */
export interface TestFleet {
  tracks(): {
    id: string;
    selected: boolean;
    points: { lon: number; lat: number }[];
  }[];
  drawnClusters(): string[][];
}

declare global {
  interface Window {
    __semMap?: TestMap;
    __semFleet?: TestFleet;
  }
}

/** axe's violations, each as its rule and the elements it found, so a failure says what to fix; of the elements
 * `within` (CSS selectors) when given, else of the page. */
export async function violations(page: Page, ...within: string[]): Promise<string[]> {
  // every rule still runs; only its violations are gathered with all their elements (axe's resultTypes), not the
  // thousands of elements that pass: an analysis took 1.6 CPU-s of the browser and 0.7 of Playwright's worker against
  // 2.5 and 1.3 (measured on the streaming dashboard)
  const axe = new AxeBuilder({ page }).options({ resultTypes: ["violations"] });
  for (const selector of within) axe.include(selector);
  const { violations } = await axe.analyze();
  return violations.map(
    (v) =>
      `${v.id} (${v.impact}): ${v.help}: ${v.nodes.map((n) => `${n.target.join(" ")}${n.failureSummary ? ` [${n.failureSummary.replace(/\s+/g, " ")}]` : ""}`).join("; ")}`,
  );
}
