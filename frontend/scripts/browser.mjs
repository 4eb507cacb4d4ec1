// What the screenshot and frame-time scripts share: Debian's Chromium launched headless with the
// project's flags, and a page that refuses (and lists) every request to another origin than the console's.
import { chromium } from "playwright-core";

const ARGS = [
  "--headless",
  "--no-sandbox",
  "--disable-gpu",
  "--enable-unsafe-swiftshader",
  "--disable-background-networking",
  "--disable-component-update",
  "--disable-sync",
  "--no-first-run",
];

/** Headless Chromium (`CHROMIUM`, else /usr/bin/chromium) with the project's flags and `extra` ones. */
export function launchChromium(extra = []) {
  return chromium.launch({ executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", args: [...ARGS, ...extra] });
}

/** Abort every request of `page` to another origin than `url`'s; returns the list they are added to. */
export async function refuseOtherOrigins(page, url) {
  const origin = new URL(url).origin;
  const foreign = [];
  await page.route("**/*", (route) => {
    if (new URL(route.request().url()).origin === origin) return route.continue();
    foreign.push(route.request().url());
    return route.abort();
  });
  return foreign;
}

/** In the page: start measuring frame intervals (requestAnimationFrame), long tasks and renders per panel (the
 * dashboard's ?renders counters); `window.__semMeter.stop()` returns them over the window since. */
export function startMeter() {
  const longTasks = [];
  const observer = new PerformanceObserver((list) => {
    for (const e of list.getEntries()) longTasks.push(e.duration);
  });
  observer.observe({ type: "longtask" });
  const rendersStart = { ...(window.__semRenders ?? {}) };
  const frames = [];
  const t0 = performance.now();
  let last = t0;
  let running = true;
  const tick = (t) => {
    frames.push(t - last);
    last = t;
    if (running) requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
  window.__semMeter = {
    stop: () => {
      running = false;
      observer.disconnect();
      const elapsed = (performance.now() - t0) / 1000;
      const renders = {};
      for (const [k, v] of Object.entries(window.__semRenders ?? {}))
        renders[k] = +((v - (rendersStart[k] ?? 0)) / elapsed).toFixed(2);
      return { frames: frames.slice(1), longTasks, renders, elapsed }; // the first interval starts mid-frame
    },
  };
}
