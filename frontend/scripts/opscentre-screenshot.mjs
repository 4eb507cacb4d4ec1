// Screenshots of one station of an operations centre, in headless Chromium, signed in with an operator token and a
// vehicle selected: <out>.png the first screen (header, fleet bar, map), <out>-alarms.png the alarm panel with its
// flood grouped, its shelved alarms listed and its planned silences.
// Usage: node scripts/opscentre-screenshot.mjs <console URL> <out, without .png> <vehicle to select> <operator token>
import { launchChromium } from "./browser.mjs";

const [url = "http://127.0.0.1:8000", out = "../docs/opscentre", vehicle = "", token = ""] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  if (token) await page.addInitScript((t) => sessionStorage.setItem("sem-console-token", t), token);
  await page.goto(vehicle ? `${url}/?vehicle=${vehicle}` : url);
  await page.getByTestId("alarm-group").first().waitFor({ timeout: 20_000 });
  await page.waitForTimeout(1500);
  await page.screenshot({ path: `${out}.png`, fullPage: false });
  await page.getByTestId("alarms-shelved").click();
  const alarms = page.getByTestId("alarms-panel");
  await alarms.scrollIntoViewIfNeeded();
  await page.waitForTimeout(500);
  await alarms.screenshot({ path: `${out}-alarms.png` });
  console.log(`screenshots: ${out}.png, ${out}-alarms.png`);
} finally {
  await browser.close();
}
