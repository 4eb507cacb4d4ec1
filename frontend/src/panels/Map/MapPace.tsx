import { useOthersEvery } from "../../data/hooks";

/** How often the map's dots of the vehicles the page does not draw move: the console sends each of their reports at
 * most once a pace (`pace`), so their positions are up to that much older than the selected vehicle's. Nothing while
 * the console paces none. */
export function MapPace() {
  const othersEvery = useOthersEvery();
  if (othersEvery === null) return null;
  return (
    <span
      data-testid="map-pace"
      title="the console sends each vehicle not selected at most this often, the selected one as it reports"
    >
      vehicles not selected: at most a position every {othersEvery} s
    </span>
  );
}
