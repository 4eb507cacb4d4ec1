// The replay data source (sem-console --replay): the same WebSocket as the live source for the data,
// plus the playback. Its clock is the recording's time at the position shown, so ages, freshness,
// trails and charts are those of the recording, and stand still while paused.
import { controlReplay, type ReplayRequest } from "../api/rest";
import type { ReplayStatus, ServerMessage } from "../api/types";
import { getToken } from "./auth";
import { Connection } from "./connection";
import { REPLAY, type Capabilities, type PlaybackControls } from "./source";
import { withPace } from "./slices/vehicles";
import { forNewInstant } from "./state";
import { update } from "./store";

export class ReplaySource extends Connection {
  override readonly kind = "replay" as const;
  override readonly capabilities: Capabilities = REPLAY;
  override readonly playback: PlaybackControls = {
    play: () => this.control({ action: "play" }),
    pause: () => this.control({ action: "pause" }),
    seek: (position: number) => this.control({ action: "seek", position }),
    setSpeed: (speed: number) => this.control({ action: "speed", speed }),
  };
  private status: ReplayStatus | null = null;
  private statusAt = 0; // wall-clock seconds when `status` arrived

  override getPlayback = (): ReplayStatus | null => this.status;

  /** The position shown: the last one the console sent, moved on by the time since at the speed while playing. */
  override now = (): number => {
    const s = this.status;
    if (!s) return Date.now() / 1000;
    if (s.state !== "playing") return s.position;
    return Math.min(s.end, s.position + (Date.now() / 1000 - this.statusAt) * s.speed);
  };

  /** The recording's clock is its console's: the instant shown. */
  override consoleNow = (): number => this.now();

  protected override receive(msg: ServerMessage): void {
    if (msg.type === "replay") {
      this.setStatus(msg.replay);
      return;
    }
    if (msg.type === "snapshot" && msg.replay) {
      // a seek (or a reconnect): the state of another instant, so trails, charts and alerts start again from it;
      // reports still queued for the next frame are from before it (a hidden tab applies them only every second)
      this.setStatus(msg.replay);
      this.inbox.discardQueued();
      update(this.inbox.store, forNewInstant);
    }
    super.receive(msg);
  }

  /** A replay's pong says the console's wall time, and the page's clock is the recording's, as the snapshot's
   * `serverTime` is: the console's clock against the page's stays the snapshot's (both the recording's). */
  protected override clockRead(): void {}

  private setStatus(s: ReplayStatus): void {
    this.status = s;
    this.statusAt = Date.now() / 1000;
    // the console paces the vehicles the page does not draw by wall time; the page's clock runs at the speed
    update(this.inbox.store, (st) => withPace(st, st.paceWall, s.speed));
    this.notify();
  }

  private async control(request: ReplayRequest): Promise<void> {
    this.setStatus(await controlReplay(request, getToken()));
  }
}
