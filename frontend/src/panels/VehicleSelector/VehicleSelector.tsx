import { Fragment, startTransition, useEffect, useMemo, useRef, useState } from "react";
import { useFocusWhenGone } from "../../components/focus";
import { VehicleTag } from "../../components/VehicleTag";
import {
  useCapabilities,
  useConnectionState,
  useNow,
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
import { RECORDED_TITLE, pageLink, recordedState, stateWords } from "../../lib/freshness";
import { fixWord, inline, insWord, linkOrPlanned } from "../../lib/labels";
import { age } from "../../lib/units";
import { vehicleMatcher } from "../../lib/vehicle";
import { STALE_AFTER_S } from "../FleetBar/FleetBar";
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
}: {
  filter: string;
  onFilter: (q: string) => void;
  matches: number;
  total: number;
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
        {filter.trim() ? `${matches} of ${total} ${total === 1 ? "vehicle" : "vehicles"}` : ""}
      </span>
    </div>
  );
}

export function VehicleSelector() {
  const providers = useProvidersOnFrame(SAME_LIST); // on the frame, when what it shows changed
  const selected = useSelector((s) => s.selected);
  const selectVehicle = useSelectVehicle();
  const now = useNow();
  const signedOut = useConnectionState() === "signed-out";
  const recorded = useCapabilities().playback; // a replay: the links are the recording's
  const receiving = useReceiving();
  const silences = useSilences();
  const list = useRef<HTMLElement>(null);
  const [filter, setFilter] = useState(""); // the search's query, as the list shows it (FindVehicle)
  const [searches, setSearches] = useState(0); // a new search field (empty) each time the list clears it
  const matching = useMemo(() => providers.filter(vehicleMatcher(filter)), [providers, filter]);
  const shown = matching.some((p) => p.id === selected);
  // the selected vehicle (from a chip, the map, an alarm) hidden by the search: said in the list, with its way back
  const hidden = shown ? undefined : providers.find((p) => p.id === selected);
  const focus = useFocusWhenGone();
  const showAll = (button: HTMLElement) => {
    focus.pressed(button, () => list.current?.querySelector<HTMLElement>(".vehicle.selected"));
    setFilter("");
    setSearches((n) => n + 1);
  };
  // A vehicle selected elsewhere (a chip of the fleet bar, the map, an alarm) is brought into the list's view, its
  // Rename with it: with a fleet the list scrolls within itself. Only the list scrolls, never the page.
  useEffect(() => {
    const nav = list.current;
    const row = nav?.querySelector<HTMLElement>(".vehicle.selected"); // its row, or what the list says of it
    if (!nav || !row) return;
    const after = row.nextElementSibling;
    const end = after instanceof HTMLElement && !after.classList.contains("vehicle") ? after : row; // its Rename
    const top = row.offsetTop; // the list is positioned: offsets are within it
    const bottom = end.offsetTop + end.offsetHeight;
    if (top < nav.scrollTop) nav.scrollTop = top;
    else if (bottom > nav.scrollTop + nav.clientHeight) nav.scrollTop = Math.min(top, bottom - nav.clientHeight);
  }, [selected, shown, filter]); // and when the search has changed the rows above it
  return (
    <>
      {(providers.length > 1 || filter) && (
        <FindVehicle key={searches} filter={filter} onFilter={setFilter} matches={matching.length} total={providers.length} />
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
            No vehicle's name or id has “{filter.trim()}”.
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
              <VehicleTag v={hidden} /> selected, not among the matches of the search
            </span>
            <button type="button" className="small" onClick={(e) => showAll(e.currentTarget)}>
              Show all vehicles
            </button>
          </p>
        )}
        {matching.map((p) => {
          const seen = lastHeardAt(p);
          const ageS = seen === null ? null : Math.max(0, now - seen);
          const link = pageLink(p.link, ageS, STALE_AFTER_S, receiving);
          const until = plannedUntil(silences, p.id, link); // lost in its planned silence: named so, not lost
          const rec = recordedState(link, recorded); // "not updating" is the page's now, in a replay too
          const fix = fixWord(report(p, "GPSFixStatusReport")?.fixValid, p.umaaVersion);
          const ins = report(p, "InertialSensorReport");
          const insSaid = insWord(ins?.state, ins?.status, p.umaaVersion);
          return (
            <Fragment key={p.id}>
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
            </Fragment>
          );
        })}
      </nav>
    </>
  );
}
