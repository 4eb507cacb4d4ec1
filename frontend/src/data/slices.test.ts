// Panels subscribe to the slices they draw: a report of one topic wakes only the subscriptions to it.
import { afterEach, describe, expect, it, vi } from "vitest";
import type { ReportTypes, ServerMessage, Topic } from "../api/types";
import { Store } from "./connection";
import { sliceSource, throttle } from "./hooks";
import { reportMessage, type DeepPartial } from "./testing";
import { allProviders, selectedKnown, selectedLink, selectedLinkConfig, selectedName, selectedTopic, selectedTrails, type State } from "./store";

const A = "77b2ceb8-5afe-554e-8450-93db17c48923";
const B = "0f3c52aa-1d7e-5b1e-9c1f-6f7d2d8e0c11";
const CONFIG = { commsLostTimeout: 3, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 } as const;

function snapshot(): ServerMessage {
  const provider = (id: string) => ({
    id, name: "Alpha", link: "live", ageSeconds: 0, topics: {}, linkConfig: CONFIG, jausId: null,
    reports: { GPSReport: null, GPSFixReport: null, GPSFixStatusReport: null, InertialSensorReport: null },
  });
  return {
    type: "snapshot", consoleId: "c", serverTime: 0, authRequired: false, commands: [], gateways: [],
    recording: { state: "off", directory: "var/recordings", file: null, startedAt: null, messages: 0, dropped: 0, error: null },
    providers: [provider(A), provider(B)],
  } as unknown as ServerMessage;
}

let t = 100;
function reportMsg(providerId: string, topic: Topic): ServerMessage {
  t += 0.1;
  const bodies: { [T in Topic]: DeepPartial<ReportTypes[T]> } = {
    GPSReport: { numberSatellitesInView: 2, satellites: [{ satelliteId: "s3", azimuth: 1, elevation: 0.5, usedInFix: true }, { satelliteId: "s70", azimuth: 2, elevation: 0.2 }] },
    GPSFixReport: { position2DWithTime: { geodeticPosition: { geodeticLatitude: { latitude: 0.1 + t * 1e-6 }, geodeticLongitude: { longitude: 0.2 } } }, trueCourse: 1 },
    GPSFixStatusReport: { fixValid: true },
    InertialSensorReport: { state: "ON", status: "OPERATIONAL" },
  };
  return reportMessage(providerId, topic, bodies[topic], [], t);
}

/** A store with vehicles A and B, A selected, and a counter of notifications per slice. */
function setup(slices: Record<string, (s: State) => unknown>) {
  const store = new Store(A);
  store.clock = () => t;
  store.enqueue(snapshot());
  store.flush();
  const notified: Record<string, number> = {};
  for (const [name, select] of Object.entries(slices)) {
    notified[name] = 0;
    store.subscribeTo(select, () => notified[name]++);
  }
  const send = (providerId: string, topic: Topic) => {
    store.enqueue(reportMsg(providerId, topic));
    store.flush(); // one frame per message: each could wake a panel
  };
  return { store, notified, send };
}

