// The fleet bar: every vehicle's link, fix and INS state and the counts of live and lost vehicles and of
// unacknowledged alarms, held at the top of the page, so whatever the operator has scrolled to, a lost
// vehicle or a new alarm is in view. It also carries the page's alarm annunciation (the tab title and
// the tone, with its mute), and says why the vehicle panels are empty when none is selected.
import { memo, useEffect, useMemo, useRef, useState, type KeyboardEvent } from "react";
import type { Alarm } from "../../api/generated/ws";
import {
  useAlarms,
  useCapabilities,
  useCommanded,
  useConnectionState,
  useNow,
  useOthersEvery,
  usePaceOf,
  useProvidersOnFrame,
  useReceiving,
  sameOverview,
  useSelector,
  useSilences,
  useSelectVehicle,
} from "../../data/hooks";
import { useConsoleHealth } from "../../data/loaders";
import { useCollapsed, useSetting } from "../../data/settings";
import { FLOOD_AT, inView, pageTitle, plannedUntil, shelved, unacknowledged } from "../../data/slices/alarms";
import { lastHeardAt, report, type ProviderView } from "../../data/slices/vehicles";
import type { GPSFixStatusReportType, InertialSensorReportType } from "../../api/types";
import {
  RECORDED_TITLE,
  STALE_AFTER_S,
  fleetState,
  pageLink,
  recordedState,
  staleTitle,
  stateWords,
  type FleetState,
  type PageLink,
} from "../../lib/freshness";
import {
  ALARM_SEVERITY,
  FLEET_STATE,
  fixWord,
  floodText,
  inline,
  insWord,
  linkText,
  plannedCount,
  plannedText,
  plannedTitle,
  shelvedCount,
  type UmaaVersion,
  type Word,
} from "../../lib/labels";
import { RelayHop } from "../../components/RelayHop";
import { LastHeard } from "../../components/LastHeard";
import { Burst, NewAlarms, beep, unlockAudioOnGesture } from "../../lib/tone";
import { shortId, vehicleColor } from "../../lib/vehicle";
import { clockTime } from "../../lib/units";
import "../fleet.css";
import { unreachable as isUnreachable } from "../../data/source";

/** The bar shows every vehicle, and any of them reports many times a second: it draws (on the frame) only when
 * what it shows of one changed, ages to the second. */
const SAME_BAR = sameOverview();
/** How long a live vehicle may be silent before it is "stale": STALE_AFTER_S, and seen through a relay, the longest
 * that relay's rate caps keep its data quiet (the console adds it to its comms-lost timeout too: at the satellite caps
 * a fix comes every 5 s, and such a vehicle was "stale" two seconds in every five). */
export const staleAfterOf = (p: ProviderView): number => STALE_AFTER_S + p.relayQuiet;

export type FleetLink = PageLink;

/** The vehicle's link as the page can vouch for it (`pageLink`): "stale" for a live vehicle silent a few seconds (and
 * its pace, `paceS`, for one the console sends at the others' pace: `paceOf`), "unreachable" at once when the page does
 * not hear the console. */
export function fleetLink(p: ProviderView, now: number, receiving: boolean, paceS = 0): FleetLink {
  const seen = lastHeardAt(p);
  return pageLink(p.link, seen === null ? null : now - seen, staleAfterOf(p) + paceS, receiving);
}

/** At most this many chips (and the selected vehicle's): a fleet of a thousand is counted, its exceptional vehicles
 * shown first, and the rest found in the vehicle list. */
export const CHIP_LIMIT = 24;

/** The chips the bar draws, in order: the lost vehicles, then those with an unacknowledged alarm, then those with a
 * command in progress, then the rest, at most `limit` of them, and the selected vehicle's chip whatever its place. */
