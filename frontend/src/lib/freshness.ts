// Freshness: a value is stale once its topic has been silent for longer than its expected
// interval allows, lost when the backend says the provider is lost, and "unreachable" at once when the
// page no longer hears the console (nothing it shows is current then, however recent). Displays never
// show a stale value as if it were live.
import type { LinkState, Topic } from "../api/types";
import { inline, linkText } from "./labels";

/** A live vehicle silent this long is shown "stale" before the console calls it lost (the fleet bar, the vehicle list);
 * one the console paces, this and its pace, on the map too: its report may have waited a pace at the console, and
 * came up to a second before that (at 1 Hz). */
export const STALE_AFTER_S = 3;

/** The longest a topic may be silent before its values are stale, in seconds. */
export function staleAfter(topic: Topic, observedInterval: number | null): number {
  const floor = topic === "GPSReport" ? 3 : 1.5; // GPSReport comes at 1 Hz, the others faster
  if (observedInterval === null || !Number.isFinite(observedInterval)) return floor;
  return Math.max(floor, 3 * observedInterval);
}

export type Freshness = "live" | "stale" | "lost" | "none" | "unreachable";

/** `receiving`: the page hears the console (its data source is connected); false: "unreachable", whatever the age.
 * `paceS`: the console sends this vehicle's reports at most this often (a vehicle the page does not draw, `paceOf`):
 * stale only once silent over STALE_AFTER_S and its pace, as the fleet bar says (`staleTitle`; its observed interval is
 * the pace's, not its own). */
export function freshness(
  ageSeconds: number | null,
  topic: Topic,
  observedInterval: number | null,
  link: LinkState | null,
  receiving: boolean,
  paceS = 0,
): Freshness {
  if (ageSeconds === null) return "none";
  if (link === "lost") return "lost"; // a lost vehicle stays lost when the page cannot hear the console, as `pageLink`
  if (!receiving) return "unreachable";
  const bound = paceS > 0 ? STALE_AFTER_S + paceS : staleAfter(topic, observedInterval);
  return ageSeconds > bound ? "stale" : "live";
}

/** What "stale" means in the fleet bar and the vehicle list: silent over `staleAfterS`, and over that beyond its pace
 * for a vehicle the console paces (`othersEvery`, null: none). */
export function staleTitle(staleAfterS: number, othersEvery: number | null): string {
  const base = `no report for over ${staleAfterS} s`;
  if (othersEvery === null) return base;
  const paced = Math.round((staleAfterS + othersEvery) * 10) / 10;
  return `${base} (over ${paced} s for a vehicle not selected: the console sends each of them every ${othersEvery} s)`;
}

/** Data shown but not current (greyed): stale, of a lost vehicle, or with the console unreachable. */
export const notCurrent = (f: Freshness): boolean => f === "stale" || f === "lost" || f === "unreachable";

/** A vehicle's link as the page can vouch for it: the console's (`link`), "stale" for a live or regained vehicle
 * silent longer than `staleAfterS` (as its panels' `freshness`), "unreachable" whenever the page does not hear the
 * console (a lost one stays lost: the worse of what it may be now). The fleet bar, the vehicle list and the map say it. */
export type PageLink = LinkState | "stale" | "unreachable";

/** The one state the fleet bar counts a vehicle in and the vehicle list's state filter matches it by: "live" for a
 * live or regained link, "planned" for one lost in its planned silence (expected, not counted lost). */
export type FleetState = "live" | "stale" | "unchecked" | "unreachable" | "lost" | "planned";
export function fleetState(link: PageLink, inPlannedSilence: boolean): FleetState {
  if (link === "regained") return "live";
  if (link === "lost" && inPlannedSilence) return "planned";
  return link;
}
export function pageLink(link: LinkState, silentS: number | null, staleAfterS: number, receiving: boolean): PageLink {
  if (!receiving && link !== "lost") return "unreachable";
  return (link === "live" || link === "regained") && silentS !== null && silentS > staleAfterS ? "stale" : link;
}

/** A freshness in words ("Live", "Not updating"); `recorded`: a replay's (`recordedState`, `stateWords`). */
export function freshnessText(f: Exclude<Freshness, "none">, recorded: boolean): string {
  return stateWords(linkText(f), recordedState(f, recorded));
}

/** What a replay's link and freshness badges say beside their words: the recording's state at the instant shown. */
export const RECORDED_TITLE = "the recording's state at the instant shown, not the vehicle now";

/** Whether a replay's (`recorded`) link or freshness is the recording's: every one but "unreachable", the page's own
 * state now (it does not hear the console that replays), which no recording said. */
export function recordedState(link: PageLink | FleetState | Exclude<Freshness, "none">, recorded: boolean): boolean {
  return recorded && link !== "unreachable";
}

/** A vehicle's link or freshness in words. In a replay (`recorded`) it is what the recording said, never worded as
 * the vehicle now: "Recorded: live", not "Live" (the words, not only a colour, for a screen reader too). */
export function stateWords(words: string, recorded: boolean): string {
  return recorded ? `Recorded: ${inline(words)}` : words;
}

/** Exponentially weighted mean of inter-arrival times, ignoring gaps (a gap is not the rate). */
export function nextInterval(previous: number | null, gap: number): number | null {
  if (!(gap > 0) || !Number.isFinite(gap)) return previous;
  if (previous === null) return gap;
  if (gap > 5 * previous) return previous;
  return previous * 0.8 + gap * 0.2;
}
