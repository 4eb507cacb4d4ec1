import { describe, expect, it, vi } from "vitest";
import type { Alarm } from "../api/generated/ws";
import type { ServerMessage } from "../api/types";
import { Burst, NewAlarms, SAID_AT_MOST, alarmWords } from "../lib/tone";
import { clockTime } from "../lib/units";
import { Inbox, createStateStore } from "./store";
import { reportMessage } from "./testing";
import { initialState, reduce, type State } from "./state";
import { pageTitle, unacknowledged } from "./slices/alarms";
import { select } from "./slices/vehicles";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0c1f3a52-2d6e-5f0e-9a43-6f1b1d2a9e11";

function alarm(id: number, over: Partial<Alarm> = {}): Alarm {
  return {
    id,
    kind: "ins-failure",
    severity: "alarm",
    providerId: A,
    vehicle: A.slice(0, 8),
    sessionId: null,
    text: `Inertial sensor failure on ${A.slice(0, 8)}`,
    since: 1000 + id,
    state: "active-unacknowledged",
    clearedAt: null,
    ackedAt: null,
    ackedBy: null,
    cause: "INS failure",
    chattering: false,
    shelf: null,
    returned: null,
    ...over,
  };
}

const provider = (id: string) => ({
  id,
  name: null,
  link: "live",
  ageSeconds: 0,
  topics: {},
  linkConfig: null,
  jausId: null,
  umaaVersion: "3.0.1",
  reports: { GPSReport: null, GPSFixReport: null, GPSFixStatusReport: null, InertialSensorReport: null },
});

function snapshot(ids: string[], alarms: Alarm[] = []): ServerMessage {
  return {
    type: "snapshot",
    consoleId: "c",
    serverTime: 0,
    authRequired: false,
    commands: [],
    gateways: [],
    replay: null,
    alarms,
    recording: { state: "off", directory: "var/recordings", file: null, startedAt: null, messages: 0, dropped: 0, error: null },
    providers: ids.map(provider),
  } as unknown as ServerMessage;
}

const report = (id: string): ServerMessage => reportMessage(id, "InertialSensorReport", { state: "ON", status: "INIT" });

function apply(msgs: ServerMessage[], start: State = initialState): State {
  return msgs.reduce((s, m, i) => reduce(s, m, 2000 + i), start);
}

describe("the console's alarms in the store", () => {
  it("takes the active set from the snapshot (a new or reloaded page shows it at once)", () => {
    const s = apply([snapshot([A, B], [alarm(2), alarm(1, { state: "active-acknowledged" })])]);
    expect(s.alarms.map((a) => a.id)).toEqual([2, 1]);
    expect(unacknowledged(s.alarms).map((a) => a.id)).toEqual([2]);
  });

  it("replaces the whole set with each `alarms` message: raised, acknowledged, cleared, gone", () => {
    let s = apply([snapshot([A, B])]);
    expect(s.alarms).toEqual([]);
    s = apply([{ type: "alarms", alarms: [alarm(1)] }], s);
    expect(s.alarms).toEqual([alarm(1)]);
    s = apply(
      [
        {
          type: "alarms",
          alarms: [
            alarm(2, { kind: "link-lost", providerId: B }),
            alarm(1, { state: "cleared-unacknowledged", clearedAt: 1500 }),
          ],
        },
      ],
      s,
    );
    expect(s.alarms.map((a) => [a.id, a.state])).toEqual([
      [2, "active-unacknowledged"],
      [1, "cleared-unacknowledged"],
    ]);
    expect(unacknowledged(s.alarms)).toHaveLength(2); // cleared, but the operator has not seen it acknowledged
    s = apply(
      [
        {
          type: "alarms",
          alarms: [alarm(2, { kind: "link-lost", providerId: B, state: "active-acknowledged", ackedAt: 1600, ackedBy: "alice" })],
        },
      ],
      s,
    );
    expect(unacknowledged(s.alarms)).toEqual([]);
    expect(s.alarms).toHaveLength(1); // acknowledged and still active: listed
  });

  it("derives none from reports or link changes, and wakes only subscribers of the alarms when they change", () => {
    const inbox = new Inbox(createStateStore());
    const store = inbox.store;
    inbox.enqueue(snapshot([A, B], [alarm(1)]));
    inbox.flush();
    let woken = 0;
    store.subscribe(
      (s) => s.alarms,
      () => woken++,
    );
    inbox.enqueue(report(A));
    inbox.enqueue({ type: "provider", event: "lost", provider: { ...provider(B), link: "lost" } } as unknown as ServerMessage);
    inbox.flush();
    expect(woken).toBe(0);
    expect(store.getState().alarms).toEqual([alarm(1)]);
    inbox.enqueue({ type: "alarms", alarms: [] });
    inbox.flush();
    expect(woken).toBe(1);
  });
});

describe("the tab title", () => {
  it("counts the unacknowledged alarms, and is plain at zero", () => {
    expect(pageTitle(2)).toBe("(2) SEM Console");
    expect(
      pageTitle(
        unacknowledged([alarm(1), alarm(2, { state: "cleared-unacknowledged" }), alarm(3, { state: "active-acknowledged" })])
          .length,
      ),
    ).toBe("(2) SEM Console");
    expect(pageTitle(0)).toBe("SEM Console");
    expect(pageTitle(2, true)).toBe("(2) Replay · SEM Console"); // a replay's alarms never pass for a live console's
    expect(pageTitle(0, true)).toBe("Replay · SEM Console");
    expect(pageTitle(2, false, true)).toBe("(2) Console unreachable · SEM Console"); // the count may be out of date
  });
});

