// A lost vehicle projected: a moving vehicle's simulator killed, the console calls it lost; wherever the page names it,
// it says when it was last heard, counting, and the map shows its dead-reckoned position as a guess (dashed, labelled
// "projected"), along its last course at its last speed from its last fix.
import { execFileSync } from "node:child_process";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";
import { expect, test, type Locator } from "@playwright/test";
import { jumpMap } from "../helpers";
import { OWN_STACK, freeDomain, load, startExtraConsole, startGuardedConsole, startSpecSim } from "../stack";

const SEM_SIM = join(dirname(fileURLToPath(import.meta.url)), "..", "..", ".venv", "bin", "sem-sim");
const R = 6_371_008.8; // the mean Earth radius the dashboard's geometry uses

type Fix = {
  SOG: number;
  trueCourse: number;
  position2DWithTime: {
    geodeticPosition: {
      geodeticLatitude: { latitude: number };
      geodeticLongitude: { longitude: number };
    };
  };
};

/** The seconds a "Last heard 2 min 10 s ago" says. */
async function heardSeconds(l: Locator): Promise<number> {
  const m = /^Last heard (?:(\d+) min )?(\d+) s ago$/.exec((await l.textContent()) ?? "");
  return m ? Number(m[1] ?? 0) * 60 + Number(m[2]) : NaN;
}

/** Distance (m) and initial bearing (degrees) from a to b on the sphere, worked here apart from the dashboard's. */
function legOf(a: { lat: number; lon: number }, b: { lat: number; lon: number }): { m: number; deg: number } {
  const r = Math.PI / 180;
  const dLat = (b.lat - a.lat) * r;
  const dLon = (b.lon - a.lon) * r;
  const h = Math.sin(dLat / 2) ** 2 + Math.cos(a.lat * r) * Math.cos(b.lat * r) * Math.sin(dLon / 2) ** 2;
  const y = Math.sin(dLon) * Math.cos(b.lat * r);
  const x = Math.cos(a.lat * r) * Math.sin(b.lat * r) - Math.sin(a.lat * r) * Math.cos(b.lat * r) * Math.cos(dLon);
  return {
    m: 2 * R * Math.asin(Math.sqrt(h)),
    deg: (Math.atan2(y, x) / r + 360) % 360,
  };
}

