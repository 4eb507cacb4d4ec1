// Freshness: a value is stale once its topic has been silent for longer than its expected
// interval allows, and lost when the backend says the provider is lost. Displays never show
// a stale value as if it were live.
import type { LinkState, Topic } from "../api/types";

/** The longest a topic may be silent before its values are stale, in seconds. */
export function staleAfter(topic: Topic, observedInterval: number | null): number {
  const floor = topic === "GPSReport" ? 3 : 1.5; // GPSReport comes at 1 Hz, the others faster
  if (observedInterval === null || !Number.isFinite(observedInterval)) return floor;
  return Math.max(floor, 3 * observedInterval);
}

export type Freshness = "live" | "stale" | "lost" | "none";

export function freshness(ageSeconds: number | null, topic: Topic, observedInterval: number | null, link: LinkState | null): Freshness {
  if (ageSeconds === null) return "none";
  if (link === "lost") return "lost";
  return ageSeconds > staleAfter(topic, observedInterval) ? "stale" : "live";
}

/** What a replay's link and freshness badges say beside their words: the recording's state at the instant shown. */
export const RECORDED_TITLE = "the recording's state at the instant shown, not the vehicle now";

/** A vehicle's link or freshness in words. In a replay (`recorded`) it is what the recording said, never worded as
 * the vehicle now: "Recorded: live", not "Live" (the words, not only a colour, for a screen reader too). */
export function stateWords(words: string, recorded: boolean): string {
  return recorded ? `Recorded: ${words.toLowerCase()}` : words;
}

/** Exponentially weighted mean of inter-arrival times, ignoring gaps (a gap is not the rate). */
export function nextInterval(previous: number | null, gap: number): number | null {
  if (!(gap > 0) || !Number.isFinite(gap)) return previous;
  if (previous === null) return gap;
  if (gap > 5 * previous) return previous;
  return previous * 0.8 + gap * 0.2;
}
