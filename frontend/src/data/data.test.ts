import { afterEach, describe, expect, expectTypeOf, it, vi } from "vitest";
import type {
  Command,
  GPSFixStatusReportType,
  InertialSensorOpStatusEnumType,
  InertialSensorReportType,
  ReplayStatus,
  ServerMessage,
} from "../api/types";
import { Connection, PING_EVERY_MS, SILENT_AFTER_MS, backoff } from "./connection";
import { Inbox, createStateStore, update } from "./store";
import { unreachable } from "./source";
import { openEarly } from "./early";
import { ReplaySource } from "./replay";
import { brief, reportMessage, snapshotMessage, vehicle } from "./testing";
import { freshness } from "../lib/freshness";
import { vehicleMark } from "../panels/Map/layers";
import {
  HISTORY_SECONDS,
  briefLoaded,
  historyLoaded,
  historyPoint,
  mergeHistory,
  paceOf,
  report,
  select,
  viewPace,
  type HistoryPoint,
} from "./slices/vehicles";
import { initialState, reduce, reduceAll, type State } from "./state";

const P = "77b2ceb8-5afe-554e-8450-93db17c48923";
const Q = "0b6a4c1e-2f4d-5e8a-9c3b-7d1e2f3a4b5c";

function env(report: Record<string, unknown>, invalid: string[] = [], receivedAt = 1) {
  return { report, invalid, receivedAt };
}

function cmd(over: Partial<Command> = {}): Command {
  return {
    sessionId: "s1",
    service: "GPSFix",
    providerId: P,
    state: null,
    operator: null,
    createdAt: 1,
    status: null,
    terminal: false,
    unanswered: false,
    cancelRequested: false,
    canceledBy: null,
    cleanedUp: false,
    console: null,
    ackedAt: null,
    violations: [],
    transitions: [],
    ...over,
  };
}

function snapshot(): ServerMessage {
  return {
    type: "snapshot",
    consoleId: "c",
    serverTime: 0,
    authRequired: true,
    commands: [cmd()],
    gateways: [],
    recording: { state: "off", directory: "var/recordings", file: null, startedAt: null, messages: 0, dropped: 0, error: null },
    providers: [
      {
        id: P,
        link: "live",
        ageSeconds: 0,
        topics: { GPSReport: { ageSeconds: 2, samples: 1, alive: true, receivedAt: 0 } },
        reports: {
          GPSReport: env({ satellites: [], numberSatellitesInView: 0 }),
          GPSFixReport: null,
          GPSFixStatusReport: null,
          InertialSensorReport: null,
        },
      },
    ],
  } as unknown as ServerMessage;
}

const CONFIG = { commsLostTimeout: 3, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 } as const;
const summary = (link: "live" | "lost" | "regained", ageSeconds = 0) => ({
  id: P,
  name: null,
  link,
  ageSeconds,
  topics: {},
  linkConfig: CONFIG,
  jausId: null,
  umaaVersion: "3.0.1" as const,
});

function apply(msgs: ServerMessage[], start: State = initialState, t0 = 1000): State {
  return msgs.reduce((s, m, i) => reduce(s, m, t0 + i), start);
}

