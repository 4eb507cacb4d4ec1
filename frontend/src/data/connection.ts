// The live data source: one WebSocket to the console with explicit states, reconnect with backoff,
// a fresh snapshot on every (re)connect, and messages handed to the store's inbox (applied once per frame).
import type { ClientMessage, ReplayStatus, ServerMessage } from "../api/types";
import { LIVE, type Capabilities, type DataSource, type PlaybackControls, type SourceState } from "./source";
import { socketUrl, takeEarly, type EarlySocket } from "./early";
import { consoleClock, withConsoleAhead, type ClockSample } from "./slices/vehicles";
import { update, type Inbox } from "./store";
import { isVehicleId } from "../lib/vehicle";

export type ConnectionState = SourceState;

export const BACKOFF_MIN_MS = 500;
export const BACKOFF_MAX_MS = 10_000;
export const OFFLINE_AFTER_FAILURES = 5;

/** How often the page pings the console while its socket is open: the console answers each with a pong, so a socket
 * that works brings a frame at least this often, vehicles or none. */
export const PING_EVERY_MS = 1000;
/** A socket that answers nothing this long after it was asked (its opening, or a ping: not even a pong) is taken as
 * gone, as one the console closed: the page says "Not updating" by that one rule (the socket dropped, the console
 * stopped, or the link went silent with its socket still open) and connects again. The time runs from the question, not
 * from the last frame: a hidden tab's timers may wake once a minute, and its pings go as seldom, answered all the same. */
export const SILENT_AFTER_MS = 4000;

export function backoff(failures: number): number {
  return Math.min(BACKOFF_MAX_MS, BACKOFF_MIN_MS * 2 ** Math.max(0, failures - 1));
}

type Listener = () => void;

export class Connection implements DataSource {
  readonly kind: "live" | "replay" = "live";
  readonly capabilities: Capabilities = LIVE;
  readonly playback: PlaybackControls | null = null;
  state: ConnectionState = "connecting";
  private ws: WebSocket | null = null;
  private failures = 0;
  private timer: ReturnType<typeof setTimeout> | null = null;
  private watchdog: ReturnType<typeof setInterval> | null = null;
  private stopped = false;
  private listeners = new Set<Listener>();
  private unwatchSelected: (() => void) | null = null;
  private told: { ws: WebSocket; providerId: string | null } | null = null; // the last `select` sent, and its socket
  private clock: ClockSample[] = []; // the last pongs' readings of the console's clock (consoleClock)

  /** `protocols`: the WebSocket subprotocols of the next (re)connect (they carry the operator token). */
  constructor(
    private readonly url: string,
    protected readonly inbox: Inbox,
    private readonly protocols: () => string[] = () => [],
  ) {}

  subscribe = (l: Listener): (() => void) => {
    this.listeners.add(l);
    return () => this.listeners.delete(l);
  };

  getState = (): ConnectionState => this.state;

  getPlayback = (): ReplayStatus | null => null;

  now = (): number => Date.now() / 1000;

  consoleNow = (): number => this.now() + (this.inbox.store.getState().consoleAhead ?? 0);

  protected notify(): void {
    for (const l of this.listeners) l();
  }

  start(): void {
    this.stopped = false;
    // the console sends the other vehicles' GPSReports without their satellites (only the selected one's are drawn)
    this.unwatchSelected ??= this.inbox.store.subscribe(
      (s) => s.selected,
      () => this.sendSelected(this.ws),
    );
    this.setState("connecting");
    this.open(takeEarly(this.url, this.protocols())); // the page's own socket (early.ts), if it is still the right one
  }

  /** Sign-out when reads need a token: close, stay closed, and clear the store (nothing of the
   * vehicles stays on screen; a message still in flight on the old socket is dropped). */
  stop(): void {
    this.stopped = true;
    if (this.timer) clearTimeout(this.timer);
    this.stopWatchdog();
    const old = this.ws;
    this.ws = null;
    old?.close();
    this.inbox.clear();
    this.setState("signed-out");
  }

  /** Connect afresh at once (e.g. with a new token); the old socket's close is ignored. */
  restart(): void {
    if (this.timer) clearTimeout(this.timer);
    this.stopWatchdog();
    const old = this.ws;
    this.ws = null;
    old?.close();
    this.failures = 0;
    this.stopped = false;
    this.setState("connecting");
    this.open();
  }

  private setState(s: ConnectionState): void {
    if (s === this.state) return;
    this.state = s;
    this.notify();
  }

  /** Tell the console which vehicle's satellites the page draws (`select`; a ?vehicle= that is no vehicle id: none). */
  private sendSelected(ws: WebSocket | null): void {
    if (!ws || ws !== this.ws || ws.readyState !== WebSocket.OPEN) return;
    const selected = this.inbox.store.getState().selected;
    const providerId = selected && isVehicleId(selected) ? selected : null;
    // once: the early socket's held snapshot may select its lone vehicle (and tell) before the socket's own `select`
    if (this.told?.ws === ws && this.told.providerId === providerId) return;
    this.told = { ws, providerId };
    const msg: ClientMessage = { type: "select", providerId };
    ws.send(JSON.stringify(msg));
  }

