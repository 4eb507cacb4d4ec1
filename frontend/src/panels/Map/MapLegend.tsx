import type { FeatureCollection } from "geojson";
import { coverageText } from "../../lib/labels";

/** The areas' colours (layers.ts) in the words the CoMap panel gives each area's coverage (words.json). */
const AREAS = `areas: ${coverageText("COMPLETED")} (green), ${coverageText("PARTIAL")} (amber), ${coverageText("NONE")} (red)`;

/** What the map's marks mean; the areas' coverage colours only when the map draws an area (the CoMap world model shown
 * has a feature: none while CoMap is off, where the console serves an empty one). */
export function MapLegend({ model }: { model: FeatureCollection | null }) {
  return (
    <p className="map-legend muted" data-testid="map-legend">
      <span className="lg lg-valid">fix valid</span> <span className="lg lg-invalid">no fix</span>{" "}
      <span className="lg lg-unknown">unknown</span> · ring: stale (amber) or lost (red) · ○ origin · dashed: a lost vehicle's
      projected position (dead reckoning, not a report) and the circle it is probably within
      {model?.features.length ? ` · ${AREAS}` : ""}
    </p>
  );
}