describe("reducer", () => {
  it("applies a frame's messages together as one by one, leaving the state it started from as it was", () => {
    const fix = (id: string, lat: number) =>
      reportMessage(id, "GPSFixReport", {
        position2DWithTime: { geodeticPosition: { geodeticLatitude: { latitude: lat }, geodeticLongitude: { longitude: 1 } } },
      });
    const lost = { type: "provider", event: "lost", provider: { ...summary("lost", 5), id: "b" } } as unknown as ServerMessage;
    const msgs = [
      fix("a", 1),
      fix("b", 2),
      lost,
      fix("a", 3),
      reportMessage("c", "InertialSensorReport", { state: "ON", status: "INIT" }),
      fix("b", 4),
    ];
    const start = apply([snapshot()]);
    const frozen = JSON.stringify(start);
    const one = msgs.reduce((s, m) => reduce(s, m, 1005), start);
    const all = reduceAll(start, msgs, 1005);
    expect(all).toEqual(one);
    expect(JSON.stringify(start)).toBe(frozen);
    expect(all.providers[P]).toBe(start.providers[P]); // a vehicle without a report keeps its view
    // a lone vehicle is selected by itself within a run of reports too, as by reduce
    const first = [fix("a", 1), fix("b", 2)];
    expect(reduceAll(initialState, first, 1)).toEqual(first.reduce((s, m) => reduce(s, m, 1), initialState));
    expect(reduceAll(initialState, first, 1).selected).toBe("a");
  });

  it("keeps the database's reach from the snapshot and each database message (the banner's)", () => {
    const away = { unavailableSince: 1_700_000_000, writesHeld: 3, writesDropped: 0 };
    const s = apply([snapshot(), { type: "database", database: away }]);
    expect(s.database).toEqual(away);
    expect(apply([{ type: "database", database: { ...away, unavailableSince: null } }], s).database?.unavailableSince).toBeNull();
  });

  it("takes the snapshot as the baseline and selects its lone vehicle (alarms.test.ts: when not)", () => {
    const s = apply([snapshot()]);
    expect(s.consoleId).toBe("c");
    expect(s.authRequired).toBe(true);
    expect(s.selected).toBe(P);
    expect(report(s.providers[P], "GPSReport")).toEqual({ satellites: [], numberSatellitesInView: 0 });
    expect(s.providers[P].topics.GPSReport!.at).toBe(998); // arrived ageSeconds before the snapshot
    expect(Object.keys(s.commands)).toEqual(["s1"]);
  });

  it("a GPSReport sent again whole on a select keeps when it arrived: a silent vehicle selected is not heard from now", () => {
    const s = apply([snapshot()]); // the vehicle's GPSReport arrived 2 s before the snapshot, at 998
    const again = reportMessage(P, "GPSReport", { satellites: [{ azimuth: 1 }], numberSatellitesInView: 1 }, [], 1); // the same sample
    const after = reduce(s, again, 1100);
    expect(after.providers[P].topics.GPSReport!.at).toBe(998);
    expect(report(after.providers[P], "GPSReport")?.satellites).toHaveLength(1); // its satellites taken all the same
    const newer = reduce(after, reportMessage(P, "GPSReport", { satellites: [] }, [], 2), 1101);
    expect(newer.providers[P].topics.GPSReport!.at).toBe(1101); // a new sample arrived now
  });

  it("paces every vehicle by the console's pace but the selected one once its reports come at full rate", () => {
    const fix = (id: string) => reportMessage(id, "GPSFixReport", {});
    let s = select(apply([snapshot()]), "a");
    expect(paceOf(s, "a")).toBe(0); // the console paces none until it says so
    s = apply([{ type: "pace", othersEvery: 10 }], s);
    expect([paceOf(s, "a"), paceOf(s, "b")]).toEqual([10, 10]); // a: none of its reports came since it was selected
    s = apply([fix("b"), fix("a")], s);
    expect([paceOf(s, "a"), paceOf(s, "b")]).toEqual([0, 10]);
    s = select(s, "b"); // b at the others' pace until its first report at full rate; a at the others' pace again
    expect([paceOf(s, "a"), paceOf(s, "b")]).toEqual([10, 10]);
    s = reduce(s, fix("b"), 1001);
    expect([paceOf(s, "a"), paceOf(s, "b")]).toEqual([10, 0]);
  });

  it("takes a paced report as heard when the console received it, on the page's clock, not when it came", () => {
    // the console's clock 5 s ahead of the page's; b's fix received by it at 1005 (the page's 1000), held for its pace
    let s = select(reduce(initialState, snapshotMessage({ serverTime: 1005 }), 1000), "a");
    s = reduce(s, { type: "pace", othersEvery: 2.5 } as ServerMessage, 1000);
    s = reduce(s, reportMessage("b", "GPSFixReport", {}, [], 1005), 1002.4);
    expect(s.providers.b.topics.GPSFixReport!.at).toBe(1000);
    s = reduce(s, reportMessage("b", "GPSFixReport", {}, [], 1009), 1003); // ahead of its arrival: no later than it
    expect(s.providers.b.topics.GPSFixReport!.at).toBe(1003);
    s = reduce(s, reportMessage("a", "GPSFixReport", {}, [], 1005), 1002.4); // the selected one's first may be held
    expect(s.providers.a.topics.GPSFixReport!.at).toBe(1000);
    s = reduce(s, reportMessage("a", "GPSFixReport", {}, [], 1006), 1003.5); // then at full rate: as it comes
    expect(s.providers.a.topics.GPSFixReport!.at).toBe(1003.5);
  });

  it("paces a vehicle selected again until its first report since, though it was at full rate before", () => {
    // a at full rate, then b selected (lost: nothing of it comes), then a again before any report of b came: a's
    // reports held for the pace meanwhile come first, received by the console up to a pace before
    let s = select(reduce(initialState, snapshotMessage({ serverTime: 1000 }), 1000), "a");
    s = reduce(s, { type: "pace", othersEvery: 2.5 } as ServerMessage, 1000);
    s = reduce(s, reportMessage("a", "GPSFixReport", {}, [], 1000.1), 1000.1);
    expect(paceOf(s, "a")).toBe(0);
    s = select(select(s, "b"), "a");
    expect(paceOf(s, "a")).toBe(2.5); // none of its reports came since it was selected again
    s = reduce(s, reportMessage("a", "GPSFixReport", {}, [], 1001), 1003.4); // held by the pace: heard at 1001
    expect(s.providers.a.topics.GPSFixReport!.at).toBe(1001);
  });

  it("keeps the selection through reports, new vehicles and a snapshot that lacks it (reconnect, restart)", () => {
    const other = reportMessage("other", "InertialSensorReport", { state: "ON", status: "INIT" });
    const appeared = {
      type: "provider",
      event: "appeared",
      provider: { id: "third", name: "Alpha", link: "live", ageSeconds: 0, topics: {} },
    } as unknown as ServerMessage;
    let s = select(apply([snapshot()]), "other");
    s = apply([other, appeared], s);
    expect(s.selected).toBe("other");
    expect(s.providers.third.name).toBe("Alpha");
    s = apply([snapshot()], s);
    expect(s.selected).toBe("other");
    expect(s.providers.other).toBeUndefined(); // the fresh snapshot does not have it (yet): still selected
    expect(apply([other], s).selected).toBe("other");
    const linked = apply([snapshot()], select(initialState, "from-a-link"));
    expect(linked.selected).toBe("from-a-link");
  });

  it("applies reports and keeps untouched providers identical", () => {
    const other: ServerMessage = reportMessage("other", "InertialSensorReport", { state: "ON", status: "INIT" });
    const s1 = apply([snapshot(), other]);
    const s2 = reduce(s1, reportMessage(P, "InertialSensorReport", { state: "OFF", status: "INIT" }), 2000);
    expect(s2.providers.other).toBe(s1.providers.other);
    expect(report(s2.providers[P], "InertialSensorReport")?.state).toBe("OFF");
  });

  it("raises no alarm itself for fix lost, INS failure, failed commands, violations, unanswered, lost and regained: the console does", () => {
    const fix = (v: boolean) => reportMessage(P, "GPSFixStatusReport", { fixValid: v, carrierToNoise: [40] });
    const ins = (st: InertialSensorOpStatusEnumType) => reportMessage(P, "InertialSensorReport", { state: "ON", status: st });
    const tr = (status: string, reason: string, violation: string | null): ServerMessage => ({
      type: "transition",
      sessionId: "s1",
      command: cmd({ status }),
      transition: { seq: 1, status, reason, logMessage: "x", violation, providerTime: 1, receivedAt: 1 },
    });
    const s = apply([
      snapshot(),
      fix(true),
      fix(false),
      ins("OPERATIONAL"),
      ins("INERTIAL_SENSOR_FAILURE"),
      ins("INERTIAL_SENSOR_FAILURE"),
      tr("EXECUTING", "SUCCEEDED", "ISSUED -> EXECUTING is not a Figure 4 transition"),
      tr("FAILED", "RESOURCE_FAILED", null),
      { type: "command", command: cmd({ sessionId: "s2", unanswered: true }) },
      { type: "provider", event: "lost", provider: summary("lost", 3) },
      { type: "provider", event: "regained", provider: summary("regained") },
      { type: "provider", event: "live", provider: summary("live") },
    ]);
    expect(s.alarms).toEqual([]);
    expect(s.providers[P].link).toBe("live");
    expect(s.commands.s1.status).toBe("FAILED");
  });

  it("keeps satellite trails and a bounded C/N0 history, one point per second of the console's clock", () => {
    const gps = (az: number, at: number): ServerMessage =>
      reportMessage(
        P,
        "GPSReport",
        {
          numberSatellitesInView: 9,
          satellites: [
            {
              azimuth: az,
              elevation: 0.5,
              satelliteId: "ca5d35fb-bcc2-5b9a-b20c-df56b7b90207",
              usedInFix: true,
              antennaCarrierNoiseDensity: 40,
            },
          ],
        },
        [],
        at,
      );
    let s = apply([snapshot()]);
    for (let t = 0; t < HISTORY_SECONDS * 2; t += 1) s = reduce(s, gps(t / 1000, 7000 + t / 2), 5000 + t);
    const trail = s.providers[P].trails.E07;
    expect(trail.length).toBeGreaterThan(10);
    expect(trail[trail.length - 1].t - trail[0].t).toBeLessThanOrEqual(600);
    const history = s.providers[P].history;
    expect(history.length).toBe(HISTORY_SECONDS); // 2 reports a second, one kept
    expect(history.at(-1)).toEqual({ t: 7000 + (HISTORY_SECONDS * 2 - 2) / 2, cn0: 40, used: 1, inView: 9 });
  });

  it("computes chart points as the console does and merges the console's history after a reload", () => {
    const sats = [
      { antennaCarrierNoiseDensity: 30, usedInFix: true },
      { antennaCarrierNoiseDensity: 50, usedInFix: false },
      { usedInFix: true },
    ];
    expect(historyPoint({ satellites: sats, numberSatellitesInView: 3 } as never, 5)).toEqual({
      t: 5,
      cn0: 40,
      used: 2,
      inView: 3,
    });
    expect(historyPoint({ satellites: [], numberSatellitesInView: 0 } as never, 5).cn0).toBe(null);
    const pt = (t: number, used = 1): HistoryPoint => ({ t, cn0: 40, used, inView: 9 });
    const live = [pt(1000.2, 7), pt(1001.1, 7)];
    const stored = [pt(690), pt(999.5), pt(1000.0), pt(1001.9)];
    // one per second, the live point first; older than HISTORY_SECONDS before the latest: dropped
    expect(mergeHistory(live, stored)).toEqual([pt(999.5), pt(1000.2, 7), pt(1001.1, 7)]);
    let s = apply([snapshot()]);
    s = historyLoaded(s, P, stored);
    expect(s.providers[P].history.map((p) => p.t)).toEqual([999.5, 1000.0, 1001.9]);
    expect(historyLoaded(s, "unknown", stored)).toBe(s); // a vehicle the dashboard does not know: nothing
    expect(historyLoaded(s, P, [])).toBe(s);
  });

  it("follows the recording, failed too (a full disk: the console raises the alarm)", () => {
    const rec = {
      state: "recording",
      directory: "/rec",
      file: "a.mcap",
      startedAt: 1,
      messages: 0,
      dropped: 0,
      error: null,
    } as const;
    let s = apply([{ ...snapshot(), recording: rec } as ServerMessage]);
    expect(s.recording?.state).toBe("recording");
    const failed = {
      ...rec,
      state: "failed",
      startedAt: null,
      error: "recording stopped: the disk is full (/rec/a.mcap)",
    } as const;
    s = apply(
      [
        { type: "recording", recording: failed },
        { type: "recording", recording: failed },
      ],
      s,
    );
    expect(s.recording?.state).toBe("failed");
    expect(s.recording?.error).toBe(failed.error);
    s = apply([{ type: "recording", recording: { ...rec, file: "b.mcap" } }], s);
    expect(s.recording?.file).toBe("b.mcap");
  });

  it("keeps gateway states and a vehicle's link configuration and JAUS id", () => {
    const gw = {
      name: "jaus",
      enabled: true,
      endpoint: "udp://127.0.0.1:3794 subsystem 5",
      messagesOut: 4,
      messagesPerSecond: 0.8,
      lastError: null,
      lastErrorAt: null,
      counters: { received: 4 },
    } as const;
    const configured = {
      ...summary("live"),
      linkConfig: { ...CONFIG, commsLostTimeout: 9, policy: "CONTINUE_MISSION" as const },
      jausId: "5.1.1",
    };
    const s = apply([
      snapshot(),
      { type: "gateways", gateways: [gw] },
      { type: "provider", event: "configured", provider: configured },
    ]);
    expect(s.gateways).toEqual([gw]);
    expect(s.providers[P].linkConfig?.commsLostTimeout).toBe(9);
    expect(s.providers[P].jausId).toBe("5.1.1");
    expect(s.alarms).toEqual([]); // a new configuration is no alarm
  });

  it("keeps the UMAA version each vehicle speaks", () => {
    const s = apply([snapshot(), { type: "provider", event: "appeared", provider: { ...summary("live"), umaaVersion: "6.0" } }]);
    expect(s.providers[P].umaaVersion).toBe("6.0");
  });

  it("ignores errors, pongs and replay playback messages", () => {
    const s = apply([snapshot()]);
    expect(reduce(s, { type: "pong", serverTime: 1 }, 1)).toBe(s);
    expect(reduce(s, { type: "error", message: "x" }, 1)).toBe(s);
    expect(reduce(s, { type: "replay", replay: playback("paused", 5, 1) }, 1)).toBe(s);
  });
});