export function fleetChips<C extends { p: { id: string } }>(
  all: readonly C[],
  ex: { lost: readonly C[]; alarmed: ReadonlyMap<string, number>; commanded: ReadonlySet<string>; selected: string | null },
  limit = CHIP_LIMIT,
): C[] {
  const lost = new Set(ex.lost);
  const alarmed = all.filter((c) => !lost.has(c) && ex.alarmed.has(c.p.id));
  const first = new Set([...ex.lost, ...alarmed]);
  const commanded = all.filter((c) => !first.has(c) && ex.commanded.has(c.p.id));
  for (const c of commanded) first.add(c);
  const ordered = first.size ? [...ex.lost, ...alarmed, ...commanded, ...all.filter((c) => !first.has(c))] : [...all];
  const shown = ordered.slice(0, limit);
  const chosen = ordered.find((c, i) => i >= limit && c.p.id === ex.selected);
  return chosen ? [...shown, chosen] : shown;
}

/** The names a count's tooltip lists: a few, then how many more (a thousand lost is not a readable tooltip). */
function namesTitle(names: readonly string[], most = 20): string | undefined {
  if (!names.length) return undefined;
  const said = names.slice(0, most).join(", ");
  return names.length > most ? `${said} and ${names.length - most} more` : said;
}

/** The vehicle list's search, scrolled into view with the focus in it: where the vehicles the bar has no chip for are
 * found. */
function showVehicleList() {
  const find = document.querySelector<HTMLElement>('[data-testid="find-vehicle"]');
  (find ?? document.querySelector<HTMLElement>('[data-testid="vehicles"]'))?.scrollIntoView({ block: "nearest" });
  find?.focus({ preventScroll: true });
}

const UNREACHABLE_TITLE = "the console cannot be reached: the last state it sent, not updating";
const LINK: Record<FleetLink, Word> = {
  live: { text: linkText("live"), tone: "ok", title: "reports arriving" },
  regained: { text: linkText("regained"), tone: "info", title: "back after a loss, not yet steady" },
  stale: { text: linkText("stale"), tone: "warn", title: staleTitle(STALE_AFTER_S, null) },
  lost: { text: linkText("lost"), tone: "bad", title: "no report within the link timeout" },
  unchecked: {
    text: linkText("unchecked"),
    tone: "muted",
    title: "silent while this console is behind, no longer than its own delay may explain: not judged (nor blamed)",
  },
  unreachable: { text: linkText("unreachable"), tone: "muted", title: UNREACHABLE_TITLE },
};

type FixValid = GPSFixStatusReportType["fixValid"] | undefined; // undefined: no report yet
type InsState = InertialSensorReportType["state"] | undefined;
type InsStatus = InertialSensorReportType["status"] | undefined;

function name(p: { id: string; name: string | null }): string {
  return p.name ?? shortId(p.id);
}

// primitives only, so the memo below compares them by value
interface ChipProps {
  id: string;
  label: string;
  link: FleetLink;
  fixValid: FixValid;
  insState: InsState;
  insStatus: InsStatus;
  umaaVersion: UmaaVersion | null; // what its reports can say (a 6.0 vehicle has no GPS fix status)
  alarms: number;
  heardAt: number | null | undefined; // a lost vehicle's last-heard time (null: never heard); undefined: not lost
  silence: { until: number; title: string } | null; // a planned silence ("out of comms until")
  until: number | null; // lost in its planned silence: when it ends (plannedUntil)
  staleAfterS: number; // silent this long, it is stale (STALE_AFTER_S, its relay's quiet and its pace)
  recorded: boolean; // a replay: the link is the recording's
  relayed: boolean; // seen through a sem-relay (RelayHop says which, and how old its data is)
  selected: boolean;
  tabbable: boolean; // the bar's one Tab stop (the selected chip, else the first); the arrow keys go through the rest
  onSelect: (id: string) => void;
}

