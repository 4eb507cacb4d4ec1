// The words of alarm management on a watch (shelving, planned silence, floods, chattering), in one place: the
// dashboard says them from here only. The alarms' own text and causes come from the console (console/alarms.py).
import { utc } from "./units";

/** HH:MM of UTC seconds, as the watch says a time ("until 14:20"), with the date when it is not today's (UTC). */
export function clockTime(t: number, now = Date.now() / 1000): string {
  const hhmm = utc(t, false).slice(0, 5);
  const day = (s: number) => new Date(s * 1000).toISOString().slice(0, 10);
  return day(t) === day(now) ? hhmm : `${day(t)} ${hhmm}`;
}

export const SHELVED_COUNT = (n: number): string => `${n} shelved`;
export const SHELVED_LIST = "Shelved alarms";
export const SHELVE = "Shelve";
export const SHELVE_REASON = "Why shelve it";
export const SHELVE_FOR = "For";
export const SHELVE_CONFIRM = "Shelve alarm";
export const UNSHELVE = "Unshelve";
export const CANCEL = "Cancel";
export const SHELVED_BY = (by: string | null, station: string | null, until: number, reason: string): string =>
  `shelved${by ? ` by ${by}` : ""}${station ? ` on ${station}` : ""} until ${clockTime(until)} UTC: ${reason}`;
/** The shelving times offered (minutes); the console refuses one outside its bounds (15 min to 8 h by default). */
export const SHELVE_MINUTES: readonly { minutes: number; text: string }[] = [
  { minutes: 15, text: "15 min" },
  { minutes: 30, text: "30 min" },
  { minutes: 60, text: "1 h" },
  { minutes: 120, text: "2 h" },
  { minutes: 240, text: "4 h" },
  { minutes: 480, text: "8 h" },
];
export const CHATTERING = "Chattering";
export const CHATTERING_TITLE = "it cleared and came back again and again: it is not sounded again until acknowledged";

/** A flood: many alarms of one cause at once, shown as one group ("Link lost: 20 vehicles"). */
export const FLOOD_AT = 5;
export const GROUP_WORDS = (cause: string, n: number): string => `${cause}: ${n} ${n === 1 ? "vehicle" : "vehicles"}`;
export const GROUP_SHOW = "Show each";
export const GROUP_HIDE = "Hide each";

export const SILENCE_WORD = (until: number): string => `Out of comms (planned) until ${clockTime(until)}`;
export const SILENCE_TITLE = (reason: string, by: string | null): string =>
  `planned silence${by ? ` declared by ${by}` : ""}: ${reason}; a loss raises no alarm until then and the console's grace after it`;
export const SILENCE_COUNT = (n: number): string => `${n} out of comms (planned)`;
export const SILENCES_TITLE = "Planned silences";
export const SILENCE_FORM = "Out of comms until";
export const SILENCE_UNTIL = "Until (UTC)";
export const SILENCE_REASON = "Why (diving, over the horizon, a relay down)";
export const SILENCE_DECLARE = "Declare planned silence";
export const SILENCE_CANCEL = "Cancel silence";
export const SILENCE_ENTRY = (vehicle: string, until: number, reason: string, by: string | null): string =>
  `${vehicle}: out of comms (planned) until ${clockTime(until)} UTC: ${reason}${by ? ` (declared by ${by})` : ""}`;
export const SILENCE_PICK = "Select a vehicle to declare its planned silence.";