describe("CoMap world model and tasks", () => {
  const fc = (coverage: string | null) => ({
    type: "FeatureCollection",
    updatedAt: 1,
    source: "put",
    features: [{ type: "Feature", geometry: { type: "Point", coordinates: [1, 2] }, properties: { featureId: 1, coverage } }],
  });
  const task = (state: string, updatedAt: number, taskId = 1, more: object = {}) => ({
    taskId,
    kind: "survey",
    vehicle: P,
    imcId: 8193,
    featureId: 1,
    sensor: "SIDESCAN",
    resolution: 1,
    deadline: null,
    point: null,
    state,
    progress: 0,
    quality: null,
    synch: null,
    operator: null,
    createdAt: taskId,
    updatedAt,
    stateAt: updatedAt,
    ...more,
  });
  it("takes the world model and tasks from the WebSocket; a REST answer older than a message does not undo it", async () => {
    const { tasksLoaded, worldModelLoaded } = await import("./slices/comap");
    let s = reduce(initialState, { type: "worldmodel", worldModel: fc(null) } as unknown as ServerMessage, 1);
    const seqBefore = s.worldModelSeq; // a GET /api/worldmodel starts here...
    s = reduce(s, { type: "worldmodel", worldModel: fc("PARTIAL") } as unknown as ServerMessage, 2); // ...a message overtakes it
    expect(worldModelLoaded(s, fc(null) as never, seqBefore)).toBe(s);
    expect(s.worldModel?.features[0].properties?.coverage).toBe("PARTIAL");
    const fresh = worldModelLoaded(s, fc("COMPLETED") as never, s.worldModelSeq);
    expect(fresh.worldModel?.features[0].properties?.coverage).toBe("COMPLETED");

    s = reduce(s, { type: "task", task: task("ASSIGNED", 10) } as unknown as ServerMessage, 3);
    s = reduce(s, { type: "task", task: task("ACCEPTED", 11) } as unknown as ServerMessage, 3);
    expect(s.tasks[1].state).toBe("ACCEPTED");
    const kept = tasksLoaded(s, [task("ASSIGNED", 10) as never, task("COMPLETED", 30, 2) as never]); // REST: task 1 older, task 2 new
    expect(kept.tasks[1].state).toBe("ACCEPTED");
    expect(kept.tasks[2].state).toBe("COMPLETED");
    expect(tasksLoaded(kept, [task("ASSIGNED", 10) as never])).toBe(kept); // nothing newer: the same state
    // a HOLD (state decided at 40, progress as it was) came as a message; a GET answered before it, read after, has
    // newer progress (35) but the older state: the HOLD stays, the progress is taken
    const running = reduce(
      kept,
      { type: "task", task: task("IN_PROGRESS", 30, 3, { progress: 20 }) } as unknown as ServerMessage,
      4,
    );
    const held = reduce(
      running,
      { type: "task", task: task("HELD", 30, 3, { stateAt: 40, synch: "HOLD", progress: 20 }) } as unknown as ServerMessage,
      5,
    );
    const merged = tasksLoaded(held, [task("IN_PROGRESS", 35, 3, { stateAt: 30, progress: 60 }) as never]).tasks[3];
    expect([merged.state, merged.synch, merged.progress, merged.stateAt, merged.updatedAt]).toEqual(["HELD", "HOLD", 60, 40, 35]);
    // the vehicle COMPLETED it (at 38) before another station's HOLD (at 40) reached it: the console keeps it COMPLETED
    // (comap.c2.decided_over) and says so; the page does not keep the later HOLD over it
    const done = reduce(
      held,
      { type: "task", task: task("COMPLETED", 38, 3, { stateAt: 38, progress: 100 }) } as unknown as ServerMessage,
      6,
    );
    expect([done.tasks[3].state, done.tasks[3].progress]).toEqual(["COMPLETED", 100]);
    expect(tasksLoaded(done, [task("HELD", 30, 3, { stateAt: 40, synch: "HOLD" }) as never]).tasks[3].state).toBe("COMPLETED");
  });
  it("the REST load per connection says which tasks exist: a restarted console's old tasks go", async () => {
    const { tasksReplaced } = await import("./slices/comap");
    let s = reduce(initialState, { type: "task", task: task("EXECUTING", 10, 1) } as unknown as ServerMessage, 1);
    s = reduce(s, { type: "task", task: task("EXECUTING", 10, 2) } as unknown as ServerMessage, 1);
    const seq = s.taskSeq; // the console restarts, the page reconnects and asks GET /api/tasks here...
    s = reduce(s, { type: "task", task: task("ASSIGNED", 20, 3) } as unknown as ServerMessage, 2); // ...a new task's message overtakes it
    const after = tasksReplaced(s, [task("ASSIGNED", 5, 1) as never], seq); // the new console's task 1
    expect(Object.keys(after.tasks).map(Number).sort()).toEqual([1, 3]); // old task 2 gone; task 3 came after the request
    expect(after.tasks[1].state).toBe("ASSIGNED");
    expect(tasksReplaced(s, [], s.taskSeq).tasks).toEqual({});
  });
});