// Redrawn only when what it shows changes: most chips stay as they are at each of the bar's redraws.
const Chip = memo(function Chip({
  id,
  label,
  link,
  fixValid,
  insState,
  insStatus,
  umaaVersion,
  alarms,
  heardAt,
  silence,
  until,
  staleAfterS,
  recorded,
  relayed,
  selected,
  tabbable,
  onSelect,
}: ChipProps) {
  // a vehicle lost during its planned silence: expected, said so rather than "Lost"
  const planned = until !== null;
  const l: Word = planned
    ? { text: plannedText(until), tone: "info", title: silence?.title }
    : link === "stale"
      ? { ...LINK.stale, title: staleTitle(staleAfterS, null) }
      : LINK[link];
  const rec = recordedState(link, recorded); // "not updating" is the page's now, in a replay too
  const fix = fixWord(fixValid, umaaVersion);
  const ins = insWord(insState, insStatus, umaaVersion);
  const old = link === "lost" || link === "unreachable" ? " (last known)" : "";
  return (
    <button
      className={`fleet-chip fleet-${l.tone}${selected ? " selected" : ""}`}
      data-testid="fleet-vehicle"
      data-link={link}
      data-vehicle={id}
      aria-pressed={selected}
      tabIndex={tabbable ? 0 : -1}
      title={id}
      onClick={() => onSelect(id)}
    >
      <span className="fleet-name">
        <span className="vehicle-mark" style={{ background: vehicleColor(id) }} aria-hidden="true" />
        {label}
      </span>
      <span
        className={`fleet-word tone-${l.tone}${planned ? " fleet-planned" : ""}${rec ? " recorded" : ""}`}
        title={rec ? [l.title, RECORDED_TITLE].filter(Boolean).join(": ") : l.title}
        data-testid="fleet-link"
      >
        {stateWords(l.text, rec)}
      </span>
      {heardAt !== undefined && <LastHeard since={heardAt} className="fleet-word tone-bad" />}
      {relayed && <RelayHop id={id} className="fleet-word" />}
      <span className={`fleet-word tone-${fix.tone}${old ? " fleet-old" : ""}`} title={(fix.title ?? "") + old}>
        {fix.text}
      </span>
      <span className={`fleet-word tone-${ins.tone}${old ? " fleet-old" : ""}`} title={(ins.title ?? "") + old}>
        {ins.text}
      </span>
      {silence && link !== "lost" && (
        <span className="fleet-word fleet-planned" title={silence.title} data-testid="fleet-silence">
          {plannedText(silence.until)}
        </span>
      )}
      {alarms > 0 && <span className="fleet-word tone-bad">{alarms === 1 ? "1 alarm" : `${alarms} alarms`}</span>}
    </button>
  );
});

/** The tab title counts the unacknowledged alarms; a new one sounds the tone unless muted and is said to a screen
 * reader (the returned words, for a live region), not in a replay. */
function useAnnunciation(alarms: readonly Alarm[], unacked: number, muted: boolean): string {
  const { command, playback } = useCapabilities(); // a replay's alarms are history: no sound, and its title says so
  const ready = useSelector((s) => s.consoleId !== null); // the first snapshot is in
  const news = useRef(new NewAlarms());
  const [said, setSaid] = useState("");
  // a flood (a relay down: 20 vehicles lost over a second or two) sounds once and is said once, by its cause
  const burst = useRef<Burst | null>(null);
  burst.current ??= new Burst(setSaid);
  useEffect(() => () => burst.current?.stop(), []);
  useEffect(() => unlockAudioOnGesture(), []);
  const conn = useConnectionState();
  const unreachable = isUnreachable(conn);
  useEffect(() => {
    document.title = pageTitle(unacked, playback, unreachable);
  }, [unacked, playback, unreachable]);
  useEffect(() => {
    if (!ready) return;
    const fresh = news.current.take(alarms);
    if (!fresh.length || !command) return;
    // the tone's words: a screen reader hears no colour, and the tone may be muted or not heard (its "since" makes
    // an alarm raised again with the same text a change the live region says again)
    if (burst.current?.add(fresh) && !muted) beep();
  }, [alarms, ready, command, muted]);
  return said;
}

const isBool = (v: unknown): v is boolean => typeof v === "boolean";

