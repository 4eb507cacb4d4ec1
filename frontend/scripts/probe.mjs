// Sample to pixel in headless Chromium (bench/probe.py drives it): the dashboard opened on a probe vehicle whose
// shown values encode a sequence number (latitude, INS time, satellites in view). A MutationObserver on each panel
// records every change of the shown value, stamped after the next frame (rAF, then a task: the frame has been
// painted); the map's marker of the selected vehicle (the overlay's ring) likewise.
// Also, over the same window: frame intervals, long tasks, render counts (?renders) and the CPU time of the
// renderer and GPU processes (CDP SystemInfo.getProcessInfo). First: a new client's time from navigation to the
// full dashboard (fix, INS and satellites shown, the map ready), the median of FIRST_SCREENS new clients. The probe's fix reports are stamped as they reach the
// page too (a WebSocket wrapped before the dashboard loads).
// Usage: node scripts/probe.mjs <console URL> <probe vehicle id> [seconds=20] [--no-map]
// Prints one JSON line.
import { launchChromium, startMeter } from "./browser.mjs";

const argv = process.argv.slice(2);
const noMap = argv.includes("--no-map");
const [url, probe, seconds = "20"] = argv.filter((a) => !a.startsWith("--"));
const WATCHED = { latitude: "fix-panel", "ins-time": "ins-panel", "sats-in-view": "satellites-panel" };
// a new client's time to the full dashboard is one load's, and one load's spreads by a third on a shared machine
// (650-960 ms with 50 vehicles): the figure is the median of this many new clients, each in a context of its own
const FIRST_SCREENS = 5;

/** A new client: navigation to every panel's value shown and the map ready (ms since navigation start). */
async function firstScreen(page) {
  await page.goto(`${url}/?renders&vehicle=${probe}`);
  const full = await page.waitForFunction(
    ({ ids, noMap }) => {
      const shown = ids.every((id) => {
        const t = document.querySelector(`[data-testid="${id}"]`)?.textContent;
        return t && t !== "—";
      });
      const map = noMap || document.querySelector('[data-testid="map"][data-ready="true"]');
      return shown && map ? performance.now() : false;
    },
    { ids: Object.keys(WATCHED), noMap },
    { polling: "raf", timeout: 60_000 },
  );
  return await full.jsonValue();
}

async function newContext(browser) {
  const context = await browser.newContext({ viewport: { width: 1440, height: 900 } });
  if (noMap) await context.addInitScript(() => localStorage.setItem("sem-console.collapsed", JSON.stringify(["map-panel"])));
  return context;
}

const browser = await launchChromium(["--enable-precise-memory-info"]);
try {
  const firstScreens = [];
  for (let i = 1; i < FIRST_SCREENS; i++) {
    // the others; the last is the page measured below
    const other = await newContext(browser);
    firstScreens.push(await firstScreen(await other.newPage()));
    await other.close();
  }
  const context = await newContext(browser);
  // the probe's GPSFixReports as the page's WebSocket gives them (before the dashboard applies them): the part of
  // the latency before the rendering (the console, the socket's buffers, the page's queue of messages)
  await context.addInitScript((probe) => {
    const arrived = (window.__probeArrivals = []);
    const Base = window.WebSocket;
    window.WebSocket = class extends Base {
      constructor(...args) {
        super(...args);
        this.addEventListener("message", (e) => {
          if (typeof e.data !== "string" || !e.data.includes(probe) || !e.data.includes('"GPSFixReport"')) return;
          const at = performance.timeOrigin + performance.now();
          const data = JSON.parse(e.data);
          for (const m of Array.isArray(data) ? data : [data]) {
            // a batch of reports (/ws?batch=1) or one message
            if (m.providerId !== probe || m.topic !== "GPSFixReport") continue;
            const lat = m.report?.report?.position2DWithTime?.geodeticPosition?.geodeticLatitude?.latitude;
            if (typeof lat === "number") arrived.push([lat.toFixed(6), at]);
          }
        });
      }
    };
  }, probe);
  const page = await context.newPage();
  firstScreens.push(await firstScreen(page));
  const sorted = [...firstScreens].sort((a, b) => a - b);
  const fullMs = sorted[Math.floor(sorted.length / 2)];
  await page.waitForTimeout(3000); // settle: the map's first frame, the tracks' REST loads
  const cdp = await browser.newBrowserCDPSession();
  const cpu = async () => {
    const { processInfo } = await cdp.send("SystemInfo.getProcessInfo");
    const sum = (type) => processInfo.filter((p) => p.type === type).reduce((a, p) => a + p.cpuTime, 0);
    return { renderer: sum("renderer"), gpu: sum("GPU") };
  };
  const cpuStart = await cpu();
  await page.evaluate(startMeter);
  const watched = await page.evaluate(
    ({ ms, watched, probe, noMap }) =>
      new Promise((resolve) => {
        const wall = () => performance.timeOrigin + performance.now();
        const afterFrame = (f) => requestAnimationFrame(() => setTimeout(f, 0));
        const shown = [];
        const observers = [];
        for (const [id, panel] of Object.entries(watched)) {
          let last = null;
          const check = () => {
            const text = document.querySelector(`[data-testid="${id}"]`)?.textContent ?? null;
            if (text === last) return;
            last = text;
            afterFrame(() => shown.push([id, text, wall()]));
          };
          const o = new MutationObserver(check);
          o.observe(document.querySelector(`[data-testid="${panel}"]`), { subtree: true, childList: true, characterData: true });
          observers.push(o);
        }
        // the map: the selected vehicle's ring (HTML over the map, moved on the frame after its fix), its latitude
        const map = [];
        const ring = document.querySelector('[data-testid="map-selected"]');
        if (!noMap && ring) {
          const o = new MutationObserver(() => {
            const lat = ring.dataset.lat;
            afterFrame(() => map.push([lat, wall()]));
          });
          o.observe(ring, { attributes: true, attributeFilter: ["data-lat"] });
          observers.push(o);
        }
        const start = wall();
        setTimeout(() => {
          for (const o of observers) o.disconnect();
          const end = wall();
          const arrived = window.__probeArrivals.filter(([, t]) => t >= start && t <= end);
          setTimeout(() => resolve({ shown, map, arrived, start, end }), 100); // the last changes' stamps
        }, ms);
      }),
    { ms: Number(seconds) * 1000, watched: WATCHED, probe, noMap },
  );
  const run = { ...watched, ...(await page.evaluate(() => window.__semMeter.stop())) };
  const cpuEnd = await cpu();
  const cores = (k) => +((cpuEnd[k] - cpuStart[k]) / run.elapsed).toFixed(3);
  console.log(
    JSON.stringify({
      ...run,
      full_dashboard_ms: +fullMs.toFixed(1),
      full_dashboard_all_ms: firstScreens.map((t) => +t.toFixed(1)),
      renderer_cores: cores("renderer"),
      gpu_cores: cores("gpu"),
    }),
  );
} finally {
  await browser.close();
}