  /** One message from the console (a replay source looks at some first). */
  protected receive(msg: ServerMessage): void {
    if (msg.type === "snapshot") {
      this.failures = 0;
      this.inbox.enqueue(msg);
      this.inbox.flush(); // the snapshot is the baseline: apply it at once
      this.setState("live");
      return;
    }
    this.inbox.enqueue(msg);
  }

  /** A message the console stamped with its clock (`serverTime`) after `sent` arrived at `arrived` (ms on the page's
   * clock): a pong to the ping sent then, or a snapshot of the socket opened then. The console's clock against the
   * page's again (consoleAhead), so a step of the page's clock misjudges paced reports' ages for a ping or two, not
   * until the next snapshot; the snapshot's reading is one of them, so a first pong slowed by a backlog is no better. */
  protected clockRead(sent: number, serverTime: number, arrived: number): void {
    const { samples, ahead } = consoleClock(this.clock, sent / 1000, serverTime, arrived / 1000);
    this.clock = samples;
    if (ahead !== null) update(this.inbox.store, (s) => withConsoleAhead(s, ahead));
  }

  /** A new socket, or `early`'s with the messages it held. A new one names the vehicle selected (`socketUrl`): its
   * snapshot is built for it. */
  private open(early: EarlySocket | null = null): void {
    const protocols = this.protocols();
    const url = socketUrl(this.url, this.inbox.store.getState().selected);
    const ws = early?.ws ?? (protocols.length ? new WebSocket(url, protocols) : new WebSocket(url));
    this.ws = ws;
    let frames = 0; // frames taken from this socket, acknowledged to the console (?ack=1, defaultUrl)
    const opened = early?.opened ?? Date.now(); // its snapshot was stamped after
    let asked: number | null = Date.now(); // when the oldest question this socket has not answered was asked (null: none)
    const pings: number[] = []; // when each ping not answered yet was sent (its pong answers the oldest)
    const onMessage = (ev: MessageEvent<string>) => {
      if (this.ws !== ws) return; // a socket closed by stop() or restart(), or dropped as silent
      asked = null;
      frames += 1;
      const ack: ClientMessage = { type: "ack", frames };
      if (ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(ack));
      let data: ServerMessage | ServerMessage[];
      try {
        data = JSON.parse(ev.data) as ServerMessage | ServerMessage[];
      } catch {
        return;
      }
      const arrived = Date.now();
      // an array: the reports that waited for the console's sender (?batch=1, defaultUrl), in order
      for (const msg of Array.isArray(data) ? data : [data]) {
        const sent = msg.type === "pong" ? pings.shift() : opened;
        this.receive(msg); // a snapshot sets the console's clock by its arrival alone: read it again with its round trip
        if ((msg.type === "pong" || msg.type === "snapshot") && sent !== undefined) this.clockRead(sent, msg.serverTime, arrived);
      }
    };
    ws.onmessage = onMessage;
    if (early?.told !== undefined) this.told = { ws, providerId: early.told }; // what the early socket named on open
    for (const ev of early?.held.splice(0) ?? []) onMessage(ev);
    if (ws.readyState === WebSocket.OPEN) this.sendSelected(ws);
    else ws.onopen = () => this.sendSelected(ws);
    ws.onclose = () => this.dropped(ws);
    ws.onerror = () => ws.close();
    // a ping a second; a socket that leaves one unanswered SILENT_AFTER_MS is dropped at once (its close may wait for
    // a console that answers nothing)
    this.stopWatchdog();
    this.watchdog = setInterval(() => {
      const now = Date.now();
      if (asked !== null && now - asked >= SILENT_AFTER_MS) {
        ws.close();
        this.dropped(ws);
      } else if (ws.readyState === WebSocket.OPEN) {
        const ping: ClientMessage = { type: "ping" };
        ws.send(JSON.stringify(ping));
        pings.push(now);
        asked ??= now;
      }
    }, PING_EVERY_MS);
  }

  /** The socket `ws` is gone (closed, or silent): "reconnecting" (or "offline"), and a new one after the backoff. */
  private dropped(ws: WebSocket): void {
    if (this.ws !== ws || this.stopped) return;
    this.ws = null;
    this.stopWatchdog();
    this.failures += 1;
    this.setState(this.failures >= OFFLINE_AFTER_FAILURES ? "offline" : "reconnecting");
    this.timer = setTimeout(() => this.open(), backoff(this.failures));
  }

  private stopWatchdog(): void {
    if (this.watchdog) clearInterval(this.watchdog);
    this.watchdog = null;
  }
}

export { defaultUrl } from "./early";