/** A speaker, crossed out when muted (drawn: an emoji needs a font the console's computer may not have). */
function SpeakerIcon({ muted }: { muted: boolean }) {
  return (
    <svg className="fleet-icon" viewBox="0 0 16 16" width="14" height="14" aria-hidden="true">
      <path d="M2 6h3l4-3v10l-4-3H2z" fill="currentColor" />
      {muted ? (
        <path d="M11 5.5l4 5M15 5.5l-4 5" stroke="currentColor" strokeWidth="1.6" />
      ) : (
        <path d="M11 5a4 4 0 0 1 0 6M12.5 3a7 7 0 0 1 0 10" stroke="currentColor" strokeWidth="1.4" fill="none" />
      )}
    </svg>
  );
}

/** With no vehicle on the bus: where the console looks, and what to check, in two lines. */
function NoVehicleHelp() {
  const health = useConsoleHealth();
  const conn = useConnectionState();
  if (conn === "signed-out") return <p className="fleet-help">Sign in to see the vehicles.</p>;
  if (conn !== "live") return <p className="fleet-help">No vehicles: the console is not connected.</p>;
  if (health?.replay) return <p className="fleet-help">No vehicle in the recording at this point.</p>;
  return (
    <div className="fleet-help" data-testid="no-vehicle-help">
      <p>
        No vehicle on DDS domain {health ? health.domain : "…"}
        {health?.ddsNetwork ? ` (${health.ddsNetwork})` : ""}.
      </p>
      <p>
        Check the vehicle's domain id and network interface (CYCLONEDDS_URI for another network): see “Pointing the console at a
        real vehicle” in the docs.
      </p>
    </div>
  );
}