describe("store and connection", () => {
  it("applies queued messages together and notifies once", () => {
    const inbox = new Inbox(createStateStore());
    const store = inbox.store;
    let calls = 0;
    store.subscribe(() => calls++);
    inbox.enqueue(snapshot());
    inbox.enqueue(reportMessage(P, "InertialSensorReport", { state: "ON" }));
    expect(calls).toBe(0);
    inbox.flush();
    expect(calls).toBe(1);
    expect(report(store.getState().providers[P], "InertialSensorReport")?.state).toBe("ON");
  });

  it("backs off exponentially up to a ceiling", () => {
    expect([1, 2, 3, 4, 5, 6, 10].map(backoff)).toEqual([500, 1000, 2000, 4000, 8000, 10000, 10000]);
  });

  describe("sign-out when reads need a token", () => {
    // The browser's WebSocket as far as Connection uses it: the test plays the console's side.
    class FakeSocket {
      static all: FakeSocket[] = [];
      static readonly OPEN = 1;
      readyState = 0; // CONNECTING
      onmessage: ((ev: { data: string }) => void) | null = null;
      onclose: (() => void) | null = null;
      onerror: (() => void) | null = null;
      onopen: (() => void) | null = null;
      closed = false;
      sent: string[] = []; // what the source sent the console (its acks)
      constructor(
        readonly url: string,
        readonly protocols?: string[],
      ) {
        FakeSocket.all.push(this);
      }
      send(text: string): void {
        this.sent.push(text);
      }
      close(): void {
        if (this.closed) return;
        this.closed = true;
        this.readyState = 3; // CLOSED
        queueMicrotask(() => this.onclose?.());
      }
      receive(msg: ServerMessage | ServerMessage[]): void {
        this.onmessage?.({ data: JSON.stringify(msg) });
      }
    }
    afterEach(() => {
      vi.unstubAllGlobals();
      // a socket left open is a connection left running, its ping timer firing into the next test file (they share
      // their workers, vite.config.ts): each test stops what it started
      const open = FakeSocket.all.filter((ws) => !ws.closed).map((ws) => ws.url);
      FakeSocket.all = [];
      expect(open).toEqual([]);
    });

    it("stops in a clear state, keeps the selection and shows nothing of the vehicles, even from a late message", async () => {
      vi.stubGlobal("WebSocket", FakeSocket);
      const inbox = new Inbox(createStateStore(P));
      const store = inbox.store;
      update(store, (s) => ({ ...s, readAuthRequired: true, authRequired: true }));
      const conn = new Connection("ws://console/ws", inbox, () => ["sem-console", "bearer.dG9rZW4"]);
      const states: string[] = [];
      conn.subscribe(() => states.push(conn.getState()));
      conn.start();
      const ws = FakeSocket.all[0];
      expect(ws.protocols).toEqual(["sem-console", "bearer.dG9rZW4"]);
      ws.receive(snapshot());
      expect(conn.getState()).toBe("live");
      expect(Object.keys(store.getState().providers)).toEqual([P]);

      conn.stop(); // the operator signed out
      ws.receive(snapshot()); // still in flight on the closed socket
      inbox.flush();
      await Promise.resolve(); // the close event
      expect(ws.closed).toBe(true);
      expect(conn.getState()).toBe("signed-out");
      const s = store.getState();
      expect(s.providers).toEqual({});
      expect(s.commands).toEqual({});
      expect(s.consoleId).toBe(null);
      expect(s.selected).toBe(P);
      expect(s.readAuthRequired).toBe(true);
      expect(FakeSocket.all).toHaveLength(1); // no reconnect

      conn.restart(); // signed in again
      expect(conn.getState()).toBe("connecting");
      FakeSocket.all[1].receive(snapshot());
      expect(conn.getState()).toBe("live");
      expect(states).toEqual(["live", "signed-out", "connecting", "live"]);
      conn.stop(); // its ping timer with it: the test files share their workers (vite.config.ts)
    });

    it("a socket that brings nothing (no pong of its pings) is taken as dropped, as a closed one: not updating, and a new one", () => {
      vi.useFakeTimers();
      try {
        vi.stubGlobal("WebSocket", FakeSocket);
        const conn = new Connection("ws://console/ws", new Inbox(createStateStore(P)));
        conn.start();
        const ws = FakeSocket.all[0];
        ws.readyState = 1;
        ws.receive(snapshot());
        expect(conn.getState()).toBe("live");
        for (let i = 0; i < 8; i++) {
          vi.advanceTimersByTime(PING_EVERY_MS);
          ws.receive({ type: "pong", serverTime: i }); // the console answers: however long, still live
        }
        expect(conn.getState()).toBe("live");
        expect(ws.sent.filter((m) => JSON.parse(m).type === "ping").length).toBe(8);
        // the link goes silent, the socket not closed: within SILENT_AFTER_MS and a ping, what a closed socket says
        vi.advanceTimersByTime(SILENT_AFTER_MS + PING_EVERY_MS);
        expect(conn.getState()).toBe("reconnecting");
        expect(unreachable(conn.getState())).toBe(true);
        expect(ws.closed).toBe(true);
        vi.advanceTimersByTime(backoff(1));
        expect(FakeSocket.all).toHaveLength(2); // connecting again
        // one that never opens (a console that accepts, then answers nothing) is given up the same way
        vi.advanceTimersByTime(SILENT_AFTER_MS + PING_EVERY_MS);
        expect(FakeSocket.all[1].closed).toBe(true);
        vi.advanceTimersByTime(backoff(2));
        expect(FakeSocket.all).toHaveLength(3);
        FakeSocket.all[2].readyState = 1;
        FakeSocket.all[2].receive(snapshot());
        expect(conn.getState()).toBe("live");
        conn.stop();
      } finally {
        vi.useRealTimers();
      }
    });

    it("a hidden tab whose timers wake once a minute stays live while its pings are answered, and a silent socket is still dropped", () => {
      vi.useFakeTimers();
      try {
        vi.stubGlobal("WebSocket", FakeSocket);
        const conn = new Connection("ws://console/ws", new Inbox(createStateStore(P)));
        conn.start();
        const ws = FakeSocket.all[0];
        ws.readyState = 1;
        ws.receive(snapshot());
        // the browser throttles the hidden tab: the watchdog's timer runs once a minute, each ping answered at once
        const minute = () => {
          vi.setSystemTime(Date.now() + 60_000 - PING_EVERY_MS);
          vi.advanceTimersByTime(PING_EVERY_MS);
        };
        for (let i = 0; i < 3; i++) {
          minute();
          expect(conn.getState()).toBe("live");
          ws.receive({ type: "pong", serverTime: i });
        }
        expect(ws.closed).toBe(false);
        expect(ws.sent.filter((m) => JSON.parse(m).type === "ping").length).toBe(3);
        // a ping left unanswered a minute is a silent socket, hidden tab or not
        minute();
        expect(conn.getState()).toBe("live");
        minute();
        expect(conn.getState()).toBe("reconnecting");
        expect(ws.closed).toBe(true);
        conn.stop();
      } finally {
        vi.useRealTimers();
      }
    });

    /** `conn` on a FakeSocket, open, its store given the console's snapshot at `serverTime`; the socket. */
    function opened(conn: Connection, serverTime: number): FakeSocket {
      conn.start();
      const ws = FakeSocket.all[FakeSocket.all.length - 1];
      ws.readyState = 1;
      ws.receive({ ...snapshot(), serverTime } as ServerMessage);
      return ws;
    }
    let sinceTick = 0; // ms since the last ping
    /** The next ping, answered `rtt` s (under a ping's period) later by a console whose clock is `ahead` of the page's,
     * `at` s after the ping. */
    function pong(ws: FakeSocket, ahead: number, rtt: number, at = rtt / 2): void {
      vi.advanceTimersByTime(PING_EVERY_MS - sinceTick);
      const sent = Date.now() / 1000;
      vi.advanceTimersByTime(rtt * 1000);
      sinceTick = rtt * 1000;
      ws.receive({ type: "pong", serverTime: sent + at + ahead });
    }

    /** `test` on a live Connection of a fresh store, at a fixed time with fake timers, and the FakeSocket stubbed. */
    function onClockedConnection(test: (conn: Connection, inbox: Inbox) => void): void {
      vi.useFakeTimers({ now: 1_700_000_000_000 });
      try {
        vi.stubGlobal("WebSocket", FakeSocket);
        const inbox = new Inbox(createStateStore(P));
        const conn = new Connection("ws://console/ws", inbox);
        sinceTick = 0;
        test(conn, inbox);
        conn.stop();
      } finally {
        vi.useRealTimers();
      }
    }

    it("maps the console's clock onto the page's again by each pong's round trip: a step of the page's clock is undone at once", () =>
      onClockedConnection((conn, inbox) => {
        const ws = opened(conn, Date.now() / 1000 + 100);
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(100); // the snapshot's
        pong(ws, 100, 0.2);
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(100);
        vi.setSystemTime(Date.now() + 30_000); // the page's clock steps 30 s ahead (NTP, a laptop waking)
        pong(ws, 70, 0.2);
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(70); // not 100 until the next snapshot
        expect(conn.consoleNow()).toBeCloseTo(Date.now() / 1000 + 70); // the console's clock, for what it stamped
        // a slow round trip, the console answering late in it: the short one's reading stays
        pong(ws, 70, 0.9, 0.8);
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(70);
        // a paced report is heard when the console received it, on the page's clock now
        update(inbox.store, (st) => ({ ...st, othersEvery: 2.5 }));
        const receivedAt = Date.now() / 1000 + 70 - 2; // 2 s ago on the console's clock
        ws.receive(reportMessage(Q, "GPSFixReport", {}, [], receivedAt));
        inbox.flush();
        expect(inbox.store.getState().providers[Q].topics.GPSFixReport!.at).toBeCloseTo(Date.now() / 1000 - 2);
      }));

    it("a pong slowed by a backlog does not replace the snapshot's reading of the console's clock by a worse one", () =>
      onClockedConnection((conn, inbox) => {
        // the snapshot came at once on the new socket: the console's clock 100 s ahead, within that round trip
        const ws = opened(conn, Date.now() / 1000 + 100);
        // the first pong waited 3 s behind the reports in the socket (the console answered 0.2 s into it)
        pong(ws, 100, 3, 0.2);
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(100, 1); // not the slow pong's midpoint, 98.7
      }));

    it("a replay's pong (the console's wall time) leaves the console's clock the recording's, as the page's", () => {
      vi.useFakeTimers({ now: 1_700_000_000_000 });
      try {
        vi.stubGlobal("WebSocket", FakeSocket);
        const inbox = new Inbox(createStateStore(P));
        const replay = new ReplaySource("ws://console/ws", inbox);
        inbox.clock = replay.now;
        replay.start();
        const ws = FakeSocket.all[0];
        ws.readyState = 1;
        ws.receive({ ...snapshot(), serverTime: 1042, replay: playback("paused", 1042, 1) } as ServerMessage);
        sinceTick = 0;
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(0);
        pong(ws, 30, 0.2); // the console's wall clock 30 s ahead of the page's
        expect(inbox.store.getState().consoleAhead).toBeCloseTo(0);
        replay.stop();
      } finally {
        vi.useRealTimers();
      }
    });

    it("takes over the page's early socket with the messages it held, in order; one of another token is closed", () => {
      vi.stubGlobal("WebSocket", FakeSocket);
      const token = ["sem-console", "bearer.dG9rZW4"];
      const early = openEarly("ws://console/ws?batch=1", token);
      const ins = (status: string) =>
        reportMessage(P, "InertialSensorReport", { state: "ON", status: status as InertialSensorOpStatusEnumType });
      FakeSocket.all[0].readyState = 1;
      FakeSocket.all[0].receive(snapshot());
      FakeSocket.all[0].receive([ins("INIT"), ins("OPERATIONAL")]);
      expect(early.held).toHaveLength(2);
      expect(FakeSocket.all[0].sent).toEqual([]); // held, not taken: not acknowledged (the console holds what is newer)
      const inbox = new Inbox(createStateStore(P));
      const store = inbox.store;
      const applied = vi.spyOn(inbox, "enqueue");
      const conn = new Connection("ws://console/ws?batch=1", inbox, () => token);
      conn.start();
      expect(FakeSocket.all).toHaveLength(1); // no second socket
      expect(applied.mock.calls.map(([m]) => m.type)).toEqual(["snapshot", "report", "report"]); // each once
      expect(conn.getState()).toBe("live");
      // each frame taken is acknowledged, counted from the socket's first (?ack=1: the console's window)
      // then the vehicle it draws (the console sends the others' GPSReports without their satellites)
      expect(FakeSocket.all[0].sent.map((t) => JSON.parse(t) as unknown)).toEqual([
        { type: "ack", frames: 1 },
        { type: "ack", frames: 2 },
        { type: "select", providerId: P },
      ]);
      inbox.flush();
      expect(report(store.getState().providers[P], "InertialSensorReport")?.status).toBe("OPERATIONAL");
      FakeSocket.all[0].receive([ins("INERTIAL_SENSOR_FAILURE")]); // the socket's later messages reach the source
      expect(applied).toHaveBeenCalledTimes(4);
      expect(JSON.parse(FakeSocket.all[0].sent[3])).toEqual({ type: "ack", frames: 3 });
      update(store, (s) => ({ ...s, selected: "not-a-vehicle-id" })); // a ?vehicle= link to nothing: no vehicle's
      update(store, (s) => ({ ...s, selected: Q }));
      expect(FakeSocket.all[0].sent.slice(4).map((t) => JSON.parse(t) as unknown)).toEqual([
        { type: "select", providerId: null },
        { type: "select", providerId: Q },
      ]);
      inbox.flush();
      expect(report(store.getState().providers[P], "InertialSensorReport")?.status).toBe("INERTIAL_SENSOR_FAILURE");

      const loneInbox = new Inbox(createStateStore());

      const lone = loneInbox.store; // no ?vehicle=: the held snapshot selects its lone vehicle, told once
      openEarly("ws://console/ws?batch=1", token);
      FakeSocket.all[1].readyState = 1;
      FakeSocket.all[1].receive(snapshot());
      const alone = new Connection("ws://console/ws?batch=1", loneInbox, () => token);
      alone.start();
      expect(lone.getState().selected).toBe(P);
      expect(FakeSocket.all[1].sent.filter((t) => t.includes('"select"'))).toEqual([
        JSON.stringify({ type: "select", providerId: P }),
      ]);
      alone.stop();
      FakeSocket.all.splice(1, 1); // the indices below as before

      // open before the code came: the early socket names the link's vehicle at once (its URL, for the snapshot built
      // for it, and a `select`), and the source does not again
      openEarly("ws://console/ws?batch=1", token, P);
      expect(FakeSocket.all[1].url).toBe(`ws://console/ws?batch=1&vehicle=${P}`);
      FakeSocket.all[1].readyState = 1;
      FakeSocket.all[1].onopen?.();
      expect(FakeSocket.all[1].sent).toEqual([JSON.stringify({ type: "select", providerId: P })]);
      FakeSocket.all[1].receive(snapshot());
      const linked = new Connection("ws://console/ws?batch=1", new Inbox(createStateStore(P)), () => token);
      linked.start();
      expect(FakeSocket.all[1].sent.filter((t) => t.includes('"select"'))).toHaveLength(1);
      linked.stop();
      FakeSocket.all.splice(1, 1);

      openEarly("ws://console/ws", token); // another URL's
      const elsewhere = new Connection("ws://console/ws?batch=1", new Inbox(createStateStore(P)), () => token);
      elsewhere.start();
      expect(FakeSocket.all[1].closed).toBe(true);
      // its own, naming the vehicle selected: the console builds its snapshot for it
      expect(FakeSocket.all[2].url).toBe(`ws://console/ws?batch=1&vehicle=${P}`);
      elsewhere.stop();
      FakeSocket.all.splice(1, 2); // the indices below as before

      openEarly("ws://console/ws?batch=1", []); // opened before the operator signed in
      const other = new Connection("ws://console/ws?batch=1", new Inbox(createStateStore(P)), () => token);
      other.start();
      expect(FakeSocket.all[1].closed).toBe(true);
      expect(FakeSocket.all).toHaveLength(3); // its own, with the token
      expect(FakeSocket.all[2].protocols).toEqual(token);
      conn.stop();
      other.stop();
    });

    it("does not take over an early socket the console closed before the source started: a new one, and its close is no failure", async () => {
      vi.stubGlobal("WebSocket", FakeSocket);
      openEarly("ws://console/ws?batch=1", []);
      FakeSocket.all[0].readyState = 1;
      FakeSocket.all[0].receive(snapshot());
      FakeSocket.all[0].close(); // e.g. the console restarted while the page's code loaded
      const inbox = new Inbox(createStateStore(P));
      const store = inbox.store;
      const conn = new Connection("ws://console/ws?batch=1", inbox);
      const states: string[] = [];
      conn.subscribe(() => states.push(conn.getState()));
      conn.start();
      await Promise.resolve(); // the closed socket's close event
      expect(FakeSocket.all).toHaveLength(2);
      expect(states).toEqual([]); // still "connecting": no "reconnecting" for the old socket's close
      expect(store.getState().providers).toEqual({}); // nothing from the closed socket
      expect(FakeSocket.all[1].sent).toEqual([]);
      FakeSocket.all[1].readyState = 1;
      FakeSocket.all[1].onopen?.(); // open: the vehicle the page draws, first
      expect(FakeSocket.all[1].sent.map((t) => JSON.parse(t) as unknown)).toEqual([{ type: "select", providerId: P }]);
      FakeSocket.all[1].receive(snapshot());
      expect(conn.getState()).toBe("live");
      conn.stop();
    });

    it("takes a batch of reports (an array in one frame, /ws?batch=1) as the messages one by one, in order", () => {
      vi.stubGlobal("WebSocket", FakeSocket);
      const inbox = new Inbox(createStateStore(P));
      const store = inbox.store;
      const conn = new Connection("ws://console/ws?batch=1", inbox);
      conn.start();
      const ws = FakeSocket.all[0];
      ws.receive(snapshot());
      const ins = (status: string) =>
        reportMessage(P, "InertialSensorReport", { state: "ON", status: status as InertialSensorOpStatusEnumType });
      ws.receive([ins("INIT"), reportMessage("other", "GPSFixStatusReport", { fixValid: true }), ins("OPERATIONAL")]);
      inbox.flush();
      expect(report(store.getState().providers[P], "InertialSensorReport")?.status).toBe("OPERATIONAL"); // the later one
      expect(report(store.getState().providers.other, "GPSFixStatusReport")?.fixValid).toBe(true);
      conn.stop();
    });
  });
});