describe("slice subscriptions", () => {
  it("a GPSFixReport at 10 Hz does not notify the satellites (sky plot, table) subscriptions", () => {
    const { notified, send } = setup({ satellites: selectedTopic("GPSReport"), trails: selectedTrails, fix: selectedTopic("GPSFixReport") });
    for (let i = 0; i < 10; i++) send(A, "GPSFixReport");
    expect(notified).toEqual({ satellites: 0, trails: 0, fix: 10 });
    send(A, "GPSReport");
    expect(notified).toEqual({ satellites: 1, trails: 1, fix: 10 });
  });

  it("other topics and other vehicles' reports do not notify the selected vehicle's slices", () => {
    const slices = { satellites: selectedTopic("GPSReport"), fix: selectedTopic("GPSFixReport"), status: selectedTopic("GPSFixStatusReport"), ins: selectedTopic("InertialSensorReport") };
    const { notified, send } = setup(slices);
    for (const topic of ["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"] as Topic[]) send(B, topic);
    expect(notified).toEqual({ satellites: 0, fix: 0, status: 0, ins: 0 });
    send(A, "InertialSensorReport");
    send(A, "GPSFixStatusReport");
    expect(notified).toEqual({ satellites: 0, fix: 0, status: 1, ins: 1 });
  });

  it("what a panel shows of the vehicle itself (name, link, configuration) is not notified by its reports", () => {
    const { store, notified, send } = setup({ name: selectedName, link: selectedLink, config: selectedLinkConfig, known: selectedKnown, all: allProviders });
    for (const topic of ["GPSReport", "GPSFixReport", "GPSFixStatusReport", "InertialSensorReport"] as Topic[]) send(A, topic);
    expect(notified).toEqual({ name: 0, link: 0, config: 0, known: 0, all: 4 }); // the overview of every vehicle sees each
    store.enqueue({ type: "provider", event: "lost", provider: { id: A, name: "Alpha", link: "lost", ageSeconds: 5, topics: {}, linkConfig: CONFIG, jausId: null } } as unknown as ServerMessage);
    store.flush();
    expect(notified.link).toBe(1);
    store.update((s) => ({ ...s, selected: B }));
    expect(notified.link).toBe(2); // B is live
    expect(notified.known).toBe(0); // B is on the bus too
    send(A, "GPSFixReport"); // A is no longer shown
    expect(notified.link).toBe(2);
  });
});

describe("throttle", () => {
  afterEach(() => {
    vi.useRealTimers();
  });

  it("calls at once, then at most once per period with the calls in between folded into one", () => {
    vi.useFakeTimers();
    vi.setSystemTime(0);
    let calls = 0;
    const f = throttle(() => calls++, 500);
    f();
    expect(calls).toBe(1);
    for (let i = 0; i < 20; i++) f();
    expect(calls).toBe(1);
    vi.advanceTimersByTime(500);
    expect(calls).toBe(2);
    vi.advanceTimersByTime(500); // nothing new: nothing more
    expect(calls).toBe(2);
    vi.advanceTimersByTime(1000);
    f();
    expect(calls).toBe(3);
    f();
    f.cancel();
    vi.advanceTimersByTime(1000);
    expect(calls).toBe(3);
  });

  it("throttles of one period wait on one timer: the panels they wake render in the same task", () => {
    vi.useFakeTimers();
    vi.setSystemTime(0);
    const order: string[] = [];
    const a = throttle(() => order.push("a"), 500);
    const b = throttle(() => order.push("b"), 500);
    a();
    b();
    a();
    b();
    expect(vi.getTimerCount()).toBe(1);
    vi.advanceTimersByTime(500);
    expect(order).toEqual(["a", "b", "a", "b"]);
  });
});

describe("a throttled slice", () => {
  afterEach(() => {
    vi.useRealTimers();
  });

  it("reads the value of its last notification: a render for another reason does not show a newer one", () => {
    vi.useFakeTimers();
    vi.setSystemTime(0);
    const { store, send } = setup({});
    const src = sliceSource(store, allProviders, 1000);
    let woken = 0;
    const off = src.subscribe(() => woken++);
    const first = src.getSnapshot();
    send(A, "GPSFixReport"); // at once: it was quiet
    expect(woken).toBe(1);
    const second = src.getSnapshot();
    expect(second).not.toBe(first);
    send(A, "GPSFixReport");
    send(B, "GPSFixReport");
    expect(woken).toBe(1);
    expect(src.getSnapshot()).toBe(second); // the store changed, the throttled value did not
    expect(store.getState().providers).not.toBe(second);
    vi.advanceTimersByTime(1000);
    expect(woken).toBe(2);
    expect(src.getSnapshot()).toBe(store.getState().providers);
    off();
    const unthrottled = sliceSource(store, allProviders);
    send(A, "GPSFixReport");
    expect(unthrottled.getSnapshot()).toBe(store.getState().providers);
  });
});
