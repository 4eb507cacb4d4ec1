// The map panel's buttons: follow the selected vehicle, fit every vehicle, measure, coordinate format.
import type { Dispatch, SetStateAction } from "react";

interface Props {
  follow: boolean;
  setFollow: Dispatch<SetStateAction<boolean>>;
  canFit: boolean;
  fitAll: () => void;
  measuring: boolean;
  toggleMeasure: () => void;
  useDms: boolean;
  setDms: (v: boolean) => void;
}

export function MapToolbar({ follow, setFollow, canFit, fitAll, measuring, toggleMeasure, useDms, setDms }: Props) {
  return (
    <div className="map-tools">
      <button
        className="small"
        aria-pressed={follow}
        onClick={() => setFollow((f) => !f)} // from the state as it is, not as this render saw it
        data-testid="map-follow"
        title="keep the selected vehicle in view"
      >
        Follow
      </button>
      <button
        className="small"
        data-testid="map-fit-all"
        disabled={!canFit}
        title="every vehicle with a position in view (stops following)"
        onClick={fitAll}
      >
        Fit all
      </button>
      <button
        className="small"
        aria-pressed={measuring}
        data-testid="map-measure"
        onClick={toggleMeasure}
        title="click points on the map to measure the distance along them"
      >
        Measure
      </button>
      <button
        className="small"
        onClick={() => setDms(!useDms)}
        aria-pressed={useDms}
        title="coordinates in degrees-minutes-seconds or decimal degrees"
      >
        {useDms ? "DMS" : "Decimal"}
      </button>
    </div>
  );
}
