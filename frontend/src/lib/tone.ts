// The audible alarm: a short beep generated with the Web Audio API (an oscillator, no sound file) for
// each new unacknowledged alarm, and the operator's mute. Audio is a help, never a requirement: where it
// is unavailable or not yet allowed, nothing throws and the screen still shows the alarm.
import type { Alarm } from "../api/generated/ws";
import { utc } from "./units";
import { ALARM_SEVERITY, floodText } from "./labels";

let context: AudioContext | null = null;
let unlocked = false; // a gesture let the page play sound (browsers then let it resume its context at any time)
let rest: ReturnType<typeof setTimeout> | null = null;
/** How long after its last tone the context is suspended: a running context renders silence on its audio thread all
 * the time (about 1.4 % of a core, measured in Chromium), waking an idle laptop at sea as often. */
const REST_MS = 2000;
const WAKE_S = 0.1;

function restSoon(c: AudioContext): void {
  if (rest !== null) clearTimeout(rest);
  rest = setTimeout(() => {
    rest = null;
    try {
      c.suspend().catch(() => undefined);
    } catch {
      /* no suspend: it keeps running, as it did */
    }
  }, REST_MS);
}

function audioContext(): AudioContext | null {
  if (context) return context;
  try {
    const Ctor = typeof window !== "undefined" ? window.AudioContext : undefined;
    if (!Ctor) return null;
    context = new Ctor();
  } catch {
    return null; // no audio device, or audio disabled
  }
  return context;
}

/** Browsers start audio only after a user gesture: the context is created (or resumed) on the first click
 * or key press of the page, and the listeners go once it runs. Returns the removal of the listeners. */
export function unlockAudioOnGesture(): () => void {
  const events = ["pointerdown", "keydown"] as const;
  const remove = () => events.forEach((e) => window.removeEventListener(e, unlock, true));
  function unlock() {
    const c = audioContext();
    if (!c) return remove();
    const allowed = () => {
      unlocked = true;
      remove();
      restSoon(c); // no tone yet: it rests until one sounds
    };
    if (c.state === "running") return allowed();
    c.resume().then(allowed, () => undefined); // refused: the next gesture tries again
  }
  events.forEach((e) => window.addEventListener(e, unlock, true));
  return remove;
}

/** Two short falling tones (880 then 660 Hz), about half a second: heard over a room, not startling. */
export function beep(): void {
  const c = context;
  if (!c || !unlocked) return; // no gesture yet: the screen alone tells
  if (rest !== null) clearTimeout(rest);
  rest = null;
  // resting since the last tone, or about to (a suspend under way still reads "running"): resumed first, whatever it
  // says; a device woken from rest may drop its first 0.1 s or so, so a tone after a rest starts that much later
  const lead = c.state === "running" ? 0 : WAKE_S;
  try {
    c.resume().then(
      () => play(c, lead),
      () => undefined,
    );
  } catch {
    /* audio failed: the alarm is on screen all the same */
  }
}

function play(c: AudioContext, lead: number): void {
  try {
    const t0 = c.currentTime + (lead > 0 ? Math.max(lead, c.outputLatency || 0) : 0); // after a rest: its latency at least
    for (const [start, freq] of [
      [0, 880],
      [0.25, 660],
    ]) {
      const osc = c.createOscillator();
      const gain = c.createGain();
      osc.type = "sine";
      osc.frequency.value = freq;
      gain.gain.setValueAtTime(0.0001, t0 + start);
      gain.gain.exponentialRampToValueAtTime(0.25, t0 + start + 0.02);
      gain.gain.exponentialRampToValueAtTime(0.0001, t0 + start + 0.2);
      osc.connect(gain).connect(c.destination);
      osc.start(t0 + start);
      osc.stop(t0 + start + 0.22);
    }
  } catch {
    /* audio failed: the alarm is on screen all the same */
  }
  restSoon(c);
}