describe("the map's track", () => {
  const fix = (lat: number, lon: number, t: number) =>
    reportMessage(
      P,
      "GPSFixReport",
      {
        position2DWithTime: { geodeticPosition: { geodeticLatitude: { latitude: lat }, geodeticLongitude: { longitude: lon } } },
      },
      [],
      t,
    );
  it("takes at most one valid position a second from GPSFixReports, then merges the console's stored track", async () => {
    const { trackLoaded, TRACK_SECONDS } = await import("./slices/vehicles");
    let s = apply([snapshot(), fix(1, 2, 5000.1), fix(1.1, 2, 5000.6), fix(200, 2, 5001.2), fix(1.2, 2, 5002.0)]);
    expect(s.providers[P].track).toEqual([
      { lat: 1, lon: 2, t: 5000.1 },
      { lat: 1.2, lon: 2, t: 5002.0 },
    ]); // 1.1 same second, 200 invalid
    s = trackLoaded(s, P, [
      { lat: 0, lon: 0, t: 5002.0 - TRACK_SECONDS - 1 },
      { lat: 0.5, lon: 2, t: 4990 },
      { lat: 9, lon: 9, t: 5000.3 },
    ]);
    expect(s.providers[P].track.map((p) => p.t)).toEqual([4990, 5000.1, 5002.0]); // too old dropped; the live point kept for its second
    expect(trackLoaded(s, "nobody", [{ lat: 0, lon: 0, t: 1 }])).toBe(s);
  });
});

