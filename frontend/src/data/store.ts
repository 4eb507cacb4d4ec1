// The dashboard's store: one zustand store holding the state (state.ts, a slice per concern), read by the panels
// through selectors (hooks.ts), and the inbox that applies the data source's messages to it once per frame.
import { subscribeWithSelector } from "zustand/middleware";
import { createStore } from "zustand/vanilla";
import type { ServerMessage } from "../api/types";
import { onFrame } from "./frame";
import { initialState, reduceAll, signedOut, type State } from "./state";

/** The store; `selected`: the vehicle to show first (the page's ?vehicle= link), null for none. Its `subscribe` takes
 * a selector too: the listener hears only of changes of that selector's value (Object.is), so a GPSFixReport does not
 * wake the sky plot. */
export function createStateStore(selected: string | null = null) {
  return createStore<State>()(subscribeWithSelector(() => ({ ...initialState, selected })));
}

export type StateStore = ReturnType<typeof createStateStore>;

/** A local change of the state (select a vehicle, a REST answer merged): `fn` gives the whole next state. */
export function update(store: StateStore, fn: (s: State) => State): void {
  store.setState(fn, true);
}

/** The data source's messages on their way into the store: queued, and applied together on the next animation frame
 * (frame.ts), before the panels they wake draw in that same frame. */
export class Inbox {
  private queue: ServerMessage[] = [];
  private scheduled = false;
  /** The data source's clock (UTC seconds): when each batch of messages is applied. */
  clock: () => number = () => Date.now() / 1000;

  constructor(readonly store: StateStore) {
    // hidden with a frame asked for: the browser runs no frames, so the queue is applied on the timer instead
    if (typeof document !== "undefined" && typeof document.addEventListener === "function")
      document.addEventListener("visibilitychange", () => document.hidden && this.scheduled && setTimeout(this.flushJob, 50));
  }

  /** Queue a server message; queued messages are applied together on the next frame. */
  enqueue(msg: ServerMessage): void {
    this.queue.push(msg);
    if (this.scheduled) return;
    this.scheduled = true;
    // a hidden page has no frames, and its state stays current for the tab's title and the alarm tone
    if (typeof requestAnimationFrame === "function" && typeof document !== "undefined" && !document.hidden)
      onFrame(this.flushJob);
    else setTimeout(this.flushJob, 50);
  }

  /** Forget everything the console sent (on sign-out when reads need a token); the operator's
   * selection and what /api/health said stay. */
  clear(): void {
    this.queue = [];
    update(this.store, signedOut);
  }

  /** Drop the messages not yet applied (a replay's new instant: they were from before it). */
  discardQueued(): void {
    this.queue = [];
  }

  private flushJob = (): void => this.flush();

  /** Apply the queued messages now. */
  flush(): void {
    this.scheduled = false;
    if (!this.queue.length) return;
    const queued = this.queue;
    this.queue = [];
    update(this.store, (s) => reduceAll(s, queued, this.clock()));
  }
}
