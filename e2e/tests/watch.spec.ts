// Alarm management for a watch: a planned silence, a flood of 20 vehicles lost at once grouped by its cause with one
// tone and one announcement, and shelving, on the screen of a console of its own (its own domain and 21 vehicles, so
// the stack's console keeps its three for the other specs).
import { execFileSync } from "node:child_process";
import { join } from "node:path";
import { expect, test, type Page } from "@playwright/test";
import { SEM_SIM, violations } from "../helpers";
import { OWN_STACK, freeDomain, load, startGuardedConsole, startSpecSim } from "../stack";

/** HH:MM UTC `minutes` from now. */
function utcIn(minutes: number): string {
  return new Date(Date.now() + minutes * 60_000).toISOString().slice(11, 16);
}

/** How the dashboard says the next UTC `hhmm` to come: "14:20" today, else with its date. */
function said(hhmm: string): string {
  const today = new Date().toISOString().slice(0, 10);
  let t = Date.parse(`${today}T${hhmm}:00Z`);
  if (t <= Date.now()) t += 86_400_000;
  const day = new Date(t).toISOString().slice(0, 10);
  return day === today ? hhmm : `${day} ${hhmm}`;
}

/** Count the alarm tones the page sounds: a stand-in for the Web Audio API whose oscillators are counted (two per tone);
 * returns the count so far. */
async function countTones(page: Page): Promise<() => Promise<number>> {
  await page.addInitScript(() => {
    const w = window as unknown as {
      __oscillators: number;
      AudioContext: unknown;
    };
    w.__oscillators = 0;
    const node = {
      connect: (n: unknown) => n,
      gain: { setValueAtTime() {}, exponentialRampToValueAtTime() {} },
    };
    w.AudioContext = class {
      state = "running";
      currentTime = 0;
      destination = {};
      resume() {
        return Promise.resolve();
      }
      suspend() {
        return Promise.resolve();
      }
      createGain() {
        return node;
      }
      createOscillator() {
        w.__oscillators++;
        return {
          ...node,
          type: "sine",
          frequency: { value: 0 },
          start() {},
          stop() {},
        };
      }
    };
  });
  return async () => (await page.evaluate(() => (window as unknown as { __oscillators: number }).__oscillators)) / 2;
}

