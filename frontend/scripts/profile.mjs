// A CPU profile of the dashboard (bench/profile.py drives it): the page opened on a vehicle, settled, then the V8
// sampling profiler (CDP Profiler) over a window, with the long tasks' start and duration. Prints the top functions by
// self time, and the heaviest stacks of the samples inside long tasks, as one JSON line.
// Usage: node scripts/profile.mjs <console URL> <vehicle id> [seconds=10] [out.cpuprofile]
import { writeFileSync } from "node:fs";
import { launchChromium } from "./browser.mjs";

const [url, vehicle, seconds = "10", out] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const context = await browser.newContext({ viewport: { width: 1440, height: 900 } });
  const page = await context.newPage();
  const cdp = await context.newCDPSession(page);
  await cdp.send("Profiler.enable");
  await cdp.send("Profiler.setSamplingInterval", { interval: 200 });
  const nav = Date.now();
  await cdp.send("Profiler.start"); // the first screen too
  await page.goto(`${url}/?vehicle=${vehicle}`);
  await page.waitForSelector('[data-testid="map"][data-ready="true"]', { timeout: 60_000 });
  const first = await cdp.send("Profiler.stop");
  const firstMs = Date.now() - nav;
  await page.waitForTimeout(3000);
  await page.evaluate(() => {
    window.__long = [];
    new PerformanceObserver((l) => {
      for (const e of l.getEntries()) window.__long.push([e.startTime, e.duration]);
    }).observe({ type: "longtask" });
  });
  await cdp.send("Profiler.start");
  const t0 = await page.evaluate(() => performance.timeOrigin + performance.now());
  await page.waitForTimeout(Number(seconds) * 1000);
  const { profile } = await cdp.send("Profiler.stop");
  const long = await page.evaluate(() => window.__long.map(([s, d]) => [performance.timeOrigin + s, d]));
  if (out) writeFileSync(out, JSON.stringify(profile));
  console.log(
    JSON.stringify({ steady: summarize(profile, long, t0), first: { ms: firstMs, ...summarize(first.profile, [], 0) } }),
  );
} finally {
  await browser.close();
}

function summarize(profile, long, t0) {
  const byId = new Map(profile.nodes.map((n) => [n.id, n]));
  const parent = new Map();
  for (const n of profile.nodes) for (const c of n.children ?? []) parent.set(c, n.id);
  const name = (n) => `${n.callFrame.functionName || "(anon)"} ${n.callFrame.url.split("/").pop()}:${n.callFrame.lineNumber + 1}`;
  const self = new Map();
  const total = new Map();
  const stacks = new Map(); // within long tasks
  let t = profile.startTime; // µs, the profiler's clock
  const wallStart = t0 * 1000; // µs since the epoch, matches profile.startTime approximately
  const inLong = (tw) => long.some(([s, d]) => tw >= s && tw <= s + d);
  let all = 0;
  profile.samples.forEach((id, i) => {
    const dt = (profile.timeDeltas[i] ?? 0) / 1000; // ms
    t += profile.timeDeltas[i] ?? 0;
    const n = byId.get(id);
    const nm = name(n);
    all += dt;
    self.set(nm, (self.get(nm) ?? 0) + dt);
    const seen = new Set();
    for (let c = id; c !== undefined; c = parent.get(c)) {
      const k = name(byId.get(c));
      if (seen.has(k)) continue;
      seen.add(k);
      total.set(k, (total.get(k) ?? 0) + dt);
    }
    if (long.length && inLong((wallStart + (t - profile.startTime)) / 1000)) {
      const chain = [];
      for (let c = id; c !== undefined && chain.length < 40; c = parent.get(c))
        chain.push(byId.get(c).callFrame.functionName || "(anon)");
      const k = chain
        .filter((x) => x !== "(anon)")
        .slice(0, 12)
        .join(" < ");
      stacks.set(k, (stacks.get(k) ?? 0) + dt);
    }
  });
  const top = (m, k) =>
    [...m.entries()]
      .sort((a, b) => b[1] - a[1])
      .slice(0, k)
      .map(([n, v]) => [n, +v.toFixed(1)]);
  return {
    total_ms: +all.toFixed(0),
    long: long.map(([, d]) => d),
    self: top(self, 30),
    total: top(total, 40),
    long_stacks: top(stacks, 15),
  };
}
