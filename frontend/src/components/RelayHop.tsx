import { useNow, useSelector } from "../data/hooks";
import { relayDataAt } from "../data/slices/vehicles";
import { inline, relayText } from "../lib/labels";

/** "Via relay ship-1, 1.4 s old" of a vehicle seen through a sem-relay (nothing for one on the console's own domain):
 * the relay's name and how old the vehicle's newest data is by its own time stamp, counting with the clock of ages
 * (useNow's one shared timer). `inline`: said inside a line ("via relay ..."). */
export function RelayHop({ id, className, inline: within }: { id: string; className?: string; inline?: boolean }) {
  const relay = useSelector((s) => s.providers[id]?.relay ?? null);
  const dataAt = useSelector((s) => {
    const p = s.providers[id];
    return p?.relay ? relayDataAt(p) : null;
  });
  const now = useNow();
  if (!relay) return null;
  const said = relayText(relay, dataAt === null ? null : Math.max(0, now - dataAt));
  return (
    <span className={`relay-hop${className ? ` ${className}` : ""}`} title={said.title} data-testid="relay-hop">
      {within ? inline(said.text) : said.text}
    </span>
  );
}

/** The selected vehicle's panels: the relay it is seen through, if any. */
export function SelectedRelay() {
  const selected = useSelector((s) => (s.selected && s.providers[s.selected]?.relay ? s.selected : null));
  if (!selected) return null;
  return (
    <p className="selected-relay" data-testid="selected-relay">
      <RelayHop id={selected} />
    </p>
  );
}