test(
  "a planned silence, a flood of 20 vehicles grouped with one tone and one announcement, and a shelf",
  { tag: OWN_STACK },
  async ({ page }) => {
    test.setTimeout(180_000);
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const token = "watch-token";
    const extra = await startGuardedConsole(token, ["--domain", String(domain), "--db", join(stack.dir, "watch.sqlite3")]);
    const ids = execFileSync(SEM_SIM, ["--list", "--vehicles", "21", "--first-vehicle", "30"], { encoding: "utf8" })
      .trim()
      .split("\n")
      .map((l) => l.split(": ")[1]);
    const sim = await startSpecSim([
      "--domain",
      String(domain),
      "--vehicles",
      "21",
      "--first-vehicle",
      "30",
      "--state-file",
      join(stack.dir, "watch-sim.json"),
      "--log-level",
      "warning",
    ]);
    const tones = await countTones(page); // the tone, counted
    try {
      await page.goto(extra.url);
      const { consoleName } = (await (await page.request.get(`${extra.url}/api/health`)).json()) as { consoleName: string };
      await expect(page.getByTestId("console-station")).toHaveText(`station ${consoleName}`); // its name; the GUID in a tooltip
      await page.getByLabel("Operator token").fill(token);
      await page.getByRole("button", { name: "Sign in" }).click();
      await expect(page.getByTestId("signed-in")).toBeVisible();
      const chips = page.getByTestId("fleet-bar").getByTestId("fleet-vehicle");
      await expect(chips).toHaveCount(21, { timeout: 60_000 });
      await expect(page.getByTestId("fleet-live")).toHaveText("21 live", {
        timeout: 30_000,
      });

      // the 21st vehicle will dive: its planned silence, declared on screen
      const diver = ids[20];
      const diverChip = chips.filter({ hasText: diver.slice(0, 8) });
      await diverChip.click();
      const region = page.getByRole("region", { name: "Alarms" });
      const until = utcIn(30);
      const form = region.getByRole("form", {
        name: `Out of comms until: Vehicle ${diver.slice(0, 8)}`,
      }); // named as everywhere
      await form.getByLabel(/^Why/).fill("dive to 40 m");
      await form.getByLabel("Until (UTC)").fill("2:20 PM"); // a 12-hour time: the field is 24-hour UTC, and says so
      await form.getByRole("button", { name: "Declare planned silence" }).click();
      await expect(region.getByRole("alert")).toHaveText("Until: write a UTC time of day as HH:MM, 24-hour (14:20)");
      await expect(region.getByTestId("planned-silence")).toHaveCount(0);
      await form.getByLabel("Until (UTC)").fill(until);
      await form.getByRole("button", { name: "Declare planned silence" }).click();
      await expect(region.getByTestId("planned-silence")).toHaveText(
        new RegExp(
          `^Vehicle ${diver.slice(0, 8)}: out of comms \\(planned\\) until ${said(until)} UTC: dive to 40 m \\(declared by e2e-operator on ${consoleName}\\)`,
        ),
      );
      await expect(diverChip.getByTestId("fleet-silence")).toHaveText(`Out of comms (planned) until ${said(until)} UTC`);
      // silenced: the form offers to change its end or end it, not to declare it again
      await expect(form.getByTestId("silence-form-title")).toHaveText(
        `Vehicle ${diver.slice(0, 8)}: planned silence until ${said(until)} UTC`,
      );
      await expect(form.getByRole("button", { name: "Declare planned silence" })).toHaveCount(0);
      await expect(form.getByRole("button", { name: "Change end" })).toBeVisible();
      await expect(form.getByRole("button", { name: "End silence now" })).toBeVisible();

      // the relay fails: every vehicle lost at once
      const before = await tones();
      await sim.stop();
      await expect(page.getByTestId("fleet-lost")).toHaveText("20 lost", {
        timeout: 30_000,
      });
      await expect(page.getByTestId("fleet-planned")).toHaveText(`1 out of comms (planned) until ${said(until)} UTC`);
      // one name on the whole page: the chip, the vehicle list, the INS and GPS panels, the Commands panel (no red box)
      const planned = `Out of comms (planned) until ${said(until)} UTC`;
      await expect(diverChip.getByTestId("fleet-link")).toHaveText(planned);
      await expect(page.getByTestId("vehicle").filter({ hasText: diver }).getByTestId("vehicle-link")).toHaveText(planned);
      await expect(page.getByTestId("selected-lost").first()).toContainText(planned);
      await expect(page.getByTestId("command-lost")).toContainText(
        `is out of comms (planned) until ${said(until)} UTC: last heard`,
      );
      await expect(page.getByTestId("command-lost")).not.toHaveClass(/alarm/);
      const group = region.getByTestId("alarm-group");
      await expect(group.getByTestId("alarm-group-title")).toHaveText("Link lost: 20 vehicles");
      await expect(region.getByTestId("alarm")).toHaveCount(0); // one line, not twenty: the first screen stays readable
      await expect(page.getByTestId("fleet-newest-alarm")).toHaveText("Alarm: Link lost: 20 vehicles");
      await expect(page.getByTestId("alarm-announcement")).toHaveText("Alarm: Link lost: 20 vehicles: see the alarm list");
      await page.waitForTimeout(2000); // anything late of the flood would have sounded by now
      expect((await tones()) - before).toBe(1);
      await expect(page.getByTestId("fleet-alarms")).toHaveText("20 unacknowledged alarms");

      // expandable: each vehicle's alarm
      await group.getByRole("button", { name: "Show each" }).click();
      await expect(group.getByTestId("alarm")).toHaveCount(20);

      // shelve one, with a reason: counted apart, out of the group and the count, shown with who, why and until
      const first = group.getByTestId("alarm").first();
      const text = (await first.locator(".alarm-text").textContent())!;
      await first.getByRole("button", { name: `Shelve: ${text}` }).click();
      const shelveForm = first.getByRole("form", { name: `Shelve: ${text}` });
      // what this changes of the page (the map's edge arrows, 21 vehicles out of its view, are another matter)
      const watched = ['[data-testid="fleet-bar"]', '[data-testid="alarms-panel"]'];
      expect(await violations(page, ...watched)).toEqual([]); // the group open, a shelve form open
      await shelveForm.getByLabel("Why shelve it").fill("relay down, known");
      await shelveForm.getByLabel("For").selectOption("1 h");
      await shelveForm.getByRole("button", { name: "Shelve alarm" }).click();
      await expect(group.getByTestId("alarm-group-title")).toHaveText("Link lost: 19 vehicles");
      await expect(page.getByTestId("fleet-shelved")).toHaveText("1 shelved");
      await expect(page.getByTestId("fleet-alarms")).toHaveText("19 unacknowledged alarms");
      await region.getByTestId("alarms-shelved").click();
      const shelvedEntry = region.getByTestId("shelved-alarm");
      await expect(shelvedEntry).toContainText(text);
      expect(await violations(page, ...watched)).toEqual([]); // the shelved list open
      await expect(shelvedEntry.getByTestId("shelf-words")).toHaveText(
        /^shelved by e2e-operator on \S+ until (\d{4}-\d\d-\d\d )?\d\d:\d\d UTC: relay down, known$/,
      );

      // unshelved: back in view, saying why
      await shelvedEntry.getByRole("button", { name: `Unshelve: ${text}` }).click();
      await expect(group.getByTestId("alarm-group-title")).toHaveText("Link lost: 20 vehicles");
      await expect(page.getByTestId("fleet-shelved")).toHaveCount(0);
      await expect(group.getByTestId("alarm").filter({ hasText: text }).getByTestId("alarm-returned")).toHaveText(
        "back from shelving: unshelved by e2e-operator",
      );

      // the planned silence cancelled: the diver's loss is an alarm at once
      await region
        .getByRole("button", {
          name: `Cancel silence: Vehicle ${diver.slice(0, 8)}`,
        })
        .click();
      await expect(region.getByTestId("planned-silence")).toHaveCount(0);
      await expect(group.getByTestId("alarm-group-title")).toHaveText("Link lost: 21 vehicles");
      await expect(page.getByTestId("fleet-lost")).toHaveText("21 lost");
    } finally {
      await sim.stop();
      await extra.stop();
    }
  },
);

