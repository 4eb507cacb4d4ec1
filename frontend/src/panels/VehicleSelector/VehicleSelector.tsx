import { startTransition, useEffect, useEffectEvent, useMemo, useRef, useState } from "react";
import { defaultRangeExtractor, useVirtualizer, type Range } from "@tanstack/react-virtual";
import { useFocusWhenGone } from "../../components/focus";
import { VehicleTag } from "../../components/VehicleTag";
import {
  useAlarmed,
  useCapabilities,
  useCommanded,
  useConnectionState,
  useNow,
  usePaceOf,
  useProvidersOnFrame,
  useReceiving,
  sameOverview,
  useSelector,
  useSilences,
  useSelectVehicle,
} from "../../data/hooks";
import { lastHeardAt, report } from "../../data/slices/vehicles";
import { plannedUntil } from "../../data/slices/alarms";
import { LastHeard } from "../../components/LastHeard";
import { RelayHop } from "../../components/RelayHop";
import { RECORDED_TITLE, fleetState, pageLink, recordedState, stateWords, type FleetState } from "../../lib/freshness";
import { FLEET_STATE, fixWord, inline, insWord, linkOrPlanned, linkText } from "../../lib/labels";
import { age } from "../../lib/units";
import { vehicleMatcher } from "../../lib/vehicle";
import { staleAfterOf } from "../FleetBar/FleetBar";
import { RenameVehicle } from "../RenameVehicle/RenameVehicle";

/** The list draws when a vehicle's name, link, fix or INS changed; its ages with the clock (useNow, 0.5 s). */
const SAME_LIST = sameOverview();

/** Find a vehicle in a fleet by a part of its name or id: the list shows the matches as typed, Esc or Clear brings back
 * the whole fleet, and the count of matches (of `filter`, the query the list shows) is said politely. A key redraws
 * the field alone at once; the list (250 rows) follows in a transition, which the next key interrupts. */
function FindVehicle({
  filter,
  onFilter,
  matches,
  total,
  narrowed,
}: {
  filter: string;
  onFilter: (q: string) => void;
  matches: number;
  total: number;
  narrowed: boolean; // a filter (state, version, relay) is set: the count is said without a query too
}) {
  const field = useRef<HTMLInputElement>(null);
  const [query, setQuery] = useState(filter);
  const clear = () => (setQuery(""), onFilter(""));
  return (
    <div className="find-vehicle" role="search" aria-label="Find a vehicle">
      <label>
        Find{" "}
        <input
          ref={field}
          type="search"
          value={query}
          placeholder="name or id"
          autoComplete="off"
          spellCheck={false}
          onChange={(e) => {
            const q = e.target.value;
            setQuery(q);
            startTransition(() => onFilter(q));
          }}
          onKeyDown={(e) => {
            if (e.key !== "Escape" || !query) return;
            e.preventDefault(); // cleared here, not by anything else Esc closes
            clear();
          }}
          data-testid="find-vehicle"
        />
      </label>
      {/* always laid out, hidden without a query: the list under it does not move as the operator starts typing */}
      <button
        type="button"
        className="small"
        style={{ visibility: query ? "visible" : "hidden" }}
        onClick={() => (clear(), field.current?.focus())}
        aria-label="Clear the vehicle search"
      >
        Clear
      </button>
      <span className="muted find-count" role="status" data-testid="find-vehicle-count">
        {filter.trim() || narrowed ? `${matches} of ${total} ${total === 1 ? "vehicle" : "vehicles"}` : ""}
      </span>
    </div>
  );
}

/** The list's filters beside the search: "" is any. `state` is what the fleet bar counts. */
export interface Filters {
  state: "" | FleetState | "alarm" | "commanded";
  version: string;
  relay: string; // a relay's name, or DIRECT
}
const ANY: Filters = { state: "", version: "", relay: "" };
const DIRECT = "(direct)";
/** The state filter's choices: each state the fleet bar counts (`fleetState`), in its words; in a replay (`recorded`)
 * the links are the recording's, worded so ("Recorded: live"), but "Not updating", the page's own state now. */
