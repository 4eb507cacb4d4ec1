// Screenshot of the dashboard replaying a recording, with the replay controls, in headless Chromium.
// Usage: node scripts/replay-screenshot.mjs <replay console URL> <out.png> <vehicle id> [seconds from the start to show]
import { launchChromium } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/replay.png", vehicle = "", at = "0"] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 1180 } });
  await page.goto(vehicle ? `${url}/?vehicle=${vehicle}` : url);
  await page.getByTestId("replay-bar").waitFor({ timeout: 20_000 });
  const status = await (await page.request.get(`${url}/api/replay`)).json();
  const post = (body) => page.request.post(`${url}/api/replay`, { data: body });
  await post({ action: "seek", position: Math.min(status.end, status.start + Number(at)) });
  await post({ action: "speed", speed: 2 });
  await post({ action: "play" });
  await page.waitForTimeout(5000); // trails, charts and ages fill in as it plays
  await post({ action: "pause" });
  await page.waitForTimeout(800);
  await page.screenshot({ path: out, fullPage: false });
  console.log(`screenshot: ${out}`);
} finally {
  await browser.close();
}