/** Which alarms are new to this page: an unacknowledged alarm it has not seen raised before, by its id and since (a
 * condition back before it was acknowledged, e.g. a vehicle lost, back and lost again, keeps its id and is raised
 * anew with a new since: it sounds again). The first set it is given (the page's first snapshot) is taken as seen:
 * those alarms are on screen when the page opens. An alarm seen once does not sound again (cleared, acknowledged,
 * or after a reconnect). */
export class NewAlarms {
  private seen: Set<string> | null = null;

  /** The alarms of `alarms` new since the last call (none on the first call). A shelved alarm is not new (out of view)
   * and sounds when it comes back (`returned`); a chattering one does not sound again until acknowledged. */
  take(alarms: readonly Alarm[]): Alarm[] {
    const first = this.seen === null;
    const seen = (this.seen ??= new Set());
    const raised = (a: Alarm) => `${a.id}@${a.since}@${a.returned ?? ""}`;
    const fresh = alarms.filter((a) => !seen.has(raised(a)) && a.state !== "active-acknowledged" && !a.shelf && !a.chattering);
    for (const a of alarms) seen.add(raised(a));
    return first ? [] : fresh;
  }
}

/** New alarms in words for the live region: each named, but a burst (a fleet of 250 lost at once) in one sentence
 * with its newest few named first, or the screen reader would read on for minutes and hide whatever comes next. */
export const SAID_AT_MOST = 3;
export function alarmWords(fresh: readonly Alarm[]): string {
  const one = (a: Alarm) => `${ALARM_SEVERITY[a.severity]}: ${a.text}, since ${utc(a.since, false, "s")}`;
  if (fresh.length <= SAID_AT_MOST) return fresh.map(one).join(". ");
  // a flood of one cause (a relay down: 20 vehicles lost) is one sentence naming the cause and the count
  const causes = new Set(fresh.map((a) => a.cause));
  const [cause] = causes;
  if (causes.size === 1 && cause !== undefined) {
    const severity = ALARM_SEVERITY[fresh.some((a) => a.severity === "alarm") ? "alarm" : "warning"];
    return `${severity}: ${floodText(cause, fresh)}: see the alarm list`;
  }
  const newest = [...fresh].sort((a, b) => b.since - a.since || b.id - a.id);
  return `${newest
    .slice(0, SAID_AT_MOST - 1)
    .map(one)
    .join(". ")}. And ${fresh.length - (SAID_AT_MOST - 1)} more new alarms: see the alarm list`;
}

/** One tone and one announcement for a burst of new alarms (a flood comes over a second or two, in several `alarms`
 * messages): the tone at the burst's first alarm, the words once it has been quiet for `quietMs` (or `longestMs` after
 * its start), naming every alarm of the burst. */
export class Burst {
  private fresh: Alarm[] = [];
  private started = 0;
  private timer: ReturnType<typeof setTimeout> | null = null;

  constructor(
    private readonly say: (words: string) => void,
    private readonly quietMs = 1000,
    private readonly longestMs = 3000,
  ) {}

  /** New alarms: true when they start a burst (sound the tone). */
  add(fresh: readonly Alarm[], now = Date.now()): boolean {
    if (!fresh.length) return false;
    const first = this.timer === null;
    if (first) this.started = now;
    this.fresh.push(...fresh);
    if (this.timer !== null) clearTimeout(this.timer);
    this.timer = setTimeout(() => this.flush(), Math.max(0, Math.min(this.quietMs, this.started + this.longestMs - now)));
    return first;
  }

  flush(): void {
    if (this.timer !== null) clearTimeout(this.timer);
    this.timer = null;
    const fresh = this.fresh;
    this.fresh = [];
    if (fresh.length) this.say(alarmWords(fresh));
  }

  stop(): void {
    if (this.timer !== null) clearTimeout(this.timer);
    this.timer = null;
    this.fresh = [];
  }
}
