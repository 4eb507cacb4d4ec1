// The dashboard's data sources, after Foxglove Studio's Player: the live console (connection.ts) and a
// replay of a recording (replay.ts) behind one interface. Panels never see which one they read: they
// read state through the hooks, and what the source can do through its capabilities.
import type { ReplayStatus } from "../api/types";

/** connecting → live; a dropped socket: reconnecting, then offline after repeated failures (still retrying);
 * signed-out: stopped because reads need a token and there is none (the store holds no vehicle data then). */
export type SourceState = "connecting" | "live" | "reconnecting" | "offline" | "signed-out";
/** The console cannot be reached: the connection was lost and is being tried again, or the browser is offline. */
export const unreachable = (state: SourceState): boolean => state === "reconnecting" || state === "offline";

export interface Capabilities {
  command: boolean; // commands and cancels can be sent
  record: boolean; // the console can record to MCAP
  playback: boolean; // play, pause, speed and seek (a replay)
}

export interface PlaybackControls {
  play(): Promise<void>;
  pause(): Promise<void>;
  /** UTC seconds within the recording: the state at that instant is rebuilt. */
  seek(position: number): Promise<void>;
  /** 0.25 to 20. */
  setSpeed(speed: number): Promise<void>;
}

export interface DataSource {
  readonly kind: "live" | "replay";
  readonly capabilities: Capabilities;
  /** Present exactly when capabilities.playback. */
  readonly playback: PlaybackControls | null;
  /** Listeners hear of changes of the state and of the playback. */
  subscribe(listener: () => void): () => void;
  getState(): SourceState;
  /** The playback (a replay), the same object until it changes; null for a live source. */
  getPlayback(): ReplayStatus | null;
  /** The source's time in UTC seconds: the wall clock live, the instant shown in a replay. Ages and freshness use it. */
  now(): number;
  /** The console's clock in UTC seconds: live, the page's moved by how far the console's is ahead (read at each ping,
   * `consoleAhead`); in a replay, the instant shown. The ages of what the console stamped (an alarm's since, a
   * command's start, a recording's) and the header's clock use it: a page on a clock minutes off says "2 s ago" of an
   * alarm raised 2 s ago, not of one raised minutes ago. */
  consoleNow(): number;
  start(): void;
  stop(): void;
  /** Connect afresh at once (e.g. with a new token). */
  restart(): void;
}

export const LIVE: Capabilities = { command: true, record: true, playback: false };
export const REPLAY: Capabilities = { command: false, record: false, playback: true };
export const SPEEDS: readonly number[] = [0.25, 0.5, 1, 2, 5, 10, 20];