function states(recorded: boolean): { value: Filters["state"]; text: string }[] {
  const link = (s: FleetState) => ({ value: s, text: stateWords(linkText(s), recordedState(s, recorded)) });
  return [
    { value: "", text: "Any state" },
    ...(["live", "stale", "unchecked", "lost", "planned", "unreachable"] as const).map(link),
    { value: "alarm", text: FLEET_STATE.alarm },
    { value: "commanded", text: FLEET_STATE.commanded },
  ];
}

/** A filter's drop-down: its choices, "" first (any). */
function Choice({
  label,
  value,
  options,
  onChange,
  testId,
}: {
  label: string;
  value: string;
  options: readonly { value: string; text: string }[];
  onChange: (v: string) => void;
  testId: string;
}) {
  return (
    <select aria-label={label} value={value} onChange={(e) => onChange(e.target.value)} data-testid={testId}>
      {options.map((o) => (
        <option key={o.value} value={o.value}>
          {o.text}
        </option>
      ))}
    </select>
  );
}

/** The filters by state, by UMAA version and by relay: a version's and a relay's only when the fleet has a choice. */
function FleetFilters({
  filters,
  onFilters,
  versions,
  relays,
  recorded,
}: {
  recorded: boolean;
  filters: Filters;
  onFilters: (f: Filters) => void;
  versions: readonly string[];
  relays: readonly string[];
}) {
  const set = (f: Partial<Filters>) => startTransition(() => onFilters({ ...filters, ...f }));
  return (
    <div className="fleet-filters" role="group" aria-label="Filter the vehicles">
      <Choice
        label="State"
        value={filters.state}
        options={states(recorded)}
        onChange={(v) => set({ state: v as Filters["state"] })}
        testId="filter-state"
      />
      {(versions.length > 1 || filters.version) && (
        <Choice
          label="UMAA version"
          value={filters.version}
          options={[{ value: "", text: "Any UMAA version" }, ...versions.map((v) => ({ value: v, text: `UMAA ${v}` }))]}
          onChange={(v) => set({ version: v })}
          testId="filter-version"
        />
      )}
      {(relays.length > 0 || filters.relay) && (
        <Choice
          label="Relay"
          value={filters.relay}
          options={[
            { value: "", text: "Any relay" },
            { value: DIRECT, text: "No relay" },
            ...relays.map((r) => ({ value: r, text: `Via ${r}` })),
          ]}
          onChange={(v) => set({ relay: v })}
          testId="filter-relay"
        />
      )}
    </div>
  );
}

/** A row's height before it is measured, and the rows drawn beyond the list's view each way: a fleet of a thousand
 * is a few tens of rows in the page, whatever its size. */
const ROW_PX = 64;
const OVERSCAN = 12;
const ROW_GAP = 6;

