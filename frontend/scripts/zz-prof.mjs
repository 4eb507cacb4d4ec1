import { chromium } from "playwright-core";
const [url, collapse] = process.argv.slice(2);
const browser = await chromium.launch({ executablePath: "/usr/bin/chromium",
  args: ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader"] });
const context = await browser.newContext({ viewport: { width: 1440, height: 900 } });
const page = await context.newPage();
await page.goto(`${url}/?renders`);
await page.getByTestId("connection-state").filter({ hasText: "Live" }).waitFor({ timeout: 30_000 });
if (collapse) { await page.getByTestId(`${collapse}-collapse`).click(); console.log("collapsed", await page.getByTestId(`${collapse}-collapse`).getAttribute("aria-expanded"), await page.locator(".maplibregl-canvas").count()); }
await page.getByTestId("vehicle").first().click();
await page.getByTestId("sky-satellite").first().waitFor({ timeout: 30_000 });
const cdp = await context.newCDPSession(page);
await cdp.send("Emulation.setCPUThrottlingRate", { rate: 4 });
await page.waitForTimeout(3000);

const events = [];
cdp.on("Tracing.dataCollected", (d) => events.push(...d.value));
const done = new Promise((r) => cdp.once("Tracing.tracingComplete", r));
await cdp.send("Tracing.start", { traceConfig: { includedCategories: ["devtools.timeline", "disabled-by-default-devtools.timeline", "v8.execute"] }, transferMode: "ReportEvents" });
await page.waitForTimeout(10000);
await cdp.send("Tracing.end");
await done;
const byTid = new Map();
for (const e of events) if (e.name === "RunTask" && e.dur) byTid.set(`${e.pid}:${e.tid}`, (byTid.get(`${e.pid}:${e.tid}`) ?? 0) + e.dur);
const main = [...byTid.entries()].sort((a,b)=>b[1]-a[1])[0][0];
const ev = events.filter((e) => `${e.pid}:${e.tid}` === main && e.ph === "X" && e.dur).sort((a, b) => a.ts - b.ts);
const long = ev.filter((e) => e.name === "RunTask" && e.dur > 50000);
console.log("long tasks", long.length, "main busy ms", (byTid.get(main)/1000).toFixed(0));
const agg = new Map();
for (const t of long) {
  const kids = ev.filter((e) => e !== t && e.ts >= t.ts && e.ts + e.dur <= t.ts + t.dur && e.name !== "RunTask");
  // direct-ish children: depth 1 = not contained in another kid
  const top = kids.filter((k) => !kids.some((o) => o !== k && o.ts <= k.ts && o.ts + o.dur >= k.ts + k.dur && o.dur > k.dur));
  const desc = top.map((k) => `${k.name}${k.args?.data?.functionName ? ":" + k.args.data.functionName : ""}${k.args?.data?.url ? "@" + k.args.data.url.split("/").pop() + ":" + k.args.data.lineNumber : ""} ${(k.dur/1000).toFixed(0)}`).join(", ");
  console.log((t.dur/1000).toFixed(0).padStart(5), "ms:", desc.slice(0, 300));
}
await browser.close();
