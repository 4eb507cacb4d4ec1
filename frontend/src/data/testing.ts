// Test fixtures: server messages built from the parts a test needs, and the mock data source of component tests.
import type { Alarm } from "../api/generated/ws";
import type {
  Command,
  LinkConfig,
  ReplayStatus,
  ReportTypes,
  ServerMessage,
  Topic,
  TypedProviderDetail,
  TypedSnapshotMessage,
  VehicleBrief,
} from "../api/types";
import { LIVE, type Capabilities, type DataSource, type PlaybackControls, type SourceState } from "./source";
import { Inbox, createStateStore, type StateStore } from "./store";

/** Every member optional, at every depth: the part of a report a test sets. */
export type DeepPartial<T> = T extends (infer U)[]
  ? DeepPartial<U>[]
  : T extends object
    ? { [K in keyof T]?: DeepPartial<T[K]> }
    : T;

/** A `report` message of `topic` carrying `report` (members the test leaves out are absent, as a reducer must bear). */
export function reportMessage<T extends Topic>(
  providerId: string,
  topic: T,
  report: DeepPartial<ReportTypes[T]>,
  invalid: string[] = [],
  receivedAt = 1,
): ServerMessage {
  const sample = report as ReportTypes[T];
  return { type: "report", providerId, topic, report: { report: sample, invalid, receivedAt } } as ServerMessage;
}

const CONFIG: LinkConfig = { commsLostTimeout: 3, regainedTime: 3, policy: "STOP_MISSION", regainedBehavior: 0 };

/** A vehicle as the snapshot gives it: live, named, UMAA 3.0.1, no reports; `over` sets the rest. */
export function vehicle(id: string, over: Partial<TypedProviderDetail> = {}): TypedProviderDetail {
  return {
    id,
    name: null,
    link: "live",
    ageSeconds: 0,
    topics: {},
    linkConfig: CONFIG,
    jausId: null,
    umaaVersion: "3.0.1",
    reports: {},
    ...over,
  };
}

/** A vehicle as the snapshot's `fleet` has it (to a page that named another): live at 36.8 N 75.7 W, its fix valid and
 * its INS operational, each report received at `receivedAt`; `over` sets the rest. */
export function brief(id: string, receivedAt = 1000, over: Partial<VehicleBrief> = {}): VehicleBrief {
  return {
    id,
    name: null,
    link: "live",
    umaaVersion: "3.0.1",
    jausId: null,
    relay: null,
    fix: { lat: 36.8, lon: -75.7, course: 1.5, sog: 1.8, latLongValid: true, invalid: [], receivedAt },
    fixStatus: { fixValid: true, originLat: 36.7, originLon: -75.6, receivedAt },
    ins: { state: "ON", status: "OPERATIONAL", receivedAt },
    ...over,
  };
}

/** The snapshot a console sends on a (re)connect: no vehicle, alarm or command unless `over` gives them; stamped at
 * 1000, TestSource's clock at its start (the console's clock and the page's agree). */
export function snapshotMessage(over: Partial<TypedSnapshotMessage> = {}): ServerMessage {
  return {
    type: "snapshot",
    consoleId: "test-console",
    serverTime: 1000,
    authRequired: false,
    commands: [],
    gateways: [],
    alarms: [],
    silences: [],
    recording: { state: "off", directory: "var/recordings", file: null, startedAt: null, messages: 0, dropped: 0, error: null },
    replay: null,
    providers: [],
    ...over,
  };
}

/** An alarm of the console's active set: active and unacknowledged unless `over` says otherwise. */
export function alarm(id: number, providerId: string | null, over: Partial<Alarm> = {}): Alarm {
  return {
    id,
    kind: "link-lost",
    severity: "alarm",
    providerId,
    vehicle: providerId?.slice(0, 8) ?? "",
    sessionId: null,
    text: "link lost",
    since: 1000,
    state: "active-unacknowledged",
    clearedAt: null,
    ackedAt: null,
    ackedBy: null,
    cause: "Link lost",
    chattering: false,
    shelf: null,
    returned: null,
    ...over,
  };
}

/** The mock data provider of component tests: a data source (as the live WebSocket and the replay are) that feeds the
 * store the typed messages a test gives it, applied at once, on a clock the test sets. */
export class TestSource implements DataSource {
  readonly kind: "live" | "replay";
  readonly playback: PlaybackControls | null = null;
  readonly inbox: Inbox;
  clock = 1000; // the source's time, UTC seconds
  private state: SourceState = "live";
  private listeners = new Set<() => void>();

  constructor(
    selected: string | null = null,
    readonly capabilities: Capabilities = LIVE,
  ) {
    this.kind = capabilities.playback ? "replay" : "live";
    this.inbox = new Inbox(createStateStore(selected));
    this.inbox.clock = () => this.clock;
  }

  get store(): StateStore {
    return this.inbox.store;
  }

  /** The console's messages, applied to the store at once (as one frame). */
  send(...msgs: ServerMessage[]): void {
    for (const m of msgs) this.inbox.enqueue(m);
    this.inbox.flush();
  }

  /** The connection's state: "reconnecting" and "offline" are the console out of reach. */
  setState(state: SourceState): void {
    this.state = state;
    for (const l of this.listeners) l();
  }

  subscribe = (l: () => void): (() => void) => {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  };

  getState = (): SourceState => this.state;
  getPlayback = (): ReplayStatus | null => null;
  now = (): number => this.clock;
  consoleNow = (): number => this.clock + (this.kind === "live" ? (this.store.getState().consoleAhead ?? 0) : 0);
  start(): void {}
  stop(): void {}
  restart(): void {}
}

/** A command as the console follows it: GPSFix to `providerId`, just asked, no answer yet; `over` sets the rest. */
export function command(providerId: string, over: Partial<Command> = {}): Command {
  return {
    sessionId: "s1",
    service: "GPSFix",
    providerId,
    state: null,
    operator: null,
    createdAt: 1000,
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
