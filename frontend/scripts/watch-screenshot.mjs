// Screenshot of a watch's alarm management: a flood grouped, a shelved alarm listed, a planned silence, in headless
// Chromium. Usage: node scripts/watch-screenshot.mjs <console URL> <out.png> <vehicle to select>
import { launchChromium } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/watch.png", vehicle = ""] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  await page.goto(vehicle ? `${url}/?vehicle=${vehicle}` : url);
  await page.getByTestId("alarm-group").waitFor({ timeout: 20_000 });
  await page.getByTestId("alarms-shelved").click();
  const alarms = page.getByTestId("alarms-panel");
  await alarms.scrollIntoViewIfNeeded();
  await page.waitForTimeout(800);
  await page.screenshot({ path: out, fullPage: false });
  console.log(`screenshot: ${out}`);
} finally {
  await browser.close();
}