function playback(state: "playing" | "paused", position: number, speed: number): ReplayStatus {
  return { file: "20261122T101530.123Z.mcap", state, speed, position, start: 1000, end: 1100 };
}

/** A data source's message handler, as its WebSocket calls it. */
function deliver(source: Connection, msg: ServerMessage): void {
  (source as unknown as { receive(m: ServerMessage): void }).receive(msg);
}

describe("data sources", () => {
  afterEach(() => vi.useRealTimers());

  it("the live source commands and records, has no playback, and its clock is the wall clock", () => {
    vi.useFakeTimers({ now: 1_700_000_000_000 });
    const live = new Connection("ws://x/ws", new Inbox(createStateStore()));
    expect(live.capabilities).toEqual({ command: true, record: true, playback: false });
    expect(live.playback).toBe(null);
    expect(live.getPlayback()).toBe(null);
    expect(live.now()).toBe(1_700_000_000);
  });

  it("the replay source's clock is the recording's: at the speed while playing, still when paused, never past the end", () => {
    vi.useFakeTimers({ now: 1_700_000_000_000 });
    const inbox = new Inbox(createStateStore());
    const store = inbox.store;
    const replay = new ReplaySource("ws://x/ws", inbox);
    expect(replay.capabilities).toEqual({ command: false, record: false, playback: true });
    let heard = 0;
    replay.subscribe(() => heard++);
    deliver(replay, { type: "replay", replay: playback("playing", 1010, 4) });
    expect(heard).toBe(1);
    expect(replay.getPlayback()?.position).toBe(1010);
    expect(replay.getPlayback()).toBe(replay.getPlayback()); // the same object until it changes
    vi.advanceTimersByTime(2500);
    expect(replay.now()).toBeCloseTo(1020);
    vi.advanceTimersByTime(60_000);
    expect(replay.now()).toBe(1100);
    deliver(replay, { type: "replay", replay: playback("paused", 1042, 4) });
    vi.advanceTimersByTime(5000);
    expect(replay.now()).toBe(1042);
    // a store driven by it stamps what it applies with the recording's time
    inbox.clock = replay.now;
    deliver(replay, { ...snapshot(), replay: playback("paused", 1042, 4) } as ServerMessage);
    expect(store.getState().providers[P].topics.GPSReport!.at).toBe(1040); // 2 s old at the instant shown
  });

  /** A replay source on a store with P selected, at `position` of the recording. */
  function replayAt(
    state: "playing" | "paused",
    position: number,
  ): { inbox: Inbox; store: Inbox["store"]; replay: ReplaySource } {
    vi.useFakeTimers({ now: 1_700_000_000_000 });
    const inbox = new Inbox(createStateStore(P));
    const store = inbox.store;
    const replay = new ReplaySource("ws://x/ws", inbox);
    inbox.clock = replay.now;
    deliver(replay, { ...snapshot(), replay: playback(state, position, 1) } as ServerMessage);
    return { inbox, store, replay };
  }
  const gpsReport = reportMessage(P, "GPSReport", {
    satellites: [{ azimuth: 1, elevation: 0.5, satelliteId: "ca5d35fb-bcc2-5b9a-b20c-df56b7b90207", usedInFix: true }],
  });

  it("a replay played at 20x judges a vehicle not drawn by its pace in the recording's time, as its reports come", () => {
    // the console paces by wall time (0.25 s: a report of Q every 5 s of the recording at 20x, rendering.md); the
    // page's clock is the recording's
    const { inbox, store, replay } = replayAt("playing", 1000);
    deliver(replay, { type: "replay", replay: playback("playing", 1000, 20) });
    deliver(replay, { type: "pace", othersEvery: 0.25 });
    deliver(replay, reportMessage(Q, "GPSFixReport", {}, [], 1000));
    inbox.flush();
    vi.advanceTimersByTime(200); // 0.2 s of wall time, 4 s of the recording: Q's next report not due yet
    const s = store.getState();
    const view = s.providers[Q].topics.GPSFixReport!;
    expect(freshness(replay.now() - view.at, "GPSFixReport", view.interval, "live", true, paceOf(s, Q))).toBe("live");
    expect(s.othersEvery).toBe(5); // what the map's caption says: a position every 5 s of the recording
    deliver(replay, { type: "replay", replay: playback("playing", 1000, 1) });
    expect(store.getState().othersEvery).toBe(0.25); // at 1x, the pace as the console said it
  });

  it("a replay slowed below 1x says the pace of the vehicles not drawn no sparser than they come", () => {
    const { inbox, store, replay } = replayAt("playing", 1000);
    deliver(replay, { type: "pace", othersEvery: 0.25 });
    inbox.flush();
    deliver(replay, { type: "replay", replay: playback("playing", 1000, 0.5) });
    // a report of each every 0.125 s of the recording: the caption's "at most a position every 0.13 s" was untrue
    expect(store.getState().othersEvery).toBeLessThanOrEqual(0.125);
    expect(store.getState().othersEvery).toBeGreaterThan(0.1);
  });

  it("a replay snapshot (a seek) starts trails, charts and commands again, takes its alarms and keeps the selection", () => {
    const { inbox, store, replay } = replayAt("paused", 1050);
    deliver(replay, gpsReport);
    inbox.flush();
    deliver(replay, {
      type: "alarms",
      alarms: [
        {
          id: 1,
          kind: "link-lost",
          severity: "alarm",
          providerId: P,
          vehicle: P.slice(0, 8),
          sessionId: null,
          text: "lost",
          since: 1049,
          state: "active-unacknowledged",
          clearedAt: null,
          ackedAt: null,
          ackedBy: null,
          cause: "Link lost",
          chattering: false,
          shelf: null,
          returned: null,
        },
      ],
    });
    inbox.flush();
    expect(store.getState().providers[P].trails.E07).toHaveLength(1);
    expect(store.getState().alarms).toHaveLength(1);
    deliver(replay, { ...snapshot(), commands: [], replay: playback("paused", 1010, 1) } as ServerMessage); // seek back
    const s = store.getState();
    expect(s.providers[P].trails).toEqual({});
    expect(s.providers[P].history).toEqual([]);
    expect(s.alarms).toEqual([]); // the snapshot's: none at that instant
    expect(s.commands).toEqual({});
    expect(s.selected).toBe(P);
    expect(replay.getPlayback()?.position).toBe(1010);
  });

  it("a seek drops the reports still queued from before it, and moves the instant on (history reloads)", () => {
    const { inbox, store, replay } = replayAt("playing", 1050);
    const instant = store.getState().instant;
    deliver(replay, gpsReport);
    // not applied yet (the next frame), when the seek back's snapshot comes
    deliver(replay, { ...snapshot(), commands: [], replay: playback("paused", 1010, 1) } as ServerMessage);
    inbox.flush();
    vi.advanceTimersByTime(1000);
    expect(store.getState().providers[P].trails).toEqual({});
    expect(store.getState().instant).toBe(instant + 1);
  });
});

