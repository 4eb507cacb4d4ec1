// The rendering model: panels draw on the browser's animation frame from the newest state, never on a timer.
// A change of what a panel draws asks for the next frame; the frame draws whatever is newest then, once. The
// browser runs no animation frame for a hidden page, so nothing draws while it is hidden, and the first frame
// after it shows draws the newest state.
import type { State } from "./state";
import type { StateStore } from "./store";

type Job = () => void;

const due = new Set<Job>(); // the jobs of the next frame, in the order asked
const ran = new Set<Job>(); // the jobs the frame being run has run
const later = new Set<Job>(); // asked for again in the frame that ran them: the next frame's
let requested = false;
let running = false;

function request(): void {
  if (requested) return;
  requested = true;
  if (typeof requestAnimationFrame === "function") requestAnimationFrame(runFrame);
  else setTimeout(runFrame, 0); // no browser (a script, a test without frames)
}

function runFrame(): void {
  requested = false;
  running = true;
  try {
    // a job asked for while the frame runs (the store's flush waking a panel) runs in this frame too, but a
    // job runs at most once a frame: asked again, it waits for the next one
    for (const job of due) {
      due.delete(job);
      if (ran.has(job)) continue;
      ran.add(job);
      job();
    }
  } finally {
    running = false;
    ran.clear();
    for (const job of later) due.add(job);
    later.clear();
    if (due.size) request();
  }
}

/** Run `job` on the next animation frame (once, however often asked before it); `cancel` forgets it. Asked
 * from within a frame, it runs later in that same frame unless it ran in it already. */
export function onFrame(job: Job): void {
  if (running && ran.has(job)) {
    later.add(job); // it ran in this frame: the next one
    return;
  }
  due.add(job);
  if (!running) request();
}

/** Forget a job asked for and not yet run. */
export function cancelFrame(job: Job): void {
  due.delete(job);
  later.delete(job);
}

/** A slice of the state as an external store for useSyncExternalStore, drawn on animation frames: a change of
 * the slice asks for a frame, and the frame takes the newest value (changes between two frames are one draw).
 * `same` says when a new value draws the same as the old one (default: Object.is), e.g. an overview that
 * shows a few fields of every vehicle. `everyMs` > 0: drawn on the first frame at least that long after the
 * last draw (the map's fleet: a software-rendered map cannot redraw every frame), still on a frame, asked for by a
 * timer at the end of the period. */
export function frameSource<T>(
  store: StateStore,
  select: (s: State) => T,
  same: (a: T, b: T) => boolean = Object.is,
  everyMs = 0,
): { subscribe: (onChange: () => void) => () => void; getSnapshot: () => T } {
  let value = select(store.getState());
  let drawnAt = -Infinity;
  return {
    subscribe: (onChange) => {
      value = select(store.getState()); // what changed while nobody listened (useSyncExternalStore renders it)
      let waiting: ReturnType<typeof setTimeout> | undefined; // too soon: the frame after the period is asked for then
      const draw = () => {
        const now = performance.now();
        if (now - drawnAt < everyMs) {
          // not a frame asked for each frame until then (a page kept producing frames for nothing)
          waiting ??= setTimeout(
            () => {
              waiting = undefined;
              onFrame(draw);
            },
            everyMs - (now - drawnAt),
          );
          return;
        }
        const next = select(store.getState());
        const alike = same(value, next);
        value = next; // alike, not drawn now; but a render for another reason (the clock of ages) shows the newest
        if (alike) return;
        drawnAt = now;
        onChange();
      };
      const off = store.subscribe(select, () => onFrame(draw));
      return () => {
        off();
        cancelFrame(draw);
        clearTimeout(waiting);
        waiting = undefined;
      };
    },
    getSnapshot: () => value,
  };
}