test(
  "a moving vehicle killed: 'Last heard … ago' counts wherever it is named, and the map projects it from its last fix, drawn as a guess",
  { tag: OWN_STACK },
  async ({ page, request }) => {
    // its own domain and console: the killed vehicle stays on a console as lost, and the stack's keeps its three
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const extra = await startGuardedConsole("projection-token", [
      "--domain",
      String(domain),
      "--db",
      join(stack.dir, "projection.sqlite3"),
    ]);
    const id = execFileSync(SEM_SIM, ["--list", "--vehicles", "1", "--first-vehicle", "11"], { encoding: "utf8" })
      .trim()
      .split(": ")[1];
    const sim = await startSpecSim([
      "--domain",
      String(domain),
      "--vehicles",
      "1",
      "--first-vehicle",
      "11",
      "--fix-rate",
      "5",
      "--state-file",
      join(stack.dir, "projection-sim.json"),
      "--log-level",
      "warning",
    ]);
    // the page's errors and warnings, named when the test fails
    const said: string[] = [];
    page.on("console", (m) => ["error", "warning"].includes(m.type()) && said.push(`${m.type()}: ${m.text()}`));
    page.on("pageerror", (e) => said.push(`pageerror: ${e.message}`));
    try {
      await page.goto(extra.url);
      await expect(page.getByTestId("connection-state")).toHaveText("Live");
      const chip = page.getByTestId("fleet-bar").getByTestId("fleet-vehicle");
      await expect(chip).toHaveAttribute("data-link", "live");
      await expect(chip).toHaveAttribute("aria-pressed", "true"); // the lone vehicle, selected
      await expect(page.getByTestId("map")).toHaveAttribute("data-vehicles", "1");
      await expect(page.getByTestId("map-projection")).toBeHidden(); // a live vehicle is not projected
      await expect(page.getByTestId("last-heard")).toHaveCount(0);

      await sim.stop("SIGKILL");
      await expect(chip).toHaveAttribute("data-link", "lost");
      // its last fix, as the console keeps it: it was moving
      const r = await request.get(`${extra.url}/api/providers/${id}`);
      const fix = ((await r.json()) as { reports: { GPSFixReport: { report: Fix } } }).reports.GPSFixReport.report;
      const g = fix.position2DWithTime.geodeticPosition;
      const last = {
        lat: g.geodeticLatitude.latitude,
        lon: g.geodeticLongitude.longitude,
      };
      expect(fix.SOG).toBeGreaterThan(1);

      // "Last heard" on its chip, counting each second, and on its row, its link-lost alarm and the selected vehicle's panels
      const heard = chip.getByTestId("last-heard");
      await expect(heard).toHaveText(/^Last heard \d+ s ago$/);
      const first = await heardSeconds(heard);
      await expect.poll(() => heardSeconds(heard)).toBeGreaterThanOrEqual(first + 2);
      await expect(page.getByTestId("vehicle").getByTestId("last-heard")).toHaveText(/^Last heard \d+ s ago$/);
      const alarm = page.getByTestId("alarm").and(page.locator('[data-kind="link-lost"]'));
      await expect(alarm.getByTestId("last-heard")).toHaveText(/^Last heard \d+ s ago$/);
      for (const panel of ["ins-panel", "fix-panel"])
        await expect(page.getByTestId(panel).getByTestId("selected-lost")).toContainText(/Lost · Last heard \d+ s ago/);
      // one age of one fact: each panel's badge says the seconds its "Last heard" line says, read in the same instant
      const ages = () =>
        page.evaluate(() =>
          ["ins-panel", "fix-panel"].map((p) => {
            const panel = document.querySelector(`[data-testid=${p}]`)!;
            return [
              panel.querySelector(`[data-testid=${p}-freshness]`)!.textContent,
              panel.querySelector("[data-testid=last-heard]")!.textContent,
            ];
          }),
        );
      for (let i = 0; i < 6; i++) {
        for (const [badge, line] of await ages()) expect(`Lost · ${/^Last heard (.*) ago$/.exec(line ?? "")?.[1]}`).toBe(badge);
        await page.waitForTimeout(400);
      }
      await expect(page.getByTestId("command-lost")).toContainText(/is lost: last heard \d+ s ago/);
      // none of them in a live region: a screen reader would say the count again every second
      const live = await page.evaluate(() =>
        [...document.querySelectorAll("[data-testid=last-heard], [data-testid=selected-lost], [data-testid=command-lost]")]
          .filter((e) =>
            e.closest("[role=status], [role=alert], [role=log], [role=marquee], [aria-live=polite], [aria-live=assertive]"),
          )
          .map((e) => e.getAttribute("data-testid")),
      );
      expect(live).toEqual([]);
      // and its name on the map
      await expect(page.getByTestId("map-label")).toHaveText(/ · lost · last heard \d+ s ago$/);

      // the map: its projection, labelled so, along its last course at its last speed for the time since it was heard
      const proj = page.getByTestId("map-projection");
      await expect(proj).toBeVisible();
      await expect(proj).toHaveAttribute("data-kind", "projected");
      await expect(proj).toHaveText(/^projected · within \d+ m$/);
      // read right after its vehicle's name, not before it (where it would pass for the previous vehicle's)
      expect(await proj.evaluate((p) => p.previousElementSibling?.getAttribute("data-testid"))).toBe("map-label");
      const at = async () => ({
        lat: Number(await proj.getAttribute("data-lat")),
        lon: Number(await proj.getAttribute("data-lon")),
        radius: Number(await proj.getAttribute("data-radius")),
        heard: await heardSeconds(heard),
      });
      const a = await at();
      await expect.poll(async () => (await at()).radius).toBeGreaterThan(a.radius); // the circle grows with time
      const b = await at();
      const leg = legOf(last, b);
      expect(Math.abs(((leg.deg - (fix.trueCourse * 180) / Math.PI + 540) % 360) - 180)).toBeLessThan(1);
      expect(Math.abs(leg.m / fix.SOG - b.heard)).toBeLessThan(2.5); // SOG × the seconds since it was heard
      expect(legOf(last, a).m).toBeLessThan(leg.m);

      // on the screen: stop following, zoom in on the projection; its label beside the ghost, and the fleet's canvas
      // drew the ghost there (and no report: the vehicle's dot stays at its last fix, away from it)
      await page.getByTestId("map-follow").click();
      await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "false"); // else it jumps back to the fix
      await jumpMap(page, { center: [b.lon, b.lat], zoom: 19 });
      // the map's view and the projection label's state, named when the test fails
      const view = () =>
        page.evaluate(() => {
          const map = window.__semMap;
          const follow = document.querySelector("[data-testid=map-follow]")?.getAttribute("aria-pressed");
          const p = document.querySelector<HTMLElement>("[data-testid=map-projection]");
          const box = document.querySelector("[data-testid=map]")?.getBoundingClientRect();
          const label = p && {
            hidden: p.hidden,
            text: p.textContent,
            at: [p.dataset.lat, p.dataset.lon],
            rect: p.getBoundingClientRect(),
            transform: p.style.transform,
            ghost: p.dataset.lon && p.dataset.lat ? map?.project([Number(p.dataset.lon), Number(p.dataset.lat)]) : null,
          };
          return JSON.stringify({ follow, center: map?.getCenter(), zoom: map?.getZoom(), box, label });
        });
      await expect
        .poll(
          () =>
            page.evaluate(() => {
              const p = document.querySelector<HTMLElement>("[data-testid=map-projection]")!;
              // the label and the ghost it names read in one instant, the map centred on the ghost where it is now
              // (the overlay places its labels on the map's move, in the same task): the ghost moves on each second,
              // about 15 px at zoom 19, and out of the map its label is hidden
              if (p.dataset.lon && p.dataset.lat)
                window.__semMap!.jumpTo({ center: [Number(p.dataset.lon), Number(p.dataset.lat)] });
              const l = p.getBoundingClientRect(); // empty while the label is drawn again for the new view: poll on
              if (p.hidden || l.width === 0) return false;
              const box = document.querySelector("[data-testid=map]")!.getBoundingClientRect();
              const ghost = window.__semMap!.project([Number(p.dataset.lon), Number(p.dataset.lat)]);
              return Math.abs(l.right - (box.x + ghost.x - 12)) < 3 && Math.abs(l.y - (box.y + ghost.y - 8)) < 3;
            }),
          { message: "the projection's label beside its ghost" },
        )
        .toBe(true)
        .catch(async (e: unknown) => {
          throw new Error(`${String(e)}\nthe map: ${await view()} (the ghost at ${JSON.stringify(b)})\n${said.join("\n")}`);
        });
      await expect(page.getByTestId("map-follow")).toHaveAttribute("aria-pressed", "false"); // not following again
      // the circle's faint fill just past the ghost's middle (beyond the end of the line from the last fix): drawn, and
      // not opaque as a vehicle's dot is. Read where the page says the ghost is, two frames on (any drawing of the
      // canvas asked before is done), and only if the page still says so: a new second's ghost drawn in between
      // would put the old place on the dashed line behind it
      const fillAlpha = () =>
        page.evaluate(
          async ([lon0, lat0]) => {
            const p = document.querySelector<HTMLElement>("[data-testid=map-projection]")!;
            const place = `${p.dataset.lon} ${p.dataset.lat}`;
            await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
            if (`${p.dataset.lon} ${p.dataset.lat}` !== place || !p.dataset.lon) return null; // moved on: read again
            const map = window.__semMap!;
            const xy = map.project([Number(p.dataset.lon), Number(p.dataset.lat)]);
            const from = map.project([lon0, lat0]);
            const d = Math.hypot(xy.x - from.x, xy.y - from.y) || 1;
            const canvas = document.querySelector<HTMLCanvasElement>("[data-testid=map-fleet]")!;
            const dpr = canvas.width / canvas.clientWidth;
            const x = xy.x + (4 * (xy.x - from.x)) / d;
            const y = xy.y + (4 * (xy.y - from.y)) / d;
            return canvas.getContext("2d")!.getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data[3];
          },
          [last.lon, last.lat] as [number, number],
        );
      let alpha: number | null = null;
      await expect.poll(async () => (alpha = await fillAlpha()) ?? 0).toBeGreaterThan(0); // drawn (null: read again)
      expect(alpha).toBeLessThan(100); // and faint
    } finally {
      await sim.stop("SIGKILL");
      await extra.stop();
    }
  },
);

