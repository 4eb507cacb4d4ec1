// Panels subscribe to the slices they draw: a report of one topic wakes only the subscriptions to it.
import { afterEach, describe, expect, it, vi } from "vitest";
import type { ReportTypes, ServerMessage, Topic } from "../api/types";
import { Inbox, createStateStore, update } from "./store";
import { frameSource, onFrame } from "./frame";
import { sameOverview } from "./hooks";
import { reportMessage, type DeepPartial } from "./testing";
import {
  allProviders,
  selectedKnown,
  selectedPlannedUntil,
  selectedLink,
  selectedLinkConfig,
  selectedName,
  selectedTopic,
  selectedTrails,
  type TopicView,
} from "./slices/vehicles";
import { plannedUntil } from "./slices/alarms";
import { type State } from "./state";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";
const CONFIG = { commsLostTimeout: 3, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 } as const;

function snapshot(): ServerMessage {
  const provider = (id: string) => ({
    id,
    name: "Alpha",
    link: "live",
    ageSeconds: 0,
    topics: {},
    linkConfig: CONFIG,
    jausId: null,
    umaaVersion: "3.0.1",
    reports: { GPSReport: null, GPSFixReport: null, GPSFixStatusReport: null, InertialSensorReport: null },
  });
  return {
    type: "snapshot",
    consoleId: "c",
    serverTime: 0,
    authRequired: false,
    commands: [],
    gateways: [],
    recording: { state: "off", directory: "var/recordings", file: null, startedAt: null, messages: 0, dropped: 0, error: null },
    providers: [provider(A), provider(B)],
  } as unknown as ServerMessage;
}

let t = 100;
function reportMsg(providerId: string, topic: Topic): ServerMessage {
  t += 0.1;
  const bodies: { [T in Topic]: DeepPartial<ReportTypes[T]> } = {
    GPSReport: {
      numberSatellitesInView: 2,
      satellites: [
        { satelliteId: "s3", azimuth: 1, elevation: 0.5, usedInFix: true },
        { satelliteId: "s70", azimuth: 2, elevation: 0.2 },
      ],
    },
    GPSFixReport: {
      position2DWithTime: {
        geodeticPosition: { geodeticLatitude: { latitude: 0.1 + t * 1e-6 }, geodeticLongitude: { longitude: 0.2 } },
      },
      trueCourse: 1,
    },
    GPSFixStatusReport: { fixValid: true },
    InertialSensorReport: { state: "ON", status: "OPERATIONAL" },
  };
  return reportMessage(providerId, topic, bodies[topic], [], t);
}

/** A store with vehicles A and B, A selected, and a counter of notifications per slice. */
function setup(slices: Record<string, (s: State) => unknown>) {
  const inbox = new Inbox(createStateStore(A));
  const store = inbox.store;
  inbox.clock = () => t;
  inbox.enqueue(snapshot());
  inbox.flush();
  const notified: Record<string, number> = {};
  for (const [name, select] of Object.entries(slices)) {
    notified[name] = 0;
    store.subscribe(select, () => notified[name]++);
  }
  const send = (providerId: string, topic: Topic) => {
    inbox.enqueue(reportMsg(providerId, topic));
    inbox.flush(); // one frame per message: each could wake a panel
  };
  return { inbox, store, notified, send };
}