describe("the tone's new alarms", () => {
  it("sounds for an unacknowledged alarm not seen before, not for the page's first set nor twice", () => {
    const news = new NewAlarms();
    expect(news.take([alarm(1)])).toEqual([]); // on screen when the page opened
    expect(news.take([alarm(2), alarm(1)]).map((a) => a.id)).toEqual([2]);
    expect(news.take([alarm(2, { state: "cleared-unacknowledged" }), alarm(1)])).toEqual([]);
    expect(news.take([alarm(3, { state: "active-acknowledged" })])).toEqual([]); // acknowledged elsewhere first
    expect(news.take([alarm(4, { severity: "warning" })]).map((a) => a.id)).toEqual([4]);
    // lost, back (cleared, not acknowledged) and lost again: the console raises the same alarm anew, since moved on
    expect(news.take([alarm(2, { state: "cleared-unacknowledged", clearedAt: 1010 })])).toEqual([]);
    expect(news.take([alarm(2, { since: 1020 })]).map((a) => a.id)).toEqual([2]);
  });

  it("does not sound for a shelved alarm, sounds when it comes back, and not again for a chattering one", () => {
    const news = new NewAlarms();
    news.take([]);
    const shelf = { id: "s", reason: "relay down", by: "alice", station: "watch", at: 1000, until: 2000 };
    expect(news.take([alarm(1, { shelf })])).toEqual([]);
    expect(news.take([alarm(1, { returned: "back from shelving: its time ended" })]).map((a) => a.id)).toEqual([1]);
    expect(news.take([alarm(2)]).map((a) => a.id)).toEqual([2]);
    expect(news.take([alarm(2, { since: 1100, chattering: true })])).toEqual([]); // back once more: no tone
  });
});

describe("a burst of new alarms", () => {
  it("sounds once at its start and is said once, when it has been quiet, naming the whole flood by its cause", () => {
    vi.useFakeTimers();
    const said: string[] = [];
    const burst = new Burst((w) => said.push(w), 1000, 3000);
    const lost = (i: number) =>
      alarm(i, { kind: "link-lost", cause: "Link lost", text: `V${i}: link lost`, providerId: `v${i}` });
    expect(burst.add([lost(1), lost(2)], 0)).toBe(true); // the tone
    vi.advanceTimersByTime(500);
    expect(
      burst.add(
        Array.from({ length: 18 }, (_, i) => lost(i + 3)),
        500,
      ),
    ).toBe(false); // no second tone
    expect(said).toEqual([]);
    vi.advanceTimersByTime(1000);
    expect(said).toEqual(["Alarm: Link lost: 20 vehicles: see the alarm list"]);
    expect(burst.add([lost(21)], 5000)).toBe(true); // a later one is a burst of its own
    vi.advanceTimersByTime(1000);
    expect(said[1]).toBe("Alarm: V21: link lost, since 00:17:01 UTC");
    vi.useRealTimers();
  });
});

describe("the live region's words for new alarms", () => {
  it("names each of a few, and a burst (a fleet lost at once) in one sentence with its newest", () => {
    expect(alarmWords([alarm(1), alarm(2, { severity: "warning" })])).toBe(
      `Alarm: Inertial sensor failure on ${A.slice(0, 8)}, since 00:16:41 UTC. Warning: Inertial sensor failure on ${A.slice(0, 8)}, since 00:16:42 UTC`,
    );
    const fleet = Array.from({ length: 250 }, (_, i) =>
      alarm(i + 1, { text: `Vehicle ${i + 1}: link lost`, cause: i % 2 ? "Link lost" : "INS failure" }),
    );
    const said = alarmWords(fleet);
    expect(said).toBe(
      "Alarm: Vehicle 250: link lost, since 00:20:50 UTC. Alarm: Vehicle 249: link lost, since 00:20:49 UTC. And 248 more new alarms: see the alarm list",
    );
    expect(said.split("link lost")).toHaveLength(SAID_AT_MOST); // never read on for the whole fleet
  });
});

describe("the lone vehicle", () => {
  it("is selected at once when it is the only one on the bus", () => {
    expect(apply([snapshot([A])]).selected).toBe(A);
    expect(apply([report(A)]).selected).toBe(A); // first heard of by its report
  });

  it("is not chosen for the operator among several", () => {
    expect(apply([snapshot([A, B])]).selected).toBe(null);
    const later = apply([snapshot([]), report(A), report(B)]);
    expect(later.selected).toBe(A); // alone at first: selected then, and kept when B comes
  });

  it("does not override the operator's choice or the page's ?vehicle= link", () => {
    const linkedInbox = new Inbox(createStateStore("from-a-link"));
    const linked = linkedInbox.store;
    linkedInbox.enqueue(snapshot([A]));
    linkedInbox.flush();
    expect(linked.getState().selected).toBe("from-a-link");
    const chosen = apply([snapshot([B])], select(initialState, A)); // A chosen, then only B on the bus
    expect(chosen.selected).toBe(A);
  });
});

describe("a watch's times", () => {
  it("are HH:MM UTC today, with the date on another day (a glider out of comms for days)", () => {
    const now = Date.UTC(2026, 10, 28, 22, 0) / 1000;
    expect(clockTime(now + 20 * 60, now)).toBe("22:20 UTC");
    expect(clockTime(now + 3 * 3600, now)).toBe("2026-11-29 01:00 UTC");
  });
});
