// Locators and steps shared by the specs.
import type { ChildProcess } from "node:child_process";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import AxeBuilder from "@axe-core/playwright";
import { expect, type APIRequestContext, type Locator, type Page } from "@playwright/test";
import { load } from "./stack";

/** The simulator, for a spec's own vehicles on a domain of its own. */
export const SEM_SIM = join(dirname(fileURLToPath(import.meta.url)), "..", ".venv", "bin", "sem-sim");

/** Stop a process a spec started and wait for it to exit (SIGKILL after 15 s). */
export async function stopChild(child: ChildProcess): Promise<void> {
  if (child.exitCode !== null || child.signalCode !== null) return;
  const exited = new Promise<void>((resolve) => child.once("exit", () => resolve()));
  child.kill("SIGINT");
  const timer = setTimeout(() => child.kill("SIGKILL"), 15_000);
  await exited;
  clearTimeout(timer);
}

export function vehicle(page: Page, id: string): Locator {
  return page.getByTestId("vehicle").filter({ hasText: id.slice(0, 8) });
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
  const axe = new AxeBuilder({ page });
  for (const selector of within) axe.include(selector);
  const { violations } = await axe.analyze();
  return violations.map(
    (v) =>
      `${v.id} (${v.impact}): ${v.help}: ${v.nodes.map((n) => `${n.target.join(" ")}${n.failureSummary ? ` [${n.failureSummary.replace(/\s+/g, " ")}]` : ""}`).join("; ")}`,
  );
}