export function VehicleSelector() {
  const providers = useProvidersOnFrame(SAME_LIST); // on the frame, when what it shows changed
  const selected = useSelector((s) => s.selected);
  const selectVehicle = useSelectVehicle();
  const now = useNow();
  const signedOut = useConnectionState() === "signed-out";
  const recorded = useCapabilities().playback; // a replay: the links are the recording's
  const receiving = useReceiving();
  const paceOf = usePaceOf();
  const silences = useSilences();
  const alarmed = useAlarmed();
  const commanded = useCommanded();
  const list = useRef<HTMLElement>(null);
  const rows = useRef<HTMLDivElement>(null);
  const focusedRow = useRef<string | null>(null); // the id of the row the focus is in (its button, its Rename)
  const [filter, setFilter] = useState(""); // the search's query, as the list shows it (FindVehicle)
  const [filters, setFilters] = useState<Filters>(ANY);
  const [searches, setSearches] = useState(0); // a new search field (empty) each time the list clears it
  const narrowed = filters.state !== "" || filters.version !== "" || filters.relay !== "";
  const versions = useMemo(
    () => [...new Set(providers.flatMap((p) => (p.umaaVersion ? [p.umaaVersion] : [])))].sort(),
    [providers],
  );
  const relays = useMemo(() => [...new Set(providers.flatMap((p) => (p.relay ? [p.relay] : [])))].sort(), [providers]);
  const views = useMemo(
    () =>
      providers.map((p) => {
        const seen = lastHeardAt(p);
        const ageS = seen === null ? null : Math.max(0, now - seen);
        const link = pageLink(p.link, ageS, staleAfterOf(p) + paceOf(p.id), receiving);
        return { p, seen, ageS, link, until: plannedUntil(silences, p.id, link) };
      }),
    [providers, now, receiving, silences, paceOf],
  );
  const matching = useMemo(() => {
    const named = vehicleMatcher(filter);
    const inState = (v: (typeof views)[number]): boolean => {
      switch (filters.state) {
        case "":
          return true;
        case "alarm":
          return alarmed.has(v.p.id);
        case "commanded":
          return commanded.has(v.p.id);
        default:
          return fleetState(v.link, v.until !== null) === filters.state;
      }
    };
    return views.filter(
      (v) =>
        named(v.p) &&
        inState(v) &&
        (!filters.version || v.p.umaaVersion === filters.version) &&
        (!filters.relay || (v.p.relay ?? DIRECT) === filters.relay),
    );
  }, [views, filter, filters, alarmed, commanded]);
  const at = matching.findIndex((v) => v.p.id === selected);
  const shown = at >= 0;
  // the selected vehicle (from a chip, the map, an alarm) hidden by the search: said in the list, with its way back
  const hidden = shown ? undefined : providers.find((p) => p.id === selected);
  const focus = useFocusWhenGone();
  const showAll = (button: HTMLElement) => {
    focus.pressed(button, () => list.current?.querySelector<HTMLElement>(".vehicle.selected"));
    setFilter("");
    setFilters(ANY);
    setSearches((n) => n + 1);
  };
  // Only the rows in the list's view (and a few each side) are in the page; their heights are measured as drawn (the
  // selected row has its Rename under it).
  // eslint-disable-next-line react-hooks/incompatible-library -- no React Compiler here: its functions are read in this render
  const virtual = useVirtualizer({
    count: matching.length,
    getScrollElement: () => list.current,
    estimateSize: () => ROW_PX,
    getItemKey: (i) => matching[i]?.p.id ?? i,
    overscan: OVERSCAN,
    // the selected row (its Rename) and the one with the focus stay in the page when scrolled out of view: the focus
    // and a name being typed are not lost to a scroll
    rangeExtractor: (range: Range) => {
      const drawn = defaultRangeExtractor(range);
      const focusedAt = focusedRow.current ? matching.findIndex((v) => v.p.id === focusedRow.current) : -1;
      const kept = [at, focusedAt].filter((i) => i >= 0 && !drawn.includes(i));
      return kept.length ? [...drawn, ...kept].sort((x, y) => x - y) : drawn;
    },
    gap: ROW_GAP,
    scrollMargin: rows.current?.offsetTop ?? 0,
    initialRect: { width: 320, height: 480 }, // before the list is measured (and in a test's page without layout)
    useFlushSync: false,
  });
  // A vehicle selected elsewhere (a chip of the fleet bar, the map, an alarm) is brought into the list's view, its
  // Rename with it: with a fleet the list scrolls within itself. Only the list scrolls, never the page.
  // Only when the selection, the search or the filters change: the operator's own scrolling is left alone.
  const reveal = useEffectEvent(() => {
    if (at >= 0) virtual.scrollToIndex(at, { align: "auto" });
    else if (selected && list.current) list.current.scrollTop = 0; // what the list says of it, at its top
  });
  useEffect(() => reveal(), [selected, shown, filter, filters]);
  const margin = virtual.options.scrollMargin;
  return (
    <>
      {(providers.length > 1 || filter || narrowed) && (
        <>
          <FindVehicle
            key={searches}
            filter={filter}
            onFilter={setFilter}
            matches={matching.length}
            total={providers.length}
            narrowed={narrowed}
          />
          <FleetFilters
            key={`f${searches}`}
            filters={filters}
            onFilters={setFilters}
            versions={versions}
            relays={relays}
            recorded={recorded}
          />
        </>
      )}
      <nav className="vehicles" aria-label="Vehicles" data-testid="vehicles" ref={list}>
        {providers.length === 0 && (
          <p className="muted">
            {signedOut ? "Sign in to see the vehicles." : "No vehicle on the bus yet: see the fleet bar above."}
          </p>
        )}
        {providers.length > 0 && !selected && (
          <p className="muted" data-testid="select-vehicle">
            Select a vehicle.
          </p>
        )}
        {providers.length > 0 && matching.length === 0 && (
          <p className="muted" data-testid="find-vehicle-none">
            {narrowed ? "No vehicle matches the search and the filters." : `No vehicle's name or id has “${filter.trim()}”.`}
          </p>
        )}
        {selected && !providers.some((p) => p.id === selected) && (
          <p className="vehicle selected missing" data-testid="selected-missing">
            <VehicleTag v={{ id: selected, name: null }} /> selected, {signedOut ? "shown after sign-in" : "not on the bus (yet)"}
          </p>
        )}
        {hidden && (
          <p className="vehicle selected missing" data-testid="selected-hidden">
            <span>
              <VehicleTag v={hidden} /> selected, not among the matches of the search{narrowed ? " and the filters" : ""}
            </span>
            <button type="button" className="small" onClick={(e) => showAll(e.currentTarget)}>
              Show all vehicles
            </button>
          </p>
        )}
        <div
          className="vehicle-rows"
          role="list"
          ref={rows}
          style={{ height: virtual.getTotalSize() }}
          onFocus={(e) => (focusedRow.current = e.target.closest<HTMLElement>(".vehicle-row")?.dataset.id ?? null)}
          onBlur={(e) => {
            if (!(e.relatedTarget instanceof Node && e.currentTarget.contains(e.relatedTarget))) focusedRow.current = null;
          }}
        >
          {virtual.getVirtualItems().map((item) => {
            const { p, seen, ageS, link, until } = matching[item.index];
            const rec = recordedState(link, recorded); // "not updating" is the page's now, in a replay too
            const fix = fixWord(report(p, "GPSFixStatusReport")?.fixValid, p.umaaVersion);
            const ins = report(p, "InertialSensorReport");
            const insSaid = insWord(ins?.state, ins?.status, p.umaaVersion);
            return (
              <div
                key={item.key}
                className="vehicle-row"
                role="listitem"
                aria-posinset={item.index + 1}
                aria-setsize={matching.length}
                data-index={item.index}
                data-id={p.id}
                ref={virtual.measureElement}
                style={{ transform: `translateY(${item.start - margin}px)` }}
              >
                <button
                  className={`vehicle${p.id === selected ? " selected" : ""}`}
                  aria-pressed={p.id === selected}
                  data-testid="vehicle"
                  data-link={link}
                  onClick={() => selectVehicle(p.id)}
                >
                  <span className="vehicle-name">
                    <VehicleTag v={p} />
                  </span>
                  <span
                    className={`link link-${until !== null ? "planned" : link}${rec ? " recorded" : ""}`}
                    data-testid="vehicle-link"
                    title={rec ? RECORDED_TITLE : undefined}
                  >
                    {stateWords(linkOrPlanned(link, until), rec)}
                  </span>
                  <span className="vehicle-meta">
                    {p.umaaVersion && (
                      <span
                        className="umaa-version"
                        data-testid="vehicle-umaa"
                        title="the UMAA version of the topics the vehicle reports on"
                      >
                        UMAA {p.umaaVersion}
                      </span>
                    )}{" "}
                    <span title={fix.title}>{inline(fix.text)}</span> · <span title={insSaid.title}>{insSaid.text}</span>
                    {link === "lost" ? (
                      <>
                        {" "}
                        · <LastHeard since={seen} />
                      </>
                    ) : (
                      ` · ${age(ageS)}`
                    )}
                    {p.relay && (
                      <>
                        {" "}
                        · <RelayHop id={p.id} inline />
                      </>
                    )}
                  </span>
                  <span className="vehicle-id muted">{p.id}</span>
                </button>
                {p.id === selected && <RenameVehicle v={p} />}
              </div>
            );
          })}
        </div>
      </nav>
    </>
  );
}