describe("report payloads typed per topic", () => {
  it("a report message's topic narrows its report; a topic's view holds that topic's report", async () => {
    const { selectedTopic, viewReport } = await import("./slices/vehicles");
    const msg = reportMessage(P, "GPSFixStatusReport", { fixValid: true });
    if (msg.type === "report" && msg.topic === "GPSFixStatusReport")
      expectTypeOf(msg.report.report).toEqualTypeOf<GPSFixStatusReportType>();
    const s = apply([snapshot(), msg]);
    const status = viewReport(selectedTopic("GPSFixStatusReport")(s));
    expectTypeOf(status).toEqualTypeOf<GPSFixStatusReportType | null>();
    expect(status?.fixValid).toBe(true);
    expectTypeOf(report(s.providers[P], "InertialSensorReport")).toEqualTypeOf<InertialSensorReportType | null>();
  });
});

describe("the first screen of a page that named its vehicle: every other vehicle's brief", () => {
  it("draws a vehicle from its brief, and fills in the rest when it is selected: the whole reports and its detail", async () => {
    const { briefLoaded, fromBrief } = await import("./slices/vehicles");
    const { vehicleMark } = await import("../panels/Map/layers");
    const { brief, snapshotMessage } = await import("./testing");
    const s = apply([snapshotMessage({ serverTime: 1002, fleet: [brief(P, 1000)] })], initialState);
    const p = s.providers[P];
    expect(p.brief).toBe(true);
    expect(p.linkConfig).toBeNull();
    expect(p.topics.GPSFixReport?.at).toBe(1000 - 2); // 2 s old at the console: 2 s old here
    const mark = vehicleMark(p, 999, null, new Set(), true, [])!;
    expect(mark).toMatchObject({ position: { lat: 36.8, lon: -75.7 }, fix: "valid", gpsPosition: true, link: "live" });
    expect(mark.courseDeg).toBeCloseTo((1.5 * 180) / Math.PI);
    expect(report(p, "InertialSensorReport")).toMatchObject({ state: "ON", status: "OPERATIONAL" });
    expect(report(p, "GPSFixReport")?.altitudeMSL).toBeNull(); // not in the brief: not known yet, no error
    // each view says so: its nulls are the brief's, not the vehicle's (the panels show them as loading, not as a dash)
    expect([p.topics.GPSFixReport?.brief, p.topics.GPSFixStatusReport?.brief, p.topics.InertialSensorReport?.brief]).toEqual([
      true,
      true,
      true,
    ]);
    // selected: the console sends its newest reports whole (the same samples: heard when they first came)
    const whole = reportMessage(
      P,
      "GPSFixReport",
      { position2DWithTime: { timeAtPosition: 5 }, altitudeMSL: { altitude: -3 } },
      [],
      1000,
    );
    const selected = reduce(select(s, P), whole, 1005);
    expect(report(selected.providers[P], "GPSFixReport")?.altitudeMSL).toEqual({ altitude: -3 });
    expect(selected.providers[P].topics.GPSFixReport?.at).toBe(998);
    expect(selected.providers[P].topics.GPSFixReport?.brief).toBeUndefined(); // whole now: its nulls are the vehicle's
    expect(selected.providers[P].topics.InertialSensorReport?.brief).toBe(true); // none of its topic came yet
    // and its detail over REST: its link configuration, the reports it has whole
    const detail = {
      ...summary("live"),
      reports: {
        InertialSensorReport: env({ state: "ON", status: "OPERATIONAL", timeStamp: { seconds: 7, nanoseconds: 0 } }, [], 1000),
      },
    } as never;
    const loaded = briefLoaded(selected, P, detail);
    expect(loaded.providers[P].brief).toBe(false);
    expect(loaded.providers[P].linkConfig).toEqual(CONFIG);
    expect(report(loaded.providers[P], "InertialSensorReport")?.timeStamp).toEqual({ seconds: 7, nanoseconds: 0 });
    expect(loaded.providers[P].topics.InertialSensorReport).toEqual({
      envelope: detail["reports"]["InertialSensorReport"],
      at: 998,
      interval: null,
    }); // whole: no longer the brief's
    // a topic the detail has not (or has newer): the brief's view stays marked until the WebSocket's whole report
    expect(loaded.providers[P].topics.GPSFixStatusReport?.brief).toBe(true);
    const status = reportMessage(P, "GPSFixStatusReport", { fixValid: true, pCode: null }, [], 1001);
    expect(reduce(loaded, status, 1006).providers[P].topics.GPSFixStatusReport?.brief).toBeUndefined();
    expect(briefLoaded(loaded, P, detail)).toBe(loaded); // once
    // a vehicle of a later snapshot sent whole is no longer a brief's
    expect(fromBrief(undefined, brief(P), 0, 0).brief).toBe(true);
    // behind a relay's caps, the brief says its quiet, as the whole summary does (the bar's "stale" waits for it)
    const relay = { name: "ship-1", dataTime: null, ageSeconds: null, quietSeconds: 5 };
    expect(fromBrief(undefined, brief(P, 1000, { relay }), 0, 0)).toMatchObject({ relay: "ship-1", relayQuiet: 5 });
    expect(apply([snapshot()], loaded).providers[P].brief).toBe(false);
  });
});