test(
  "a chattering alarm: back too often, marked so, and not sounded again until acknowledged",
  { tag: OWN_STACK },
  async ({ page }) => {
    test.setTimeout(120_000);
    const stack = load();
    const domain = await freeDomain([stack.domain]);
    const token = "chatter-token";
    // chattering at its second return within 10 minutes; a vehicle lost after 1 s without samples
    const extra = await startGuardedConsole(token, [
      "--domain",
      String(domain),
      "--db",
      join(stack.dir, "chatter.sqlite3"),
      "--chatter-count",
      "2",
      "--comms-lost-timeout",
      "1",
    ]);
    const simArgs = [
      "--domain",
      String(domain),
      "--vehicles",
      "1",
      "--first-vehicle",
      "60",
      "--state-file",
      join(stack.dir, "chatter-sim.json"),
      "--log-level",
      "warning",
    ];
    const startSim = () => startSpecSim(simArgs);
    let sim = await startSim();
    const tones = await countTones(page);
    try {
      await page.goto(extra.url);
      await page.getByLabel("Operator token").fill(token);
      await page.getByRole("button", { name: "Sign in" }).click();
      await expect(page.getByTestId("signed-in")).toBeVisible();
      const chip = page.getByTestId("fleet-bar").getByTestId("fleet-vehicle");
      await expect(chip).toHaveAttribute("data-link", "live", {
        timeout: 30_000,
      });
      const alarm = page
        .getByRole("region", { name: "Alarms" })
        .getByTestId("alarm")
        .and(page.locator('[data-kind="link-lost"]'));
      const lose = async () => {
        await sim.stop();
        await expect(chip).toHaveAttribute("data-link", "lost", {
          timeout: 15_000,
        });
      };
      const regain = async () => {
        sim = await startSim();
        await expect(chip).not.toHaveAttribute("data-link", "lost", {
          timeout: 30_000,
        });
        await expect(alarm).toHaveAttribute("data-state", "cleared-unacknowledged");
      };

      await lose(); // the link lost: an alarm, sounded
      await expect(alarm).toHaveAttribute("data-state", "active-unacknowledged");
      await expect.poll(tones).toBe(1);
      await regain();
      await lose(); // back once: sounded again, not chattering yet
      await expect(alarm).toHaveAttribute("data-state", "active-unacknowledged");
      await expect.poll(tones).toBe(2);
      await expect(alarm.getByTestId("alarm-chattering")).toHaveCount(0);
      await regain();
      await lose(); // back a second time within the window (--chatter-count 2): chattering, and not sounded again
      await expect(alarm).toHaveAttribute("data-state", "active-unacknowledged");
      await expect(alarm.getByTestId("alarm-chattering")).toHaveText("Chattering");
      await page.waitForTimeout(2000); // a tone for it would have sounded by now
      expect(await tones()).toBe(2);

      // acknowledged: no longer chattering; its next return sounds again
      await alarm.getByRole("button", { name: /^Acknowledge: / }).click();
      await expect(alarm).toHaveAttribute("data-state", "active-acknowledged");
      await expect(alarm.getByTestId("alarm-chattering")).toHaveCount(0);
      sim = await startSim();
      await expect(chip).not.toHaveAttribute("data-link", "lost", {
        timeout: 30_000,
      });
      await lose();
      await expect(alarm).toHaveAttribute("data-state", "active-unacknowledged");
      await expect.poll(tones).toBe(3);
      await expect(alarm.getByTestId("alarm-chattering")).toHaveCount(0);
    } finally {
      await sim.stop();
      await extra.stop();
    }
  },
);