test(
  "in a replay, the selected vehicle lost in the recording is said lost there, not now",
  { tag: OWN_STACK },
  async ({ page, request }) => {
    test.setTimeout(120_000);
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const token = "replay-lost-token";
    const auth = { Authorization: `Bearer ${token}` };
    // its recordings apart from the stack's, whose list the stack's tests read meanwhile
    const recordings = join(stack.dir, "replay-lost-recordings");
    const extra = await startGuardedConsole(token, [
      "--domain",
      String(domain),
      "--db",
      join(stack.dir, "replay-lost.sqlite3"),
      "--recordings-dir",
      recordings,
    ]);
    const id = execFileSync(SEM_SIM, ["--list", "--vehicles", "1", "--first-vehicle", "12"], { encoding: "utf8" })
      .trim()
      .split(": ")[1];
    const simOf = (n: number) =>
      startSpecSim([
        "--domain",
        String(domain),
        "--vehicles",
        "1",
        "--first-vehicle",
        String(n),
        "--state-file",
        join(stack.dir, `replay-lost-sim-${n}.json`),
        "--log-level",
        "warning",
      ]);
    const sim = await simOf(12);
    const other = await simOf(13); // heard to the end: the recording goes on past the loss, and the replay's console calls it lost
    const link = async () => ((await (await request.get(`${extra.url}/api/providers/${id}`)).json()) as { link?: string }).link;
    let replay: { url: string; stop: () => Promise<void> } | null = null;
    try {
      await expect.poll(link, { timeout: 30_000 }).toBe("live");
      expect(
        (
          await request.post(`${extra.url}/api/recordings`, {
            headers: auth,
            data: { action: "start" },
          })
        ).ok(),
      ).toBe(true);
      await page.waitForTimeout(2000);
      await sim.stop("SIGKILL");
      await expect.poll(link, { timeout: 30_000 }).toBe("lost");
      await page.waitForTimeout(4000);
      const stopped = await request.post(`${extra.url}/api/recordings`, {
        headers: auth,
        data: { action: "stop" },
      });
      const { file } = (await stopped.json()) as { file: string };
      replay = await startExtraConsole(["--replay", join(recordings, file)]);
      // the recording's last instant, paused: the vehicle lost there
      const { end } = (await (await request.get(`${replay.url}/api/replay`)).json()) as { end: number };
      await request.post(`${replay.url}/api/replay`, {
        data: { action: "pause" },
      });
      await request.post(`${replay.url}/api/replay`, {
        data: { action: "seek", position: end },
      });
      await page.goto(`${replay.url}/?vehicle=${id}`);
      await expect(page.getByTestId("fleet-vehicle").and(page.locator(`[data-vehicle="${id}"]`))).toHaveAttribute(
        "data-link",
        "lost",
      );
      for (const panel of ["ins-panel", "fix-panel"])
        await expect(page.getByTestId(panel).getByTestId("selected-lost")).toHaveText(
          /^Recorded: lost · Last heard \d+ s ago · shown: what it last reported$/,
        );
    } finally {
      await sim.stop("SIGKILL");
      await other.stop("SIGKILL");
      await replay?.stop();
      await extra.stop();
    }
  },
);