describe("slice subscriptions", () => {
  it("a GPSFixReport at 10 Hz does not notify the satellites (sky plot, table) subscriptions", () => {
    const { notified, send } = setup({
      satellites: selectedTopic("GPSReport"),
      trails: selectedTrails,
      fix: selectedTopic("GPSFixReport"),
    });
    for (let i = 0; i < 10; i++) send(A, "GPSFixReport");
    expect(notified).toEqual({ satellites: 0, trails: 0, fix: 10 });
    send(A, "GPSReport");
    expect(notified).toEqual({ satellites: 1, trails: 1, fix: 10 });
    // the same satellites within a trail's step (t moves 0.1 s a report): a trail gets a point every 5 s, not each report
    for (let i = 0; i < 10; i++) send(A, "GPSReport");
    expect(notified).toEqual({ satellites: 11, trails: 1, fix: 10 });
    for (let i = 0; i < 45; i++) send(A, "GPSReport"); // past 5 s
    expect(notified.trails).toBe(2);
  });

  it("other topics and other vehicles' reports do not notify the selected vehicle's slices", () => {
    const slices = {
      satellites: selectedTopic("GPSReport"),
      fix: selectedTopic("GPSFixReport"),
      status: selectedTopic("GPSFixStatusReport"),
      ins: selectedTopic("InertialSensorReport"),
    };
    const { notified, send } = setup(slices);
    for (const topic of ["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"] as Topic[]) send(B, topic);
    expect(notified).toEqual({ satellites: 0, fix: 0, status: 0, ins: 0 });
    send(A, "InertialSensorReport");
    send(A, "GPSFixStatusReport");
    expect(notified).toEqual({ satellites: 0, fix: 0, status: 1, ins: 1 });
  });

  it("what a panel shows of the vehicle itself (name, link, configuration) is not notified by its reports", () => {
    const { inbox, store, notified, send } = setup({
      name: selectedName,
      link: selectedLink,
      config: selectedLinkConfig,
      known: selectedKnown,
      all: allProviders,
    });
    for (const topic of ["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"] as Topic[]) send(A, topic);
    expect(notified).toEqual({ name: 0, link: 0, config: 0, known: 0, all: 4 }); // the overview of every vehicle sees each
    inbox.enqueue({
      type: "provider",
      event: "lost",
      provider: {
        id: A,
        name: "Alpha",
        link: "lost",
        ageSeconds: 5,
        topics: {},
        linkConfig: CONFIG,
        jausId: null,
        umaaVersion: "3.0.1" as const,
      },
    } as unknown as ServerMessage);
    inbox.flush();
    expect(notified.link).toBe(1);
    update(store, (s) => ({ ...s, selected: B }));
    expect(notified.link).toBe(2); // B is live
    expect(notified.known).toBe(0); // B is on the bus too
    send(A, "GPSFixReport"); // A is no longer shown
    expect(notified.link).toBe(2);
  });

  it("names the selected vehicle out of comms (planned) only while it is lost in a planned silence in force", () => {
    const { inbox, store } = setup({});
    const silence = {
      id: "s1",
      providerId: A,
      vehicle: "Alpha",
      until: 5000,
      reason: "dive",
      at: 0,
      by: "alice",
      station: "watch",
    };
    inbox.enqueue({ type: "silences", silences: [silence] } as unknown as ServerMessage);
    inbox.flush();
    expect(selectedPlannedUntil(store.getState())).toBeNull(); // heard: its silence says nothing of its link
    inbox.enqueue({
      type: "provider",
      event: "lost",
      provider: {
        id: A,
        name: "Alpha",
        link: "lost",
        ageSeconds: 5,
        topics: {},
        linkConfig: CONFIG,
        jausId: null,
        umaaVersion: "3.0.1" as const,
      },
    } as unknown as ServerMessage);
    inbox.flush();
    expect(selectedPlannedUntil(store.getState())).toBe(5000);
    expect(plannedUntil(store.getState().silences, B, "lost")).toBeNull(); // lost without a silence: lost
    inbox.enqueue({ type: "silences", silences: [] } as unknown as ServerMessage);
    inbox.flush();
    expect(selectedPlannedUntil(store.getState())).toBeNull();
  });
});

/** Animation frames run by the test: requestAnimationFrame queues, `frame()` runs what is queued (one frame). */
function frames(hidden = false) {
  let queued: FrameRequestCallback[] = [];
  vi.stubGlobal("requestAnimationFrame", (cb: FrameRequestCallback) => queued.push(cb));
  vi.stubGlobal("document", { hidden });
  return {
    pending: () => queued.length,
    frame: () => {
      const run = queued;
      queued = [];
      for (const cb of run) cb(performance.now());
    },
  };
}

const latitude = (v: TopicView<"GPSFixReport"> | null) =>
  v?.envelope.report.position2DWithTime?.geodeticPosition?.geodeticLatitude?.latitude;

