import { useCapabilities, useNow, useSelector } from "../data/hooks";
import { selectedLostSince, selectedPlannedUntil } from "../data/slices/vehicles";
import { RECORDED_TITLE, stateWords } from "../lib/freshness";
import { lastHeardText, linkOrPlanned, lostText } from "../lib/labels";
import { DASH, elapsedText } from "../lib/units";
import { vehicleLabel, type VehicleIdentity } from "../lib/vehicle";

/** "Last heard 2 min 10 s ago" of a lost vehicle last heard at `since` (the source's clock; null: never), counting
 * each second: the one leaf that draws with the clock of ages (useNow's one shared timer), not the chip, row or panel
 * that names the vehicle. */
export function LastHeard({ since, className }: { since: number | null; className?: string }) {
  const now = useNow(1000);
  return (
    <span className={`last-heard${className ? ` ${className}` : ""}`} data-testid="last-heard">
      {lastHeardText(since === null ? null : now - since)}
    </span>
  );
}

/** The selected vehicle's panels, while it is lost: when it was last heard, and that what they show is what it last
 * reported. No live region: its count changes every second, and a screen reader would say it every second (the loss
 * itself is announced with its alarm). */
export function SelectedLost() {
  const since = useSelector(selectedLostSince);
  const until = useSelector(selectedPlannedUntil); // lost in its planned silence: named so, not lost
  const recorded = useCapabilities().playback; // a replay: lost in the recording, not now
  if (since === null) return null;
  return (
    <p
      className={`selected-lost${until !== null ? " planned" : ""}`}
      data-testid="selected-lost"
      title={recorded ? RECORDED_TITLE : undefined}
    >
      {stateWords(linkOrPlanned("lost", until), recorded)} · <LastHeard since={since > 0 ? since : null} /> · shown: what it last
      reported
    </p>
  );
}

/** "Alpha (77b2ceb8) is lost: last heard 12 s ago" (or "is out of comms (planned) until 14:20 UTC" while lost in its
 * planned silence, `until` its end), counting; `since` 0 or null: no report of it received. */
export function LostFor({
  target,
  since,
  until = null,
}: {
  target: VehicleIdentity;
  since: number | null;
  until?: number | null;
}) {
  const now = useNow(1000);
  return <>{lostText(vehicleLabel(target), since ? now - since : null, until)}</>;
}

/** A panel's freshness badge while the selected vehicle is lost: "Lost · 13 s" (or "Out of comms (planned) until 14:20
 * UTC · 13 s"), its age the one "Last heard 13 s ago" says beside it: the same instant (the vehicle's newest report of
 * any topic), the same clock (useNow's one timer of a second) and the same rule (elapsedText). */
export function LostBadge({ recorded }: { recorded: boolean }) {
  const since = useSelector(selectedLostSince);
  const until = useSelector(selectedPlannedUntil);
  const now = useNow(1000);
  return (
    <>
      {stateWords(linkOrPlanned("lost", until), recorded)} · {since ? elapsedText(now - since) : DASH}
    </>
  );
}
