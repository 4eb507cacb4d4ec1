// The CoMap slice: the console's world model and its tasks, from the WebSocket's `worldmodel` and `task` messages
// after one REST load per connection.
import type { FeatureCollection } from "geojson";
import type { Task } from "../../api/rest";

export interface ComapState {
  // the world model (null: none known; a console without CoMap answers 404) and the tasks by id
  worldModel: FeatureCollection | null;
  worldModelSeq: number; // `worldmodel` messages received: a REST answer older than one of them is dropped
  tasks: Record<number, Task>;
  taskSeq: number; // `task` messages received
  taskMessageSeq: Record<number, number>; // each task's last `task` message (its taskSeq then)
}

export const initialComap: ComapState = { worldModel: null, worldModelSeq: 0, tasks: {}, taskSeq: 0, taskMessageSeq: {} };

/** A `task` message: merged by id (tasksLoaded), its taskSeq kept so that an older REST answer does not undo it. */
export function taskReceived<S extends ComapState>(state: S, t: Task): S {
  const taskSeq = state.taskSeq + 1;
  return { ...tasksLoaded(state, [t]), taskSeq, taskMessageSeq: { ...state.taskMessageSeq, [t.taskId]: taskSeq } };
}

/** The world model as GET /api/worldmodel gave it, asked when `worldModelSeq` was `seq`: dropped if a
 * `worldmodel` message came since (it is newer). */
export function worldModelLoaded<S extends ComapState>(state: S, model: FeatureCollection | null, seq: number): S {
  return state.worldModelSeq !== seq || state.worldModel === model ? state : { ...state, worldModel: model };
}

/** A CoMap task's states that end it (the console's comap.c2.FINAL). */
export const FINISHED = new Set(["REJECTED", "COMPLETED", "ERROR", "INTERRUPTED"]);

/** Whether a task's `state`, decided at `at`, replaces its `other` decided at `otherAt`: the console's rule
 * (comap.c2.decided_over): the one decided later, except that a finished task is never made unfinished again, and of
 * two finished states the first stands. */
export function decidedOver(state: string, at: number, other: string, otherAt: number): boolean {
  if (FINISHED.has(state)) return !FINISHED.has(other) || at < otherAt;
  return !FINISHED.has(other) && at > otherAt;
}

/** Tasks (GET /api/tasks or a `task` message) merged by id, as the consoles merge them: state and synch from the copy
 * decided over the other (`decidedOver`, by stateAt), progress and quality from the copy with the newer progress
 * (updatedAt). A GET answered before a HOLD but read after its `task` message does not undo the HOLD (a synch moves
 * stateAt only), and a task its vehicle finished stays finished. */
export function tasksLoaded<S extends ComapState>(state: S, tasks: Task[]): S {
  let next: Record<number, Task> | null = null;
  for (const t of tasks) {
    const old = (next ?? state.tasks)[t.taskId];
    let merged = t;
    if (old && old.createdAt === t.createdAt) {
      const decided = decidedOver(t.state, t.stateAt, old.state, old.stateAt);
      const progressed = t.updatedAt > old.updatedAt;
      if (!decided && !progressed) continue; // nothing newer
      if (!decided) merged = { ...merged, state: old.state, synch: old.synch, stateAt: old.stateAt };
      if (!progressed) merged = { ...merged, progress: old.progress, quality: old.quality, updatedAt: old.updatedAt };
    } else if (old && old.createdAt > t.createdAt) continue; // a finished task of that id, which this one replaced
    next = { ...(next ?? state.tasks), [t.taskId]: merged };
  }
  return next ? { ...state, tasks: next } : state;
}

/** The tasks as GET /api/tasks gave them, asked when `taskSeq` was `seq`: the console's list is what exists
 * (a task of a console since restarted goes), except a task whose `task` message came after the request
 * (kept, merged by updatedAt). */
export function tasksReplaced<S extends ComapState>(state: S, tasks: Task[], seq: number): S {
  const kept: Record<number, Task> = {};
  for (const [id, t] of Object.entries(state.tasks)) if ((state.taskMessageSeq[Number(id)] ?? 0) > seq) kept[Number(id)] = t;
  return tasksLoaded({ ...state, tasks: kept }, tasks);
}