describe("the rendering model: a panel draws on the animation frame", () => {
  afterEach(() => {
    vi.unstubAllGlobals();
    vi.restoreAllMocks();
    vi.useRealTimers();
  });

  it("draws at most once per frame, the newest sample, in the frame the store applies it", () => {
    const { inbox, store } = setup({});
    const { frame, pending } = frames();
    const src = frameSource(store, selectedTopic("GPSFixReport"));
    let draws = 0;
    src.subscribe(() => draws++);
    for (let i = 0; i < 5; i++) inbox.enqueue(reportMsg(A, "GPSFixReport"));
    expect(draws).toBe(0); // nothing before the frame
    expect(pending()).toBe(1); // one frame asked for, not one per sample
    frame();
    expect(draws).toBe(1);
    expect(latitude(src.getSnapshot())).toBe(latitude(store.getState().providers[A].topics.GPSFixReport!));
    expect(pending()).toBe(0); // drawn in the frame that applied the samples: no frame more
    inbox.enqueue(reportMsg(B, "GPSFixReport")); // another vehicle: not this panel's
    frame();
    expect(draws).toBe(1);
  });

  it("a sample arriving after the last one drawn is drawn, even within the frame that drew", () => {
    const { inbox, store } = setup({});
    const { frame, pending } = frames();
    const src = frameSource(store, selectedTopic("GPSFixReport"));
    let draws = 0;
    // a sample applied later in the frame of the second draw (after the panel drew)...
    const late = () => {
      inbox.enqueue(reportMsg(A, "GPSFixReport"));
      inbox.flush();
    };
    src.subscribe(() => ++draws === 2 && onFrame(late));
    inbox.enqueue(reportMsg(A, "GPSFixReport"));
    frame();
    expect(draws).toBe(1);
    inbox.enqueue(reportMsg(A, "GPSFixReport"));
    frame();
    expect(draws).toBe(2); // ...is not a second draw in that frame...
    const newest = store.getState().providers[A].topics.GPSFixReport!;
    expect(src.getSnapshot()).not.toBe(newest);
    expect(pending()).toBe(1); // ...but drawn on the next
    frame();
    expect(draws).toBe(3);
    expect(src.getSnapshot()).toBe(newest);
  });

  it("nothing draws while the page is hidden; its first frame draws the newest", () => {
    const { inbox, store } = setup({});
    const { frame } = frames(true);
    const src = frameSource(store, selectedTopic("GPSFixReport"));
    let draws = 0;
    src.subscribe(() => draws++);
    for (let i = 0; i < 3; i++) {
      inbox.enqueue(reportMsg(A, "GPSFixReport"));
      inbox.flush(); // a hidden page applies messages on a timer (the tab's title, the alarm tone)
    }
    expect(draws).toBe(0);
    frame(); // shown again: the browser runs frames
    expect(draws).toBe(1);
    expect(src.getSnapshot()).toBe(store.getState().providers[A].topics.GPSFixReport);
  });

  it("a rate-limited slice (the map's fleet) draws on the first frame after its period, with the newest", () => {
    const { inbox, store } = setup({});
    const { frame, pending } = frames();
    vi.useFakeTimers({ toFake: ["setTimeout", "clearTimeout", "performance"] });
    const src = frameSource(store, allProviders, Object.is, 500);
    let draws = 0;
    src.subscribe(() => draws++);
    inbox.enqueue(reportMsg(A, "GPSFixReport"));
    frame();
    expect(draws).toBe(1);
    for (let i = 0; i < 10; i++) {
      vi.advanceTimersByTime(40);
      inbox.enqueue(reportMsg(B, "GPSFixReport"));
      frame();
    }
    expect(draws).toBe(1); // 400 ms: not yet
    expect(pending()).toBe(0); // and no frame asked for in the meantime, only the end of the period
    vi.advanceTimersByTime(100);
    expect(pending()).toBe(1);
    frame(); // no new sample, but one is waiting: drawn
    expect(draws).toBe(2);
    expect(src.getSnapshot()).toBe(store.getState().providers);
    vi.advanceTimersByTime(1000);
    frame();
    expect(draws).toBe(2); // nothing new: nothing drawn
  });
});

describe("an overview's slice", () => {
  afterEach(() => {
    vi.unstubAllGlobals();
  });

  it("skips a frame that draws alike, yet a render for another reason (the clock of ages) reads the newest", () => {
    const { inbox, store } = setup({});
    const { frame } = frames();
    const src = frameSource(store, allProviders, sameOverview()); // the samples below show alike
    let draws = 0;
    src.subscribe(() => draws++);
    inbox.enqueue(reportMsg(A, "GPSFixStatusReport")); // its fix valid: drawn
    frame();
    expect(draws).toBe(1);
    const drawn = src.getSnapshot();
    inbox.enqueue(reportMsg(A, "GPSFixReport")); // a position and a newer age: drawn alike
    frame();
    expect(draws).toBe(1);
    expect(src.getSnapshot()).not.toBe(drawn); // an age computed from it is the newest report's
    expect(src.getSnapshot()).toBe(store.getState().providers);
  });

  it("draws alike when no shown field changed (a newer report: its age is the clock's to draw), not when a link did", () => {
    const { inbox, store, send } = setup({});
    const same = sameOverview();
    send(A, "GPSFixReport");
    const before = store.getState().providers;
    for (let i = 0; i < 20; i++) send(A, "GPSFixReport"); // 2 s of reports: ages across several seconds
    expect(before).not.toBe(store.getState().providers);
    expect(same(before, store.getState().providers)).toBe(true);
    const a = store.getState().providers;
    inbox.enqueue({
      type: "provider",
      event: "lost",
      provider: {
        id: A,
        name: "Alpha",
        link: "lost",
        ageSeconds: 5,
        topics: {},
        linkConfig: CONFIG,
        jausId: null,
        umaaVersion: "3.0.1" as const,
      },
    } as unknown as ServerMessage);
    inbox.flush();
    expect(same(a, store.getState().providers)).toBe(false);
  });
});