export function FleetBar() {
  const providers = useProvidersOnFrame(SAME_BAR);
  const selected = useSelector((s) => s.selected);
  const alarms = useAlarms();
  const onSelect = useSelectVehicle();
  const now = useNow(1000);
  const recorded = useCapabilities().playback; // a replay: the links and counts are the recording's
  const [muted, setMuted] = useSetting("sem-console.mute", false, isBool);
  const open = useMemo(() => unacknowledged(alarms), [alarms]);
  const shelvedCountNow = useMemo(() => shelved(alarms).length, [alarms]);
  const silences = useSilences();
  const silenceOf = useMemo(
    () => new Map(silences.map((x) => [x.providerId, { until: x.until, title: plannedTitle(x.reason, x.by, x.station) }])),
    [silences],
  );
  const announced = useAnnunciation(alarms, open.length, muted);
  const byVehicle = useMemo(() => {
    const m = new Map<string, number>();
    for (const a of open) if (a.providerId) m.set(a.providerId, (m.get(a.providerId) ?? 0) + 1);
    return m;
  }, [open]);
  const receiving = useReceiving();
  const commanded = useCommanded();
  const paceOf = usePaceOf();
  const othersEvery = useOthersEvery();
  // each vehicle in the one state the bar counts it in, the one the vehicle list's state filter matches it by: a vehicle
  // silent for seconds is not counted live, nor is any with the console unreachable (all "not updating"), nor one
  // silent while the console is behind ("unchecked"), nor one lost during its planned silence (expected, counted apart)
  const all = providers.map((p) => {
    const link = fleetLink(p, now, receiving, paceOf(p.id));
    const until = plannedUntil(silences, p.id, link);
    return { p, link, until, state: fleetState(link, until !== null) };
  });
  const planned = all.flatMap((c) => (c.until === null ? [] : [{ c, until: c.until }]));
  const lost = all.filter((c) => c.state === "lost");
  const count = (state: FleetState) => all.filter((c) => c.state === state).length;
  const stale = count("stale");
  const notUpdating = count("unreachable");
  const unchecked = count("unchecked");
  const live = count("live");
  const inAlarm = all.filter((c) => byVehicle.has(c.p.id)).length;
  const underCommand = all.filter((c) => commanded.has(c.p.id)).length;
  const chips = fleetChips(all, { lost, alarmed: byVehicle, commanded, selected });
  const more = all.length - chips.length;
  // lost vehicles beyond the chips (more lost than the bar holds): the note says they are among the rest
  const shownIds = new Set(chips.map((c) => c.p.id));
  const lostMore = lost.filter((c) => !shownIds.has(c.p.id)).length;
  // the bar's one Tab stop: the selected chip, else the first (worked out once, not per chip)
  const tabStop = chips.some((c) => c.p.id === selected) ? selected : chips[0]?.p.id;
  // the newest alarm still active first: a cleared one ("link lost" of a vehicle back) is named as cleared
  const newest = open.find((a) => a.state === "active-unacknowledged") ?? open[0] ?? null;
  // in a flood the newest is one of many of its cause: the bar names the cause and the count instead, of the alarms in
  // view as the alarm list's group does (acknowledged ones too; the unacknowledged are counted beside)
  const flood = newest ? inView(alarms).filter((a) => a.cause === newest.cause) : [];
  const [alarmsFolded, setAlarmsFolded] = useCollapsed("alarms-panel");
  // Show the alarm list: opened if it was collapsed, scrolled into view (below the top bars: the page's scroll
  // padding) and the focus on its first alarm, so a keyboard operator acknowledges next rather than tabbing through
  // every vehicle of the fleet to get there.
  const showAlarms = () => {
    if (alarmsFolded) setAlarmsFolded(false);
    requestAnimationFrame(() => {
      const region = document.querySelector<HTMLElement>('section[aria-label="Alarms"]');
      region?.scrollIntoView({ block: "nearest" });
      (region?.querySelector<HTMLElement>(".alarm-ack") ?? region?.querySelector<HTMLElement>(".alarm-main"))?.focus({
        preventScroll: true,
      });
    });
  };
  return (
    <nav className="fleet-bar" data-testid="fleet-bar" aria-label="Fleet">
      <div role="alert" className="visually-hidden" data-testid="alarm-announcement">
        {announced}
      </div>
      <div className="fleet-counts">
        <span className="fleet-counts" role="status">
          {notUpdating > 0 ? (
            <span className="fleet-count tone-muted" data-testid="fleet-not-updating" title={UNREACHABLE_TITLE}>
              {notUpdating} {inline(linkText("unreachable"))}
            </span>
          ) : (
            <span
              className={`fleet-count tone-${live ? "ok" : "muted"}${recorded ? " recorded" : ""}`}
              data-testid="fleet-live"
              title={recorded ? RECORDED_TITLE : undefined}
            >
              {stateWords(`${live} ${inline(linkText("live"))}`, recorded)}
            </span>
          )}
          {stale > 0 && (
            <span className="fleet-count tone-warn" data-testid="fleet-stale" title={staleTitle(STALE_AFTER_S, othersEvery)}>
              {stale} {inline(linkText("stale"))}
            </span>
          )}
          {unchecked > 0 && (
            <span className="fleet-count tone-warn" data-testid="fleet-unchecked" title={LINK.unchecked.title}>
              {unchecked} {inline(linkText("unchecked"))}
            </span>
          )}
          <span
            className={`fleet-count tone-${lost.length ? "bad" : "muted"}`}
            data-testid="fleet-lost"
            title={namesTitle(lost.map((c) => name(c.p)))}
          >
            {lost.length} {inline(linkText("lost"))}
          </span>
          {planned.length > 0 && (
            <span
              className="fleet-count fleet-planned"
              data-testid="fleet-planned"
              title={planned.map(({ c, until }) => `${name(c.p)}: until ${clockTime(until)}`).join("; ")}
            >
              {plannedCount(planned.map((x) => x.until))}
            </span>
          )}
          {inAlarm > 0 && (
            <span className="fleet-count tone-bad" data-testid="fleet-in-alarm" title="vehicles with an unacknowledged alarm">
              {inAlarm} {inline(FLEET_STATE.alarm)}
            </span>
          )}
          {underCommand > 0 && (
            <span className="fleet-count tone-info" data-testid="fleet-commanded" title="vehicles with a command in progress">
              {underCommand} {inline(FLEET_STATE.commanded)}
            </span>
          )}
        </span>
        <button
          className={`fleet-count fleet-alarms tone-${open.length ? "bad" : "muted"}`}
          data-testid="fleet-alarms"
          onClick={showAlarms}
          title="show the alarm list"
        >
          {open.length === 1 ? "1 unacknowledged alarm" : `${open.length} unacknowledged alarms`}
        </button>
        {shelvedCountNow > 0 && (
          <button
            className="fleet-count tone-muted"
            data-testid="fleet-shelved"
            onClick={showAlarms}
            title="alarms shelved by an operator: show them"
          >
            {shelvedCount(shelvedCountNow)}
          </button>
        )}
        <button
          className="fleet-mute"
          aria-pressed={muted}
          data-testid="mute"
          onClick={() => setMuted(!muted)}
          title={muted ? "the alarm tone is off" : "the alarm tone is on"}
        >
          <SpeakerIcon muted={muted} /> Mute tone
        </button>
      </div>
      {newest && (
        <button
          className={`fleet-newest tone-${newest.severity === "alarm" ? "bad" : "warn"}`}
          data-testid="fleet-newest-alarm"
          onClick={() => {
            if (newest.providerId) onSelect(newest.providerId);
            showAlarms();
          }}
          title="newest unacknowledged alarm: show it"
        >
          {ALARM_SEVERITY[newest.severity]}: {flood.length >= FLOOD_AT ? floodText(newest.cause, flood) : newest.text}
          {flood.length < FLOOD_AT && newest.state === "cleared-unacknowledged" && " (cleared)"}
        </button>
      )}
      {providers.length === 0 ? (
        <NoVehicleHelp />
      ) : (
        <div className="fleet-chips" role="toolbar" aria-label="Vehicles in the fleet" onKeyDown={moveAmongChips}>
          {chips.map(({ p, link }) => (
            <Chip
              key={p.id}
              id={p.id}
              label={name(p)}
              link={link}
              fixValid={report(p, "GPSFixStatusReport")?.fixValid}
              insState={report(p, "InertialSensorReport")?.state}
              insStatus={report(p, "InertialSensorReport")?.status}
              umaaVersion={p.umaaVersion}
              alarms={byVehicle.get(p.id) ?? 0}
              heardAt={link === "lost" ? lastHeardAt(p) : undefined}
              silence={silenceOf.get(p.id) ?? null}
              until={plannedUntil(silences, p.id, link)}
              staleAfterS={Math.round((staleAfterOf(p) + paceOf(p.id)) * 10) / 10}
              recorded={recorded}
              relayed={p.relay !== null}
              selected={p.id === selected}
              tabbable={p.id === tabStop}
              onSelect={onSelect}
            />
          ))}
          {more > 0 && (
            <button
              className="fleet-chip fleet-more muted"
              data-testid="fleet-more"
              tabIndex={-1}
              onClick={showVehicleList}
              title="the vehicle list finds and filters the whole fleet"
            >
              {more} more in the vehicle list{lostMore > 0 ? `, ${lostMore} of them ${inline(linkText("lost"))}` : ""}
            </button>
          )}
        </div>
      )}
    </nav>
  );
}

