// What the screenshot and frame-time scripts share: Debian's Chromium launched headless with the
// project's flags, and a page that refuses (and lists) every request to another origin than the console's.
import { chromium } from "playwright-core";

const ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--disable-background-networking",
  "--disable-component-update", "--disable-sync", "--no-first-run"];

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