describe("the first screen: the snapshot's GPSReport without its satellites", () => {
  it("is completed by the vehicle's REST detail, unless a report came since", async () => {
    const { detailLoaded, selectedGpsPartial } = await import("./slices/vehicles");
    const sats = [{ satelliteId: "s3", azimuth: 1, elevation: 0.5 }];
    const full = { GPSReport: env({ satellites: sats, numberSatellitesInView: 1 }, [], 1) } as never;
    const s = apply([snapshot()]);
    expect(selectedGpsPartial(s)).toBe(true);
    const done = detailLoaded(s, P, full);
    expect(selectedGpsPartial(done)).toBe(false);
    expect(report(done.providers[P], "GPSReport")?.satellites).toEqual(sats);
    expect(detailLoaded(done, P, full)).toBe(done); // once: no longer partial
    const live = apply([reportMessage(P, "GPSReport", { satellites: [], numberSatellitesInView: 0 }, [], 2)], s);
    expect(selectedGpsPartial(live)).toBe(false); // the next report is whole
    expect(detailLoaded(live, P, full)).toBe(live);
  });

  it("completed for a vehicle just selected, is still the report that came at the others' pace", async () => {
    const { detailLoaded, viewPace } = await import("./slices/vehicles");
    let s = select(apply([snapshot(), { type: "pace", othersEvery: 2.5 }]), "b");
    s = reduce(
      s,
      { ...reportMessage(P, "GPSReport", { numberSatellitesInView: 1 }, [], 5), partial: true } as ServerMessage,
      1000,
    );
    s = select(s, P); // its GPSReport came thin at the pace: the REST detail completes it
    const done = detailLoaded(s, P, { GPSReport: env({ satellites: [], numberSatellitesInView: 1 }, [], 5) } as never);
    expect(viewPace(done.providers[P].topics.GPSReport, done.othersEvery)).toBe(2.5); // judged by the pace still
  });

  it("a live partial GPSReport (another vehicle selected) keeps the satellites it had, the trails and the chart", async () => {
    const { selectedGpsPartial } = await import("./slices/vehicles");
    const sats = [
      {
        satelliteId: "ca5d35fb-bcc2-5b9a-b20c-df56b7b90207",
        azimuth: 1,
        elevation: 0.5,
        usedInFix: true,
        antennaCarrierNoiseDensity: 40,
      },
    ];
    const whole = apply([snapshot(), reportMessage(P, "GPSReport", { satellites: sats, numberSatellitesInView: 9 }, [], 2)]);
    const thin = {
      ...reportMessage(P, "GPSReport", { satellites: [], numberSatellitesInView: 8 }, [], 3),
      partial: true,
    } as ServerMessage;
    const s = reduce(whole, thin, 10);
    expect(selectedGpsPartial(s)).toBe(true); // completed by the console's whole one (or GET /api/providers/{id})
    expect(report(s.providers[P], "GPSReport")).toEqual({ satellites: sats, numberSatellitesInView: 8 });
    expect(s.providers[P].trails).toBe(whole.providers[P].trails);
    expect(s.providers[P].history).toBe(whole.providers[P].history); // no chart point of C/N0 0, 0 used
    const first = reduce(apply([snapshot()]), thin, 10); // none before: none now
    expect(report(first.providers[P], "GPSReport")?.satellites).toEqual([]);
    expect(first.providers[P].history).toEqual([]);
  });

  it("a vehicle not selected: its whole GPSReport of every 5 s gives its trails a point, a few ms early or not", () => {
    const sat = (az: number) => [{ satelliteId: "ca5d35fb-bcc2-5b9a-b20c-df56b7b90207", azimuth: az, elevation: 0.5 }];
    const whole = (az: number, at: number) => reportMessage(P, "GPSReport", { satellites: sat(az) }, [], at);
    const thin = (at: number) =>
      ({ ...reportMessage(P, "GPSReport", { satellites: [] }, [], at), partial: true }) as ServerMessage;
    let s = reduce(apply([snapshot()]), whole(1, 100), 100);
    for (const t of [101, 102, 103, 104]) s = reduce(s, thin(t), t);
    s = reduce(s, whole(2, 104.98), 104.98); // the console's 5 s, arriving 20 ms sooner than the last one did
    expect(s.providers[P].trails.E07.map((p) => p.az)).toEqual([1, 2]);
  });
});

const FIX = {
  position2DWithTime: { geodeticPosition: { geodeticLatitude: { latitude: 36.8 }, geodeticLongitude: { longitude: -75.7 } } },
};

describe("the selected vehicle after being paced", () => {
  it("is stale once silent past the fix's 1.5 s floor, not past three times the pace it came at while not drawn", () => {
    // 1,000 vehicles: the console paces the vehicles the page does not draw at 10 s
    let s: State = reduce(initialState, snapshotMessage({ serverTime: 0, providers: [vehicle(P), vehicle(Q)] }), 0);
    s = select(s, Q);
    s = reduce(s, { type: "pace", othersEvery: 10 } as ServerMessage, 0);
    // P's GPSFixReport reaches the page once a pace (its rate is 10 Hz at the console)
    let t = 0;
    for (let i = 1; i <= 6; i++) s = reduce(s, reportMessage(P, "GPSFixReport", FIX, [], (t = 10 * i)), t);
    // the operator selects P: the console sends it at full rate (10 Hz) from now
    s = select(s, P);
    for (let i = 1; i <= 5; i++) s = reduce(s, reportMessage(P, "GPSFixReport", FIX, [], t + 0.1 * i), t + 0.1 * i);
    expect(paceOf(s, P)).toBe(0); // judged by its own rate now
    const view = s.providers[P].topics.GPSFixReport!;
    // then P goes silent for 5 s (the console's link timeout not yet passed for this vehicle's configuration)
    const now = view.at + 5;
    // the Fix panel's freshness (Fix.tsx) and the map's selected ring (layers.ts) of the selected vehicle
    expect(freshness(now - view.at, "GPSFixReport", view.interval, "live", true)).toBe("stale");
    expect(vehicleMark(s.providers[P], now, P, new Set(), true, [], paceOf(s, P))?.link).toBe("stale");
  });

  it("is stale once silent past the fix's floor though its first report after the selection was held a pace", () => {
    let s: State = reduce(initialState, snapshotMessage({ serverTime: 0, providers: [vehicle(P), vehicle(Q)] }), 0);
    s = select(s, Q);
    s = reduce(s, { type: "pace", othersEvery: 10 } as ServerMessage, 0);
    s = reduce(s, reportMessage(P, "GPSFixReport", FIX, [], 50), 50);
    s = select(s, P);
    // the console received P's newest fix at 55 and held it for the pace: it comes first, at 60, then the rest at 10 Hz
    s = reduce(s, reportMessage(P, "GPSFixReport", FIX, [], 55), 60);
    for (let i = 1; i <= 5; i++) s = reduce(s, reportMessage(P, "GPSFixReport", FIX, [], 60 + 0.1 * i), 60 + 0.1 * i);
    const view = s.providers[P].topics.GPSFixReport!;
    const now = view.at + 5; // then silent 5 s: its 10 Hz interval learned, not the 5 s the held one waited
    expect(freshness(now - view.at, "GPSFixReport", view.interval, "live", true, viewPace(view, s.othersEvery))).toBe("stale");
  });
});

describe("a vehicle built from a brief after a reconnect", () => {
  it("shows the link configuration the console has now, not the one the page had before it lost the console", () => {
    const old = { commsLostTimeout: 3, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 } as const;
    const now = { commsLostTimeout: 30, regainedTime: 3, policy: "CONTINUE_MISSION", regainedBehavior: 0 } as const;
    let s: State = reduce(
      initialState,
      snapshotMessage({ serverTime: 0, providers: [vehicle(P), vehicle(Q, { linkConfig: old })] }),
      0,
    );
    s = select(s, P);
    // the page lost the console; meanwhile another station changed Q's link configuration to `now`; the page
    // reconnects with ?vehicle=P: Q comes as its brief (which carries no link configuration)
    s = reduce(s, snapshotMessage({ serverTime: 100, providers: [vehicle(P)], fleet: [brief(Q, 99)] }), 100);
    // the operator selects Q: the page loads its detail (GET /api/providers/{id}), which has `now`
    s = select(s, Q);
    const detail = { ...vehicle(Q, { linkConfig: now }), reports: {} };
    s = briefLoaded(s, Q, detail as never);
    expect(s.providers[Q].linkConfig).toEqual(now); // the Gateways panel's form shows (and would send) this
  });
});