const KEY_STEP: Record<string, number> = {
  ArrowRight: 1,
  ArrowDown: 1,
  ArrowLeft: -1,
  ArrowUp: -1,
  Home: -Infinity,
  End: Infinity,
};

/** The chips are one Tab stop (a fleet of 250 would otherwise be 250 Tabs between the header and the panels): the
 * arrow keys, Home and End move the focus among them (a toolbar's keys). */
function moveAmongChips(e: KeyboardEvent<HTMLDivElement>) {
  const step = KEY_STEP[e.key];
  if (step === undefined || !(e.target instanceof HTMLElement)) return;
  const chips = [...e.currentTarget.querySelectorAll<HTMLElement>(".fleet-chip")];
  const at = chips.indexOf(e.target);
  if (at < 0) return;
  e.preventDefault();
  chips[Math.max(0, Math.min(chips.length - 1, at + step))]?.focus();
}

/** What a vehicle panel says instead of its data when no vehicle is selected. */
export function SelectionGap({ gap }: { gap: "no-vehicle" | "select" }) {
  return (
    <p className="muted" data-testid="selection-gap">
      {gap === "select"
        ? "Select a vehicle in the fleet bar or the vehicle list."
        : "No vehicle on the bus yet: see the fleet bar above."}
    </p>
  );
}
